// Small transform helpers shared by the loader, the rig builder and the solver.
#pragma once

#include <cmath>

#include "common/glm_interop.h"

namespace springbones {

inline glm::mat4 composeTransform(const glm::vec3& translation, const glm::quat& rotation, const glm::vec3& scale) {
  glm::mat4 m = glm::mat4_cast(rotation);
  m[0] *= scale.x;
  m[1] *= scale.y;
  m[2] *= scale.z;
  m[3] = glm::vec4(translation, 1.0f);
  return m;
}

inline glm::mat4 composeTransform(const Transform& t) {
  return composeTransform(toGlm(t.translation), toGlm(t.rotation), toGlm(t.scale));
}

inline bool isFinite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// `v` made unit length, false (and `v` untouched) for a zero or non-finite one. Scaled by its
/// largest component first, so a long finite vector does not overflow on the way.
inline bool toUnitLength(glm::vec3& v) {
  const float largest = std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z)));
  if (!(largest > 0.0f) || !std::isfinite(largest)) return false;
  const glm::vec3 scaled = v / largest;
  v = scaled / glm::length(scaled);
  return true;
}

/// Inverse of an affine matrix, or false when it has no usable inverse (a zero scale, or
/// non-finite entries). Callers treat a center without an inverse as world space for that step.
inline bool affineInverse(const glm::mat4& m, glm::mat4& out) {
  const glm::mat3 linear(m);
  const float det = glm::determinant(linear);
  if (!(std::fabs(det) > 1e-18f) || !std::isfinite(det)) return false;
  const glm::mat3 inv = glm::inverse(linear);
  out = glm::mat4(inv);
  out[3] = glm::vec4(-(inv * glm::vec3(m[3])), 1.0f);
  return true;
}

/// Splits an affine matrix into translation, rotation and (positive or mirrored) scale. Shear is
/// dropped: glTF requires node matrices to be decomposable into TRS, so a sheared one is invalid
/// input and the closest rotation is the best we can do.
inline Transform decomposeTransform(const glm::mat4& m) {
  const glm::vec3 x(m[0]), y(m[1]), z(m[2]);
  glm::vec3 scale(glm::length(x), glm::length(y), glm::length(z));
  if (glm::dot(glm::cross(x, y), z) < 0.0f) scale.x = -scale.x;  // mirrored
  glm::mat3 r(1.0f);
  if (scale.x != 0.0f && scale.y != 0.0f && scale.z != 0.0f) r = glm::mat3(x / scale.x, y / scale.y, z / scale.z);
  return Transform{fromGlm(glm::vec3(m[3])), fromGlm(glm::normalize(glm::quat_cast(r))), fromGlm(scale)};
}

/// Shortest-arc rotation taking unit vector `from` to unit vector `to`. For opposite vectors the
/// axis is any perpendicular one (the result is still a valid 180-degree turn).
inline glm::quat rotationBetween(const glm::vec3& from, const glm::vec3& to) {
  const float d = glm::dot(from, to);
  if (d < -0.999999f) {
    glm::vec3 axis = glm::cross(glm::vec3(1, 0, 0), from);
    if (glm::dot(axis, axis) < 1e-12f) axis = glm::cross(glm::vec3(0, 1, 0), from);
    axis = glm::normalize(axis);
    return glm::quat(0.0f, axis.x, axis.y, axis.z);
  }
  const glm::vec3 c = glm::cross(from, to);
  return glm::normalize(glm::quat(1.0f + d, c.x, c.y, c.z));
}

}  // namespace springbones
