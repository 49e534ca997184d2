#include "loading/collider_from_spec.h"

#include <cmath>
#include <string>

#include "common/shown_name.h"
#include "common/transform_math.h"
#include "loading/collider_size.h"

namespace springbones {

bool colliderFromSpec(const ColliderSpec& spec, Collider& out, std::vector<Warning>& warnings) {
  const auto warn = [&](std::string message) {
    warnings.push_back(Warning{"collider-invalid", std::move(message), ""});
    return false;
  };
  const bool plane = spec.shape == Collider::Shape::kPlane;
  const bool finite = isFinite(toGlm(spec.offset)) && isFinite(toGlm(spec.tail)) &&
                      (!plane || isFinite(toGlm(spec.normal))) && std::isfinite(spec.radius);
  if (!finite || spec.radius < 0.0f) {
    return warn("collider on '" + shownName(spec.node) + "' has a non-finite or negative size; ignored");
  }
  if (exceedsMaxColliderSize(spec)) {
    return warn("collider on '" + shownName(spec.node) + "' has a radius, offset or tail beyond " +
                std::to_string(static_cast<long>(kMaxColliderSize)) + " (the node's units); ignored");
  }
  glm::vec3 normal = toGlm(spec.normal);
  if (plane && !toUnitLength(normal)) {
    return warn("plane collider on '" + shownName(spec.node) + "' has a zero normal; ignored");
  }
  out = Collider{};
  static_cast<ColliderShape&>(out) = spec;
  out.inside = spec.inside && !plane;
  if (spec.shape != Collider::Shape::kCapsule) out.tail = spec.offset;
  out.normal = plane ? fromGlm(normal) : Vec3{0.0f, 0.0f, 1.0f};
  if (plane) out.radius = 0.0f;
  return true;
}

}  // namespace springbones
