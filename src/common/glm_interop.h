// The public value types (Vec3, Quat, Mat4 of springbones.h) to GLM and back. The core does its
// maths in GLM; these are the only crossings, plain float copies that the compiler removes, so a
// value is the same bits on both sides.
#pragma once

#include <cstring>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "springbones/springbones.h"

namespace springbones {

inline glm::vec3 toGlm(const Vec3& v) { return glm::vec3(v.x, v.y, v.z); }
inline glm::quat toGlm(const Quat& q) { return glm::quat(q.w, q.x, q.y, q.z); }
inline glm::mat4 toGlm(const Mat4& m) {
  glm::mat4 out;
  std::memcpy(&out[0][0], m.m, sizeof m.m);
  return out;
}

inline Vec3 fromGlm(const glm::vec3& v) { return Vec3{v.x, v.y, v.z}; }
inline Quat fromGlm(const glm::quat& q) { return Quat{q.x, q.y, q.z, q.w}; }
inline Mat4 fromGlm(const glm::mat4& m) {
  Mat4 out;
  std::memcpy(out.m, &m[0][0], sizeof out.m);
  return out;
}

}  // namespace springbones
