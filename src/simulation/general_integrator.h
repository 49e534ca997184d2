// The general VRM path: the VRM spring-bone update on full matrices, one joint after the other,
// parents first. It steps every rig and every driver (shear, non-uniform scale, angle limits,
// grabs, inertia); the lane integrator (lane_integrator.h) runs it whenever the lanes cannot.
#pragma once

#include <vector>

#include "simulation/matrix_drivers.h"
#include "simulation/spring_integrator.h"

namespace springbones {

class GeneralIntegrator : public SpringIntegrator {
 public:
  explicit GeneralIntegrator(std::shared_ptr<const RigConstants> constants);

  void seed(const DriverPoses& previous, const DriverPoses& current, bool with_controls) override;
  void beginFrame(const DriverPoses&, const DriverPoses&) override {}
  SpringLanes* step(const StepDrivers& drivers, float h, const glm::vec3& wind_pull, bool queue) override;
  void balance(const DriverPoses& poses, const glm::vec3& wind_pull) override;
  void setColliders(ColliderSet colliders) override;
  void tailState(std::size_t joint, glm::vec3& current, glm::vec3& previous) const override {
    current = current_tail_[joint];
    previous = previous_tail_[joint];
  }
  void setTailState(std::size_t joint, const glm::vec3& current, const glm::vec3& previous) override {
    current_tail_[joint] = current;
    previous_tail_[joint] = previous;
  }

 protected:
  struct SpringInput;

  // The joints, parents first: seeded at rest (seed_only) or advanced by one step of h seconds.
  void run(float h, bool seed_only);
  glm::vec3 integrate(std::size_t j, const Joint& joint, const SpringInput& in, float h);
  glm::vec3 collide(const Joint& joint, const SpringInput& in, glm::vec3 tail, int passes) const;
  glm::quat aimedRotation(std::size_t j, const Joint& joint, glm::vec3 local_dir) const;

  MatrixDrivers drivers_;
  std::vector<glm::vec3> current_tail_, previous_tail_;  // in the joint's center space
  glm::vec3 step_wind_{0.0f};                            // this step's wind: its pull times h
};

}  // namespace springbones
