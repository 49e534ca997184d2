// The spring-bone step.
//
// Where the update comes from: it is the VRM family's per-joint update (UniVRM's VRMSpringBone,
// credited there to @ricopin416; the VRMC_springBone 1.0 specification; @pixiv/three-vrm): Verlet
// inertia reduced by drag, an impulse toward the rest direction scaled by stiffness, a gravity
// impulse, then the tail is put back at the bone's length and the joint is turned to point at it.
// docs/semantics.md, "The step and the fixed-step rule", states it. Our own choices on top of it:
//  - Bone lengths are measured under the current parent transform (the rest tail offset carried
//    by the parent's world matrix), never from the previous frame's child position, and all
//    positions are world-space: a 0.01-scaled armature behaves like an unscaled one.
//  - Two ways to carry transforms down a chain. Avatars are almost always rotations, translations
//    and uniform scales (similarities), which compose with a quaternion, a vector and a float: the
//    lanes (lane_integrator.h). A driver with shear or non-uniform scale, or a rig with non-uniform
//    bone scales, takes this path on full matrices, so such hierarchies do not skew the bones. Both
//    compute the same update; which one runs is decided from the inputs alone, so native and
//    WebAssembly builds choose alike.
// The fixed steps, the driver interpolation across them and the substep cap are the Instance's
// (instance.cpp), the same for every integrator.
#include "simulation/general_integrator.h"

#include <algorithm>
#include <cmath>

#include "common/transform_math.h"
#include "simulation/joint_limits.h"
#include "simulation/motion_controls.h"

namespace springbones {
namespace {

constexpr float kMinLength = 1e-6f;
// The parent of a chain root that hangs from no driver.
const glm::mat4 kIdentity(1.0f);

}  // namespace

// What the spring update of one joint reads, all in world space.
struct GeneralIntegrator::SpringInput {
  glm::vec3 head;
  glm::vec3 rest_dir;
  glm::vec3 rest_offset;  // rest_dir * length
  float length;
  glm::quat limit_frame{1.0f, 0.0f, 0.0f, 0.0f};  // the joint's limit space in the world, when it has a limit
  glm::mat3 rest_linear;  // the joint at its rest rotation under its current parent (a grab's anchor)
};

GeneralIntegrator::GeneralIntegrator(std::shared_ptr<const RigConstants> constants)
    : SpringIntegrator(std::move(constants)), drivers_(rig_, colliders_, frame_world_) {
  current_tail_.resize(rig_.joints.size());
  previous_tail_.resize(rig_.joints.size());
}

void GeneralIntegrator::setColliders(ColliderSet colliders) {
  SpringIntegrator::setColliders(std::move(colliders));
  drivers_.resizeColliders();
}

void GeneralIntegrator::seed(const DriverPoses& previous, const DriverPoses& current, bool) {
  drivers_.prepare(StepDrivers{previous, current, 1.0f, true}, false);
  run(0.0f, /*seed_only=*/true);
}

SpringLanes* GeneralIntegrator::step(const StepDrivers& drivers, float h, const glm::vec3& wind_pull, bool) {
  drivers_.prepare(drivers, controls_.inertia_active);
  step_wind_ = wind_pull * h;
  if (controls_.inertia_active) {
    carryInertia(rig_, constants_->joint_chain.data(), controls_.chain_inertia.data(), drivers_.lastMatrices(),
                 drivers_.matrices(), current_tail_.data(), previous_tail_.data());
  }
  if (controls_.held.active) controls_.held.prepare(controls_.grab_point, joint_world_.data());
  run(h, /*seed_only=*/false);
  return nullptr;
}

void GeneralIntegrator::balance(const DriverPoses& poses, const glm::vec3& wind_pull) {
  const RigConstants& k = *constants_;
  balanceTails(rig_, poses, k.rest_local_matrix.data(), k.tail_axis.data(), k.tail_distance.data(), wind_pull,
               joint_world_.data(), current_tail_.data(), rotations_.data());
  previous_tail_ = current_tail_;
}

// Moves a tail out of (or into, or onto the side of) the joint's colliders, each followed by
// the length constraint again (VRMC_springBone order).
// A limited joint is kept inside its limit after each push too (VRMC_springBone_limit's order).
glm::vec3 GeneralIntegrator::collide(const Joint& joint, const SpringInput& in, glm::vec3 tail, int passes) const {
  const glm::vec3& head = in.head;
  const float length = in.length;
  const bool limited = joint.limit.kind != JointLimit::Kind::kNone;
  const ColliderTable& table = drivers_.colliders();
  // `passes`: ColliderSet::passes (1 but with the body preset), or more for a held tail; a pass
  // that moves nothing ends them (the lane path runs them all, and a pass without a push changes
  // no bit there either).
  for (int pass = 0; pass < passes; ++pass) {
    bool pushed = false;
    for (int c : colliders_.of(joint)) {
      const glm::vec3 start(table.x0[c], table.y0[c], table.z0[c]);
      const glm::vec3 end(table.x1[c], table.y1[c], table.z1[c]);
      if (!moveTailByCollider(colliders_.kind(c), start, end, table.radius[c], joint.hit_radius, tail)) { continue; }
      pushed = true;
      const glm::vec3 offset = tail - head;
      const float offset_length = glm::length(offset);
      if (offset_length > kMinLength && std::isfinite(offset_length)) tail = head + offset * (length / offset_length);
      if (limited) applyLimit(joint.limit, in.limit_frame, head, length, tail);
    }
    if (!pushed) break;
  }
  return tail;
}

// Returns the new world tail offset from the head and advances the joint's tail state.
glm::vec3 GeneralIntegrator::integrate(std::size_t j, const Joint& joint, const SpringInput& in, float h) {
  const BoneParams& p = joint.params;
  const HeldJoints& held = controls_.held;
  const glm::vec3 current = current_tail_[j];
  const glm::vec3 inertia = (current - previous_tail_[j]) * (1.0f - p.drag);
  glm::vec3 next = drivers_.fromCenter(joint.center_driver, current + inertia);
  next += in.rest_dir * (p.stiffness * h);
  next += toGlm(p.gravity_dir) * (p.gravity_power * h);
  next += step_wind_;
  if (held.active && held.slot[j] >= 0) next = held.tail(held.slot[j], in.head, in.rest_linear, in.rest_offset, next);
  glm::vec3 offset = next - in.head;
  const float offset_length = glm::length(offset);
  offset = offset_length > kMinLength && std::isfinite(offset_length)
               ? offset * (in.length / offset_length)
               : in.rest_offset;  // tail on the head (or lost): restart from rest
  glm::vec3 tail = in.head + offset;
  // The limit after inertia, stiffness and gravity, then again after each collider (collide).
  if (joint.limit.kind != JointLimit::Kind::kNone) applyLimit(joint.limit, in.limit_frame, in.head, in.length, tail);
  // A held tail is pulled toward its point every step, into a collider if the point is in one:
  // one pass (a push, then the length back) can leave it inside, so it gets the passes XPBD
  // takes, while a collider still moves it.
  const bool held_tail = held.active && held.slot[j] >= 0;
  tail = collide(joint, in, tail, held_tail ? std::max(kDefaultXpbdIterations, colliders_.passes) : colliders_.passes);
  previous_tail_[j] = current;
  current_tail_[j] = drivers_.toCenter(joint.center_driver, tail);
  return tail - in.head;
}

// The joint's local rotation that turns its rest axis toward `local_dir` (unit or not).
glm::quat GeneralIntegrator::aimedRotation(std::size_t j, const Joint& joint, glm::vec3 local_dir) const {
  const glm::vec3& axis = constants_->tail_axis[j];
  const float len = glm::length(local_dir);
  local_dir = len > 0.0f && std::isfinite(len) ? local_dir / len : axis;
  return glm::normalize(toGlm(joint.rest_local.rotation) * rotationBetween(axis, local_dir));
}

void GeneralIntegrator::run(float h, bool seed_only) {
  const RigConstants& k = *constants_;
  const auto& joints = rig_.joints;
  const glm::mat4* driver_world = drivers_.matrices();
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const glm::mat4& parent = joint.parent_joint >= 0    ? joint_world_[joint.parent_joint]
                              : joint.parent_driver >= 0 ? driver_world[joint.parent_driver]
                                                         : kIdentity;
    const glm::mat4 rest_world = parent * k.rest_local_matrix[j];
    const glm::mat3 rest_linear(rest_world);
    SpringInput in;
    in.head = glm::vec3(rest_world[3]);
    in.rest_offset = rest_linear * toGlm(joint.tail_local);
    in.length = glm::length(in.rest_offset);
    if (seed_only || !(in.length > kMinLength) || !(k.tail_distance[j] > kMinLength)) {
      if (seed_only) {
        current_tail_[j] = previous_tail_[j] = drivers_.toCenter(joint.center_driver, in.head + in.rest_offset);
      }
      joint_world_[j] = rest_world;
      writeRotation(j, toGlm(joint.rest_local.rotation));
      continue;
    }
    in.rest_dir = in.rest_offset / in.length;
    if (joint.limit.kind != JointLimit::Kind::kNone) in.limit_frame = worldRotationOf(rest_linear) * k.limit_local[j];
    in.rest_linear = rest_linear;
    const glm::vec3 offset = integrate(j, joint, in, h);
    const glm::quat rotation = aimedRotation(j, joint, glm::inverse(rest_linear) * offset);
    joint_world_[j] =
        parent * composeTransform(toGlm(joint.rest_local.translation), rotation, toGlm(joint.rest_local.scale));
    writeRotation(j, rotation);
  }
}

}  // namespace springbones
