// Scene: one call steps every avatar of a page, optionally only the nearest ones.
#include <algorithm>
#include <cmath>

#include "common/glm_interop.h"
#include "springbones/springbones.h"

namespace springbones {

std::size_t Scene::add(Instance* instance) {
  auto it = std::find(members_.begin(), members_.end(), instance);
  if (it != members_.end()) return static_cast<std::size_t>(it - members_.begin());
  // Every allocation first, then the changes that cannot fail: a failed add (out of memory)
  // leaves the scene as it was, its lists the same length (remove and step rely on that).
  const std::size_t count = members_.size() + 1;
  members_.reserve(count);
  positions_.reserve(3 * count);
  active_.reserve(count);
  by_distance_.reserve(count);
  stepping_.reserve(count);
  members_.push_back(instance);
  if (has_wind_) instance->setWind(wind_);
  positions_.resize(3 * count, 0.0f);
  active_.push_back(1);
  return count - 1;
}

void Scene::remove(Instance* instance) {
  auto it = std::find(members_.begin(), members_.end(), instance);
  if (it == members_.end()) return;
  const std::size_t slot = static_cast<std::size_t>(it - members_.begin());
  members_.erase(it);
  positions_.erase(positions_.begin() + 3 * slot, positions_.begin() + 3 * slot + 3);
  active_.erase(active_.begin() + slot);
}

void Scene::setBudget(int max_active, const Vec3& viewer) {
  max_active_ = max_active;
  if (std::isfinite(viewer.x) && std::isfinite(viewer.y) && std::isfinite(viewer.z)) viewer_ = viewer;
}

void Scene::setWind(const Wind& wind) {
  has_wind_ = true;
  wind_ = wind;
  for (Instance* instance : members_) instance->setWind(wind);
}

void Scene::step(double dt) {
  const std::size_t count = members_.size();
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    Instance::stepAll(members_.data(), count, dt);  // steps nothing; each one's lastSteps() is 0
    return;
  }
  stepping_.clear();
  if (max_active_ < 0 || static_cast<std::size_t>(max_active_) >= count) {
    for (std::size_t i = 0; i < count; ++i) {
      if (!active_[i]) members_[i]->reset();  // back in the budget: start from rest
      active_[i] = 1;
      stepping_.push_back(members_[i]);
    }
    Instance::stepAll(stepping_.data(), stepping_.size(), dt);
    return;
  }
  // Nearest first; an avatar at a non-finite position sorts last. Squared distances in double:
  // in float they overflow beyond 1.8e19 and underflow below 1e-19, and every such avatar would
  // tie with the others.
  by_distance_.clear();
  const glm::dvec3 viewer(toGlm(viewer_));
  for (std::size_t i = 0; i < count; ++i) {
    const glm::dvec3 p(positions_[3 * i], positions_[3 * i + 1], positions_[3 * i + 2]);
    const glm::dvec3 to_viewer = p - viewer;
    double d = glm::dot(to_viewer, to_viewer);
    if (!std::isfinite(d)) d = INFINITY;
    by_distance_.emplace_back(d, i);
  }
  const std::size_t budget = static_cast<std::size_t>(max_active_);
  std::nth_element(by_distance_.begin(), by_distance_.begin() + budget, by_distance_.end());
  std::vector<unsigned char>& next = active_;
  for (std::size_t rank = 0; rank < count; ++rank) {
    const std::size_t i = by_distance_[rank].second;
    const bool wanted = rank < budget;
    if (wanted && !next[i]) members_[i]->reset();
    next[i] = wanted ? 1 : 0;
    if (wanted) {
      stepping_.push_back(members_[i]);
    } else {
      members_[i]->step(0.0);  // a frame of no time: holds the pose, and lastSteps() says 0
    }
  }
  Instance::stepAll(stepping_.data(), stepping_.size(), dt);
}

}  // namespace springbones
