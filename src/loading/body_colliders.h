// The 'dcl-body' collider preset: collision shapes for a Decentraland avatar's head, neck, chest,
// shoulders and upper arms, derived from the 62-bone armature a wearable's GLB carries.
#pragma once

#include <vector>

#include "springbones/springbones.h"

namespace springbones {

/// The preset's shapes, each on the bone that carries it, in that bone's own space (so they follow
/// the bone and scale with the avatar). Sizes are fractions of the rest distances between the
/// armature's bones (docs/semantics.md, "Body colliders"), measured on `avatar` when it is not
/// empty (the avatar the wearable is worn on), else on the bones `skeleton` (the wearable's GLB)
/// carries. A shape whose bones are missing, or sit on each other, is left out, with one
/// `body-collider-skipped` warning naming every shape left out and the bones missing. `body`: every
/// radius times its scale, and the shapes it omits not built (and not warned about).
std::vector<ColliderSpec> dclBodyColliders(const Skeleton& skeleton, const std::vector<AvatarBone>& avatar,
                                           std::vector<Warning>& warnings, const BodyColliderOptions& body = {});

/// Rig::collider_passes with the preset: the neck capsule is thinner than the bones swinging round
/// it, and one push of the tail followed by the bone length can leave the tail inside it; passes
/// of push and length converge onto the bone's sphere outside the shapes.
inline constexpr int kBodyColliderPasses = 4;

}  // namespace springbones
