#include "simulation/collider_table.h"

namespace springbones {

void ColliderTable::resize(std::size_t colliders) {
  count = colliders;
  for (auto* v : {&x0, &y0, &z0, &x1, &y1, &z1, &radius}) v->assign(colliders, 0.0f);
}

void ColliderTable::set(std::size_t c, const glm::vec3& start, const glm::vec3& end, float r) {
  x0[c] = start.x;
  y0[c] = start.y;
  z0[c] = start.z;
  x1[c] = end.x;
  y1[c] = end.y;
  z1[c] = end.z;
  radius[c] = r;
}

}  // namespace springbones
