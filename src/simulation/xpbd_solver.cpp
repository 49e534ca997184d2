// The XPBD integrator (`integrator: 'xpbd'`).
//
// docs/xpbd.md describes it and the stability comparison. The usual XPBD spring-bone recipe (as
// in VRMMetalKit's GPU solver: predict, then 2-4 iterations of distance and collision constraints,
// fixed 120 Hz substeps, compliant constraints) on Macklin, Mueller and Chentanez, "XPBD:
// Position-Based Simulation of Compliant Constrained Dynamics" (MIG 2016), whose update we use:
// per compliant constraint, dlambda = (-C - alpha~ lambda) / (w |grad C|^2 + alpha~),
// alpha~ = alpha / h^2, x += w grad C dlambda.
//
// Per fixed substep h (the owner runs it at 120 Hz by default) and per joint, parents first:
//   1. predict the tail particle from its inertia (center space, as in the default path) and
//      gravity;
//   2. up to `iterations` Gauss-Seidel passes over the joint's constraints: the compliant bend
//      constraint, the hard bone-length constraint, then each collider (a hard inequality) followed
//      by the length again (VRMC_springBone's order), the length last so it is exact; passes after
//      the first run only while a collider is active (see the bend constraint below for why);
//   3. velocity stays implicit in (current - previous), as in the default path and in XPBD's
//      v = (x - previous x) / h;
//   4. the joint turns its rest axis toward the tail, exactly as the default path does, so the
//      rotations mean the same thing.
// The head of a joint is the (already solved) parent's transform, i.e. a particle of inverse mass
// 0: a child never pulls its parent. That is how the default path and every VRM renderer propagate,
// it is what the rotation outputs need, and it makes each joint's constraints a one-particle
// problem: the hard projections are exact, so bone lengths hold to float rounding after any
// number of steps rather than up to solver convergence (a GPU solver that solves all distance
// constraints in parallel needs its iterations for that).
//
// The mapping from the VRM parameters, and why. The parameters are defined by the default update
// (docs/semantics.md, The step) at the step rate it is tuned at, h0 = 1 / reference_hz = 1/60 s: per step
// the tail's velocity (metres per step) becomes (1 - drag) v + stiffness h0 restDir +
// gravityPower h0 gravityDir, then the tail goes back onto the bone-length sphere. So stiffness is
// a pull of constant size along the rest direction (a second gravity), not a Hookean spring, and
// drag is a fraction lost per 1/60 s.
//  - stiffness -> a compliant zero-length "bend" spring between the tail x and the rest tail
//    r = head + restDir L (under the current parent), compliance alpha = L / stiffness (spring
//    constant stiffness / L), written as the vector constraint C = x - r: three linear
//    constraints, one per axis, sharing that compliance (energy stiffness / (2 L) |x - r|^2). Why
//    this spring: its force (stiffness / L)(r - x) has, for the tail on the sphere, the tangential
//    part (stiffness / L) L restDir_perp = stiffness restDir_perp at every angle, exactly the
//    tangential part of the default's stiffness impulse; the radial parts are taken by the hard
//    length constraint. Same restoring torque curve, hence the same equilibrium (stiffness restDir
//    + gravityPower gravityDir along the bone), but solved implicitly, which is what keeps XPBD
//    stable at any stiffness and substep. Why not the common mapping that sets the compliance from
//    stiffness directly (compliance = 1 / (stiffness dt^2), i.e. alpha = 1 / stiffness)? With the
//    VRM meaning of stiffness it makes the bend strength depend on the bone length and
//    the world unit (a 0.05 m bone ten times stiffer than a 0.5 m one, a 0.01-scaled armature a
//    hundred times) and moves the equilibrium away from the default's; dividing by L keeps both as
//    the default has them. Why the vector form rather than the scalar C = |x - r|: the scalar
//    form's accumulated lambda counts the radial part of each correction, which the length
//    projection then throws away, so 2 or more iterations converge to a softer spring (we measured
//    45.09 degrees on a 0.3 m bone and 45.57 on a 0.05 m one where the default gives 45). The
//    linear form has no such error: one pass of bend then length already is the exact implicit
//    Euler solution of spring plus sphere, x = head + L normalize((x~ + b r) / (1 + b) - head)
//    with b = w / alpha~, and further passes reproduce it. So the iterations only matter, and only
//    run, while a collider is active.
//  - gravityPower, gravityDir -> an external force on the tail in the predict step
//    (x += h^2 F / m); the wind's pull (windAt) is another such force.
//  - drag -> implicit (backward Euler) velocity damping: each substep keeps rho = (1 -
//    drag)^(h / h0) of the velocity, so a free tail loses the same fraction per 1/60 s as in the
//    default, at any substep rate. In the solve it scales the tail's inverse mass by rho (backward
//    Euler damping c is a mass (1 + c h) m, and 1 / (1 + c h) = rho), which is what keeps drag 1
//    finite: rho = 0 is the first-order limit where the tail moves only by its impulses, as it
//    does in the default.
//  - the tail's mass m (XPBD divides forces by a mass; VRM has none): chosen so that a free
//    tail's velocity over 1/60 s follows the default's map v -> (1 - drag) v + F exactly, F =
//    stiffness restDir + gravityPower gravityDir in m/s. Over n = h0 / h substeps v -> rho (v + h F
//    / m) gives rho^n v + (h / m) F rho (1 - rho^n) / (1 - rho), so 1 / m = (1 - rho) / (drag h rho),
//    which tends to 1 / h0 as drag -> 0. The solve uses w = rho / m = (1 - rho) / (drag h), finite
//    for every drag in [0, 1]. Stiffness and gravity scale alike with m, so drag never moves the
//    equilibrium, as in the default.
// What comes out (tests/native/xpbd_solver_test.cpp, tests/native/integrator_report.cpp): the
// default's equilibria to 1e-3 degrees, bone lengths exact to float rounding, no explosion under
// the most energetic parameters at 30 fps with 0.5 s frames, collider penetration a tenth of the
// default's. Where it differs from the default, by design: the motion converges as h -> 0 (first
// order, implicit Euler) instead of depending on the step rate; the default's one projection per
// 1/60 s removes more energy than ours per 1/120 s, so at low drag the xpbd bones swing longer
// (a horizontal bone at stiffness = gravityPower = 1 settles within 1 degree in 3.0 s at drag 0
// and 0.45 s at drag 0.2, the default in 1.55 s and 0.32 s); and colliders converge over the
// iterations instead of one push-out per step.
#include "simulation/xpbd_solver.h"

#include <algorithm>
#include <cmath>

#include "common/transform_math.h"
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

void writeRotation(float* out, const glm::quat& q) {
  out[0] = q.x;
  out[1] = q.y;
  out[2] = q.z;
  out[3] = q.w;
}

}  // namespace

XpbdSolver::XpbdSolver(const Rig& rig, const XpbdOptions& options) : rig_(rig), options_(options) {
  if (!(options_.reference_hz >= 1.0)) options_.reference_hz = options_.reference_hz > 0.0 ? 1.0 : 60.0;
  options_.reference_hz = std::min(options_.reference_hz, 1000.0);
  options_.iterations = std::clamp(options_.iterations, 1, kMaxXpbdIterations);
  reference_step_ = 1.0 / options_.reference_hz;

  const std::size_t joints = rig.joints.size();
  rest_local_matrix_.resize(joints);
  tail_axis_.resize(joints);
  tail_distance_.resize(joints);
  keep_.assign(joints, 1.0f);
  inverse_mass_.assign(joints, 0.0f);
  current_tail_.assign(joints, glm::vec3(0.0f));
  previous_tail_.assign(joints, glm::vec3(0.0f));
  tail_world_.assign(joints, glm::vec3(0.0f));
  center_inverse_.assign(rig.drivers.size(), glm::mat4(1.0f));
  center_inverse_valid_.assign(rig.drivers.size(), 0);
  collider_scratch_.assign(rig.colliders.size(), XpbdCollider{});
  for (std::size_t j = 0; j < joints; ++j) {
    const Joint& joint = rig.joints[j];
    rest_local_matrix_[j] = composeTransform(joint.rest_local);
    const glm::vec3 tail_local = toGlm(joint.tail_local);
    const float len = glm::length(tail_local);
    tail_distance_[j] = len;
    tail_axis_[j] = len > kMinLength ? tail_local / len : glm::vec3(0, 1, 0);
    const int c = joint.center_driver;
    if (c >= 0 && static_cast<std::size_t>(c) < rig.drivers.size() &&
        std::find(center_drivers_.begin(), center_drivers_.end(), c) == center_drivers_.end()) {
      center_drivers_.push_back(c);
    }
  }
}

void XpbdSolver::prepareCenters(const glm::mat4* driver_world) {
  for (int c : center_drivers_) center_inverse_valid_[c] = affineInverse(driver_world[c], center_inverse_[c]) ? 1 : 0;
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
    const glm::mat4 rest_world = parentWorld(joint, driver_world, joint_world_out) * rest_local_matrix_[j];
    const glm::vec3 tail = glm::vec3(rest_world[3]) + glm::mat3(rest_world) * toGlm(joint.tail_local);
    current_tail_[j] = previous_tail_[j] = toCenter(joint.center_driver, tail);
    tail_world_[j] = tail;
    joint_world_out[j] = rest_world;
    writeRotation(rotations_out + 4 * j, toGlm(joint.rest_local.rotation));
  }
}

void XpbdSolver::step(const glm::mat4* driver_world, const ColliderTable& colliders, float h, float* rotations_out,
                      glm::mat4* joint_world_out) {
  const std::size_t count = std::min(colliders.count, collider_scratch_.size());
  for (std::size_t c = 0; c < count; ++c) {
    XpbdCollider& out = collider_scratch_[c];
    out.start = glm::vec3(colliders.x0[c], colliders.y0[c], colliders.z0[c]);
    out.end = glm::vec3(colliders.x1[c], colliders.y1[c], colliders.z1[c]);
    out.radius = colliders.radius[c];
    out.kind = colliderKind(rig_.colliders[c]);
  }
  step(driver_world, collider_scratch_.data(), count, h, rotations_out, joint_world_out);
}

void XpbdSolver::step(const glm::mat4* driver_world, const XpbdCollider* colliders, std::size_t collider_count,
                      float h, float* rotations_out, glm::mat4* joint_world_out) {
  if (!(h > 0.0f) || !std::isfinite(h)) return;
  prepareCenters(driver_world);
  prepareRates(h);
  const auto& joints = rig_.joints;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const glm::mat4& parent = parentWorld(joint, driver_world, joint_world_out);
    const glm::mat4 rest_world = parent * rest_local_matrix_[j];
    const glm::mat3 rest_linear(rest_world);
    const glm::vec3 head(rest_world[3]);
    // Measured under the current parent every substep, as in the default path: a scaled armature
    // scales its bones, and no error can accumulate from one step to the next.
    const glm::vec3 rest_offset = rest_linear * toGlm(joint.tail_local);
    const float length = glm::length(rest_offset);
    if (!(length > kMinLength) || !(tail_distance_[j] > kMinLength)) {
      // A zero-length bone (or a collapsed parent) has no direction: keep the rest pose.
      tail_world_[j] = head + rest_offset;
      joint_world_out[j] = rest_world;
      writeRotation(rotations_out + 4 * j, toGlm(joint.rest_local.rotation));
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

    // 2. Constraints.
    solveJoint(j, head, rest_offset, length, h, colliders, collider_count, x);

    previous_tail_[j] = previous;
    current_tail_[j] = toCenter(joint.center_driver, x);
    tail_world_[j] = x;
    writeOutputs(j, parent, rest_linear, x - head, rotations_out, joint_world_out);
  }
}

void XpbdSolver::solveJoint(std::size_t j, const glm::vec3& head, const glm::vec3& rest_offset, float length, float h,
                            const XpbdCollider* colliders, std::size_t collider_count, glm::vec3& x) const {
  const Joint& joint = rig_.joints[j];
  const float stiffness = joint.params.stiffness;
  const float w = inverse_mass_[j];
  const glm::vec3 target = head + rest_offset;
  // alpha~ = alpha / h^2 with alpha = L / stiffness (see the opening comment).
  const bool bend = stiffness > 0.0f && w > 0.0f;
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
    bool contact = false;
    // Colliders, hard inequalities: outside C = |x - closest point of the segment| - (radius +
    // hitRadius) >= 0, inside C = (radius - hitRadius) - |x - closest point| >= 0, plane
    // C = (x - point).normal - hitRadius >= 0. The same arithmetic as the default path's, each
    // followed by the length again.
    for (int c : joint.colliders) {
      if (c < 0 || static_cast<std::size_t>(c) >= collider_count) continue;
      const XpbdCollider& collider = colliders[c];
      if (!moveTailByCollider(collider.kind, collider.start, collider.end, collider.radius, joint.hit_radius, x)) continue;
      projectLength(head, rest_offset, length, x);
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
  local_dir = len > 0.0f && std::isfinite(len) ? local_dir / len : tail_axis_[j];
  const glm::quat rotation = glm::normalize(toGlm(joint.rest_local.rotation) * rotationBetween(tail_axis_[j], local_dir));
  Transform local = joint.rest_local;
  local.rotation = fromGlm(rotation);
  joint_world_out[j] = parent * composeTransform(local);
  writeRotation(rotations_out + 4 * j, rotation);
}

}  // namespace springbones
