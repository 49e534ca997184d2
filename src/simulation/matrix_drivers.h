// A step's drivers as full matrices, for the integrators that step on matrices (the general VRM
// path and XPBD): each driver interpolated between two frames' poses, its inverse (a center's
// space), the colliders in world space, and the drivers of the step before (inertia).
#pragma once

#include <algorithm>
#include <vector>

#include "common/glm_interop.h"
#include "simulation/collider_set.h"
#include "simulation/spring_integrator.h"
#include "simulation/spring_lanes.h"

namespace springbones {

/// A collider carried by world matrix `m`: its segment (a sphere's a point) and world radius, or
/// for a plane a point and unit normal. The radius scales by the largest axis scale of `m`; a
/// plane's normal turns with its inverse transpose (perpendicular to the plane under any scale),
/// then is made unit: a singular `m` leaves it NaN, and a NaN normal moves no tail.
inline void colliderInWorld(const Collider& collider, const glm::mat4& m, glm::vec3& start, glm::vec3& end,
                            float& radius) {
  const bool plane = collider.shape == Collider::Shape::kPlane;
  start = glm::vec3(m * glm::vec4(toGlm(collider.offset), 1.0f));
  end = plane ? glm::normalize(glm::transpose(glm::inverse(glm::mat3(m))) * toGlm(collider.normal))
              : glm::vec3(m * glm::vec4(toGlm(collider.tail), 1.0f));
  const float scale =
      std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
  radius = plane ? 0.0f : collider.radius * scale;
}

class MatrixDrivers {
 public:
  /// `colliders` and `frames` (the world matrices of its frames) belong to the integrator, which
  /// outlives this.
  MatrixDrivers(const Rig& rig, const ColliderSet& colliders, const std::vector<glm::mat4>& frames);

  /// After the collider set changed: the world colliders' table sized to it.
  void resizeColliders() { colliders_.resize(set_.colliders.size()); }

  /// This step's drivers and colliders. `keep_last`: first keep the drivers of the step before
  /// (the frame's first step: `drivers.from`'s).
  void prepare(const StepDrivers& drivers, bool keep_last);

  const glm::mat4* matrices() const { return matrices_.data(); }
  const glm::mat4* lastMatrices() const { return last_.data(); }
  const ColliderTable& colliders() const { return colliders_; }

  /// A world point into driver `center`'s space this step (-1, or a center without an inverse
  /// this step: world space), and back.
  glm::vec3 toCenter(int center, const glm::vec3& world) const {
    if (center < 0 || !inverse_valid_[center]) return world;
    return glm::vec3(inverses_[center] * glm::vec4(world, 1.0f));
  }
  glm::vec3 fromCenter(int center, const glm::vec3& local) const {
    if (center < 0 || !inverse_valid_[center]) return local;
    return glm::vec3(matrices_[center] * glm::vec4(local, 1.0f));
  }

 private:
  void prepareColliders();

  const Rig& rig_;
  const ColliderSet& set_;
  const std::vector<glm::mat4>& frames_;
  std::vector<glm::mat4> matrices_, inverses_, last_;
  std::vector<unsigned char> inverse_valid_;
  ColliderTable colliders_;
};

}  // namespace springbones
