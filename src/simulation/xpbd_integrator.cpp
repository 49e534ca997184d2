#include "simulation/xpbd_integrator.h"

#include "simulation/motion_controls.h"

namespace springbones {

XpbdIntegrator::XpbdIntegrator(std::shared_ptr<const RigConstants> constants, const XpbdOptions& options)
    : SpringIntegrator(std::move(constants)), solver_(constants_, options), drivers_(rig_, colliders_, frame_world_) {
  current_tail_.resize(rig_.joints.size());
  previous_tail_.resize(rig_.joints.size());
  // The solver reads the grab from the controls on every step; an inactive one holds nothing.
  solver_.setHeld(&controls_.held);
  solver_.setColliders(&colliders_);
}

void XpbdIntegrator::setColliders(ColliderSet colliders) {
  SpringIntegrator::setColliders(std::move(colliders));
  drivers_.resizeColliders();
  solver_.setColliders(&colliders_);
}

void XpbdIntegrator::seed(const DriverPoses& previous, const DriverPoses& current, bool) {
  drivers_.prepare(StepDrivers{previous, current, 1.0f, true}, false);
  solver_.seed(drivers_.matrices(), rotations_.data(), joint_world_.data());
}

SpringLanes* XpbdIntegrator::step(const StepDrivers& drivers, float h, const glm::vec3& wind_pull, bool) {
  drivers_.prepare(drivers, controls_.inertia_active);
  solver_.setWind(wind_pull);
  if (controls_.inertia_active) {
    for (std::size_t j = 0; j < current_tail_.size(); ++j) solver_.tailState(j, current_tail_[j], previous_tail_[j]);
    carryInertia(rig_, constants_->joint_chain.data(), controls_.chain_inertia.data(), drivers_.lastMatrices(),
                 drivers_.matrices(), current_tail_.data(), previous_tail_.data());
    for (std::size_t j = 0; j < current_tail_.size(); ++j) solver_.setTailState(j, current_tail_[j], previous_tail_[j]);
  }
  if (controls_.held.active) controls_.held.prepare(controls_.grab_point, joint_world_.data());
  solver_.step(drivers_.matrices(), drivers_.colliders(), h, rotations_.data(), joint_world_.data());
  return nullptr;
}

void XpbdIntegrator::balance(const DriverPoses& poses, const glm::vec3& wind_pull) {
  const RigConstants& k = *constants_;
  balanceTails(rig_, poses, k.rest_local_matrix.data(), k.tail_axis.data(), k.tail_distance.data(), wind_pull,
               joint_world_.data(), current_tail_.data(), rotations_.data());
  for (std::size_t j = 0; j < current_tail_.size(); ++j) solver_.setTailState(j, current_tail_[j], current_tail_[j]);
}

}  // namespace springbones
