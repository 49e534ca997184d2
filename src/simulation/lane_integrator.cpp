#include "simulation/lane_integrator.h"

#include <cstring>

#include "simulation/driver_poses.h"
#include "simulation/spring_lanes.h"

// The rare paths (a change of path, the world matrices on request) stay calls: inlined at -O3
// they cost the module kilobytes, and a call is nothing beside a step.
#if defined(__GNUC__)
#define SPRINGBONES_NOINLINE __attribute__((noinline))
#else
#define SPRINGBONES_NOINLINE
#endif

namespace springbones {
namespace {

// A rotation, translation and uniform scale.
struct Similarity {
  glm::vec3 position{0.0f};
  float scale = 1.0f;
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};

  glm::vec3 apply(const glm::vec3& p) const { return position + scale * (rotation * p); }
  glm::mat4 matrix() const {
    glm::mat4 m = glm::mat4_cast(rotation);
    m[0] *= scale;
    m[1] *= scale;
    m[2] *= scale;
    m[3] = glm::vec4(position, 1.0f);
    return m;
  }
};

Similarity jointWorldOf(const SpringLanes& lanes, std::size_t copy, std::size_t joint) {
  Similarity world;
  lanes.jointWorld(copy, joint, world.position, world.rotation, world.scale);
  return world;
}

}  // namespace

LaneIntegrator::LaneIntegrator(std::shared_ptr<const RigConstants> constants)
    : GeneralIntegrator(std::move(constants)), lanes_(SpringLanes::acquire(constants_)) {
  copy_ = lanes_->addCopy(rotations_.data());
}

LaneIntegrator::~LaneIntegrator() { lanes_->releaseCopy(copy_); }

void LaneIntegrator::seed(const DriverPoses& previous, const DriverPoses& current, bool with_controls) {
  on_lanes_ = colliders_fit_ && previous.allSimilar() && current.allSimilar() &&
              !(with_controls && controls_.needsGeneralPath());
  tails_in_lanes_ = world_from_lanes_ = on_lanes_;
  if (!on_lanes_) {
    GeneralIntegrator::seed(previous, current, with_controls);
    return;
  }
  DriverPoses::blend(previous, current, 1.0f, lanes_->drivers(), lanes_->driverIndex(copy_, 0), lanes_->driverStride());
  prepareColliders();
  const CopyRange own{copy_, copy_ + 1};
  lanes_->run(&own, 1, 0.0f, /*seed=*/true);
}

void LaneIntegrator::beginFrame(const DriverPoses& previous, const DriverPoses& current) {
  on_lanes_ = colliders_fit_ && previous.allSimilar() && current.allSimilar() && !controls_.needsGeneralPath();
  if (tails_in_lanes_ != on_lanes_) moveTailState();
}

SpringLanes* LaneIntegrator::step(const StepDrivers& drivers, float h, const glm::vec3& wind_pull, bool queue) {
  world_from_lanes_ = on_lanes_;
  if (!on_lanes_) return GeneralIntegrator::step(drivers, h, wind_pull, queue);
  DriverPoses::blend(drivers.from, drivers.to, drivers.t, lanes_->drivers(), lanes_->driverIndex(copy_, 0),
                     lanes_->driverStride());
  prepareColliders();
  lanes_->setWind(copy_, wind_pull * h);
  if (queue) {
    lanes_->queueStep(copy_, h);
    return lanes_.get();
  }
  const CopyRange own{copy_, copy_ + 1};
  lanes_->run(&own, 1, h, /*seed=*/false);
  return nullptr;
}

void LaneIntegrator::balance(const DriverPoses& poses, const glm::vec3& wind_pull) {
  GeneralIntegrator::balance(poses, wind_pull);  // the general path's arrays are its scratch
  if (tails_in_lanes_) {
    for (std::size_t j = 0; j < current_tail_.size(); ++j)
      lanes_->setTailState(copy_, j, current_tail_[j], current_tail_[j]);
  }
  world_from_lanes_ = false;
}

void LaneIntegrator::tailState(std::size_t joint, glm::vec3& current, glm::vec3& previous) const {
  if (tails_in_lanes_) {
    lanes_->tailState(copy_, joint, current, previous);
  } else {
    GeneralIntegrator::tailState(joint, current, previous);
  }
}

void LaneIntegrator::setTailState(std::size_t joint, const glm::vec3& current, const glm::vec3& previous) {
  if (tails_in_lanes_) {
    lanes_->setTailState(copy_, joint, current, previous);
  } else {
    GeneralIntegrator::setTailState(joint, current, previous);
  }
}

SPRINGBONES_NOINLINE void LaneIntegrator::writeWorldMatrices(float* out) const {
  if (!world_from_lanes_) {
    GeneralIntegrator::writeWorldMatrices(out);
    return;
  }
  for (std::size_t j = 0; j < joint_world_.size(); ++j) {
    const glm::mat4 m = jointWorldOf(*lanes_, copy_, j).matrix();
    std::memcpy(out + 16 * j, &m[0][0], sizeof(float) * 16);
  }
}

// Moves the tail state to the path this frame takes, with the joints' world transforms a grab
// starts from.
SPRINGBONES_NOINLINE void LaneIntegrator::moveTailState() {
  for (std::size_t j = 0; j < current_tail_.size(); ++j) {
    if (on_lanes_) {
      lanes_->setTailState(copy_, j, current_tail_[j], previous_tail_[j]);
    } else {
      lanes_->tailState(copy_, j, current_tail_[j], previous_tail_[j]);
      joint_world_[j] = jointWorldOf(*lanes_, copy_, j).matrix();
    }
  }
  tails_in_lanes_ = on_lanes_;
}

SPRINGBONES_NOINLINE void LaneIntegrator::setColliders(ColliderSet colliders) {
  GeneralIntegrator::setColliders(std::move(colliders));
  const ColliderSet& set = colliders_;
  colliders_fit_ = set.colliders.size() == rig_.colliders.size() && set.passes == rig_.collider_passes;
  for (std::size_t c = 0; colliders_fit_ && c < set.colliders.size(); ++c)
    colliders_fit_ = colliderKind(set.colliders[c]) == colliderKind(rig_.colliders[c]);
  for (std::size_t j = 0; colliders_fit_ && j < rig_.joints.size(); ++j)
    colliders_fit_ = set.of(rig_.joints[j]) == rig_.joints[j].colliders;
}

// Colliders in world space for this step, each carried by its driver's similarity: the radius
// scales with it, a plane's normal turns with it; or by its frame's matrix (colliderInWorld).
void LaneIntegrator::prepareColliders() {
  const auto& all = colliders_.colliders;
  const std::size_t drivers = rig_.drivers.size();
  const DriverTable& table = lanes_->drivers();
  ColliderTable& colliders = lanes_->colliders();
  for (std::size_t c = 0; c < all.size(); ++c) {
    const Collider& collider = all[c];
    const std::size_t d = static_cast<std::size_t>(collider.driver);
    if (d >= drivers) {
      glm::vec3 start, end;
      float radius;
      colliderInWorld(collider, frame_world_[d - drivers], start, end, radius);
      colliders.set(lanes_->colliderIndex(copy_, c), start, end, radius);
      continue;
    }
    const bool plane = collider.shape == Collider::Shape::kPlane;
    const std::size_t slot = lanes_->driverIndex(copy_, d);
    Similarity m;
    m.position = glm::vec3(table.px[slot], table.py[slot], table.pz[slot]);
    m.rotation = glm::quat(table.qw[slot], table.qx[slot], table.qy[slot], table.qz[slot]);
    m.scale = table.s[slot];
    const glm::vec3 start = m.apply(toGlm(collider.offset));
    const glm::vec3 end = plane ? glm::normalize(m.rotation * toGlm(collider.normal)) : m.apply(toGlm(collider.tail));
    colliders.set(lanes_->colliderIndex(copy_, c), start, end, plane ? 0.0f : collider.radius * m.scale);
  }
}

}  // namespace springbones
