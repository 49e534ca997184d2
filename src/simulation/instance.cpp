// Instance: the clock, the drivers' poses and one integrator (spring_integrator.h).
//
// Fixed steps. In the VRM update inertia and drag act once per update while stiffness and gravity
// scale with dt, so the motion depends on the update rate. We therefore always step at a fixed
// rate (stepHz) with an accumulator, run at most maxSubsteps steps per frame and drop the rest (a
// hitch or a hidden tab must not explode), and interpolate the driver matrices across the
// substeps of a frame. The same motion then comes out at 30, 60 or 144 fps, whichever integrator
// runs it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "common/transform_math.h"
#include "loading/instance_colliders.h"
#include "simulation/driver_poses.h"
#include "simulation/general_integrator.h"
#include "simulation/jump_carry.h"
#include "simulation/lane_integrator.h"
#include "simulation/spring_lanes.h"
#include "simulation/wind.h"
#include "simulation/xpbd_integrator.h"
#include "springbones/springbones.h"

namespace springbones {
namespace {

// A jump threshold as used: a finite number above 0, else 0 (detection off).
float jumpThreshold(float value) { return value > 0.0f && std::isfinite(value) ? value : 0.0f; }

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

std::unique_ptr<SpringIntegrator> makeIntegrator(const std::shared_ptr<const Rig>& rig,
                                                 const InstanceOptions& options) {
  std::shared_ptr<const RigConstants> constants = RigConstants::acquire(rig);
  if (options.integrator == Integrator::kXpbd) {
    XpbdOptions xpbd_options;
    xpbd_options.iterations = options.xpbd_iterations;
    return std::make_unique<XpbdIntegrator>(std::move(constants), xpbd_options);
  }
  if (constants->lanes_usable) return std::make_unique<LaneIntegrator>(std::move(constants));
  return std::make_unique<GeneralIntegrator>(std::move(constants));
}

}  // namespace

struct Instance::State {
  explicit State(std::shared_ptr<const Rig> r) : rig(std::move(r)) {}

  std::shared_ptr<const Rig> rig;
  InstanceOptions options;

  // The clock.
  double step_seconds = 1.0 / 60.0;
  double accumulator = 0.0;
  bool seeded = false;
  // A frame in three phases, so that a scene can interleave the steps of many instances:
  // beginFrame reads the drivers, seeds if needed and counts the steps; runStep(i) runs step i;
  // endFrame keeps the time left over and this frame's poses.
  int frame_steps = 0;
  bool frame_dropped = false;
  double frame_start = 0.0, frame_dt = 0.0;
  // Wind (springbones.h): what setWind left and the steps taken so far (the wind's clock:
  // simulated time, not wall time).
  Wind wind;
  std::uint64_t wind_steps = 0;

  // The drivers: what the caller writes, 16 floats per driver; this frame's poses, the last
  // frame's and the one before (the drivers' last motion, for jumps). They take turns every frame
  // (an index, as swapping objects of ~20 vectors each cost more than reading them).
  std::vector<float> driver_input;
  // The collider set's frames (Instance::frameMatrices): what the caller writes, 16 floats each,
  // read into the integrator's frame matrices once per frame.
  std::vector<float> frame_input;
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
  // Jumps (Instance::jump, jump_carry.h).
  bool jump_requested = false;
  int jump_count = 0;
  JumpCarry jump_carry;

  std::unique_ptr<SpringIntegrator> integrator;
  SpringLanes* queued = nullptr;            // stepAll: the pool this step was queued in
  mutable std::vector<float> world_output;  // worldMatrices(), filled on request
  std::vector<float> settle_rotations;      // settle(): the rotations before a step

  // The frames the caller wrote, each taken when every entry is a number within kMaxDriverEntry
  // (the drivers' rule), else left at its last good matrix.
  void readFrames() {
    std::vector<glm::mat4>& world = integrator->frameWorld();
    for (std::size_t f = 0; f < world.size(); ++f) {
      const float* m = frame_input.data() + 16 * f;
      bool usable = true;
      for (int k = 0; k < 16; ++k) usable = usable && std::fabs(m[k]) <= kMaxDriverEntry;  // false for NaN
      if (usable) std::memcpy(&world[f][0][0], m, sizeof(float) * 16);
    }
  }

  // The drivers as they are, held (no motion), and the tails seeded at rest under them.
  void seedHeld(bool with_controls) {
    readFrames();
    currentPoses().read(driver_input.data(), previousPoses());
    holdPoses();
    integrator->seed(previousPoses(), currentPoses(), with_controls);
  }

  glm::vec3 windNow() const { return windAt(wind, static_cast<double>(wind_steps) * step_seconds); }

  bool beginFrame(double dt) {
    frame_steps = 0;
    if (!(dt > 0.0) || !std::isfinite(dt)) return false;
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
    // The drivers read, and tested for a jump in the same pass (the thresholds are per step, so
    // the frame's steps are counted first). A first frame only seeds: there is nothing to jump from.
    const bool was_seeded = seeded;
    bool drivers_jumped = false;
    readFrames();
    if (!seeded) {
      seedHeld(/*with_controls=*/true);
      seeded = true;
    } else {
      drivers_jumped = currentPoses().read(driver_input.data(), previousPoses(),
                                           jumpLimits(frame_steps, options.jump_distance, options.jump_angle));
    }
    if (was_seeded && (jump_requested || drivers_jumped)) {
      // Every chain carried with the jump of the driver it hangs from, and every driver's last
      // pose with its own, so the frame's steps interpolate only the motion: the chain keeps its
      // shape and its motion relative to that driver, and the jump adds no velocity.
      jump_carry.prepare(olderPoses(), previousPoses(), currentPoses());
      integrator->carryAcrossJump(jump_carry);
      previousPoses().read(jump_carry.carriedPoses(), olderPoses());
      ++jump_count;
    }
    jump_requested = false;
    integrator->beginFrame(previousPoses(), currentPoses());
    return true;
  }

  // Step i of the frame, with the wind at the simulated time of its start; `queue`: see
  // SpringIntegrator::step.
  SpringLanes* runStep(int i, bool queue) {
    // Where this step falls inside the frame, for driver interpolation.
    const double h = step_seconds;
    const double at = frame_dropped ? double(i + 1) / frame_steps : ((i + 1) * h - frame_start) / frame_dt;
    const glm::vec3 pull = windNow();
    ++wind_steps;
    const StepDrivers drivers{previousPoses(), currentPoses(), static_cast<float>(std::clamp(at, 0.0, 1.0)), i == 0};
    return integrator->step(drivers, static_cast<float>(h), pull, queue);
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
  s.step_seconds = 1.0 / options.step_hz;

  const std::size_t joints = s.rig->joints.size();
  const std::size_t drivers = s.rig->drivers.size();
  s.driver_input.resize(16 * drivers);
  for (DriverPoses& poses : s.poses) poses.resize(drivers);
  s.jump_carry.resize(drivers);
  // Until the caller writes them, drivers sit at their rest world matrices.
  for (std::size_t d = 0; d < drivers; ++d) {
    const int node = s.rig->drivers[d].node;  // -1: an avatar bone outside the GLB
    const Mat4 rest = node >= 0 ? s.rig->skeleton.nodes[node].rest_world : Mat4{};
    std::memcpy(s.driver_input.data() + 16 * d, rest.m, sizeof rest.m);
  }
  s.world_output.resize(16 * joints);
  s.settle_rotations.resize(4 * joints);
  s.integrator = makeIntegrator(s.rig, options);
  s.options.inertia = kDefaultInertia;
  setInertia(options.inertia, -1);
}

Instance::~Instance() = default;

float* Instance::driverMatrices() { return state_->driver_input.data(); }

std::vector<Warning> Instance::setColliders(const ColliderOptions& options) {
  State& s = *state_;
  std::vector<Warning> warnings;
  ColliderSet set = resolveColliders(*s.rig, options, warnings);
  s.frame_input.assign(16 * set.frame_rest.size(), 0.0f);
  for (std::size_t f = 0; f < set.frame_rest.size(); ++f)
    std::memcpy(s.frame_input.data() + 16 * f, set.frame_rest[f].m, sizeof(float) * 16);
  s.integrator->setColliders(std::move(set));
  return warnings;
}

const std::vector<std::string>& Instance::frameNames() const { return state_->integrator->colliders().frame_names; }
float* Instance::frameMatrices() { return state_->frame_input.data(); }
std::size_t Instance::driverCount() const { return state_->rig->drivers.size(); }
const float* Instance::rotations() const { return state_->integrator->rotations(); }
std::size_t Instance::jointCount() const { return state_->rig->joints.size(); }
const Rig& Instance::rig() const { return *state_->rig; }
const InstanceOptions& Instance::options() const { return state_->options; }

const float* Instance::worldMatrices() const {
  state_->integrator->writeWorldMatrices(state_->world_output.data());
  return state_->world_output.data();
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
  SpringIntegrator& integrator = *s.integrator;
  seconds = std::isnan(seconds) ? 0.0 : std::clamp(seconds, 0.0, kMaxSettleSeconds);
  // The tolerance keeps 2 s at 60 Hz at 120 steps despite rounding in the product.
  const int most = static_cast<int>(std::ceil(seconds * s.options.step_hz - 1e-6));
  // Put at rest under the drivers as they are, which become the last frame's too (no motion).
  s.seedHeld(/*with_controls=*/true);
  s.seeded = true;
  s.accumulator = 0.0;
  s.jump_requested = false;
  if (s.rig->joints.empty()) return 0;
  const glm::vec3 pull = s.windNow();
  if (most > 0) integrator.balance(s.currentPoses(), pull);
  // Steps with no velocity under the held drivers: each moves the tails by what still pulls them
  // off their balance (colliders, a grab), and never overshoots it as a swing would.
  const StepDrivers held{s.previousPoses(), s.currentPoses(), 1.0f, true};
  const float h = static_cast<float>(s.step_seconds);
  const std::size_t floats = s.settle_rotations.size();
  int steps = 0;
  while (steps < most) {
    std::memcpy(s.settle_rotations.data(), integrator.rotations(), floats * sizeof(float));
    integrator.holdTails();
    integrator.step(held, h, pull, /*queue=*/false);
    ++steps;
    float turn = 0.0f;
    for (std::size_t j = 0; j < floats / 4; ++j) {
      turn = std::max(turn, halfTurnSine(s.settle_rotations.data() + 4 * j, integrator.rotations() + 4 * j));
    }
    if (!(turn > 0.5f * kSettledTurn)) break;
  }
  integrator.holdTails();
  return steps;
}

void Instance::grab(std::size_t joint, const Vec3& point) {
  MotionControls& controls = state_->integrator->controls();
  if (joint >= state_->rig->joints.size() || !isFinite(toGlm(point))) return;
  controls.grab_point = toGlm(point);
  if (controls.grab_joint != static_cast<int>(joint)) {
    controls.held.hold(*state_->rig, joint);
    controls.grab_joint = static_cast<int>(joint);
  }
  controls.held.active = true;
}

void Instance::release() {
  MotionControls& controls = state_->integrator->controls();
  controls.held.letGo();
  controls.grab_joint = -1;
}

int Instance::grabbedJoint() const { return state_->integrator->controls().grab_joint; }

void Instance::setInertia(float value, int chain) {
  MotionControls& controls = state_->integrator->controls();
  std::vector<float>& inertia = controls.chain_inertia;
  if (chain >= static_cast<int>(inertia.size())) return;
  value = std::isnan(value) ? kDefaultInertia : std::clamp(value, 0.0f, 1.0f);
  if (chain < 0) {
    std::fill(inertia.begin(), inertia.end(), value);
    state_->options.inertia = value;
  } else {
    inertia[chain] = value;
  }
  controls.inertia_active = std::any_of(inertia.begin(), inertia.end(), [](float k) { return k < 1.0f; });
}

float Instance::inertia(std::size_t chain) const {
  const std::vector<float>& inertia = state_->integrator->controls().chain_inertia;
  return chain < inertia.size() ? inertia[chain] : kDefaultInertia;
}
int Instance::jumps() const { return state_->jump_count; }

void Instance::setJumpThresholds(float distance, float angle) {
  if (!std::isnan(distance)) state_->options.jump_distance = jumpThreshold(distance);
  if (!std::isnan(angle)) state_->options.jump_angle = jumpThreshold(angle);
}

void Instance::step(double dt) {
  State& s = *state_;
  if (!s.beginFrame(dt)) return;
  for (int i = 0; i < s.frame_steps; ++i) s.runStep(i, /*queue=*/false);
  s.endFrame();
}

void Instance::stepAll(Instance* const* instances, std::size_t count, double dt) {
  // beginFrame refuses a dt for every instance or for none.
  bool stepping = false;
  int most_steps = 0;
  for (std::size_t n = 0; n < count; ++n) {
    State& s = *instances[n]->state_;
    if (!s.beginFrame(dt)) continue;
    stepping = true;
    most_steps = std::max(most_steps, s.frame_steps);
  }
  if (!stepping) return;
  // Step i of every instance that has one: the lane integrators queue their copies in their rigs'
  // pools, the others step at once; then each pool runs its queue in as few runs as the copies
  // allow (the first instance of a pool runs it, the others find it empty).
  for (int i = 0; i < most_steps; ++i) {
    for (std::size_t n = 0; n < count; ++n) {
      State& s = *instances[n]->state_;
      s.queued = i < s.frame_steps ? s.runStep(i, /*queue=*/true) : nullptr;
    }
    for (std::size_t n = 0; n < count; ++n) {
      SpringLanes* pool = instances[n]->state_->queued;
      if (pool) pool->runQueued();
    }
  }
  for (std::size_t n = 0; n < count; ++n) instances[n]->state_->endFrame();
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

  SpringIntegrator& integrator = *s.integrator;
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
    s.seedHeld(/*with_controls=*/false);
    if (pass == 0) {
      earlier_rest.resize(rig.joints.size());
      glm::vec3 unused;
      for (std::size_t j = 0; j < rig.joints.size(); ++j) integrator.tailState(j, earlier_rest[j], unused);
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
    if (node >= 0 && static_cast<std::size_t>(node) < old_joint_of_node.size())
      old_joint_of_node[node] = static_cast<int>(j);
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
      integrator.tailState(j, now, unused);
      const glm::vec3 before = now - (now - earlier_rest[j]) * per_step;
      if (std::isfinite(before.x + before.y + before.z)) integrator.setTailState(j, now, before);
      continue;
    }
    glm::vec3 now, before;
    from.integrator->tailState(static_cast<std::size_t>(o), now, before);
    const std::string* old_center = driverName(old_rig, old_joint->center_driver);
    const std::string* new_center = driverName(rig, joint.center_driver);
    const bool same_center =
        old_center == nullptr ? new_center == nullptr : new_center != nullptr && *old_center == *new_center;
    if (!same_center) {
      // Through world space: the old center as it last stepped, the new one as just read.
      glm::mat4 to_world(1.0f), to_center(1.0f);
      if (old_joint->center_driver >= 0)
        to_world = from.previousPoses().matrix(static_cast<std::size_t>(old_joint->center_driver));
      if (joint.center_driver >= 0) {
        glm::mat4 inverse;
        if (affineInverse(s.currentPoses().matrix(static_cast<std::size_t>(joint.center_driver)), inverse))
          to_center = inverse;
      }
      now = glm::vec3(to_center * (to_world * glm::vec4(now, 1.0f)));
      before = glm::vec3(to_center * (to_world * glm::vec4(before, 1.0f)));
    }
    if (!std::isfinite(now.x + now.y + now.z + before.x + before.y + before.z)) continue;  // keep the rest seed
    integrator.setTailState(j, now, before);
    std::memcpy(integrator.rotations() + 4 * j, from.integrator->rotations() + 4 * static_cast<std::size_t>(o),
                4 * sizeof(float));
  }
}

}  // namespace springbones
