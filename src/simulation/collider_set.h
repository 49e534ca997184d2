// The colliders one instance's tails meet: its rig's until Instance::setColliders replaces them.
// Every integrator reads them from here (never from the rig), so that a change reaches the
// general path, the lanes and XPBD alike.
#pragma once

#include <string>
#include <vector>

#include "simulation/collider_kind.h"
#include "springbones/springbones.h"

namespace springbones {

struct ColliderSet {
  /// The shapes, each carried by `driver`: below the rig's driver count a driver of the rig, else
  /// frame `driver - rig.drivers.size()` (a world matrix the caller writes, frameMatrices).
  std::vector<Collider> colliders;
  /// false: each joint meets the colliders its rig lists (Joint::colliders); true: every joint
  /// meets all of them, in order (`every`).
  bool every_joint = false;
  std::vector<int> every;  ///< 0 .. colliders.size() - 1 when every_joint
  /// Passes of collider pushes per step (Rig::collider_passes' rule).
  int passes = 1;
  std::vector<std::string> frame_names;
  std::vector<Mat4> frame_rest;  ///< each frame's matrix until the caller writes one

  /// The rig's own colliders.
  static ColliderSet ofRig(const Rig& rig) {
    ColliderSet set;
    set.colliders = rig.colliders;
    set.passes = rig.collider_passes;
    return set;
  }

  /// The colliders joint `joint` meets, in the order it tests them.
  const std::vector<int>& of(const Joint& joint) const { return every_joint ? every : joint.colliders; }
  ColliderKind kind(int c) const { return colliderKind(colliders[static_cast<std::size_t>(c)]); }
};

}  // namespace springbones
