#include "simulation/matrix_drivers.h"

#include <algorithm>

#include "common/transform_math.h"
#include "simulation/driver_poses.h"

namespace springbones {

MatrixDrivers::MatrixDrivers(const Rig& rig) : rig_(rig) {
  const std::size_t drivers = rig.drivers.size();
  matrices_.resize(drivers);
  inverses_.resize(drivers);
  last_.resize(drivers);
  inverse_valid_.assign(drivers, false);
  colliders_.resize(rig.colliders.size());
}

void MatrixDrivers::prepare(const StepDrivers& drivers, bool keep_last) {
  const std::size_t count = matrices_.size();
  if (keep_last) {
    for (std::size_t d = 0; d < count; ++d) last_[d] = drivers.first ? drivers.from.matrix(d) : matrices_[d];
  }
  for (std::size_t d = 0; d < count; ++d) {
    if (drivers.t >= 1.0f) {
      matrices_[d] = drivers.to.matrix(d);
    } else {
      // Rotations as the lane path interpolates them (nlerpRotation).
      const Transform a = drivers.from.transform(d), b = drivers.to.transform(d);
      glm::quat rotation;
      nlerpRotation(a.rotation.x, a.rotation.y, a.rotation.z, a.rotation.w, b.rotation.x, b.rotation.y, b.rotation.z,
                    b.rotation.w, drivers.t, rotation.x, rotation.y, rotation.z, rotation.w);
      matrices_[d] = composeTransform(glm::mix(toGlm(a.translation), toGlm(b.translation), drivers.t), rotation,
                                      glm::mix(toGlm(a.scale), toGlm(b.scale), drivers.t));
    }
    glm::mat4 inverse;
    inverse_valid_[d] = affineInverse(matrices_[d], inverse);
    if (inverse_valid_[d]) inverses_[d] = inverse;
  }
  prepareColliders();
}

// The radius scales by the largest axis scale of the driver. A plane's normal turns with the
// driver's inverse transpose (perpendicular to the plane under any scale), then is made unit; a
// singular driver leaves it NaN, and a NaN normal moves no tail.
void MatrixDrivers::prepareColliders() {
  const auto& all = rig_.colliders;
  for (std::size_t c = 0; c < all.size(); ++c) {
    const Collider& collider = all[c];
    const bool plane = collider.shape == Collider::Shape::kPlane;
    const glm::mat4& m = matrices_[collider.driver];
    const glm::vec3 start = glm::vec3(m * glm::vec4(toGlm(collider.offset), 1.0f));
    const glm::vec3 end = plane ? glm::normalize(glm::transpose(glm::inverse(glm::mat3(m))) * toGlm(collider.normal))
                                : glm::vec3(m * glm::vec4(toGlm(collider.tail), 1.0f));
    const float scale =
        std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
    colliders_.set(c, start, end, plane ? 0.0f : collider.radius * scale);
  }
}

}  // namespace springbones
