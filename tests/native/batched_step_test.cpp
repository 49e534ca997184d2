// Instance::stepAll and Scene::step run the lane-path instances of a rig through one kernel run
// per step. Every instance must come out bit for bit as if it had been stepped alone: a mixed crowd
// (three rigs, two step rates, centers, colliders, XPBD, a sheared driver on the general path, a
// freed and reused pool copy, a budget) is stepped both ways with the same inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using namespace test;

std::shared_ptr<const Rig> fixtureRig(const std::string& glb, const std::string& metadata,
                                      const RigOptions& options = {}) {
  Skeleton skeleton = loadFixtureSkeleton(glb);
  ModelEntry model;
  std::vector<Warning> warnings;
  EXPECT_FALSE(parseSpringBonesText(readFixtureText(metadata), metadataKeyOf(glb), model, warnings));
  return buildRig(std::move(skeleton), model, warnings, options);
}

RigOptions headColliders() {
  RigOptions options;
  options.colliders = {sphereSpec("Avatar_Head", {0.0f, 0.08f, 0.0f}, 0.1f),
                       capsuleSpec("Avatar_Hips", {0.0f, 0.1f, 0.0f}, {0.0f, 0.5f, 0.0f}, 0.12f)};
  options.hit_radius = 0.01f;
  return options;
}

// One avatar of the crowd and its twin, stepped alone with the same drivers.
struct Pair {
  std::shared_ptr<const Rig> rig;
  std::unique_ptr<Instance> member, twin;
  float phase = 0.0f;
  bool shear = false;  // its drivers are sheared: the general path
};

// The drivers of frame f: every driver at its rest matrix, swung and moved by the avatar's phase.
void writeDrivers(Instance& instance, const std::vector<float>& rest, int f, float phase, bool shear) {
  const float t = static_cast<float>(f) / 60.0f;
  const float angle = 0.6f * std::sin(5.0f * t + phase);
  const float c = std::cos(angle), s = std::sin(angle);
  for (std::size_t d = 0; d < instance.driverCount(); ++d) {
    float* m = instance.driverMatrices() + 16 * d;
    std::memcpy(m, rest.data() + 16 * d, sizeof(float) * 16);
    // Rotate the rest matrix about z (columns 0 and 1 mix) and move it along x.
    for (int row = 0; row < 3; ++row) {
      const float a = m[row], b = m[4 + row];
      m[row] = c * a - s * b;
      m[4 + row] = s * a + c * b;
    }
    m[12] += 0.2f * std::sin(3.0f * t + phase);
    if (shear) m[4] += 0.3f;  // the y axis leans on x: not a similarity
  }
}

std::vector<float> restDrivers(Instance& instance) {
  return std::vector<float>(instance.driverMatrices(), instance.driverMatrices() + 16 * instance.driverCount());
}

::testing::AssertionResult sameBits(const Instance& a, const Instance& b) {
  if (std::memcmp(a.rotations(), b.rotations(), sizeof(float) * 4 * a.jointCount()) != 0) {
    return ::testing::AssertionFailure() << "rotations differ";
  }
  std::vector<float> world_a(a.worldMatrices(), a.worldMatrices() + 16 * a.jointCount());
  if (std::memcmp(world_a.data(), b.worldMatrices(), sizeof(float) * 16 * a.jointCount()) != 0) {
    return ::testing::AssertionFailure() << "world matrices differ";
  }
  return ::testing::AssertionSuccess();
}

class BatchedStep : public ::testing::Test {
 protected:
  void SetUp() override {
    hair_colliders_ = fixtureRig("avatar_hair.glb", "avatar_hair.metadata.json", headColliders());
    hair_ = fixtureRig("avatar_hair.glb", "avatar_hair.metadata.json");
    adr_ = fixtureRig("adr_example.glb", "adr_example.metadata.json");
    ASSERT_GT(hair_colliders_->colliders.size(), 0u);
    InstanceOptions fast90;
    fast90.step_hz = 90.0;
    InstanceOptions xpbd;
    xpbd.integrator = Integrator::kXpbd;
    xpbd.step_hz = 120.0;
    add(hair_colliders_, {}, false);
    add(hair_colliders_, {}, false);
    add(hair_colliders_, {}, false);
    add(hair_colliders_, fast90, false);
    add(hair_colliders_, {}, true);
    add(hair_colliders_, xpbd, false);
    add(hair_, {}, false);
    add(hair_, fast90, false);
    add(adr_, {}, false);
    add(adr_, {}, false);
    // Free a pool copy in the middle and take it again: the crowd's copies are not consecutive.
    pairs_.erase(pairs_.begin() + 1);
    add(hair_colliders_, {}, false);
    // The twins come after the members, so that the members' copies of a pool are mostly
    // consecutive and the batch steps them in runs of several copies.
    for (Pair& pair : pairs_) {
      pair.twin = std::make_unique<Instance>(pair.rig, pair.member->options());
      rest_.push_back(restDrivers(*pair.member));
    }
  }

  void add(const std::shared_ptr<const Rig>& rig, const InstanceOptions& options, bool shear) {
    Pair pair;
    pair.rig = rig;
    pair.member = std::make_unique<Instance>(rig, options);
    pair.phase = 0.7f * static_cast<float>(pairs_.size());
    pair.shear = shear;
    pairs_.push_back(std::move(pair));
  }

  std::shared_ptr<const Rig> hair_colliders_, hair_, adr_;
  std::vector<Pair> pairs_;
  std::vector<std::vector<float>> rest_;  // per pair: its drivers' rest matrices
};

// Frame lengths that give zero, one and several steps at 60, 90 and 120 Hz.
double frameSeconds(int f) {
  static const double kFrames[] = {1.0 / 60, 1.0 / 144, 1.0 / 30, 1.0 / 60, 1.0 / 45, 0.25};
  return kFrames[f % 6];
}

TEST_F(BatchedStep, StepAllMatchesSteppingEachInstanceAlone) {
  std::vector<Instance*> members;
  for (Pair& pair : pairs_) members.push_back(pair.member.get());
  for (int f = 1; f <= 240; ++f) {
    for (std::size_t i = 0; i < pairs_.size(); ++i) {
      writeDrivers(*pairs_[i].member, rest_[i], f, pairs_[i].phase, pairs_[i].shear);
      writeDrivers(*pairs_[i].twin, rest_[i], f, pairs_[i].phase, pairs_[i].shear);
    }
    const double dt = frameSeconds(f);
    Instance::stepAll(members.data(), members.size(), dt);
    for (Pair& pair : pairs_) pair.twin->step(dt);
    for (std::size_t i = 0; i < pairs_.size(); ++i) {
      ASSERT_TRUE(sameBits(*pairs_[i].member, *pairs_[i].twin)) << "avatar " << i << ", frame " << f;
    }
  }
  // The crowd moved: the comparison was not between two avatars at rest.
  Instance at_rest(hair_colliders_);
  EXPECT_NE(std::memcmp(pairs_[0].member->rotations(), at_rest.rotations(), sizeof(float) * 4 * at_rest.jointCount()),
            0);
}

TEST_F(BatchedStep, SceneWithABudgetMatchesTheSameStepsTakenAlone) {
  Scene scene;
  for (Pair& pair : pairs_) scene.add(pair.member.get());
  scene.setBudget(4, Vec3{});
  std::vector<bool> was_active(pairs_.size(), true);
  for (int f = 1; f <= 180; ++f) {
    for (std::size_t i = 0; i < pairs_.size(); ++i) {
      writeDrivers(*pairs_[i].member, rest_[i], f, pairs_[i].phase, pairs_[i].shear);
      writeDrivers(*pairs_[i].twin, rest_[i], f, pairs_[i].phase, pairs_[i].shear);
      // The avatars walk past the viewer at different speeds, so the nearest four change.
      scene.positions()[3 * i] = std::sin(0.05f * static_cast<float>(f) * (1.0f + 0.3f * static_cast<float>(i)));
      scene.positions()[3 * i + 1] = 0.0f;
      scene.positions()[3 * i + 2] = static_cast<float>(i) * 0.1f;
    }
    const double dt = frameSeconds(f);
    scene.step(dt);
    for (std::size_t i = 0; i < pairs_.size(); ++i) {
      if (!scene.isActive(i)) {
        was_active[i] = false;
        continue;
      }
      if (!was_active[i]) pairs_[i].twin->reset();  // the scene re-seeds an avatar coming back
      was_active[i] = true;
      pairs_[i].twin->step(dt);
      ASSERT_TRUE(sameBits(*pairs_[i].member, *pairs_[i].twin)) << "avatar " << i << ", frame " << f;
    }
  }
}

TEST(BatchedStepPool, FreedCopiesAreReusedAndAFreshInstanceStartsAtRest) {
  auto rig = fixtureRig("avatar_hair.glb", "avatar_hair.metadata.json");
  auto reference = std::make_unique<Instance>(rig);
  const std::vector<float> rest(reference->rotations(), reference->rotations() + 4 * reference->jointCount());
  {
    std::vector<std::unique_ptr<Instance>> crowd;
    for (int i = 0; i < 9; ++i) crowd.push_back(std::make_unique<Instance>(rig));
    for (auto& instance : crowd) {
      for (std::size_t d = 0; d < instance->driverCount(); ++d) instance->driverMatrices()[16 * d + 12] += 0.3f;
      for (int f = 0; f < 20; ++f) instance->step(1.0 / 60);
    }
  }
  // The copies of the crowd, moved away from rest, are free again: a new instance takes one and
  // must still start from the rig's rest pose and move exactly like the reference.
  Instance fresh(rig);
  EXPECT_EQ(std::memcmp(fresh.rotations(), rest.data(), sizeof(float) * rest.size()), 0);
  for (int f = 0; f < 30; ++f) {
    for (Instance* instance : {&fresh, reference.get()}) {
      for (std::size_t d = 0; d < instance->driverCount(); ++d) {
        instance->driverMatrices()[16 * d + 13] = 1.0f + 0.1f * std::sin(0.3f * static_cast<float>(f));
      }
      instance->step(1.0 / 60);
    }
    ASSERT_TRUE(sameBits(fresh, *reference)) << "frame " << f;
  }
}

}  // namespace
}  // namespace springbones
