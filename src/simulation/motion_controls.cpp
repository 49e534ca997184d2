#include "simulation/motion_controls.h"

#include <cstddef>

#include "common/transform_math.h"
#include "simulation/driver_poses.h"

namespace springbones {
namespace {

constexpr float kMinLength = 1e-6f;

}  // namespace

// With no velocity, a step of either integrator leaves a tail in place exactly when the sum of its
// pulls points along the bone: the VRM update adds stiffness x rest direction, gravity and wind
// to the tail before the length constraint, and XPBD's bend constraint (compliance L / stiffness)
// balances gravity and wind at that same direction. Of the two directions along the pull, the
// stable one points with it.
void balanceTails(const Rig& rig, const DriverPoses& poses, const glm::mat4* rest_local_matrix,
                  const glm::vec3* tail_axis, const float* tail_distance, const glm::vec3& wind_pull,
                  glm::mat4* joint_world, glm::vec3* stored_tails, float* rotations) {
  const glm::mat4 identity(1.0f);
  for (std::size_t j = 0; j < rig.joints.size(); ++j) {
    const Joint& joint = rig.joints[j];
    const glm::mat4 parent = joint.parent_joint >= 0    ? joint_world[joint.parent_joint]
                             : joint.parent_driver >= 0 ? poses.matrix(joint.parent_driver)
                                                        : identity;
    const glm::mat4 rest_world = parent * rest_local_matrix[j];
    const glm::mat3 rest_linear(rest_world);
    const glm::vec3 head(rest_world[3]);
    const glm::vec3 rest_offset = rest_linear * toGlm(joint.tail_local);
    const float length = glm::length(rest_offset);
    glm::vec3 tail = head + rest_offset;
    glm::quat rotation = toGlm(joint.rest_local.rotation);
    glm::vec3 pull(0.0f);
    if (length > kMinLength && tail_distance[j] > kMinLength) {
      pull = rest_offset * (joint.params.stiffness / length) +
             toGlm(joint.params.gravity_dir) * joint.params.gravity_power + wind_pull;
    }
    if (toUnitLength(pull)) {
      tail = head + pull * length;
      // The rest rotation turned so its tail axis points at the tail (the step's own rule).
      glm::vec3 local = glm::inverse(rest_linear) * (tail - head);
      if (!toUnitLength(local)) local = tail_axis[j];
      rotation = glm::normalize(rotation * rotationBetween(tail_axis[j], local));
    }
    joint_world[j] =
        parent * composeTransform(toGlm(joint.rest_local.translation), rotation, toGlm(joint.rest_local.scale));
    storeQuat(rotations + 4 * j, rotation);
    glm::mat4 center_inverse;
    stored_tails[j] = joint.center_driver >= 0 && affineInverse(poses.matrix(joint.center_driver), center_inverse)
                          ? glm::vec3(center_inverse * glm::vec4(tail, 1.0f))
                          : tail;
  }
}

void carryInertia(const Rig& rig, const int* joint_chain, const float* chain_inertia, const glm::mat4* last_drivers,
                  const glm::mat4* drivers, glm::vec3* current, glm::vec3* previous) {
  const auto& joints = rig.joints;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const int chain = joint_chain[j];
    const float keep = chain >= 0 ? chain_inertia[chain] : kDefaultInertia;
    const int carrier = joints[joints[j].chain].parent_driver, center = joints[j].center_driver;
    if (!(keep < 1.0f) || carrier < 0) continue;
    glm::mat4 before = last_drivers[carrier], now = drivers[carrier];
    if (center >= 0 && (last_drivers[center] != drivers[center] || before != now)) {
      glm::mat4 before_inverse, now_inverse;
      if (affineInverse(last_drivers[center], before_inverse) && affineInverse(drivers[center], now_inverse)) {
        before = before_inverse * before;
        now = now_inverse * now;
      }
    }
    if (before == now) continue;  // no motion (settle, a still avatar): nothing to carry
    const Transform a = decomposeTransform(before), b = decomposeTransform(now);
    const float t = 1.0f - keep;
    glm::quat rotation;
    nlerpRotation(a.rotation.x, a.rotation.y, a.rotation.z, a.rotation.w, b.rotation.x, b.rotation.y, b.rotation.z,
                  b.rotation.w, t, rotation.x, rotation.y, rotation.z, rotation.w);
    const glm::mat4 part = composeTransform(glm::mix(toGlm(a.translation), toGlm(b.translation), t), rotation,
                                            glm::mix(toGlm(a.scale), toGlm(b.scale), t));
    glm::mat4 before_inverse;
    if (!affineInverse(before, before_inverse)) continue;
    // Into the driver's space, then out of the carried pose: two products rather than one
    // (part x before^-1), whose translation would be a difference of metres-sized terms.
    const glm::vec3 carried_now(part * (before_inverse * glm::vec4(current[j], 1.0f)));
    const glm::vec3 carried_before(part * (before_inverse * glm::vec4(previous[j], 1.0f)));
    if (!isFinite(carried_now) || !isFinite(carried_before)) continue;
    current[j] = carried_now;
    previous[j] = carried_before;
  }
}

}  // namespace springbones
