// The spring-bone step.
//
// Where the update comes from: it is the VRM family's per-joint update (UniVRM's VRMSpringBone,
// credited there to @ricopin416; the VRMC_springBone 1.0 specification; @pixiv/three-vrm): Verlet
// inertia reduced by drag, an impulse toward the rest direction scaled by stiffness, a gravity
// impulse, then the tail is put back at the bone's length and the joint is turned to point at it.
// See DESIGN.md section 5. Our own choices on top of it:
//  - Fixed steps. In that update inertia and drag act once per update while stiffness and gravity
//    scale with dt, so the motion depends on the update rate. We therefore always step at a fixed
//    rate (stepHz) with an accumulator, run at most maxSubsteps steps per frame and drop the rest
//    (a hitch or a hidden tab must not explode), and interpolate the driver matrices across the
//    substeps of a frame. The same motion then comes out at 30, 60 or 144 fps.
//  - Bone lengths are measured under the current parent transform (the rest tail offset carried
//    by the parent's world matrix), never from the previous frame's child position, and all
//    positions are world-space: a 0.01-scaled armature behaves like an unscaled one.
//  - The rest direction and the new rotation use the full parent world matrix, so non-uniform
//    scale in the hierarchy does not skew the bone.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "springbones.h"
#include "transform_math.h"

namespace springbones {
namespace {

constexpr double kMinStepHz = 1.0;
constexpr double kMaxStepHz = 1000.0;
constexpr int kMaxSubstepsLimit = 64;
constexpr float kMinLength = 1e-6f;

// A driver's world matrix split for interpolation between two frames.
struct DriverPose {
  Transform trs;
  glm::mat4 matrix{1.0f};
};

bool isFiniteMatrix(const float* m) {
  for (int i = 0; i < 16; ++i) {
    if (!std::isfinite(m[i])) return false;
  }
  return true;
}

// Inverse of an affine matrix, or false when it has no usable inverse (a zero scale).
bool affineInverse(const glm::mat4& m, glm::mat4& out) {
  const glm::mat3 linear(m);
  const float det = glm::determinant(linear);
  if (!(std::fabs(det) > 1e-18f) || !std::isfinite(det)) return false;
  const glm::mat3 inv = glm::inverse(linear);
  out = glm::mat4(inv);
  out[3] = glm::vec4(-(inv * glm::vec3(m[3])), 1.0f);
  return true;
}

glm::mat4 interpolate(const DriverPose& a, const DriverPose& b, float t) {
  if (t >= 1.0f) return b.matrix;
  Transform r;
  r.translation = glm::mix(a.trs.translation, b.trs.translation, t);
  r.rotation = glm::slerp(a.trs.rotation, b.trs.rotation, t);
  r.scale = glm::mix(a.trs.scale, b.trs.scale, t);
  return composeTransform(r);
}

}  // namespace

struct Instance::State {
  std::shared_ptr<const Rig> rig;
  InstanceOptions options;
  double step_seconds = 1.0 / 60.0;
  double accumulator = 0.0;
  bool seeded = false;

  // Rig-derived constants, per joint.
  std::vector<glm::vec3> tail_axis;  // unit tail direction in the joint's local space

  // Inputs, per driver.
  std::vector<float> driver_input;  // what the caller writes, 16 floats per driver
  std::vector<DriverPose> previous_drivers, current_drivers;
  std::vector<glm::mat4> step_drivers, step_driver_inverses;
  std::vector<bool> step_inverse_valid;

  // Simulation state, per joint.
  std::vector<glm::vec3> current_tail, previous_tail;  // in the joint's center space
  std::vector<glm::mat4> joint_world;
  std::vector<float> rotations;  // output, x y z w per joint

  void readDrivers() {
    const std::size_t count = rig->drivers.size();
    for (std::size_t d = 0; d < count; ++d) {
      const float* m = driver_input.data() + 16 * d;
      // A non-finite matrix is ignored: the driver keeps its last good pose.
      if (!isFiniteMatrix(m)) continue;
      glm::mat4 matrix;
      std::memcpy(&matrix[0][0], m, sizeof(float) * 16);
      current_drivers[d].matrix = matrix;
      current_drivers[d].trs = decomposeTransform(matrix);
    }
  }

  void prepareDrivers(float t) {
    for (std::size_t d = 0; d < current_drivers.size(); ++d) {
      step_drivers[d] = interpolate(previous_drivers[d], current_drivers[d], t);
      glm::mat4 inverse;
      if (affineInverse(step_drivers[d], inverse)) {
        step_driver_inverses[d] = inverse;
        step_inverse_valid[d] = true;
      } else {
        step_inverse_valid[d] = false;
      }
    }
  }

  const glm::mat4& parentWorld(const Joint& joint) const {
    static const glm::mat4 kIdentity(1.0f);
    if (joint.parent_joint >= 0) return joint_world[joint.parent_joint];
    if (joint.parent_driver >= 0) return step_drivers[joint.parent_driver];
    return kIdentity;
  }

  // A center whose matrix cannot be inverted this step is treated as world space for the step.
  bool centerSpace(const Joint& joint) const {
    return joint.center_driver >= 0 && step_inverse_valid[joint.center_driver];
  }

  glm::vec3 toCenter(const Joint& joint, const glm::vec3& world) const {
    if (!centerSpace(joint)) return world;
    return glm::vec3(step_driver_inverses[joint.center_driver] * glm::vec4(world, 1.0f));
  }

  glm::vec3 fromCenter(const Joint& joint, const glm::vec3& local) const {
    if (!centerSpace(joint)) return local;
    return glm::vec3(step_drivers[joint.center_driver] * glm::vec4(local, 1.0f));
  }

  void writeRotation(std::size_t j, const glm::quat& q) {
    float* out = rotations.data() + 4 * j;
    out[0] = q.x;
    out[1] = q.y;
    out[2] = q.z;
    out[3] = q.w;
  }

  // Every tail at its rest direction and length under the current drivers, zero velocity.
  void seed() {
    const auto& joints = rig->joints;
    for (std::size_t j = 0; j < joints.size(); ++j) {
      const Joint& joint = joints[j];
      joint_world[j] = parentWorld(joint) * composeTransform(joint.rest_local);
      const glm::vec3 tail = glm::vec3(joint_world[j] * glm::vec4(joint.tail_local, 1.0f));
      current_tail[j] = previous_tail[j] = toCenter(joint, tail);
      writeRotation(j, joint.rest_local.rotation);
    }
  }

  void simulate(float h) {
    const auto& joints = rig->joints;
    for (std::size_t j = 0; j < joints.size(); ++j) {
      const Joint& joint = joints[j];
      const BoneParams& p = joint.params;
      const glm::mat4& parent = parentWorld(joint);
      const glm::mat4 rest_world = parent * composeTransform(joint.rest_local);
      const glm::vec3 head(rest_world[3]);
      const glm::mat3 rest_linear(rest_world);
      const glm::vec3 rest_offset = rest_linear * joint.tail_local;
      const float length = glm::length(rest_offset);
      if (!(length > kMinLength) || !(glm::length(joint.tail_local) > kMinLength)) {
        joint_world[j] = rest_world;
        writeRotation(j, joint.rest_local.rotation);
        continue;
      }
      const glm::vec3 rest_dir = rest_offset / length;

      // Inertia in center space, then back to world for the impulses.
      const glm::vec3 current = current_tail[j];
      const glm::vec3 inertia = (current - previous_tail[j]) * (1.0f - p.drag);
      glm::vec3 next = fromCenter(joint, current + inertia);
      next += rest_dir * (p.stiffness * h);
      next += p.gravity_dir * (p.gravity_power * h);

      // Bone length: back onto the sphere of the rest length around the head.
      glm::vec3 offset = next - head;
      const float offset_length = glm::length(offset);
      offset = offset_length > kMinLength && std::isfinite(offset_length)
                   ? offset * (length / offset_length)
                   : rest_offset;  // tail on the head (or lost): restart from rest
      next = head + offset;

      previous_tail[j] = current;
      current_tail[j] = toCenter(joint, next);

      // Turn the joint so its rest axis points at the new tail, in the joint's rest local frame.
      glm::vec3 local_dir = glm::inverse(rest_linear) * offset;
      const float local_length = glm::length(local_dir);
      local_dir = local_length > 0.0f && std::isfinite(local_length) ? local_dir / local_length
                                                                     : tail_axis[j];
      const glm::quat rotation =
          glm::normalize(joint.rest_local.rotation * rotationBetween(tail_axis[j], local_dir));
      Transform local = joint.rest_local;
      local.rotation = rotation;
      joint_world[j] = parent * composeTransform(local);
      writeRotation(j, rotation);
    }
  }
};

Instance::Instance(std::shared_ptr<const Rig> rig, InstanceOptions options)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  if (!rig) rig = std::make_shared<const Rig>();
  s.rig = std::move(rig);
  if (!(options.step_hz >= kMinStepHz)) options.step_hz = options.step_hz > 0 ? kMinStepHz : 60.0;
  options.step_hz = std::min(options.step_hz, kMaxStepHz);
  options.max_substeps = std::clamp(options.max_substeps, 1, kMaxSubstepsLimit);
  s.options = options;
  s.step_seconds = 1.0 / options.step_hz;

  const std::size_t joints = s.rig->joints.size();
  const std::size_t drivers = s.rig->drivers.size();
  s.tail_axis.resize(joints);
  for (std::size_t j = 0; j < joints; ++j) {
    const glm::vec3 t = s.rig->joints[j].tail_local;
    const float len = glm::length(t);
    s.tail_axis[j] = len > kMinLength ? t / len : glm::vec3(0, 1, 0);
  }
  s.driver_input.resize(16 * drivers);
  s.previous_drivers.resize(drivers);
  s.current_drivers.resize(drivers);
  s.step_drivers.resize(drivers);
  s.step_driver_inverses.resize(drivers);
  s.step_inverse_valid.assign(drivers, false);
  // Until the caller writes them, drivers sit at their rest world matrices.
  for (std::size_t d = 0; d < drivers; ++d) {
    const glm::mat4& rest = s.rig->skeleton.nodes[s.rig->drivers[d].node].rest_world;
    std::memcpy(s.driver_input.data() + 16 * d, &rest[0][0], sizeof(float) * 16);
  }
  s.current_tail.resize(joints);
  s.previous_tail.resize(joints);
  s.joint_world.resize(joints);
  s.rotations.resize(4 * joints);
  for (std::size_t j = 0; j < joints; ++j) {
    s.writeRotation(j, s.rig->joints[j].rest_local.rotation);
    s.joint_world[j] = s.rig->skeleton.nodes[s.rig->joints[j].node].rest_world;
  }
}

Instance::~Instance() = default;

float* Instance::driverMatrices() { return state_->driver_input.data(); }
std::size_t Instance::driverCount() const { return state_->rig->drivers.size(); }
const float* Instance::rotations() const { return state_->rotations.data(); }
const float* Instance::worldMatrices() const {
  return state_->joint_world.empty() ? nullptr : &state_->joint_world[0][0][0];
}
std::size_t Instance::jointCount() const { return state_->rig->joints.size(); }
const Rig& Instance::rig() const { return *state_->rig; }
const InstanceOptions& Instance::options() const { return state_->options; }

void Instance::reset() {
  state_->seeded = false;
  state_->accumulator = 0.0;
}

void Instance::step(double dt) {
  State& s = *state_;
  if (!(dt > 0.0) || !std::isfinite(dt)) return;
  s.readDrivers();
  if (!s.seeded) {
    s.previous_drivers = s.current_drivers;
    s.prepareDrivers(1.0f);
    s.seed();
    s.seeded = true;
  }

  // Steps fall where the accumulated time crosses a multiple of h. The tolerance keeps a stream
  // of frames of exactly 1/stepHz at one step each despite rounding in the sum.
  const double h = s.step_seconds;
  const double tolerance = h * 1e-6;
  const double start = s.accumulator;
  s.accumulator += dt;
  int steps = static_cast<int>(std::floor((s.accumulator + tolerance) / h));
  const bool dropped = steps > s.options.max_substeps;
  if (dropped) steps = s.options.max_substeps;
  for (int i = 0; i < steps; ++i) {
    // Where this step falls inside the frame, for driver interpolation.
    const double at = dropped ? double(i + 1) / steps : ((i + 1) * h - start) / dt;
    s.prepareDrivers(static_cast<float>(std::clamp(at, 0.0, 1.0)));
    s.simulate(static_cast<float>(h));
  }
  s.accumulator = dropped ? 0.0 : std::max(0.0, s.accumulator - steps * h);
  s.previous_drivers = s.current_drivers;
}

}  // namespace springbones
