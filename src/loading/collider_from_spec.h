// A collider the caller describes (RigOptions::colliders, the 'dcl-body' preset's shapes,
// Instance::setColliders) checked and put in the form the integrators read, by one set of rules
// for the rig builder and for an instance's colliders changed at run time.
#pragma once

#include <vector>

#include "springbones/springbones.h"

namespace springbones {

/// `spec`'s shape as a collider (its driver left to the caller): a non-finite or negative size, a
/// size beyond kMaxColliderSize or a plane's zero normal makes it ignored, with a
/// `collider-invalid` warning, and returns false. A sphere's tail is its offset, a plane's normal
/// is made unit and its radius 0, `inside` only holds for spheres and capsules.
bool colliderFromSpec(const ColliderSpec& spec, Collider& out, std::vector<Warning>& warnings);

}  // namespace springbones
