// A step's drivers as full matrices, for the integrators that step on matrices (the general VRM
// path and XPBD): each driver interpolated between two frames' poses, its inverse (a center's
// space), the colliders in world space, and the drivers of the step before (inertia).
#pragma once

#include <vector>

#include "common/glm_interop.h"
#include "simulation/spring_integrator.h"
#include "simulation/spring_lanes.h"

namespace springbones {

class MatrixDrivers {
 public:
  explicit MatrixDrivers(const Rig& rig);

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
  std::vector<glm::mat4> matrices_, inverses_, last_;
  std::vector<bool> inverse_valid_;
  ColliderTable colliders_;
};

}  // namespace springbones
