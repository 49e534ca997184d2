#include "simulation/matrix_drivers.h"

#include "common/transform_math.h"
#include "simulation/driver_poses.h"

namespace springbones {

MatrixDrivers::MatrixDrivers(const Rig& rig, const ColliderSet& colliders, const std::vector<glm::mat4>& frames)
    : rig_(rig), set_(colliders), frames_(frames) {
  const std::size_t drivers = rig.drivers.size();
  matrices_.resize(drivers);
  inverses_.resize(drivers);
  last_.resize(drivers);
  inverse_valid_.assign(drivers, 0);
  colliders_.resize(set_.colliders.size());
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
    inverse_valid_[d] = affineInverse(matrices_[d], inverse) ? 1 : 0;
    if (inverse_valid_[d]) inverses_[d] = inverse;
  }
  prepareColliders();
}

// Each collider carried by its driver's matrix this step, or by its frame's (colliderInWorld).
void MatrixDrivers::prepareColliders() {
  const auto& all = set_.colliders;
  const std::size_t drivers = matrices_.size();
  for (std::size_t c = 0; c < all.size(); ++c) {
    const Collider& collider = all[c];
    const std::size_t d = static_cast<std::size_t>(collider.driver);
    const glm::mat4& m = d < drivers ? matrices_[d] : frames_[d - drivers];
    glm::vec3 start, end;
    float radius;
    colliderInWorld(collider, m, start, end, radius);
    colliders_.set(c, start, end, radius);
  }
}

}  // namespace springbones
