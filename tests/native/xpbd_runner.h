// A minimal fixed-step owner for XpbdSolver, used by the XPBD tests
// until Instance takes `integrator: 'xpbd'`. It follows Instance::step's rules (src/simulation/instance.cpp):
// an accumulator, at most max_substeps substeps per frame with the surplus dropped, driver
// matrices interpolated across the substeps of a frame (decomposed, slerped, as the general path
// does), a non-finite driver matrix ignored, the first step seeding at rest. Only the substep
// rate and cap defaults differ: 120 Hz (kXpbdDefaultStepHz) and 8, so 15 fps frames still get all their
// time simulated.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "common/transform_math.h"
#include "simulation/xpbd_solver.h"
#include "springbones/springbones.h"

namespace springbones {
namespace test {

class XpbdRunner {
 public:
  explicit XpbdRunner(std::shared_ptr<const Rig> rig, double step_hz = kXpbdDefaultStepHz, int max_substeps = 8,
                      XpbdOptions options = {})
      : rig_(std::move(rig)), solver_(*rig_, options), step_seconds_(1.0 / step_hz), max_substeps_(max_substeps) {
    const std::size_t drivers = rig_->drivers.size();
    input_.resize(drivers);
    for (std::size_t d = 0; d < drivers; ++d) {
      const int node = rig_->drivers[d].node;
      input_[d] = node >= 0 ? toGlm(rig_->skeleton.nodes[node].rest_world) : glm::mat4(1.0f);
    }
    previous_ = current_ = step_drivers_ = input_;
    colliders_.resize(rig_->colliders.size());
    rotations_.resize(4 * rig_->joints.size());
    joint_world_.resize(rig_->joints.size());
    for (std::size_t j = 0; j < rig_->joints.size(); ++j) {
      const Quat& q = rig_->joints[j].rest_local.rotation;
      rotations_[4 * j] = q.x;
      rotations_[4 * j + 1] = q.y;
      rotations_[4 * j + 2] = q.z;
      rotations_[4 * j + 3] = q.w;
      joint_world_[j] = toGlm(rig_->skeleton.nodes[rig_->joints[j].node].rest_world);
    }
  }

  /// World matrix per driver, written by the caller before step().
  glm::mat4* drivers() { return input_.data(); }
  const float* rotations() const { return rotations_.data(); }
  const glm::mat4* worldMatrices() const { return joint_world_.data(); }
  const XpbdSolver& solver() const { return solver_; }
  const Rig& rig() const { return *rig_; }
  std::size_t jointCount() const { return rig_->joints.size(); }
  long long substepsRun() const { return substeps_run_; }

  void reset() {
    seeded_ = false;
    accumulator_ = 0.0;
  }

  void step(double dt) {
    if (!(dt > 0.0) || !std::isfinite(dt)) return;
    for (std::size_t d = 0; d < input_.size(); ++d) {
      if (isFiniteMatrix(input_[d])) current_[d] = input_[d];
    }
    if (!seeded_) {
      previous_ = current_;
      solver_.seed(current_.data(), rotations_.data(), joint_world_.data());
      seeded_ = true;
    }
    const double h = step_seconds_;
    const double tolerance = h * 1e-6;
    const double start = accumulator_;
    accumulator_ += dt;
    const double crossed = std::floor((accumulator_ + tolerance) / h);
    const bool dropped = crossed > max_substeps_;
    const int steps = dropped ? max_substeps_ : static_cast<int>(crossed);
    for (int i = 0; i < steps; ++i) {
      const double at = dropped ? double(i + 1) / steps : ((i + 1) * h - start) / dt;
      prepare(static_cast<float>(std::clamp(at, 0.0, 1.0)));
      solver_.step(step_drivers_.data(), colliders_.data(), colliders_.size(), static_cast<float>(h), rotations_.data(),
                   joint_world_.data());
      ++substeps_run_;
    }
    accumulator_ = dropped ? 0.0 : std::max(0.0, accumulator_ - steps * h);
    previous_ = current_;
  }

 private:
  static bool isFiniteMatrix(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) {
        if (!std::isfinite(m[c][r])) return false;
      }
    }
    return true;
  }

  void prepare(float t) {
    for (std::size_t d = 0; d < current_.size(); ++d) {
      if (t >= 1.0f) {
        step_drivers_[d] = current_[d];
        continue;
      }
      const Transform a = decomposeTransform(previous_[d]), b = decomposeTransform(current_[d]);
      Transform r;
      r.translation = fromGlm(glm::mix(toGlm(a.translation), toGlm(b.translation), t));
      r.rotation = fromGlm(glm::slerp(toGlm(a.rotation), toGlm(b.rotation), t));
      r.scale = fromGlm(glm::mix(toGlm(a.scale), toGlm(b.scale), t));
      step_drivers_[d] = composeTransform(r);
    }
    for (std::size_t c = 0; c < colliders_.size(); ++c) {
      const Collider& collider = rig_->colliders[c];
      const glm::mat4& m = step_drivers_[collider.driver];
      const float scale =
          std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
      colliders_[c].start = glm::vec3(m * glm::vec4(toGlm(collider.offset), 1.0f));
      colliders_[c].end = glm::vec3(m * glm::vec4(toGlm(collider.tail), 1.0f));
      colliders_[c].radius = collider.radius * scale;
    }
  }

  std::shared_ptr<const Rig> rig_;
  XpbdSolver solver_;
  double step_seconds_;
  int max_substeps_;
  double accumulator_ = 0.0;
  bool seeded_ = false;
  long long substeps_run_ = 0;
  std::vector<glm::mat4> input_, previous_, current_, step_drivers_;
  std::vector<XpbdCollider> colliders_;
  std::vector<float> rotations_;
  std::vector<glm::mat4> joint_world_;
};

}  // namespace test
}  // namespace springbones
