// The XPBD integrator (`integrator: 'xpbd'`): an alternative to the default VRM update, with the
// same parameters. See xpbd_solver.cpp for the method and how the parameters map onto it.
//
// The solver knows nothing about frames: the owner (Instance, through XpbdIntegrator) keeps the accumulator, caps the
// substeps, interpolates the driver matrices and calls step() once per fixed substep, exactly as
// it runs the default paths. The solver keeps the per-joint state (tails in center space) and
// writes the same outputs as the default: a local rotation per joint and the joint world matrices.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "common/glm_interop.h"
#include "simulation/collider_kind.h"
#include "simulation/collider_set.h"
#include "simulation/rig_constants.h"

namespace springbones {

struct ColliderTable;  // spring_lanes.h
struct HeldJoints;     // grab.h

/// The substep rate the XPBD integrator is meant to run at (docs/xpbd.md): its default step rate
/// (integratorDefaults in springbones.h).
inline constexpr double kXpbdDefaultStepHz = integratorDefaults(Integrator::kXpbd).step_hz;

struct XpbdOptions {
  /// The step rate the VRM parameters are defined at: the default integrator's 60 Hz. Drag and the
  /// impulse sizes are converted from "per step of 1/reference_hz" to per second with it, so the
  /// motion does not change with the substep rate. [1, 1000]
  double reference_hz = 60.0;
  /// Gauss-Seidel passes over a joint's constraints per substep (XPBD designs use 2-4). [1, 64]
  /// Passes after the first run only while a collider pushes the tail: without contact the
  /// first pass is already the exact solution (xpbd_solver.cpp).
  int iterations = kDefaultXpbdIterations;
};

/// One collider in world space for one substep: the segment start..end (start == end for a
/// sphere) and the radius, already scaled by its driver; for a plane a point of it and its unit
/// normal (moveTailByCollider's arguments).
struct XpbdCollider {
  glm::vec3 start{0.0f};
  glm::vec3 end{0.0f};
  float radius = 0.0f;
  ColliderKind kind = ColliderKind::kOutside;
};

class XpbdSolver {
 public:
  /// Steps the rig of `constants` (RigConstants::acquire: shared with the rig's other instances).
  explicit XpbdSolver(std::shared_ptr<const RigConstants> constants, const XpbdOptions& options = {});
  /// Keeps a reference to `rig`, which must outlive the solver, and derives its constants alone.
  explicit XpbdSolver(const Rig& rig, const XpbdOptions& options = {});

  /// Puts every tail at its rest direction and length under `driver_world` (one matrix per rig
  /// driver) with no velocity, and writes the rest pose: `rotations_out` gets x, y, z, w per
  /// joint, `joint_world_out` one matrix per joint.
  void seed(const glm::mat4* driver_world, float* rotations_out, glm::mat4* joint_world_out);

  /// Advances every joint by one substep of h seconds (h > 0) under this substep's driver matrices
  /// and world colliders (`colliders[c]` for rig collider c; indices >= collider_count are
  /// skipped), writing the same outputs as seed(). Allocates nothing.
  void step(const glm::mat4* driver_world, const XpbdCollider* colliders, std::size_t collider_count, float h,
            float* rotations_out, glm::mat4* joint_world_out);
  /// Same, reading the colliders from the Instance's ColliderTable (the table of the default
  /// paths, filled by MatrixDrivers::prepare).
  void step(const glm::mat4* driver_world, const ColliderTable& colliders, float h, float* rotations_out,
            glm::mat4* joint_world_out);

  /// The wind's pull for the following steps (windAt, world space): a force on every tail like
  /// gravityPower x gravityDir.
  void setWind(const glm::vec3& pull) { wind_ = pull; }

  /// The joints a grab holds (Instance::grab), read by every step until set again; null: none.
  /// The holder owns it and keeps it alive while set.
  void setHeld(const HeldJoints* held) { held_ = held; }

  /// The colliders the joints meet (an instance's, collider_set.h), read by every step until set
  /// again: their kinds and which joint meets which; the holder keeps it alive while set, and sets
  /// it again after it changes. Null: the rig's own (Joint::colliders, Rig::colliders).
  void setColliders(const ColliderSet* colliders);

  /// World position of a joint's tail particle after the last seed/step (tests, reports).
  glm::vec3 tailWorld(std::size_t joint) const { return tail_world_[joint]; }
  /// A joint's tail state: the current and previous tail particle, in the joint's center space.
  /// Read and rewritten when the owner carries the chains across a jump of the drivers.
  void tailState(std::size_t joint, glm::vec3& current, glm::vec3& previous) const {
    current = current_tail_[joint];
    previous = previous_tail_[joint];
  }
  void setTailState(std::size_t joint, const glm::vec3& current, const glm::vec3& previous) {
    current_tail_[joint] = current;
    previous_tail_[joint] = previous;
  }
  std::size_t jointCount() const { return rig_.joints.size(); }
  const XpbdOptions& options() const { return options_; }

 private:
  void prepareCenters(const glm::mat4* driver_world);
  void prepareRates(float h);
  glm::vec3 toCenter(int center, const glm::vec3& world) const;
  glm::vec3 fromCenter(int center, const glm::vec3& local, const glm::mat4* driver_world) const;
  void solveJoint(std::size_t j, const glm::vec3& head, const glm::vec3& rest_offset, float length, float h,
                  const XpbdCollider* colliders, std::size_t collider_count, const glm::quat& limit_frame,
                  glm::vec3& x) const;
  void writeOutputs(std::size_t j, const glm::mat4& parent, const glm::mat3& rest_linear, const glm::vec3& offset,
                    float* rotations_out, glm::mat4* joint_world_out) const;

  std::shared_ptr<const RigConstants> constants_;
  const Rig& rig_;
  XpbdOptions options_;
  double reference_step_ = 1.0 / 60.0;

  // Per joint, for the current substep length (recomputed when h changes).
  float rates_h_ = -1.0f;
  std::vector<float> keep_;  // velocity kept per substep, (1 - drag)^(h / h0)
  glm::vec3 wind_{0.0f};
  std::vector<float> inverse_mass_;  // w of the tail in the solve, finite even at drag 1

  // Per joint, simulation state.
  std::vector<glm::vec3> current_tail_, previous_tail_;  // center space
  std::vector<glm::vec3> tail_world_;

  // Per driver, this substep: the inverse of every center driver (others untouched).
  std::vector<glm::mat4> center_inverse_;
  std::vector<unsigned char> center_inverse_valid_;

  const HeldJoints* held_ = nullptr;        // setHeld
  const ColliderSet* colliders_ = nullptr;  // setColliders

  // Colliders of the current step (the ColliderTable overload copies into it).
  std::vector<XpbdCollider> collider_scratch_;
};

}  // namespace springbones
