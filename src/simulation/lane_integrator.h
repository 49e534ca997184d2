// The lane integrator: the VRM update on the rig's lanes (spring_lanes.h), one copy in the pool
// every instance of the rig shares, so that a scene steps all of them together. The lanes take
// similarities only (rotation, translation, uniform scale) and neither grab nor inertia; a frame
// whose drivers or controls they cannot take runs the general path it extends
// (general_integrator.h), and the tail state moves over when the path changes.
#pragma once

#include <memory>

#include "simulation/general_integrator.h"

namespace springbones {

class LaneIntegrator final : public GeneralIntegrator {
 public:
  /// `constants` must come from RigConstants::acquire (its rig is shared) and allow the lanes.
  explicit LaneIntegrator(std::shared_ptr<const RigConstants> constants);
  ~LaneIntegrator() override;

  void seed(const DriverPoses& previous, const DriverPoses& current, bool with_controls) override;
  void beginFrame(const DriverPoses& previous, const DriverPoses& current) override;
  SpringLanes* step(const StepDrivers& drivers, float h, const glm::vec3& wind_pull, bool queue) override;
  void balance(const DriverPoses& poses, const glm::vec3& wind_pull) override;
  void tailState(std::size_t joint, glm::vec3& current, glm::vec3& previous) const override;
  void setTailState(std::size_t joint, const glm::vec3& current, const glm::vec3& previous) override;
  void writeWorldMatrices(float* out) const override;
  /// Colliders that differ from the rig's in number, kind, passes or which joints meet them keep
  /// the instance on the general path: the lanes' collider kinds and masks are the rig's.
  void setColliders(ColliderSet colliders) override;

 private:
  void moveTailState();
  void prepareColliders();

  std::shared_ptr<SpringLanes> lanes_;
  std::size_t copy_ = 0;
  bool on_lanes_ = false;          // the path of the current frame's steps
  bool colliders_fit_ = true;      // the colliders are laid out as the rig's (setColliders)
  bool tails_in_lanes_ = false;    // where the tail state is: the lanes, or the general path's arrays
  bool world_from_lanes_ = false;  // where the joints' world transforms of the last step are
};

}  // namespace springbones
