// The public value types (Vec3, Quat, Mat4 of springbones.h) to GLM and back: the only crossings
// between the API and the core's maths. Plain float copies, so a value keeps its bits on both
// sides. Always inlined: the WebAssembly build compiles most files at -Oz, where they stayed
// calls in per-frame code (jump_carry.cpp, xpbd_solver.cpp).
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "springbones/springbones.h"

namespace springbones {

// Member by member rather than through GLM's constructors, which are calls at -Oz.
[[gnu::always_inline]] inline glm::vec3 toGlm(const Vec3& v) {
  glm::vec3 out;
  out.x = v.x, out.y = v.y, out.z = v.z;
  return out;
}
[[gnu::always_inline]] inline glm::quat toGlm(const Quat& q) {
  glm::quat out;
  out.x = q.x, out.y = q.y, out.z = q.z, out.w = q.w;
  return out;
}
[[gnu::always_inline]] inline glm::mat4 toGlm(const Mat4& m) { return glm::make_mat4(m.m); }

[[gnu::always_inline]] inline Vec3 fromGlm(const glm::vec3& v) { return Vec3{v.x, v.y, v.z}; }
[[gnu::always_inline]] inline Quat fromGlm(const glm::quat& q) { return Quat{q.x, q.y, q.z, q.w}; }
/// A rotation into an instance's rotations buffer: x, y, z, w at `out`.
[[gnu::always_inline]] inline void storeQuat(float* out, const glm::quat& q) {
  out[0] = q.x;
  out[1] = q.y;
  out[2] = q.z;
  out[3] = q.w;
}
[[gnu::always_inline]] inline Mat4 fromGlm(const glm::mat4& m) {
  Mat4 out;
  for (int i = 0; i < 16; ++i) out.m[i] = glm::value_ptr(m)[i];
  return out;
}

}  // namespace springbones
