// The angle limits' arithmetic (joint_limits.h). Its own file, at the size-optimised level in
// WebAssembly: the solver around it is compiled for speed (-O3), where these functions, inlined at
// each of their call sites with their series unrolled, cost the module kilobytes for joints that
// only rigs with limits have.
#include "simulation/joint_limits.h"

#include <algorithm>
#include <cmath>

namespace springbones {

/// The part of a joint's limit space that does not move: the turn taking +Y onto the rest bone
/// axis `axis` (unit, in the joint's own space), then the limit's rotation.
glm::quat limitFrameLocal(const glm::vec3& axis, const Quat& rotation) {
  glm::quat to_axis;
  if (axis.x == 0.0f && axis.y == -1.0f && axis.z == 0.0f) {
    to_axis = glm::quat(0.0f, 1.0f, 0.0f, 0.0f);  // w, x, y, z: half a turn about X (the draft's rule)
  } else {
    // (cross(+Y, axis), 1 + dot(+Y, axis)), normalized: the shortest turn.
    to_axis = glm::normalize(glm::quat(1.0f + axis.y, axis.z, 0.0f, -axis.x));
  }
  return glm::normalize(to_axis * toGlm(rotation));
}

/// The rotation of a rest world matrix's linear part: its columns made orthonormal (scale and, for a
/// sheared parent, shear taken out), X first.
glm::quat worldRotationOf(const glm::mat3& m) {
  const glm::vec3 x = glm::normalize(m[0]);
  const glm::vec3 y = glm::normalize(m[1] - x * glm::dot(x, m[1]));
  return glm::normalize(glm::quat_cast(glm::mat3(x, y, glm::cross(x, y))));
}

/// cos and sin of an angle in [0, pi], by their Taylor series in double: +, x and / only, so no libm
/// trigonometry (and its tables) enters the module, and every build gives the same bits. Twenty
/// terms leave an error under 1e-25 at pi.
void cosSin(float angle, float& cos_out, float& sin_out) {
  const double x = angle, x2 = x * x;
  double c = 0.0, s = 0.0, term_c = 1.0, term_s = x;
  for (int n = 0; n < 20; ++n) {
    c += term_c;
    s += term_s;
    term_c *= -x2 / ((2 * n + 1) * (2 * n + 2));
    term_s *= -x2 / ((2 * n + 2) * (2 * n + 3));
  }
  cos_out = static_cast<float>(c);
  sin_out = static_cast<float>(s);
}

/// Keeps a unit direction `d`, in limit space, inside the limit. Returns whether it moved it.
/// Angles are compared through their cosines and sines (every limit angle is in [0, pi], where
/// they are monotonic), which is the same test as comparing the angles.
bool limitDirection(const JointLimit& limit, glm::vec3& d) {
  switch (limit.kind) {
    case JointLimit::Kind::kCone: {
      float cos_limit, sin_limit;
      cosSin(limit.angle, cos_limit, sin_limit);
      if (!(d.y < cos_limit)) return false;
      const float horizontal2 = d.x * d.x + d.z * d.z;
      if (horizontal2 < kLimitSingular) {
        d = glm::vec3(0.0f, cos_limit, sin_limit);  // -Y: the boundary on the +Z side
      } else {
        const float scale = sin_limit / std::sqrt(horizontal2);
        d = glm::vec3(d.x * scale, cos_limit, d.z * scale);
      }
      return true;
    }
    case JointLimit::Kind::kHinge: {
      const float projected2 = d.y * d.y + d.z * d.z;
      if (projected2 < kLimitSingular) {
        d = glm::vec3(0.0f, 1.0f, 0.0f);  // +-X: +Y
        return true;
      }
      bool moved = false;
      if (d.x != 0.0f) {  // onto the hinge's plane
        const float scale = 1.0f / std::sqrt(projected2);
        d = glm::vec3(0.0f, d.y * scale, d.z * scale);
        moved = true;
      }
      float cos_limit, sin_limit;
      cosSin(limit.angle, cos_limit, sin_limit);
      if (d.y < cos_limit) {
        d = glm::vec3(0.0f, cos_limit, d.z < 0.0f ? -sin_limit : sin_limit);
        moved = true;
      }
      return moved;
    }
    case JointLimit::Kind::kSpherical: {
      // Pitch = atan2(d.z, d.y), the turn about X from +Y toward +Z; yaw = asin(d.x), the turn
      // toward X. cos(pitch), sin(pitch) are the unit (d.y, d.z); cos(yaw) = |(d.y, d.z)|.
      const float projected = std::sqrt(d.y * d.y + d.z * d.z);
      float cos_pitch = 1.0f, sin_pitch = 0.0f;  // +-X: pitch 0 (the +Y side)
      if (projected * projected >= kLimitSingular) {
        cos_pitch = d.y / projected;
        sin_pitch = d.z / projected;
      }
      float cos_yaw = projected, sin_yaw = d.x;
      bool moved = false;
      float cos_limit, sin_limit;
      cosSin(limit.pitch, cos_limit, sin_limit);
      if (cos_pitch < cos_limit) {  // |pitch| beyond its bound; -Y (no side) goes to +Z
        cos_pitch = cos_limit;
        sin_pitch = sin_pitch < 0.0f ? -sin_limit : sin_limit;
        moved = true;
      }
      cosSin(limit.yaw, cos_limit, sin_limit);
      if (std::fabs(sin_yaw) > sin_limit) {  // |yaw| beyond its bound (yaw and its bound in [0, pi/2])
        sin_yaw = sin_yaw < 0.0f ? -sin_limit : sin_limit;
        cos_yaw = cos_limit;
        moved = true;
      }
      if (moved) d = glm::vec3(sin_yaw, cos_yaw * cos_pitch, cos_yaw * sin_pitch);
      return moved;
    }
    case JointLimit::Kind::kNone: break;
  }
  return false;
}

/// Keeps `tail` (world) inside the joint's limit: `frame` is the limit space in the world (the
/// joint's rest world rotation x limitFrameLocal), `length` the bone's. Returns whether it moved.
bool applyLimit(const JointLimit& limit, const glm::quat& frame, const glm::vec3& head, float length, glm::vec3& tail) {
  const glm::vec3 offset = tail - head;
  const float offset_length = glm::length(offset);
  if (!(offset_length > 1e-6f) || !std::isfinite(offset_length)) return false;
  glm::vec3 d = glm::conjugate(frame) * (offset / offset_length);
  if (!limitDirection(limit, d)) return false;
  tail = head + (frame * d) * length;
  return true;
}

}  // namespace springbones
