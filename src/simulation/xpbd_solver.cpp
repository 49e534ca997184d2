// The XPBD integrator (`integrator: 'xpbd'`): Macklin, Mueller and Chentanez, "XPBD:
// Position-Based Simulation of Compliant Constrained Dynamics" (MIG 2016), in the usual
// spring-bone recipe (predict, then Gauss-Seidel passes of distance and collision constraints at
// fixed substeps, compliant constraints). docs/xpbd.md is its description: one substep, the
// mapping from the VRM parameters (stiffness -> a bend compliance L / stiffness on three linear
// constraints, drag -> the kept fraction rho = (1 - drag)^(h / h0) that also scales the inverse
// mass, the tail's mass matching the default's velocity map over 1/60 s), each with its reason,
// and the comparison with the default update. In short, per substep and per joint, parents first:
// predict the tail from its inertia and the external pulls; pass over bend, length, then each
// collider followed by the length again (the length last, so it is exact), repeating only while a
// collider pushes; turn the rest axis toward the tail as the default update does. The head is
// the solved parent's transform (a particle of infinite mass), so each joint's constraints are a
// problem of one particle and the hard projections are exact.
#include "simulation/xpbd_solver.h"

#include <algorithm>
#include <cmath>

#include "common/transform_math.h"
#include "simulation/grab.h"
#include "simulation/joint_limits.h"
#include "simulation/spring_lanes.h"

namespace springbones {
namespace {

// The parent of a chain root that hangs from no driver.
const glm::mat4 kIdentity(1.0f);

// A joint's parent in the world: the joint before it in its chain (already stepped this
// substep), the driver its chain hangs from, or the identity for a scene root.
const glm::mat4& parentWorld(const Joint& joint, const glm::mat4* driver_world, const glm::mat4* joint_world) {
  return joint.parent_joint >= 0    ? joint_world[joint.parent_joint]
         : joint.parent_driver >= 0 ? driver_world[joint.parent_driver]
                                    : kIdentity;
}

constexpr float kMinLength = 1e-6f;

// The hard bone-length constraint with a kinematic head: exact projection onto the sphere. A tail
// on the head (or lost to a non-finite value) restarts at rest, as in the default path.
inline void projectLength(const glm::vec3& head, const glm::vec3& rest_offset, float length, glm::vec3& x) {
  const glm::vec3 offset = x - head;
  const float offset_length = glm::length(offset);
  x = offset_length > kMinLength && std::isfinite(offset_length) ? head + offset * (length / offset_length)
                                                                 : head + rest_offset;
}

}  // namespace

XpbdSolver::XpbdSolver(const Rig& rig, const XpbdOptions& options)
    : XpbdSolver(std::make_shared<const RigConstants>(rig), options) {}

XpbdSolver::XpbdSolver(std::shared_ptr<const RigConstants> constants, const XpbdOptions& options)
    : constants_(std::move(constants)), rig_(constants_->rig), options_(options) {
  if (!(options_.reference_hz >= 1.0)) options_.reference_hz = options_.reference_hz > 0.0 ? 1.0 : 60.0;
  options_.reference_hz = std::min(options_.reference_hz, 1000.0);
  options_.iterations = std::clamp(options_.iterations, 1, kMaxXpbdIterations);
  reference_step_ = 1.0 / options_.reference_hz;

  const std::size_t joints = rig_.joints.size();
  keep_.assign(joints, 1.0f);
  inverse_mass_.assign(joints, 0.0f);
  current_tail_.assign(joints, glm::vec3(0.0f));
  previous_tail_.assign(joints, glm::vec3(0.0f));
  tail_world_.assign(joints, glm::vec3(0.0f));
  center_inverse_.assign(rig_.drivers.size(), glm::mat4(1.0f));
  center_inverse_valid_.assign(rig_.drivers.size(), 0);
  collider_scratch_.assign(rig_.colliders.size(), XpbdCollider{});
}

void XpbdSolver::prepareCenters(const glm::mat4* driver_world) {
  for (int c : constants_->center_drivers)
    center_inverse_valid_[c] = affineInverse(driver_world[c], center_inverse_[c]) ? 1 : 0;
}

// keep and w depend on h only through h / h0, so they are recomputed only when h changes (never,
// under a fixed-step owner). Double precision and expm1/log1p: for a small drag 1 - rho is a tiny
// difference that float would round away.
void XpbdSolver::prepareRates(float h) {
  if (h == rates_h_) return;
  rates_h_ = h;
  const double ratio = double(h) / reference_step_;
  for (std::size_t j = 0; j < keep_.size(); ++j) {
    const double drag = std::clamp(double(rig_.joints[j].params.drag), 0.0, 1.0);
    if (drag > 0.0) {
      const double lost = -std::expm1(std::log1p(-drag) * ratio);  // 1 - rho; 1 at drag 1
      keep_[j] = static_cast<float>(1.0 - lost);
      inverse_mass_[j] = static_cast<float>(lost / (drag * double(h)));
    } else {
      keep_[j] = 1.0f;
      inverse_mass_[j] = static_cast<float>(1.0 / reference_step_);
    }
  }
}

glm::vec3 XpbdSolver::toCenter(int center, const glm::vec3& world) const {
  if (center < 0 || !center_inverse_valid_[center]) return world;
  return glm::vec3(center_inverse_[center] * glm::vec4(world, 1.0f));
}

glm::vec3 XpbdSolver::fromCenter(int center, const glm::vec3& local, const glm::mat4* driver_world) const {
  if (center < 0 || !center_inverse_valid_[center]) return local;
  return glm::vec3(driver_world[center] * glm::vec4(local, 1.0f));
}

void XpbdSolver::seed(const glm::mat4* driver_world, float* rotations_out, glm::mat4* joint_world_out) {
  prepareCenters(driver_world);
  const auto& joints = rig_.joints;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const glm::mat4 rest_world = parentWorld(joint, driver_world, joint_world_out) * constants_->rest_local_matrix[j];
    const glm::vec3 tail = glm::vec3(rest_world[3]) + glm::mat3(rest_world) * toGlm(joint.tail_local);
    current_tail_[j] = previous_tail_[j] = toCenter(joint.center_driver, tail);
    tail_world_[j] = tail;
    joint_world_out[j] = rest_world;
    storeQuat(rotations_out + 4 * j, toGlm(joint.rest_local.rotation));
  }
}

void XpbdSolver::setColliders(const ColliderSet* colliders) {
  colliders_ = colliders;
  collider_scratch_.assign(colliders_ ? colliders_->colliders.size() : rig_.colliders.size(), XpbdCollider{});
}

void XpbdSolver::step(const glm::mat4* driver_world, const ColliderTable& colliders, float h, float* rotations_out,
                      glm::mat4* joint_world_out) {
  const std::size_t count = std::min(colliders.count, collider_scratch_.size());
  for (std::size_t c = 0; c < count; ++c) {
    XpbdCollider& out = collider_scratch_[c];
    out.start = glm::vec3(colliders.x0[c], colliders.y0[c], colliders.z0[c]);
    out.end = glm::vec3(colliders.x1[c], colliders.y1[c], colliders.z1[c]);
    out.radius = colliders.radius[c];
    out.kind = colliders_ ? colliders_->kind(static_cast<int>(c)) : colliderKind(rig_.colliders[c]);
  }
  step(driver_world, collider_scratch_.data(), count, h, rotations_out, joint_world_out);
}

void XpbdSolver::step(const glm::mat4* driver_world, const XpbdCollider* colliders, std::size_t collider_count, float h,
                      float* rotations_out, glm::mat4* joint_world_out) {
  if (!(h > 0.0f) || !std::isfinite(h)) return;
  prepareCenters(driver_world);
  prepareRates(h);
  const auto& joints = rig_.joints;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const glm::mat4& parent = parentWorld(joint, driver_world, joint_world_out);
    const glm::mat4 rest_world = parent * constants_->rest_local_matrix[j];
    const glm::mat3 rest_linear(rest_world);
    const glm::vec3 head(rest_world[3]);
    // Measured under the current parent every substep, as in the default path: a scaled armature
    // scales its bones, and no error can accumulate from one step to the next.
    const glm::vec3 rest_offset = rest_linear * toGlm(joint.tail_local);
    const float length = glm::length(rest_offset);
    if (!(length > kMinLength) || !(constants_->tail_distance[j] > kMinLength)) {
      // A zero-length bone (or a collapsed parent) has no direction: keep the rest pose.
      tail_world_[j] = head + rest_offset;
      joint_world_out[j] = rest_world;
      storeQuat(rotations_out + 4 * j, toGlm(joint.rest_local.rotation));
      continue;
    }

    // 1. Predict: inertia in center space, kept by rho; gravity as a force, x += h^2 w F.
    const glm::vec3 current = current_tail_[j];
    glm::vec3 x = fromCenter(joint.center_driver, current + (current - previous_tail_[j]) * keep_[j], driver_world);
    x += toGlm(joint.params.gravity_dir) * (joint.params.gravity_power * h * h * inverse_mass_[j]);
    x += wind_ * (h * h * inverse_mass_[j]);
    glm::vec3 previous = current;
    if (!isFinite(x)) {
      // Lost (a center or a state that overflowed): restart at rest with no velocity.
      x = head + rest_offset;
      previous = toCenter(joint.center_driver, x);
    }
    // A grabbed chain's joint: its tail turned toward the grab's reach (grab.h), the constraints
    // below still applied (its bend aside, solveJoint).
    const int held_at = held_ != nullptr && held_->active ? held_->slot[j] : -1;
    if (held_at >= 0) x = held_->tail(static_cast<std::size_t>(held_at), head, rest_linear, rest_offset, x);

    // 2. Constraints.
    const glm::quat limit_frame = joint.limit.kind != JointLimit::Kind::kNone
                                      ? worldRotationOf(rest_linear) * constants_->limit_local[j]
                                      : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
    solveJoint(j, head, rest_offset, length, h, colliders, collider_count, limit_frame, x);

    previous_tail_[j] = previous;
    current_tail_[j] = toCenter(joint.center_driver, x);
    tail_world_[j] = x;
    writeOutputs(j, parent, rest_linear, x - head, rotations_out, joint_world_out);
  }
}

void XpbdSolver::solveJoint(std::size_t j, const glm::vec3& head, const glm::vec3& rest_offset, float length, float h,
                            const XpbdCollider* colliders, std::size_t collider_count, const glm::quat& limit_frame,
                            glm::vec3& x) const {
  const Joint& joint = rig_.joints[j];
  // An angle limit is a hard constraint on the direction alone (the length stays exact): it follows
  // the length projection, and each collider's, as in the default update.
  const bool limited = joint.limit.kind != JointLimit::Kind::kNone;
  const float stiffness = joint.params.stiffness;
  const float w = inverse_mass_[j];
  const glm::vec3 target = head + rest_offset;
  // alpha~ = alpha / h^2 with alpha = L / stiffness (see the opening comment).
  // A held joint (a grab) has no bend: the hand, not the stiffness, sets its direction.
  const bool held = held_ != nullptr && held_->active && held_->slot[j] >= 0;
  const bool bend = stiffness > 0.0f && w > 0.0f && !held;
  const float alpha_tilde = bend ? length / (stiffness * h * h) : 0.0f;
  const float inverse_denominator = bend ? 1.0f / (w + alpha_tilde) : 0.0f;
  glm::vec3 lambda(0.0f);
  for (int iteration = 0; iteration < options_.iterations; ++iteration) {
    if (bend) {
      // Three linear constraints, one per axis, sharing one compliance (see the opening comment):
      // dlambda = (-C - alpha~ lambda) / (w + alpha~) with C = x - r and grad C the identity.
      const glm::vec3 delta_lambda = (target - x - alpha_tilde * lambda) * inverse_denominator;
      x += w * delta_lambda;
      lambda += delta_lambda;
    }
    projectLength(head, rest_offset, length, x);
    if (limited) applyLimit(joint.limit, limit_frame, head, length, x);
    bool contact = false;
    // Colliders, hard inequalities: outside C = |x - closest point of the segment| - (radius +
    // hitRadius) >= 0, inside C = (radius - hitRadius) - |x - closest point| >= 0, plane
    // C = (x - point).normal - hitRadius >= 0. The same arithmetic as the default path's, each
    // followed by the length again.
    for (int c : colliders_ ? colliders_->of(joint) : joint.colliders) {
      if (c < 0 || static_cast<std::size_t>(c) >= collider_count) continue;
      const XpbdCollider& collider = colliders[c];
      if (!moveTailByCollider(collider.kind, collider.start, collider.end, collider.radius, joint.hit_radius, x))
        continue;
      projectLength(head, rest_offset, length, x);
      if (limited) applyLimit(joint.limit, limit_frame, head, length, x);
      contact = true;
    }
    // Without an active collider the pass above solved bend and length exactly (the opening
    // comment's closed form): another pass would only repeat it, so stop.
    if (!contact) break;
  }
}

// The default path's rotation: the joint's rest axis turned toward the tail, relative to its glTF
// parent, and the joint world matrix its children hang from.
void XpbdSolver::writeOutputs(std::size_t j, const glm::mat4& parent, const glm::mat3& rest_linear,
                              const glm::vec3& offset, float* rotations_out, glm::mat4* joint_world_out) const {
  const Joint& joint = rig_.joints[j];
  // rest_linear^-1 * offset up to a positive factor (only its direction is used): the adjugate
  // rows are the cross products of the columns, and the determinant's sign keeps a mirrored
  // parent the right way round. Cheaper than a full inverse and the same direction.
  const glm::vec3 c0 = rest_linear[0], c1 = rest_linear[1], c2 = rest_linear[2];
  const glm::vec3 r0 = glm::cross(c1, c2), r1 = glm::cross(c2, c0), r2 = glm::cross(c0, c1);
  const float det_sign = glm::dot(c0, r0) < 0.0f ? -1.0f : 1.0f;
  glm::vec3 local_dir = det_sign * glm::vec3(glm::dot(r0, offset), glm::dot(r1, offset), glm::dot(r2, offset));
  const float len = glm::length(local_dir);
  const glm::vec3& axis = constants_->tail_axis[j];
  local_dir = len > 0.0f && std::isfinite(len) ? local_dir / len : axis;
  const glm::quat rotation = glm::normalize(toGlm(joint.rest_local.rotation) * rotationBetween(axis, local_dir));
  joint_world_out[j] =
      parent * composeTransform(toGlm(joint.rest_local.translation), rotation, toGlm(joint.rest_local.scale));
  storeQuat(rotations_out + 4 * j, rotation);
}

}  // namespace springbones
