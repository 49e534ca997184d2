#include "simulation/spring_integrator.h"

#include <cstring>

#include "simulation/jump_carry.h"

namespace springbones {

SpringIntegrator::SpringIntegrator(std::shared_ptr<const RigConstants> constants)
    : constants_(std::move(constants)), rig_(constants_->rig), colliders_(ColliderSet::ofRig(rig_)) {
  const std::size_t joints = rig_.joints.size();
  rotations_.resize(4 * joints);
  joint_world_.resize(joints);
  for (std::size_t j = 0; j < joints; ++j) {
    writeRotation(j, toGlm(rig_.joints[j].rest_local.rotation));
    joint_world_[j] = toGlm(rig_.skeleton.nodes[rig_.joints[j].node].rest_world);
  }
  HeldJoints& held = controls_.held;
  held.slot.assign(joints, -1);
  held.path.reserve(joints);
  held.anchor.reserve(joints);
  held.reach.reserve(joints);
  controls_.chain_inertia.assign(rig_.chain_roots.size(), kDefaultInertia);
}

SpringIntegrator::~SpringIntegrator() = default;

void SpringIntegrator::writeWorldMatrices(float* out) const {
  for (std::size_t j = 0; j < joint_world_.size(); ++j)
    std::memcpy(out + 16 * j, &joint_world_[j][0][0], sizeof(float) * 16);
}

void SpringIntegrator::setColliders(ColliderSet colliders) {
  colliders_ = std::move(colliders);
  frame_world_.resize(colliders_.frame_rest.size());
  for (std::size_t f = 0; f < frame_world_.size(); ++f) frame_world_[f] = toGlm(colliders_.frame_rest[f]);
}

void SpringIntegrator::holdTails() {
  for (std::size_t j = 0; j < rig_.joints.size(); ++j) {
    glm::vec3 now, before;
    tailState(j, now, before);
    setTailState(j, now, now);
  }
}

void SpringIntegrator::carryAcrossJump(const JumpCarry& carry) {
  const auto& joints = rig_.joints;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const int carrier = joints[joints[j].chain].parent_driver, center = joints[j].center_driver;
    glm::vec3 now, before;
    tailState(j, now, before);
    setTailState(j, carry.carry(now, carrier, center), carry.carry(before, carrier, center));
  }
}

}  // namespace springbones
