// Angle limits (VRMC_springBone_limit 1.0-draft) on the scalar paths: the general VRM path
// (general_integrator.cpp) and the XPBD integrator. A rig with a limited joint never takes the lane path.
// docs/semantics.md, "Angle limits", states the rules; this is how the code holds to them:
//  - The limit space is the joint's rest world rotation under its current parent (the rotation of
//    parent world x rest local), then the shortest turn taking +Y onto the joint's rest bone axis
//    (for an axis of exactly -Y, half a turn about X, as the draft requires), then the limit's own
//    `rotation`. The fixed part after the world rotation is computed once per joint
//    (limitFrameLocal).
//  - A limit moves only the tail's direction: the tail stays at the bone's length from the head.
//  - Singular directions go where the draft says: a cone's -Y to its boundary on the +Z side; a
//    hinge's +-X to +Y, its -Y to the +Z side; a spherical limit's +-X to the +Y side of its
//    boundary, its -Y to the +Z side. "Singular" is within sqrt(double epsilon) in squared length
//    of the axis, three-vrm's tolerance, so the two agree on which directions snap.
#pragma once

#include "common/glm_interop.h"
#include "springbones/springbones.h"

namespace springbones {

// three-vrm's SINGULARITY_EPSILON: sqrt of double's epsilon, compared with a squared length.
inline constexpr float kLimitSingular = 1.4901161e-8f;

/// The part of a joint's limit space that does not move: the turn taking +Y onto the rest bone
/// axis `axis` (unit, in the joint's own space), then the limit's rotation.
glm::quat limitFrameLocal(const glm::vec3& axis, const Quat& rotation);

/// The rotation of a rest world matrix's linear part: its columns made orthonormal (scale and, for a
/// sheared parent, shear taken out), X first.
glm::quat worldRotationOf(const glm::mat3& m);

/// cos and sin of an angle in [0, pi], by their Taylor series in double: +, x and / only, so no libm
/// trigonometry (and its tables) enters the module, and every build gives the same bits.
void cosSin(float angle, float& cos_out, float& sin_out);

/// Keeps a unit direction `d`, in limit space, inside the limit. Returns whether it moved it.
bool limitDirection(const JointLimit& limit, glm::vec3& d);

/// Keeps `tail` (world) inside the joint's limit: `frame` is the limit space in the world (the
/// joint's rest world rotation x limitFrameLocal), `length` the bone's. Returns whether it moved.
bool applyLimit(const JointLimit& limit, const glm::quat& frame, const glm::vec3& head, float length, glm::vec3& tail);

}  // namespace springbones
