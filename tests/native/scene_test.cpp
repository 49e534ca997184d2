// Scene: stepping many instances in one call, with an optional nearest-N budget.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "readers/json_values.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"

namespace springbones {
namespace {

using nlohmann::json;

std::shared_ptr<const Rig> hangingBone() {
  const std::string gltf = json{{"asset", {{"version", "2.0"}}},
                                {"nodes",
                                 {{{"name", "Avatar_Hips"}, {"children", {1}}},
                                  {{"name", "springbone_a"}, {"children", {2}}},
                                  {{"name", "springbone_tip"}, {"translation", {0.2, 0, 0}}}}}}
                               .dump();
  Skeleton skeleton;
  EXPECT_FALSE(loadSkeleton(reinterpret_cast<const std::uint8_t*>(gltf.data()), gltf.size(), skeleton));
  ModelEntry model;
  std::vector<Warning> warnings;
  EXPECT_FALSE(parseSpringBones(json{{"version", 1},
                                     {"models",
                                      {{"h",
                                        {{"springbone_a",
                                          {{"isRoot", true},
                                           {"stiffness", 1},
                                           {"gravityPower", 1},
                                           {"gravityDir", {0, -1, 0}},
                                           {"drag", 0.4}}}}}}}},
                                "h", model, warnings));
  return buildRig(std::move(skeleton), model);
}

glm::quat rotationOf(const Instance& instance) {
  const float* r = instance.rotations();
  return glm::quat(r[3], r[0], r[1], r[2]);
}

void placeAt(Scene& scene, std::size_t slot, float x) {
  scene.positions()[3 * slot] = x;
  scene.positions()[3 * slot + 1] = 0;
  scene.positions()[3 * slot + 2] = 0;
}

TEST(Scene, StepsEveryInstanceLikeSteppingThemOneByOne) {
  auto rig = hangingBone();
  Instance a(rig), b(rig), alone(rig);
  Scene scene;
  scene.add(&a);
  scene.add(&b);
  for (int i = 0; i < 30; ++i) {
    scene.step(1.0 / 60);
    alone.step(1.0 / 60);
  }
  EXPECT_EQ(rotationOf(a), rotationOf(alone));
  EXPECT_EQ(rotationOf(b), rotationOf(alone));
}

TEST(Scene, AddingTwiceKeepsOneSlot) {
  auto rig = hangingBone();
  Instance a(rig);
  Scene scene;
  EXPECT_EQ(scene.add(&a), 0u);
  EXPECT_EQ(scene.add(&a), 0u);
  EXPECT_EQ(scene.size(), 1u);
}

TEST(Scene, BudgetSimulatesOnlyTheNearestAndTheOthersHoldTheirPose) {
  auto rig = hangingBone();
  Instance near(rig), middle(rig), far(rig);
  Scene scene;
  placeAt(scene, scene.add(&far), 30.0f);
  placeAt(scene, scene.add(&near), 1.0f);
  placeAt(scene, scene.add(&middle), 5.0f);
  scene.setBudget(2, Vec3{});
  for (int i = 0; i < 20; ++i) scene.step(1.0 / 60);
  EXPECT_FALSE(scene.isActive(0));
  EXPECT_TRUE(scene.isActive(1));
  EXPECT_TRUE(scene.isActive(2));
  EXPECT_EQ(rotationOf(far), glm::quat(1, 0, 0, 0));  // never stepped: rest pose
  EXPECT_NE(rotationOf(near), glm::quat(1, 0, 0, 0));
  EXPECT_EQ(rotationOf(near), rotationOf(middle));
}

TEST(Scene, AnInstanceReturningToTheBudgetIsReseeded) {
  auto rig = hangingBone();
  Instance walker(rig), other(rig), fresh(rig);
  Scene scene;
  const std::size_t w = scene.add(&walker);
  const std::size_t o = scene.add(&other);
  placeAt(scene, w, 1.0f);
  placeAt(scene, o, 2.0f);
  scene.setBudget(1, Vec3{});
  for (int i = 0; i < 50; ++i) scene.step(1.0 / 60);  // walker swings
  placeAt(scene, w, 10.0f);                           // walks away: other takes the budget
  for (int i = 0; i < 10; ++i) scene.step(1.0 / 60);
  EXPECT_FALSE(scene.isActive(w));
  const glm::quat held = rotationOf(walker);
  placeAt(scene, w, 0.5f);  // comes back: starts again from rest, like a fresh instance
  for (int i = 0; i < 5; ++i) {
    scene.step(1.0 / 60);
    fresh.step(1.0 / 60);
  }
  EXPECT_TRUE(scene.isActive(w));
  EXPECT_NE(rotationOf(walker), held);
  EXPECT_EQ(rotationOf(walker), rotationOf(fresh));
}

TEST(Scene, RemovedInstancesAreNoLongerStepped) {
  auto rig = hangingBone();
  Instance a(rig), b(rig);
  Scene scene;
  scene.add(&a);
  scene.add(&b);
  scene.remove(&a);
  EXPECT_EQ(scene.size(), 1u);
  scene.step(1.0 / 60);
  EXPECT_EQ(rotationOf(a), glm::quat(1, 0, 0, 0));
  EXPECT_NE(rotationOf(b), glm::quat(1, 0, 0, 0));
}

TEST(Scene, NonFinitePositionsSortLast) {
  auto rig = hangingBone();
  Instance lost(rig), found(rig);
  Scene scene;
  const std::size_t l = scene.add(&lost);
  const std::size_t f = scene.add(&found);
  scene.positions()[3 * l] = NAN;
  placeAt(scene, f, 100.0f);
  scene.setBudget(1, Vec3{});
  scene.step(1.0 / 60);
  EXPECT_FALSE(scene.isActive(l));
  EXPECT_TRUE(scene.isActive(f));
}

TEST(Scene, LastStepsCountsTheFixedStepsOfTheLastFrame) {
  auto rig = hangingBone();
  Instance instance(rig);  // 60 Hz, at most 4 steps a frame
  instance.step(1.0 / 60);
  EXPECT_EQ(instance.lastSteps(), 1);
  instance.step(1.0 / 30);
  EXPECT_EQ(instance.lastSteps(), 2);
  instance.step(1.0);  // 60 steps' worth: 4 run, the rest is dropped
  EXPECT_EQ(instance.lastSteps(), 4);
  instance.step(1.0 / 240);  // a quarter of a step: none yet
  EXPECT_EQ(instance.lastSteps(), 0);
  for (int i = 0; i < 3; ++i) instance.step(1.0 / 240);  // the fourth quarter completes one
  EXPECT_EQ(instance.lastSteps(), 1);
  instance.step(1.0 / 60);
  instance.step(-1.0);
  EXPECT_EQ(instance.lastSteps(), 0);
  instance.step(1.0 / 60);
  instance.step(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(instance.lastSteps(), 0);
}

TEST(Scene, LastStepsIsZeroForAnInstanceTheBudgetHolds) {
  auto rig = hangingBone();
  Instance near(rig), far(rig);
  Scene scene;
  placeAt(scene, scene.add(&near), 1.0f);
  placeAt(scene, scene.add(&far), 30.0f);
  scene.step(1.0 / 30);
  EXPECT_EQ(near.lastSteps(), 2);
  EXPECT_EQ(far.lastSteps(), 2);
  scene.setBudget(1, Vec3{});
  scene.step(1.0 / 30);
  EXPECT_EQ(near.lastSteps(), 2);
  EXPECT_EQ(far.lastSteps(), 0);
  scene.step(std::numeric_limits<double>::infinity());
  EXPECT_EQ(near.lastSteps(), 0);
  EXPECT_EQ(far.lastSteps(), 0);
}

}  // namespace
}  // namespace springbones
