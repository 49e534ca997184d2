// How a collider moves a tail, on the scalar paths (the general VRM path and the XPBD
// integrator); the lane kernel (spring_lanes.cpp, collideLanes) does the same arithmetic on lanes.
#pragma once

#include <algorithm>
#include <cstdint>

#include "common/glm_interop.h"

namespace springbones {

/// How a collider acts on a tail: pushed out of a sphere or capsule, kept inside one, or kept on
/// the normal's side of a plane. A property of the rig's collider, the same in every copy.
enum class ColliderKind : std::uint8_t { kOutside, kInside, kPlane };

inline ColliderKind colliderKind(const Collider& collider) {
  if (collider.shape == Collider::Shape::kPlane) return ColliderKind::kPlane;
  return collider.inside ? ColliderKind::kInside : ColliderKind::kOutside;
}

/// Moves `tail` (world) by one collider in world space: `start`..`end` the segment of a sphere
/// (start == end) or capsule and `radius` its world radius, or for a plane `start` a point of it
/// and `end` its unit normal. Outside: out of the shape to radius + hit_radius from the segment's
/// closest point; inside: in to radius - hit_radius from it; plane: onto the normal's side at
/// hit_radius. Returns whether it moved the tail; a NaN anywhere fails the tests and moves nothing.
inline bool moveTailByCollider(ColliderKind kind, const glm::vec3& start, const glm::vec3& end, float radius,
                               float hit_radius, glm::vec3& tail) {
  constexpr float kMinDistance = 1e-6f;
  const glm::vec3 v = tail - start;
  if (kind == ColliderKind::kPlane) {
    const float penetration = hit_radius - glm::dot(v, end);
    if (!(penetration > 0.0f)) return false;
    tail += end * penetration;
    return true;
  }
  const glm::vec3 segment = end - start;
  const float segment2 = glm::dot(segment, segment);
  const float t = segment2 > 0.0f ? std::clamp(glm::dot(v, segment) / segment2, 0.0f, 1.0f) : 0.0f;
  const glm::vec3 away = v - segment * t;
  const float distance = glm::length(away);
  const bool inside = kind == ColliderKind::kInside;
  const float penetration = inside ? distance + hit_radius - radius : radius + hit_radius - distance;
  if (!(penetration > 0.0f) || !(distance > kMinDistance)) return false;
  tail += away * (inside ? -(penetration / distance) : penetration / distance);
  return true;
}

}  // namespace springbones
