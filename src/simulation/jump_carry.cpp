#include "simulation/jump_carry.h"

#include <cstring>

#include "common/transform_math.h"

namespace springbones {

void JumpCarry::resize(std::size_t drivers) {
  delta_.resize(drivers);
  from_.resize(drivers);
  carried_to_.resize(drivers);
  valid_.assign(drivers, 0);
  carried_.resize(16 * drivers);
}

void JumpCarry::prepare(const DriverPoses& older, const DriverPoses& from, const DriverPoses& to) {
  for (std::size_t d = 0; d < to.size(); ++d) {
    const glm::mat4 m_from = from.matrix(d);
    glm::mat4 inverse_older, inverse_expected, inverse_from;
    const glm::mat4 expected = affineInverse(older.matrix(d), inverse_older) ? m_from * inverse_older * m_from : m_from;
    delta_[d] = affineInverse(expected, inverse_expected) ? to.matrix(d) * inverse_expected : glm::mat4(1.0f);
    const glm::mat4 carried = delta_[d] * m_from;
    valid_[d] = affineInverse(carried, carried_to_[d]) && affineInverse(m_from, inverse_from) ? 1 : 0;
    from_[d] = m_from;
    std::memcpy(carried_.data() + 16 * d, &carried[0][0], sizeof(float) * 16);
  }
}

glm::vec3 JumpCarry::carry(const glm::vec3& stored, int carrier, int center) const {
  const bool in_center = center >= 0 && valid_[center];
  glm::vec3 world = in_center ? glm::vec3(from_[center] * glm::vec4(stored, 1.0f)) : stored;
  if (carrier >= 0) world = glm::vec3(delta_[carrier] * glm::vec4(world, 1.0f));
  const glm::vec3 out = in_center ? glm::vec3(carried_to_[center] * glm::vec4(world, 1.0f)) : world;
  return isFinite(out) ? out : stored;
}

}  // namespace springbones
