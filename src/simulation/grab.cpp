#include "simulation/grab.h"

#include <algorithm>
#include <cmath>

#include "common/transform_math.h"

namespace springbones {

void HeldJoints::hold(const Rig& rig, std::size_t joint) {
  const auto& joints = rig.joints;
  for (int j : path) slot[j] = -1;
  path.clear();
  anchor.clear();
  // From the grabbed joint up to its chain root (a parent joint always comes first in the rig, so
  // this ends), then turned root first.
  for (int j = static_cast<int>(joint); j >= 0 && path.size() < joints.size(); j = joints[j].parent_joint) {
    anchor.push_back(path.empty() ? toGlm(joints[j].tail_local) : toGlm(joints[path.back()].rest_local.translation));
    path.push_back(j);
  }
  std::reverse(path.begin(), path.end());
  std::reverse(anchor.begin(), anchor.end());
  reach.assign(path.size(), glm::vec3(0.0f));
  for (std::size_t k = 0; k < path.size(); ++k) slot[path[k]] = static_cast<int>(k);
}

void HeldJoints::letGo() {
  for (int j : path) slot[j] = -1;
  path.clear();
  active = false;
}

glm::vec3 HeldJoints::tail(std::size_t k, const glm::vec3& head, const glm::mat3& rest_linear,
                           const glm::vec3& rest_offset, const glm::vec3& fallback) const {
  glm::vec3 from = rest_linear * anchor[k];
  glm::vec3 to = reach[k] - head;
  if (!toUnitLength(from) || !toUnitLength(to)) return fallback;
  const glm::vec3 out = head + rotationBetween(from, to) * rest_offset;
  return isFinite(out) ? out : fallback;
}

void HeldJoints::prepare(const glm::vec3& point, const glm::mat4* joint_world) {
  glm::vec3 aim = point;
  for (std::size_t k = path.size(); k-- > 0;) {
    reach[k] = aim;
    const glm::mat4& world = joint_world[path[k]];
    const glm::vec3 head(world[3]);
    const float length = glm::length(glm::mat3(world) * anchor[k]);
    glm::vec3 back = head - aim;
    aim = toUnitLength(back) && std::isfinite(length) ? aim + back * length : head;
  }
}

}  // namespace springbones
