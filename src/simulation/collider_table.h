// The colliders of one step in world space, as the lane kernel (spring_lanes.h), the general path
// and XPBD read them. A file of its own because the preview module links the general path without
// the lane kernel (lane_kernel.h).
#pragma once

#include <cstddef>
#include <vector>

#include "common/glm_interop.h"

namespace springbones {

/// Collider shapes in world space for one step: a segment (x0..x1; a point for a sphere) and a
/// radius, or for a plane a point of it (x0) and its unit normal (x1), radius 0. On the lane path,
/// one row per rig collider of one entry per copy (SpringLanes::colliderIndex).
struct ColliderTable {
  std::size_t count = 0;
  std::vector<float> x0, y0, z0, x1, y1, z1, radius;
  void resize(std::size_t colliders);
  void set(std::size_t collider, const glm::vec3& start, const glm::vec3& end, float radius);
};

}  // namespace springbones
