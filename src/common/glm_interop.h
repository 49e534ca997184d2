// The public value types (Vec3, Quat, Mat4 of springbones.h) to GLM and back: the only crossings
// between the API and the core's maths. Plain float copies the compiler removes, so a value keeps
// its bits on both sides.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "springbones/springbones.h"

namespace springbones {

inline glm::vec3 toGlm(const Vec3& v) { return glm::vec3(v.x, v.y, v.z); }
inline glm::quat toGlm(const Quat& q) { return glm::quat(q.w, q.x, q.y, q.z); }
inline glm::mat4 toGlm(const Mat4& m) { return glm::make_mat4(m.m); }

inline Vec3 fromGlm(const glm::vec3& v) { return Vec3{v.x, v.y, v.z}; }
inline Quat fromGlm(const glm::quat& q) { return Quat{q.x, q.y, q.z, q.w}; }
inline Mat4 fromGlm(const glm::mat4& m) {
  Mat4 out;
  for (int i = 0; i < 16; ++i) out.m[i] = glm::value_ptr(m)[i];
  return out;
}

}  // namespace springbones
