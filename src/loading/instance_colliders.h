// The colliders Instance::setColliders asks for, resolved against the instance's rig: the
// shapes checked as the rig builder checks them, each put on one of the rig's drivers or on a
// frame the caller supplies.
#pragma once

#include <vector>

#include "simulation/collider_set.h"
#include "springbones/springbones.h"

namespace springbones {

/// `options` as a collider set for an instance of `rig` (Instance::setColliders states the rules).
/// Ignored shapes add warnings; nothing fails.
ColliderSet resolveColliders(const Rig& rig, const ColliderOptions& options, std::vector<Warning>& warnings);

}  // namespace springbones
