// The integrator interface: what an Instance steps its joints with. Three implementations, one a
// file: the general VRM path on full matrices (general_integrator.*), the same update on the
// rig's lanes with the general path as its fallback (lane_integrator.*), and XPBD
// (xpbd_integrator.*). An instance holds one, chosen when it is made (springbones.h, Integrator;
// the lanes when the rig allows them, RigConstants::lanes_usable).
//
// The per-frame path is hot, so the interface is coarse: one virtual call per frame
// (beginFrame) and one per step (step), never one per joint. The per-joint calls (tailState,
// setTailState) serve the rare operations only: jumps, settle, carryFrom.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "common/glm_interop.h"
#include "simulation/collider_set.h"
#include "simulation/grab.h"
#include "simulation/rig_constants.h"

namespace springbones {

class DriverPoses;
class JumpCarry;
class SpringLanes;

/// A step's drivers: at fraction t of the way from one frame's poses to the next.
struct StepDrivers {
  const DriverPoses& from;
  const DriverPoses& to;
  float t;
  /// The first step of a frame: the step before ran under `from` (inertia reads it).
  bool first;
};

/// What the caller asks of the motion besides the drivers (Instance::grab, Instance::setInertia),
/// read by the integrator on every step. Sized with the rig, so that neither grabbing nor stepping
/// allocates.
struct MotionControls {
  HeldJoints held;
  int grab_joint = -1;
  glm::vec3 grab_point{0.0f};
  std::vector<float> chain_inertia;  ///< per chain, Rig::chain_roots order
  bool inertia_active = false;       ///< a chain's inertia is below 1 (motion_controls.h)

  /// Grab and inertia run on the general path (and XPBD), never on the lanes.
  bool needsGeneralPath() const { return held.active || inertia_active; }
};

class SpringIntegrator {
 public:
  virtual ~SpringIntegrator();
  SpringIntegrator(const SpringIntegrator&) = delete;
  SpringIntegrator& operator=(const SpringIntegrator&) = delete;

  /// Puts every tail at rest with no velocity under `current` (the same pose as `previous`: a
  /// held pose) and writes the rest pose. `with_controls`: a grab or inertia keeps the seed off
  /// the lanes (false: carryFrom's seed, which chooses the path by the drivers alone).
  virtual void seed(const DriverPoses& previous, const DriverPoses& current, bool with_controls) = 0;
  /// Before a frame's steps, its drivers read (and carried across a jump): the lane integrator
  /// chooses the frame's path here and moves its tail state there.
  virtual void beginFrame(const DriverPoses& previous, const DriverPoses& current) = 0;
  /// One step of h seconds under `drivers`, with the wind's pull (world, per second: windAt).
  /// With `queue`, an integrator that runs in a pool shared by several instances queues its step
  /// there and returns the pool, which the caller runs (SpringLanes::runQueued) once every
  /// instance has queued; otherwise it steps now and returns null.
  virtual SpringLanes* step(const StepDrivers& drivers, float h, const glm::vec3& wind_pull, bool queue) = 0;
  /// settle's start: every tail where its pulls balance under `poses`, parents first, with no
  /// velocity (balanceTails, motion_controls.h); the rotations and world matrices follow.
  virtual void balance(const DriverPoses& poses, const glm::vec3& wind_pull) = 0;

  /// A joint's tail state: the current and previous tail, in the joint's center space.
  virtual void tailState(std::size_t joint, glm::vec3& current, glm::vec3& previous) const = 0;
  virtual void setTailState(std::size_t joint, const glm::vec3& current, const glm::vec3& previous) = 0;

  /// The joints' world matrices after the last step, 16 floats (column-major) per joint.
  virtual void writeWorldMatrices(float* out) const;

  /// Replaces the colliders from the next step on (Instance::setColliders): the frames start at
  /// their rest matrices. Allocates; the steps after it do not.
  virtual void setColliders(ColliderSet colliders);
  const ColliderSet& colliders() const { return colliders_; }
  /// The world matrices of the collider set's frames this frame, written by the instance.
  std::vector<glm::mat4>& frameWorld() { return frame_world_; }

  /// Every tail's velocity set to zero (settle): the previous tail put on the current one.
  void holdTails();
  /// Carries every chain across a jump of the drivers (jump_carry.h): the tails (current and
  /// previous, so the velocity too) move with the jump of the driver their chain hangs from.
  void carryAcrossJump(const JumpCarry& carry);

  /// Local rotations, x y z w per joint: the rest pose until the first seed.
  const float* rotations() const { return rotations_.data(); }
  float* rotations() { return rotations_.data(); }
  MotionControls& controls() { return controls_; }
  const MotionControls& controls() const { return controls_; }

 protected:
  explicit SpringIntegrator(std::shared_ptr<const RigConstants> constants);

  void writeRotation(std::size_t j, const glm::quat& q) { storeQuat(rotations_.data() + 4 * j, q); }

  std::shared_ptr<const RigConstants> constants_;
  const Rig& rig_;
  std::vector<float> rotations_;
  /// The joints' world matrices on the matrix paths (the general path, XPBD, settle's balance).
  std::vector<glm::mat4> joint_world_;
  MotionControls controls_;
  /// The colliders the tails meet (the rig's until setColliders), and their frames' matrices.
  ColliderSet colliders_;
  std::vector<glm::mat4> frame_world_;
};

}  // namespace springbones
