#include "simulation/rig_constants.h"

#include <algorithm>

#include "common/transform_math.h"
#include "simulation/joint_limits.h"
#include "simulation/spring_lanes.h"

namespace springbones {
namespace {

constexpr float kMinLength = 1e-6f;

}  // namespace

RigConstants::RigConstants(const Rig& r) : rig(r) {
  const std::size_t joints = rig.joints.size();
  rest_local_matrix.resize(joints);
  tail_axis.resize(joints);
  tail_distance.resize(joints);
  limit_local.assign(joints, glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  joint_chain.assign(joints, -1);
  lanes_usable = rig.colliders.size() <= kMaxLaneColliders;
  const auto& roots = rig.chain_roots;
  for (std::size_t j = 0; j < joints; ++j) {
    const Joint& joint = rig.joints[j];
    rest_local_matrix[j] = composeTransform(joint.rest_local);
    const glm::vec3 tail_local = toGlm(joint.tail_local);
    const float len = glm::length(tail_local);
    tail_distance[j] = len;
    tail_axis[j] = len > kMinLength ? tail_local / len : glm::vec3(0, 1, 0);
    const Vec3 scale = joint.rest_local.scale;
    if (!(scale.x > 0.0f) || scale.y != scale.x || scale.z != scale.x) lanes_usable = false;
    if (joint.limit.kind != JointLimit::Kind::kNone) {
      limit_local[j] = limitFrameLocal(tail_axis[j], joint.limit.rotation);
      lanes_usable = false;
    }
    for (std::size_t k = 1; k < joint.colliders.size(); ++k) {
      if (joint.colliders[k] <= joint.colliders[k - 1]) lanes_usable = false;  // repeated or out of order
    }
    const auto found = std::find(roots.begin(), roots.end(), joint.chain);
    if (found != roots.end()) joint_chain[j] = static_cast<int>(found - roots.begin());
    const int c = joint.center_driver;
    if (c >= 0 && static_cast<std::size_t>(c) < rig.drivers.size() &&
        std::find(center_drivers.begin(), center_drivers.end(), c) == center_drivers.end()) {
      center_drivers.push_back(c);
    }
  }
}

std::shared_ptr<const RigConstants> RigConstants::acquire(const std::shared_ptr<const Rig>& rig) {
  // This rig's: a copied Rig carries the original's reference, to the constants of another rig.
  if (std::shared_ptr<const RigConstants> constants = rig->constants.lock(); constants && constants->owner == rig) {
    return constants;
  }
  // Not make_shared: its single allocation would outlive the constants for as long as a weak_ptr
  // does. The rig forgets them when they die, so nothing of them stays allocated while it lives on.
  std::shared_ptr<RigConstants> made(new RigConstants(*rig), [](RigConstants* dying) {
    dying->owner->constants.reset();
    delete dying;
  });
  made->owner = rig;
  rig->constants = made;
  return made;
}

}  // namespace springbones
