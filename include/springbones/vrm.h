// VRM spring bones: a .vrm avatar (glTF binary) into the same Rig the Decentraland path builds.
//
// Two formats, read from the document's root `extensions`:
//  - VRMC_springBone 1.0 (VRM 1.0): springs list joints in order; joint k's tail is joint k+1 and
//    the last listed joint is only a tail; parameters are per joint; colliders (sphere, capsule)
//    sit on nodes and are grouped; a spring names its collider groups and an optional center.
//  - VRM 0.x `extensions.VRM.secondaryAnimation`: each boneGroup's `bones` are roots; every node
//    of each root's subtree is a joint whose tail is its first child, and a leaf gets a virtual
//    tail 7 cm along its own translation; parameters are per group; colliderGroups hold spheres.
// When a file has both, VRMC_springBone wins (as in three-vrm). The decisions that differ between
// reference implementations are listed in the header comments of src/loading/'s VRM files: each
// format's reader (vrmc_spring_bone.cpp, vrm0_secondary_animation.cpp) and the rig both share
// (vrm_rig_builder.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>


#include "springbones/springbones.h"

namespace springbones {

enum class VrmSpringFormat : int {
  kNone = 0,             ///< neither extension: an empty rig (and a `vrm-no-springs` warning)
  kVrmcSpringBone1 = 1,  ///< extensions.VRMC_springBone (VRM 1.0)
  kVrm0 = 2,             ///< extensions.VRM.secondaryAnimation (VRM 0.x)
};

/// Length of the virtual tail of a VRM 0.x leaf joint, metres (local units of the leaf).
inline constexpr float kVrm0LeafTailLength = 0.07f;

/// Limit on untrusted input: joints x colliders each joint tests (the solver's per-step work and
/// the rig's memory). A file beyond it is an Error (kLimitExceeded); real avatars use a few hundred.
inline constexpr std::size_t kMaxVrmColliderReferences = std::size_t(1) << 22;

// Reading one: loadVrm, from typed input (typed_input.h) or, with the readers, from bytes
// (readers.h).

}  // namespace springbones
