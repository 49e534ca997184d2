// The rarely run parts of Instance::settle and of inertia below 1 (docs/semantics.md, "Settle" and
// "Inertia of the avatar"): matrix work that runs once per settle, or per step only for an
// instance that asked for it. Kept out of the integrators, which are built at -O3 for WebAssembly
// (wasm/CMakeLists.txt) and where this code, inlined, cost the module several KB.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "springbones/springbones.h"

namespace springbones {

class DriverPoses;

/// settle's balance: every tail, parents first, where stiffness x its rest direction (under its
/// parent as it now hangs) + gravity + `wind_pull` points along the bone, or at rest with no pull.
/// Reads the drivers of `poses`; writes per joint its world matrix, its tail in its center's
/// space (`stored_tails`) and its local rotation (x, y, z, w in `rotations`).
void balanceTails(const Rig& rig, const DriverPoses& poses, const glm::mat4* rest_local_matrix,
                  const glm::vec3* tail_axis, const float* tail_distance, const glm::vec3& wind_pull,
                  glm::mat4* joint_world, glm::vec3* stored_tails, float* rotations);

/// Inertia below 1: carries the tails (current and previous, in their center's space) of every
/// joint whose chain's inertia (`chain_inertia[joint_chain[j]]`, -1: none) is below 1 by the
/// fraction 1 - inertia of the motion of the driver its chain hangs from, from `last_drivers` to
/// `drivers` (one matrix per rig driver), seen from the joint's center.
void carryInertia(const Rig& rig, const int* joint_chain, const float* chain_inertia, const glm::mat4* last_drivers,
                  const glm::mat4* drivers, glm::vec3* current, glm::vec3* previous);

}  // namespace springbones
