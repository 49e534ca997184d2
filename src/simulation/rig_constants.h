// What stepping a rig needs that depends on the rig alone: each joint's rest matrix, tail axis
// and length, limit frame and chain, whether the lane path can run it. Computed once per rig, here,
// and shared by every instance of the rig, whichever integrator it runs (the general VRM path, the
// lanes, XPBD): no integrator derives its own.
#pragma once

#include <memory>
#include <vector>

#include "common/glm_interop.h"
#include "springbones/springbones.h"

namespace springbones {

class SpringLanes;

struct RigConstants {
  /// Derives the constants of `rig` (which must outlive them). For a rig held by a shared pointer
  /// use acquire(), which shares one set between the rig's instances.
  explicit RigConstants(const Rig& rig);

  /// The constants of `rig`, shared by its instances: the rig points at them (Rig::constants)
  /// while one of them lives; the first makes them and the last frees them.
  static std::shared_ptr<const RigConstants> acquire(const std::shared_ptr<const Rig>& rig);

  const Rig& rig;
  /// Set by acquire(): keeps the rig alive as long as its constants (and its lane pool).
  std::shared_ptr<const Rig> owner;

  // Per joint.
  std::vector<glm::mat4> rest_local_matrix;
  std::vector<glm::vec3> tail_axis;    ///< unit tail direction in the joint's local space ((0, 1, 0) for none)
  std::vector<float> tail_distance;    ///< |tail_local|
  std::vector<glm::quat> limit_local;  ///< limitFrameLocal (joint_limits.h); identity without a limit
  std::vector<int> joint_chain;        ///< index into Rig::chain_roots of the joint's chain, -1: none

  /// The drivers some joint takes as its center, each once.
  std::vector<int> center_drivers;

  /// Whether the lane path can step the rig: every rest scale a positive uniform one, at most
  /// kMaxLaneColliders colliders, each joint's colliders in index order once (its collider mask),
  /// and no angle limit.
  bool lanes_usable = true;

  /// The lane pool the rig's instances on the lane path share (SpringLanes::acquire): made by the
  /// first of them, freed with the last. Written by the instances (docs/design.md, "Threads").
  mutable std::weak_ptr<SpringLanes> lane_pool;
};

}  // namespace springbones
