// The XPBD integrator behind the integrator interface: the solver (xpbd_solver.h) stepped on the
// matrix drivers the general path uses too, with grab, inertia, wind and settle as the general
// path has them.
#pragma once

#include <vector>

#include "simulation/matrix_drivers.h"
#include "simulation/spring_integrator.h"
#include "simulation/xpbd_solver.h"

namespace springbones {

class XpbdIntegrator final : public SpringIntegrator {
 public:
  XpbdIntegrator(std::shared_ptr<const RigConstants> constants, const XpbdOptions& options);

  void seed(const DriverPoses& previous, const DriverPoses& current, bool with_controls) override;
  void beginFrame(const DriverPoses&, const DriverPoses&) override {}
  SpringLanes* step(const StepDrivers& drivers, float h, const glm::vec3& wind_pull, bool queue) override;
  void balance(const DriverPoses& poses, const glm::vec3& wind_pull) override;
  void setColliders(ColliderSet colliders) override;
  void tailState(std::size_t joint, glm::vec3& current, glm::vec3& previous) const override {
    solver_.tailState(joint, current, previous);
  }
  void setTailState(std::size_t joint, const glm::vec3& current, const glm::vec3& previous) override {
    solver_.setTailState(joint, current, previous);
  }

 private:
  XpbdSolver solver_;
  MatrixDrivers drivers_;
  // The tails in the form inertia and settle's balance write them (motion_controls.h).
  std::vector<glm::vec3> current_tail_, previous_tail_;
};

}  // namespace springbones
