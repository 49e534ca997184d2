// The bound both rig builders hold a collider to (kMaxColliderSize): beyond it the squared
// distances overflow in float and the collider would move nothing, so such a collider is refused
// with a warning rather than left to do nothing silently.
#pragma once

#include <cmath>

#include "springbones/springbones.h"

namespace springbones {

/// A radius, an offset or (a capsule's) tail component beyond kMaxColliderSize.
inline bool exceedsMaxColliderSize(const ColliderShape& c) {
  const auto beyond = [](const Vec3& v) {
    return std::fabs(v.x) > kMaxColliderSize || std::fabs(v.y) > kMaxColliderSize || std::fabs(v.z) > kMaxColliderSize;
  };
  return c.radius > kMaxColliderSize || beyond(c.offset) ||
         (c.shape == ColliderShape::Shape::kCapsule && beyond(c.tail));
}

}  // namespace springbones
