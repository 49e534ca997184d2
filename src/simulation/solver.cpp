// The spring-bone step.
//
// Where the update comes from: it is the VRM family's per-joint update (UniVRM's VRMSpringBone,
// credited there to @ricopin416; the VRMC_springBone 1.0 specification; @pixiv/three-vrm): Verlet
// inertia reduced by drag, an impulse toward the rest direction scaled by stiffness, a gravity
// impulse, then the tail is put back at the bone's length and the joint is turned to point at it.
// docs/semantics.md, "The step and the fixed-step rule", states it. Our own choices on top of it:
//  - Fixed steps. In that update inertia and drag act once per update while stiffness and gravity
//    scale with dt, so the motion depends on the update rate. We therefore always step at a fixed
//    rate (stepHz) with an accumulator, run at most maxSubsteps steps per frame and drop the rest
//    (a hitch or a hidden tab must not explode), and interpolate the driver matrices across the
//    substeps of a frame. The same motion then comes out at 30, 60 or 144 fps.
//  - Bone lengths are measured under the current parent transform (the rest tail offset carried
//    by the parent's world matrix), never from the previous frame's child position, and all
//    positions are world-space: a 0.01-scaled armature behaves like an unscaled one.
//  - Two ways to carry transforms down a chain. Avatars are almost always rotations, translations
//    and uniform scales (similarities), which compose with a quaternion, a vector and a float: the
//    fast path. A driver with shear or non-uniform scale, or a rig with non-uniform bone scales,
//    takes the general path on full matrices, so such hierarchies do not skew the bones. Both
//    compute the same update; which one runs is decided from the inputs alone, so native and
//    WebAssembly builds choose alike.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <vector>

#include "common/transform_math.h"
#include "simulation/driver_poses.h"
#include "simulation/joint_limits.h"
#include "simulation/grab.h"
#include "simulation/jump_carry.h"
#include "simulation/motion_controls.h"
#include "simulation/spring_lanes.h"
#include "simulation/wind.h"
#include "simulation/xpbd_solver.h"
#include "springbones/springbones.h"

// Functions with several callers (run and prepareDrivers: a frame's steps, the seed, settle) and
// the rare paths (settle, inertia, a change of path) stay calls: inlined at -O3 into each caller
// they cost the module kilobytes, and one call per step is nothing beside a step.
#if defined(__GNUC__)
#define SPRINGBONES_NOINLINE __attribute__((noinline))
#else
#define SPRINGBONES_NOINLINE
#endif

namespace springbones {
namespace {

constexpr float kMinLength = 1e-6f;
// The parent of a chain root that hangs from no driver.
const glm::mat4 kIdentity(1.0f);

// A jump threshold as used: a finite number above 0, else 0 (detection off).
float jumpThreshold(float value) { return value > 0.0f && std::isfinite(value) ? value : 0.0f; }

// A rotation, translation and uniform scale.
struct Similarity {
  glm::vec3 position{0.0f};
  float scale = 1.0f;
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};

  glm::vec3 apply(const glm::vec3& p) const { return position + scale * (rotation * p); }
  glm::mat4 matrix() const {
    glm::mat4 m = glm::mat4_cast(rotation);
    m[0] *= scale;
    m[1] *= scale;
    m[2] *= scale;
    m[3] = glm::vec4(position, 1.0f);
    return m;
  }
};

// Interpolated rotation between two drivers' poses, as the lane path interpolates them.
glm::quat interpolateRotation(const glm::quat& a, const glm::quat& b, float t) {
  glm::quat out;
  nlerpRotation(a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w, t, out.x, out.y, out.z, out.w);
  return out;
}

// The spring update shared by both paths: Verlet inertia (center space) reduced by drag, the
// stiffness and gravity impulses (world space), then back onto the sphere of the bone length.
// Returns the new tail offset from the head, in world space.
struct SpringInput {
  glm::vec3 head;
  glm::vec3 rest_dir;     // world
  glm::vec3 rest_offset;  // world, rest_dir * length
  float length;
  glm::quat limit_frame{1.0f, 0.0f, 0.0f, 0.0f};  // the joint's limit space in the world, when it has a limit
  glm::mat3 rest_linear;  // the joint at its rest rotation under its current parent (a grab's anchor)
};

// settle(): a step that turns no joint by more than this (radians) ends it.
constexpr float kSettledTurn = 1e-5f;

// sin(angle / 2) of the turn between two unit quaternions (x, y, z, w): the length of the vector
// part of their difference rotation, accurate for small angles, where 1 - |dot| is lost to float
// rounding (and no trigonometry: below 1e-5 rad, sin(a / 2) is a / 2 to float precision).
float halfTurnSine(const float* a, const float* b) {
  const glm::quat qa(a[3], a[0], a[1], a[2]), qb(b[3], b[0], b[1], b[2]);
  const glm::quat d = glm::conjugate(qa) * qb;
  return glm::length(glm::vec3(d.x, d.y, d.z));
}

}  // namespace

struct Instance::State {
  explicit State(std::shared_ptr<const Rig> r) : rig(std::move(r)) {}
  ~State() {
    if (lanes) lanes->releaseCopy(lane_copy);
  }

  std::shared_ptr<const Rig> rig;
  InstanceOptions options;
  double step_seconds = 1.0 / 60.0;
  double accumulator = 0.0;
  bool seeded = false;
  bool fast_path = true;       // what the current frame's steps use
  std::unique_ptr<XpbdSolver> xpbd;  // set when options.integrator is kXpbd

  // Rig-derived constants, per joint.
  std::vector<glm::mat4> rest_local_matrix;
  std::vector<glm::vec3> tail_axis;  // unit tail direction in the joint's local space
  std::vector<float> tail_distance;  // |tail_local|
  std::vector<glm::quat> limit_local;  // limitFrameLocal per joint (identity for a joint without a limit)

  // Inputs, per driver.
  std::vector<float> driver_input;  // what the caller writes, 16 floats per driver
  // This frame's driver poses, the last frame's and the one before (the drivers' last motion, for
  // jumps); they take turns every frame (an index, as swapping objects of ~20 vectors each cost
  // more than reading them).
  DriverPoses poses[3];
  int current = 0;
  DriverPoses& currentPoses() { return poses[current]; }
  const DriverPoses& currentPoses() const { return poses[current]; }
  const DriverPoses& previousPoses() const { return poses[(current + 2) % 3]; }
  DriverPoses& previousPoses() { return poses[(current + 2) % 3]; }
  const DriverPoses& olderPoses() const { return poses[(current + 1) % 3]; }
  void holdPoses() {  // no motion so far: every pose is this frame's
    poses[(current + 1) % 3] = poses[(current + 2) % 3] = currentPoses();
  }
  std::vector<glm::mat4> step_drivers, step_driver_inverses;  // general path, per step
  ColliderTable collider_table;  // world-space colliders of the current step, general paths
  std::vector<bool> step_inverse_valid;

  // Simulation state, per joint.
  std::vector<glm::vec3> current_tail, previous_tail;  // in the joint's center space
  std::shared_ptr<SpringLanes> lanes;  // the rig's lane pool (fast path); null: the rig or XPBD cannot use it
  std::size_t lane_copy = 0;           // this instance's copy in it
  bool batched = false;                // stepAll: this frame's steps go through the pool with others
  std::vector<glm::mat4> joint_world;                  // general path world transforms
  bool world_from_similarity = false;                  // which of the two is current
  mutable std::vector<float> world_output;             // worldMatrices(), filled on request
  std::vector<float> rotations;                        // output, x y z w per joint

  // Wind (springbones.h): what setWind left, the steps taken so far (the wind's clock: simulated
  // time, not wall time) and this step's pull times h, as the general path adds it.
  Wind wind;
  std::uint64_t wind_steps = 0;
  glm::vec3 step_wind{0.0f};

  // Where the tail state lives when the instance has a lane copy: in the lanes (the fast path) or
  // in current_tail / previous_tail (the general path); moved over when a frame changes path.
  bool tails_in_lanes = false;

  // Grab (Instance::grab, grab.h). A grabbing instance takes the general path.
  HeldJoints held;
  int grab_joint = -1;
  glm::vec3 grab_point{0.0f};

  // Inertia (InstanceOptions::inertia): per chain (Rig::chain_roots order), and per joint its
  // chain's index (-1: none). Below 1 on any chain, the instance takes the general path and keeps
  // the previous step's driver matrices.
  std::vector<float> chain_inertia;
  std::vector<int> joint_chain;
  bool inertia_active = false;
  std::vector<glm::mat4> last_step_drivers;
  std::vector<float> settle_rotations;  // settle(): the rotations before a step

  bool needsGeneralPath() const { return held.active || inertia_active; }

  // Moves the tail state to the path this frame uses (the lanes or the general path's arrays),
  // with the joints' world transforms a grab starts from.
  SPRINGBONES_NOINLINE void usePathState() {
    if (!lanes || xpbd || tails_in_lanes == fast_path) return;
    for (std::size_t j = 0; j < current_tail.size(); ++j) {
      if (fast_path) {
        lanes->setTailState(lane_copy, j, current_tail[j], previous_tail[j]);
      } else {
        lanes->tailState(lane_copy, j, current_tail[j], previous_tail[j]);
        Similarity world;
        lanes->jointWorld(lane_copy, j, world.position, world.rotation, world.scale);
        joint_world[j] = world.matrix();
      }
    }
    tails_in_lanes = fast_path;
  }

  // Every tail's velocity set to zero (settle): the previous tail put on the current one.
  SPRINGBONES_NOINLINE void holdTails() {
    for (std::size_t j = 0; j < current_tail.size(); ++j) {
      glm::vec3 now, before;
      if (xpbd) {
        xpbd->tailState(j, now, before);
        xpbd->setTailState(j, now, now);
      } else if (lanes && tails_in_lanes) {
        lanes->tailState(lane_copy, j, now, before);
        lanes->setTailState(lane_copy, j, now, now);
      } else {
        previous_tail[j] = current_tail[j];
      }
    }
  }

  // settle(): every tail put where its pulls balance without colliders, parents first, with no
  // velocity (balanceTails, docs/semantics.md "Settle"): the settle steps after it only have the
  // colliders (and a grab) left to resolve. Writes every path's state, the rotations and the
  // joints' world matrices; current_tail is the scratch for the paths that keep their own.
  SPRINGBONES_NOINLINE void seedBalance(const glm::vec3& wind_pull) {
    balanceTails(*rig, currentPoses(), rest_local_matrix.data(), tail_axis.data(), tail_distance.data(), wind_pull,
                 joint_world.data(), current_tail.data(), rotations.data());
    for (std::size_t j = 0; j < current_tail.size(); ++j) {
      if (xpbd) {
        xpbd->setTailState(j, current_tail[j], current_tail[j]);
      } else if (lanes && tails_in_lanes) {
        lanes->setTailState(lane_copy, j, current_tail[j], current_tail[j]);
      } else {
        previous_tail[j] = current_tail[j];
      }
    }
    world_from_similarity = false;
  }

  // Inertia below 1 (motion_controls.h): XPBD's tails go through current_tail / previous_tail,
  // which that integrator does not use otherwise.
  SPRINGBONES_NOINLINE void carryInertiaTails() {
    if (xpbd) {
      for (std::size_t j = 0; j < current_tail.size(); ++j) xpbd->tailState(j, current_tail[j], previous_tail[j]);
    }
    carryInertia(*rig, joint_chain.data(), chain_inertia.data(), last_step_drivers.data(), step_drivers.data(),
                 current_tail.data(), previous_tail.data());
    if (xpbd) {
      for (std::size_t j = 0; j < current_tail.size(); ++j) xpbd->setTailState(j, current_tail[j], previous_tail[j]);
    }
  }

  // Jumps (see carryAcrossJump).
  bool jump_requested = false;
  int jump_count = 0;
  JumpCarry jump_carry;

  // Carries every chain across a jump of the drivers (jump_carry.h): the tails (current and
  // previous, so the velocity too) move with the jump of the driver their chain hangs from, and
  // every driver's last pose with its own, so the frame's steps interpolate only the motion. The
  // chain keeps its shape and its motion relative to that driver, and the jump adds no velocity.
  void carryAcrossJump() {
    jump_carry.prepare(olderPoses(), previousPoses(), currentPoses());
    const auto& joints = rig->joints;
    for (std::size_t j = 0; j < joints.size(); ++j) {
      const int carrier = joints[joints[j].chain].parent_driver, center = joints[j].center_driver;
      glm::vec3 now, before;
      if (xpbd) {
        xpbd->tailState(j, now, before);
        xpbd->setTailState(j, jump_carry.carry(now, carrier, center), jump_carry.carry(before, carrier, center));
        continue;
      }
      current_tail[j] = jump_carry.carry(current_tail[j], carrier, center);
      previous_tail[j] = jump_carry.carry(previous_tail[j], carrier, center);
      if (lanes) {
        lanes->tailState(lane_copy, j, now, before);
        lanes->setTailState(lane_copy, j, jump_carry.carry(now, carrier, center), jump_carry.carry(before, carrier, center));
      }
    }
    previousPoses().read(jump_carry.carriedPoses(), olderPoses());
    ++jump_count;
  }

  bool driversAreSimilarities() const { return currentPoses().allSimilar() && previousPoses().allSimilar(); }

  SPRINGBONES_NOINLINE void prepareDrivers(float t) {
    if (fast_path) {
      DriverPoses::blend(previousPoses(), currentPoses(), t, lanes->drivers(), lanes->driverIndex(lane_copy, 0),
                         lanes->driverStride());
      prepareColliders();
      return;
    }
    for (std::size_t d = 0; d < currentPoses().size(); ++d) {
      if (t >= 1.0f) {
        step_drivers[d] = currentPoses().matrix(d);
      } else {
        const Transform ta = previousPoses().transform(d), tb = currentPoses().transform(d);
        step_drivers[d] = composeTransform(glm::mix(toGlm(ta.translation), toGlm(tb.translation), t),
                                           interpolateRotation(toGlm(ta.rotation), toGlm(tb.rotation), t),
                                           glm::mix(toGlm(ta.scale), toGlm(tb.scale), t));
      }
      glm::mat4 inverse;
      step_inverse_valid[d] = affineInverse(step_drivers[d], inverse);
      if (step_inverse_valid[d]) step_driver_inverses[d] = inverse;
    }
    prepareColliders();
  }

  // Colliders in world space for this step. The radius scales with the driver: uniformly on the
  // fast path, by the largest axis scale of a general matrix. A plane's normal turns with the
  // driver's inverse transpose (perpendicular to the plane under any scale), then is made unit; a
  // singular driver leaves it NaN, and a NaN normal moves no tail.
  void prepareColliders() {
    const auto& all = rig->colliders;
    for (std::size_t c = 0; c < all.size(); ++c) {
      const Collider& collider = all[c];
      const bool plane = collider.shape == Collider::Shape::kPlane;
      glm::vec3 start, end;
      float scale;
      if (fast_path) {
        const DriverTable& table = lanes->drivers();
        const std::size_t slot = lanes->driverIndex(lane_copy, collider.driver);
        Similarity m;
        m.position = glm::vec3(table.px[slot], table.py[slot], table.pz[slot]);
        m.rotation = glm::quat(table.qw[slot], table.qx[slot], table.qy[slot], table.qz[slot]);
        m.scale = table.s[slot];
        start = m.apply(toGlm(collider.offset));
        end = plane ? glm::normalize(m.rotation * toGlm(collider.normal)) : m.apply(toGlm(collider.tail));
        scale = m.scale;
      } else {
        const glm::mat4& m = step_drivers[collider.driver];
        start = glm::vec3(m * glm::vec4(toGlm(collider.offset), 1.0f));
        end = plane ? glm::normalize(glm::transpose(glm::inverse(glm::mat3(m))) * toGlm(collider.normal))
                    : glm::vec3(m * glm::vec4(toGlm(collider.tail), 1.0f));
        scale = std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
      }
      const float radius = plane ? 0.0f : collider.radius * scale;
      if (fast_path) {
        lanes->colliders().set(lanes->colliderIndex(lane_copy, c), start, end, radius);
      } else {
        collider_table.set(c, start, end, radius);
      }
    }
  }

  // Moves a tail out of (or into, or onto the side of) the joint's colliders, each followed by
  // the length constraint again (VRMC_springBone order).
  // A limited joint is kept inside its limit after each push too (VRMC_springBone_limit's order).
  glm::vec3 collide(const Joint& joint, const SpringInput& in, glm::vec3 tail, int passes) const {
    const glm::vec3& head = in.head;
    const float length = in.length;
    const bool limited = joint.limit.kind != JointLimit::Kind::kNone;
    // `passes`: Rig::collider_passes (1 but with the body preset), or more for a held tail; a pass
    // that moves nothing ends them (the lane path runs them all, and a pass without a push changes
    // no bit there either).
    for (int pass = 0; pass < passes; ++pass) {
      bool pushed = false;
      for (int c : joint.colliders) {
        const glm::vec3 start(collider_table.x0[c], collider_table.y0[c], collider_table.z0[c]);
        const glm::vec3 end(collider_table.x1[c], collider_table.y1[c], collider_table.z1[c]);
        if (!moveTailByCollider(colliderKind(rig->colliders[c]), start, end, collider_table.radius[c], joint.hit_radius,
                                tail)) {
          continue;
        }
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

  // Center space. A general-path center without an inverse this step counts as world space.
  glm::vec3 toCenter(const Joint& joint, const glm::vec3& world) const {
    const int c = joint.center_driver;
    if (c < 0 || !step_inverse_valid[c]) return world;
    return glm::vec3(step_driver_inverses[c] * glm::vec4(world, 1.0f));
  }

  glm::vec3 fromCenter(const Joint& joint, const glm::vec3& local) const {
    const int c = joint.center_driver;
    if (c < 0 || !step_inverse_valid[c]) return local;
    return glm::vec3(step_drivers[c] * glm::vec4(local, 1.0f));
  }

  void writeRotation(std::size_t j, const glm::quat& q) { storeQuat(rotations.data() + 4 * j, q); }

  // Returns the new world tail offset from the head and advances the joint's tail state.
  glm::vec3 integrate(std::size_t j, const Joint& joint, const SpringInput& in, float h) {
    const BoneParams& p = joint.params;
    const glm::vec3 current = current_tail[j];
    const glm::vec3 inertia = (current - previous_tail[j]) * (1.0f - p.drag);
    glm::vec3 next = fromCenter(joint, current + inertia);
    next += in.rest_dir * (p.stiffness * h);
    next += toGlm(p.gravity_dir) * (p.gravity_power * h);
    next += step_wind;
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
    tail = collide(joint, in, tail, held_tail ? std::max(kDefaultXpbdIterations, rig->collider_passes) : rig->collider_passes);
    previous_tail[j] = current;
    current_tail[j] = toCenter(joint, tail);
    return tail - in.head;
  }

  // The joint's local rotation that turns its rest axis toward `local_dir` (unit or not).
  glm::quat aimedRotation(std::size_t j, const Joint& joint, glm::vec3 local_dir) const {
    const float len = glm::length(local_dir);
    local_dir = len > 0.0f && std::isfinite(len) ? local_dir / len : tail_axis[j];
    return glm::normalize(toGlm(joint.rest_local.rotation) * rotationBetween(tail_axis[j], local_dir));
  }

  const glm::mat4& parentMatrix(const Joint& joint) const {
    if (joint.parent_joint >= 0) return joint_world[joint.parent_joint];
    if (joint.parent_driver >= 0) return step_drivers[joint.parent_driver];
    return kIdentity;
  }

  void stepGeneral(float h, bool seed_only) {
    const auto& joints = rig->joints;
    for (std::size_t j = 0; j < joints.size(); ++j) {
      const Joint& joint = joints[j];
      const glm::mat4& parent = parentMatrix(joint);
      const glm::mat4 rest_world = parent * rest_local_matrix[j];
      const glm::mat3 rest_linear(rest_world);
      SpringInput in;
      in.head = glm::vec3(rest_world[3]);
      in.rest_offset = rest_linear * toGlm(joint.tail_local);
      in.length = glm::length(in.rest_offset);
      if (seed_only || !(in.length > kMinLength) || !(tail_distance[j] > kMinLength)) {
        if (seed_only) current_tail[j] = previous_tail[j] = toCenter(joint, in.head + in.rest_offset);
        joint_world[j] = rest_world;
        writeRotation(j, toGlm(joint.rest_local.rotation));
        continue;
      }
      in.rest_dir = in.rest_offset / in.length;
      if (joint.limit.kind != JointLimit::Kind::kNone) in.limit_frame = worldRotationOf(rest_linear) * limit_local[j];
      in.rest_linear = rest_linear;
      const glm::vec3 offset = integrate(j, joint, in, h);
      const glm::quat rotation = aimedRotation(j, joint, glm::inverse(rest_linear) * offset);
      joint_world[j] =
          parent * composeTransform(toGlm(joint.rest_local.translation), rotation, toGlm(joint.rest_local.scale));
      writeRotation(j, rotation);
    }
  }

  SPRINGBONES_NOINLINE void run(float h, bool seed_only) {
    if (seed_only) {
      tails_in_lanes = fast_path;
    } else if (!fast_path) {
      if (inertia_active) carryInertiaTails();
      if (held.active) held.prepare(grab_point, joint_world.data());
    }
    if (xpbd) {
      // The XPBD integrator reads the general path's driver matrices and the shared collider
      // table, and writes the general path's outputs.
      world_from_similarity = false;
      if (seed_only) {
        xpbd->seed(step_drivers.data(), rotations.data(), joint_world.data());
      } else {
        xpbd->step(step_drivers.data(), collider_table, h, rotations.data(), joint_world.data());
      }
      return;
    }
    world_from_similarity = fast_path;
    if (fast_path) {
      const CopyRange own{lane_copy, lane_copy + 1};
      lanes->run(&own, 1, h, seed_only);
    } else {
      stepGeneral(h, seed_only);
    }
  }

  // A frame in three phases, so that a scene can interleave the steps of many instances:
  // beginFrame reads the drivers, seeds if needed and counts the steps; prepareStep(i) sets the
  // drivers and colliders of step i; endFrame keeps the time left over and this frame's poses.
  int frame_steps = 0;
  bool frame_dropped = false;
  double frame_start = 0.0, frame_dt = 0.0;

  bool beginFrame(double dt) {
    frame_steps = 0;
    if (!(dt > 0.0) || !std::isfinite(dt)) return false;
    currentPoses().read(driver_input.data(), previousPoses());
    const bool was_seeded = seeded;
    if (!seeded) {
      holdPoses();
      fast_path = lanes && driversAreSimilarities() && !needsGeneralPath();
      prepareDrivers(1.0f);
      run(0.0f, /*seed_only=*/true);
      seeded = true;
    }
    // Steps fall where the accumulated time crosses a multiple of h. The tolerance keeps a stream
    // of frames of exactly 1/stepHz at one step each despite rounding in the sum.
    const double h = step_seconds;
    const double tolerance = h * 1e-6;
    frame_start = accumulator;
    frame_dt = dt;
    accumulator += dt;
    // Counted in double: a frame of 1e9 s crosses more steps than an int holds.
    const double crossed = std::floor((accumulator + tolerance) / h);
    frame_dropped = crossed > options.max_substeps;
    frame_steps = frame_dropped ? options.max_substeps : static_cast<int>(crossed);
    if (was_seeded && (jump_requested || driversJumped(previousPoses(), currentPoses(), frame_steps, options.jump_distance, options.jump_angle))) carryAcrossJump();
    jump_requested = false;
    fast_path = lanes && driversAreSimilarities() && !needsGeneralPath();
    usePathState();
    return true;
  }

  void prepareStep(int i) {
    // Where this step falls inside the frame, for driver interpolation.
    const double h = step_seconds;
    const double at = frame_dropped ? double(i + 1) / frame_steps : ((i + 1) * h - frame_start) / frame_dt;
    if (inertia_active && !fast_path) {  // the drivers of the step before, for carryInertia
      for (std::size_t d = 0; d < last_step_drivers.size(); ++d) {
        last_step_drivers[d] = i == 0 ? previousPoses().matrix(d) : step_drivers[d];
      }
    }
    prepareDrivers(static_cast<float>(std::clamp(at, 0.0, 1.0)));
    prepareWind();
  }

  // The wind of the coming step, at the simulated time of its start, for whichever path runs it.
  void prepareWind() {
    const glm::vec3 pull = windAt(wind, static_cast<double>(wind_steps) * step_seconds);
    ++wind_steps;
    applyWind(pull);
  }

  void applyWind(const glm::vec3& pull) {
    if (xpbd) {
      xpbd->setWind(pull);
      return;
    }
    step_wind = pull * static_cast<float>(step_seconds);
    if (fast_path) lanes->setWind(lane_copy, step_wind);
  }

  void endFrame() {
    accumulator = frame_dropped ? 0.0 : std::max(0.0, accumulator - frame_steps * step_seconds);
    // This frame's poses become the previous ones; the next read overwrites the older.
    current = (current + 1) % 3;
  }
};

Instance::Instance(std::shared_ptr<const Rig> rig, InstanceOptions options) {
  if (!rig) rig = std::make_shared<const Rig>();
  state_ = std::make_unique<State>(std::move(rig));
  State& s = *state_;
  if (options.integrator != Integrator::kXpbd) options.integrator = Integrator::kVrm;
  const IntegratorDefaults defaults = integratorDefaults(options.integrator);
  if (!(options.step_hz > 0)) options.step_hz = defaults.step_hz;
  options.step_hz = std::clamp(options.step_hz, kMinStepHz, kMaxStepHz);
  if (options.max_substeps <= 0) options.max_substeps = defaults.max_substeps;
  options.max_substeps = std::min(options.max_substeps, kMaxSubsteps);
  options.xpbd_iterations = std::clamp(options.xpbd_iterations, 1, kMaxXpbdIterations);
  s.options = options;
  s.options.jump_distance = jumpThreshold(options.jump_distance);
  s.options.jump_angle = jumpThreshold(options.jump_angle);
  if (options.integrator == Integrator::kXpbd) {
    XpbdOptions xpbd_options;
    xpbd_options.iterations = options.xpbd_iterations;
    s.xpbd = std::make_unique<XpbdSolver>(*s.rig, xpbd_options);
  }
  s.step_seconds = 1.0 / options.step_hz;

  const std::size_t joints = s.rig->joints.size();
  const std::size_t drivers = s.rig->drivers.size();
  s.rest_local_matrix.resize(joints);
  s.tail_axis.resize(joints);
  s.tail_distance.resize(joints);
  s.limit_local.assign(joints, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  // The lane path takes every rest scale a positive uniform one, at most kMaxLaneColliders, each
  // joint's colliders in index order once (its collider mask), and no angle limit.
  bool lanes_usable = true;
  for (std::size_t j = 0; j < joints; ++j) {
    const Joint& joint = s.rig->joints[j];
    s.rest_local_matrix[j] = composeTransform(joint.rest_local);
    const glm::vec3 tail_local = toGlm(joint.tail_local);
    const float len = glm::length(tail_local);
    s.tail_distance[j] = len;
    s.tail_axis[j] = len > kMinLength ? tail_local / len : glm::vec3(0, 1, 0);
    const Vec3 scale = joint.rest_local.scale;
    if (!(scale.x > 0.0f) || scale.y != scale.x || scale.z != scale.x) lanes_usable = false;
    if (joint.limit.kind != JointLimit::Kind::kNone) {
      s.limit_local[j] = limitFrameLocal(s.tail_axis[j], joint.limit.rotation);
      lanes_usable = false;
    }
    for (std::size_t k = 1; k < joint.colliders.size(); ++k) {
      if (joint.colliders[k] <= joint.colliders[k - 1]) lanes_usable = false;  // repeated or out of order
    }
  }
  s.driver_input.resize(16 * drivers);
  for (DriverPoses& poses : s.poses) poses.resize(drivers);
  s.step_drivers.resize(drivers);
  s.step_driver_inverses.resize(drivers);
  s.step_inverse_valid.assign(drivers, false);
  s.jump_carry.resize(drivers);
  s.collider_table.resize(s.rig->colliders.size());
  if (s.rig->colliders.size() > kMaxLaneColliders) lanes_usable = false;
  // Until the caller writes them, drivers sit at their rest world matrices.
  for (std::size_t d = 0; d < drivers; ++d) {
    const int node = s.rig->drivers[d].node;  // -1: an avatar bone outside the GLB
    const Mat4 rest = node >= 0 ? s.rig->skeleton.nodes[node].rest_world : Mat4{};
    std::memcpy(s.driver_input.data() + 16 * d, rest.m, sizeof rest.m);
  }
  s.current_tail.resize(joints);
  s.previous_tail.resize(joints);
  s.joint_world.resize(joints);
  s.world_output.resize(16 * joints);
  s.rotations.resize(4 * joints);
  for (std::size_t j = 0; j < joints; ++j) {
    s.writeRotation(j, toGlm(s.rig->joints[j].rest_local.rotation));
    s.joint_world[j] = toGlm(s.rig->skeleton.nodes[s.rig->joints[j].node].rest_world);
  }
  // The lane path needs a copy in the rig's pool; the XPBD integrator never takes it.
  if (lanes_usable && !s.xpbd) {
    s.lanes = SpringLanes::acquire(s.rig);
    s.lane_copy = s.lanes->addCopy(s.rotations.data());
  }
  // Grab and inertia, sized once so that grab() and the steps allocate nothing.
  s.held.slot.assign(joints, -1);
  s.held.path.reserve(joints);
  s.held.anchor.reserve(joints);
  s.held.reach.reserve(joints);
  s.settle_rotations.resize(4 * joints);
  s.last_step_drivers.resize(drivers);
  const auto& roots = s.rig->chain_roots;
  s.chain_inertia.assign(roots.size(), kDefaultInertia);
  s.joint_chain.assign(joints, -1);
  for (std::size_t j = 0; j < joints; ++j) {
    const auto found = std::find(roots.begin(), roots.end(), s.rig->joints[j].chain);
    if (found != roots.end()) s.joint_chain[j] = static_cast<int>(found - roots.begin());
  }
  s.options.inertia = kDefaultInertia;
  setInertia(options.inertia, -1);
}

Instance::~Instance() = default;

float* Instance::driverMatrices() { return state_->driver_input.data(); }
std::size_t Instance::driverCount() const { return state_->rig->drivers.size(); }
const float* Instance::rotations() const { return state_->rotations.data(); }
std::size_t Instance::jointCount() const { return state_->rig->joints.size(); }
const Rig& Instance::rig() const { return *state_->rig; }
const InstanceOptions& Instance::options() const { return state_->options; }

const float* Instance::worldMatrices() const {
  const State& s = *state_;
  for (std::size_t j = 0; j < s.joint_world.size(); ++j) {
    glm::mat4 m = s.joint_world[j];
    if (s.world_from_similarity) {
      Similarity world;
      s.lanes->jointWorld(s.lane_copy, j, world.position, world.rotation, world.scale);
      m = world.matrix();
    }
    std::memcpy(s.world_output.data() + 16 * j, &m[0][0], sizeof(float) * 16);
  }
  return s.world_output.data();
}

int Instance::lastSteps() const { return state_->frame_steps; }

void Instance::setWind(const Wind& wind) {
  Wind& w = state_->wind;
  w = wind;
  w.strength = std::isnan(wind.strength) ? 0.0f : std::clamp(wind.strength, 0.0f, kMaxWindStrength);
  w.gust_frequency = std::isnan(wind.gust_frequency) ? 0.0f : std::clamp(wind.gust_frequency, 0.0f, kMaxGustFrequency);
  // Made unit in double, largest component first: a float length would overflow for (1e20, 0, 0)
  // and underflow for (1e-25, 0, 0), silently leaving no wind.
  if (!unitDirection(wind.direction, w.direction)) {
    w.direction = Vec3{1.0f, 0.0f, 0.0f};
    w.strength = 0.0f;
  }
}

const Wind& Instance::wind() const { return state_->wind; }

void Instance::reset() {
  state_->seeded = false;
  state_->accumulator = 0.0;
  state_->jump_requested = false;
}

void Instance::jump() { state_->jump_requested = true; }

int Instance::settle(double seconds) {
  State& s = *state_;
  seconds = std::isnan(seconds) ? 0.0 : std::clamp(seconds, 0.0, kMaxSettleSeconds);
  // The tolerance keeps 2 s at 60 Hz at 120 steps despite rounding in the product.
  const int most = static_cast<int>(std::ceil(seconds * s.options.step_hz - 1e-6));
  // Put at rest under the drivers as they are, which become the last frame's too (no motion).
  s.currentPoses().read(s.driver_input.data(), s.previousPoses());
  s.holdPoses();
  s.fast_path = s.lanes && s.driversAreSimilarities() && !s.needsGeneralPath();
  s.prepareDrivers(1.0f);
  s.run(0.0f, /*seed_only=*/true);
  s.seeded = true;
  s.accumulator = 0.0;
  s.jump_requested = false;
  if (s.rig->joints.empty()) return 0;
  s.last_step_drivers = s.step_drivers;  // still drivers: inertia carries nothing
  const glm::vec3 pull = windAt(s.wind, static_cast<double>(s.wind_steps) * s.step_seconds);
  s.applyWind(pull);
  if (most > 0) s.seedBalance(pull);
  // Steps with no velocity: each moves the tails by what still pulls them off their balance
  // (colliders, a grab), and never overshoots it as a swing would.
  int steps = 0;
  while (steps < most) {
    s.settle_rotations = s.rotations;
    s.holdTails();
    s.run(static_cast<float>(s.step_seconds), /*seed_only=*/false);
    ++steps;
    float turn = 0.0f;
    for (std::size_t j = 0; j < s.rig->joints.size(); ++j) {
      turn = std::max(turn, halfTurnSine(s.settle_rotations.data() + 4 * j, s.rotations.data() + 4 * j));
    }
    if (!(turn > 0.5f * kSettledTurn)) break;
  }
  s.holdTails();
  return steps;
}

void Instance::grab(std::size_t joint, const Vec3& point) {
  State& s = *state_;
  const auto& joints = s.rig->joints;
  if (joint >= joints.size() || !isFinite(toGlm(point))) return;
  s.grab_point = toGlm(point);
  if (s.grab_joint != static_cast<int>(joint)) {
    HeldJoints& held = s.held;
    for (int j : held.path) held.slot[j] = -1;
    held.path.clear();
    held.anchor.clear();
    // From the grabbed joint up to its chain root (a parent joint always comes first in the
    // rig, so this ends), then turned root first.
    for (int j = static_cast<int>(joint); j >= 0 && held.path.size() < joints.size(); j = joints[j].parent_joint) {
      held.anchor.push_back(held.path.empty() ? toGlm(joints[j].tail_local)
                                              : toGlm(joints[held.path.back()].rest_local.translation));
      held.path.push_back(j);
    }
    std::reverse(held.path.begin(), held.path.end());
    std::reverse(held.anchor.begin(), held.anchor.end());
    held.reach.assign(held.path.size(), glm::vec3(0.0f));
    for (std::size_t k = 0; k < held.path.size(); ++k) held.slot[held.path[k]] = static_cast<int>(k);
    s.grab_joint = static_cast<int>(joint);
  }
  s.held.active = true;
  if (s.xpbd) s.xpbd->setHeld(&s.held);
}

void Instance::release() {
  State& s = *state_;
  for (int j : s.held.path) s.held.slot[j] = -1;
  s.held.path.clear();
  s.held.active = false;
  s.grab_joint = -1;
  if (s.xpbd) s.xpbd->setHeld(nullptr);
}

int Instance::grabbedJoint() const { return state_->grab_joint; }

void Instance::setInertia(float value, int chain) {
  State& s = *state_;
  if (chain >= static_cast<int>(s.chain_inertia.size())) return;
  value = std::isnan(value) ? kDefaultInertia : std::clamp(value, 0.0f, 1.0f);
  if (chain < 0) {
    std::fill(s.chain_inertia.begin(), s.chain_inertia.end(), value);
    s.options.inertia = value;
  } else {
    s.chain_inertia[chain] = value;
  }
  s.inertia_active = std::any_of(s.chain_inertia.begin(), s.chain_inertia.end(), [](float k) { return k < 1.0f; });
}

float Instance::inertia(std::size_t chain) const {
  const State& s = *state_;
  return chain < s.chain_inertia.size() ? s.chain_inertia[chain] : kDefaultInertia;
}
int Instance::jumps() const { return state_->jump_count; }

void Instance::setJumpThresholds(float distance, float angle) {
  if (!std::isnan(distance)) state_->options.jump_distance = jumpThreshold(distance);
  if (!std::isnan(angle)) state_->options.jump_angle = jumpThreshold(angle);
}

void Instance::step(double dt) {
  State& s = *state_;
  if (!s.beginFrame(dt)) return;
  for (int i = 0; i < s.frame_steps; ++i) {
    s.prepareStep(i);
    s.run(static_cast<float>(s.step_seconds), /*seed_only=*/false);
  }
  s.endFrame();
}

void Instance::stepAll(Instance* const* instances, std::size_t count, double dt) {
  int most_steps = 0;
  for (std::size_t n = 0; n < count; ++n) {
    State& s = *instances[n]->state_;
    s.batched = false;
    if (!s.beginFrame(dt)) continue;
    if (s.fast_path && !s.xpbd) {
      s.batched = true;
      most_steps = std::max(most_steps, s.frame_steps);
      continue;
    }
    for (int i = 0; i < s.frame_steps; ++i) {  // the general path and XPBD: one by one
      s.prepareStep(i);
      s.run(static_cast<float>(s.step_seconds), /*seed_only=*/false);
    }
    s.endFrame();
  }
  // Step i of every lane-path instance that has one: each queues its copy in its rig's pool, then
  // each pool runs its queue in as few runs as the copies allow.
  for (int i = 0; i < most_steps; ++i) {
    for (std::size_t n = 0; n < count; ++n) {
      State& s = *instances[n]->state_;
      if (!s.batched || i >= s.frame_steps) continue;
      s.prepareStep(i);
      s.world_from_similarity = true;
      s.lanes->queueStep(s.lane_copy, static_cast<float>(s.step_seconds));
    }
    for (std::size_t n = 0; n < count; ++n) {
      State& s = *instances[n]->state_;
      if (s.batched) s.lanes->runQueued();  // the first instance of a pool runs it, the others find it empty
    }
  }
  for (std::size_t n = 0; n < count; ++n) {
    State& s = *instances[n]->state_;
    if (s.batched) s.endFrame();
  }
}

// Takes over a previous instance's motion after an edit of the rig (springbones.h). The joints are
// matched by node rather than by index, because added or removed chains renumber them; the tail
// state is carried rather than recomputed from the previous rotations because it holds the
// velocity too, so a chain that keeps its entries keeps swinging through the edit. It runs once
// per edit, not per frame: optimised for size, as the rest of the module off the per-frame path
// (this file is built at -O3 for the step).
#if defined(__clang__)
__attribute__((minsize))
#endif
void Instance::carryFrom(const Instance& previous) {
  if (&previous == this) return;
  const State& from = *previous.state_;
  if (!from.seeded) return;
  State& s = *state_;
  const Rig& old_rig = *from.rig;
  const Rig& rig = *s.rig;

  // A tail state as an instance last left it: its XPBD solver, its lane copy when the last run
  // took the fast path (world_from_similarity), else its general-path vectors.
  const auto tailOf = [](const State& st, std::size_t j, glm::vec3& now, glm::vec3& before) {
    if (st.xpbd) {
      st.xpbd->tailState(j, now, before);
    } else if (st.world_from_similarity && st.lanes) {
      st.lanes->tailState(st.lane_copy, j, now, before);
    } else {
      now = st.current_tail[j];
      before = st.previous_tail[j];
    }
  };
  const auto setTail = [&s](std::size_t j, const glm::vec3& now, const glm::vec3& before) {
    if (s.xpbd) {
      s.xpbd->setTailState(j, now, before);
      return;
    }
    s.current_tail[j] = now;
    s.previous_tail[j] = before;
    if (s.lanes) s.lanes->setTailState(s.lane_copy, j, now, before);
  };
  // Joints new to this rig start at rest, moving as the avatar moved over the previous instance's
  // last frame (as a chain that had hung there would): seeded first under the drivers of the frame
  // before, when the previous instance had every driver of this rig, for the velocity; then, as a
  // first frame seeds, under the drivers the caller wrote, which become every pose of the history
  // so the next frame interpolates from there.
  std::vector<int> old_driver(rig.drivers.size(), -1);
  bool drivers_known = true;
  for (std::size_t d = 0; d < rig.drivers.size(); ++d) {
    for (std::size_t o = 0; o < old_rig.drivers.size() && old_driver[d] < 0; ++o) {
      if (old_rig.drivers[o].name == rig.drivers[d].name) old_driver[d] = static_cast<int>(o);
    }
    drivers_known = drivers_known && old_driver[d] >= 0;
  }
  const bool with_earlier = drivers_known && from.frame_steps > 0;
  std::vector<glm::vec3> earlier_rest;
  std::vector<float> input;
  if (with_earlier) {
    input = s.driver_input;
    for (std::size_t d = 0; d < rig.drivers.size(); ++d) {
      const glm::mat4 m = from.olderPoses().matrix(static_cast<std::size_t>(old_driver[d]));
      std::memcpy(s.driver_input.data() + 16 * d, &m[0][0], sizeof(float) * 16);
    }
  }
  for (int pass = with_earlier ? 0 : 1; pass < 2; ++pass) {
    s.currentPoses().read(s.driver_input.data(), s.previousPoses());
    s.holdPoses();
    s.fast_path = s.lanes && s.driversAreSimilarities();
    s.prepareDrivers(1.0f);
    s.run(0.0f, /*seed_only=*/true);
    if (pass == 0) {
      earlier_rest.resize(rig.joints.size());
      glm::vec3 unused;
      for (std::size_t j = 0; j < rig.joints.size(); ++j) tailOf(s, j, earlier_rest[j], unused);
      s.driver_input = input;
    }
  }
  s.seeded = true;
  s.accumulator = from.accumulator;
  s.wind = from.wind;
  s.wind_steps = from.wind_steps;
  s.jump_requested = false;

  // A driver's name, for comparing centers across the two rigs' driver lists.
  const auto driverName = [](const Rig& r, int d) -> const std::string* {
    return d >= 0 ? &r.drivers[static_cast<std::size_t>(d)].name : nullptr;
  };
  std::vector<int> old_joint_of_node(old_rig.skeleton.nodes.size(), -1);
  for (std::size_t j = 0; j < old_rig.joints.size(); ++j) {
    const int node = old_rig.joints[j].node;
    if (node >= 0 && static_cast<std::size_t>(node) < old_joint_of_node.size()) old_joint_of_node[node] = static_cast<int>(j);
  }
  // Per step, as the tails move: the previous instance's last frame may have run several steps.
  const float per_step = 1.0f / static_cast<float>(std::max(1, from.frame_steps));
  for (std::size_t j = 0; j < rig.joints.size(); ++j) {
    const Joint& joint = rig.joints[j];
    const bool in_range = joint.node >= 0 && static_cast<std::size_t>(joint.node) < old_joint_of_node.size();
    const int o = in_range ? old_joint_of_node[joint.node] : -1;
    const Joint* old_joint = o >= 0 ? &old_rig.joints[static_cast<std::size_t>(o)] : nullptr;
    if (old_joint == nullptr || old_joint->tail_node != joint.tail_node ||
        old_rig.skeleton.nodes[joint.node].name != rig.skeleton.nodes[joint.node].name) {
      if (earlier_rest.empty()) continue;  // at rest, still
      glm::vec3 now, unused;
      tailOf(s, j, now, unused);
      const glm::vec3 before = now - (now - earlier_rest[j]) * per_step;
      if (std::isfinite(before.x + before.y + before.z)) setTail(j, now, before);
      continue;
    }
    glm::vec3 now, before;
    tailOf(from, static_cast<std::size_t>(o), now, before);
    const std::string* old_center = driverName(old_rig, old_joint->center_driver);
    const std::string* new_center = driverName(rig, joint.center_driver);
    const bool same_center = old_center == nullptr ? new_center == nullptr : new_center != nullptr && *old_center == *new_center;
    if (!same_center) {
      // Through world space: the old center as it last stepped, the new one as just read.
      glm::mat4 to_world(1.0f), to_center(1.0f);
      if (old_joint->center_driver >= 0) to_world = from.previousPoses().matrix(static_cast<std::size_t>(old_joint->center_driver));
      if (joint.center_driver >= 0) {
        glm::mat4 inverse;
        if (affineInverse(s.currentPoses().matrix(static_cast<std::size_t>(joint.center_driver)), inverse)) to_center = inverse;
      }
      now = glm::vec3(to_center * (to_world * glm::vec4(now, 1.0f)));
      before = glm::vec3(to_center * (to_world * glm::vec4(before, 1.0f)));
    }
    if (!std::isfinite(now.x + now.y + now.z + before.x + before.y + before.z)) continue;  // keep the rest seed
    setTail(j, now, before);
    std::memcpy(s.rotations.data() + 4 * j, from.rotations.data() + 4 * static_cast<std::size_t>(o), 4 * sizeof(float));
  }
}

}  // namespace springbones
