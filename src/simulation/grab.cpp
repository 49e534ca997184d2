#include "simulation/grab.h"

#include <cmath>

#include "common/transform_math.h"

namespace springbones {

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
