// Wind (springbones.h Wind, windAt; Instance::setWind, Scene::setWind): the gust function, off by
// default, the same bits for the same seed on every path (lane kernel, general path, XPBD, alone
// and batched), and the clamps.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "simulation/wind.h"
#include "springbones/springbones.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using namespace test;

Wind breeze(std::uint32_t seed = 7, float gusts = 1.5f) {
  Wind wind;
  wind.direction = Vec3{1.0f, 0.0f, 0.0f};
  wind.strength = 1.0f;
  wind.gust_frequency = gusts;
  wind.seed = seed;
  return wind;
}

// A chain of three 5 cm bones hanging from Avatar_Head at (0, 1.6, 0).
std::shared_ptr<const Rig> hangingChain() {
  const nlohmann::json nodes =
      nlohmann::json::array({node("Avatar_Head", {1}, {0, 1.6, 0}), node("SpringBone_a", {2}, {0, -0.05, 0}),
                             node("SpringBone_b", {3}, {0, -0.05, 0}), node("SpringBone_c", {4}, {0, -0.05, 0}),
                             node("SpringBone_tip", {}, {0, -0.05, 0})});
  return rigFromJson(nodes,
                     {{"SpringBone_a", {{"isRoot", true}, {"stiffness", 1.0}, {"drag", 0.4}, {"gravityPower", 0.5}}}});
}

enum class Path { kLanes, kGeneral, kXpbd };

std::unique_ptr<Instance> instanceOn(const std::shared_ptr<const Rig>& rig, Path path) {
  InstanceOptions options;
  if (path == Path::kXpbd) options.integrator = Integrator::kXpbd;
  auto instance = std::make_unique<Instance>(rig, options);
  if (path == Path::kGeneral) instance->driverMatrices()[4] = 0.2f;  // a sheared head: not a similarity
  return instance;
}

void run(Instance& instance, int frames) {
  for (int f = 0; f < frames; ++f) instance.step(1.0 / 60.0);
}

glm::vec3 lastTail(const Instance& instance) {
  const float* m = instance.worldMatrices() + 16 * (instance.jointCount() - 1);
  return glm::vec3(glm::make_mat4(m) * glm::vec4(0.0f, -0.05f, 0.0f, 1.0f));
}

bool sameRotations(const Instance& a, const Instance& b) {
  return std::memcmp(a.rotations(), b.rotations(), sizeof(float) * 4 * a.jointCount()) == 0;
}

TEST(Wind, SteadyWindIsDirectionTimesStrength) {
  Wind wind = breeze(1, 0.0f);
  wind.strength = 2.5f;
  EXPECT_TRUE(vecNear(windAt(wind, 0.0), glm::vec3(2.5f, 0.0f, 0.0f), 0.0f));
  EXPECT_TRUE(vecNear(windAt(wind, 123.4), glm::vec3(2.5f, 0.0f, 0.0f), 0.0f));
  wind.strength = 0.0f;
  EXPECT_TRUE(vecNear(windAt(wind, 1.0), glm::vec3(0.0f), 0.0f));
}

TEST(Wind, GustsStayBetweenHalfAndFullStrengthChangeSmoothlyAndFollowTheSeed) {
  const Wind a = breeze(7), b = breeze(8);
  float lowest = 1.0f, highest = 0.0f, largest_change = 0.0f;
  bool seeds_differ = false;
  for (int i = 0; i < 6000; ++i) {  // 100 s at 60 Hz
    const double t = i / 60.0;
    const float x = windAt(a, t).x;
    lowest = std::min(lowest, x);
    highest = std::max(highest, x);
    largest_change = std::max(largest_change, std::fabs(windAt(a, t + 1.0 / 60.0).x - x));
    EXPECT_EQ(windAt(a, t).x, windAt(breeze(7), t).x);  // a function of seed and time only
    seeds_differ = seeds_differ || windAt(b, t).x != x;
  }
  EXPECT_GE(lowest, 0.5f);
  EXPECT_LE(highest, 1.0f);
  EXPECT_LT(lowest, 0.6f);  // 150 knots of uniform values reach near both ends
  EXPECT_GT(highest, 0.9f);
  // The eased step between two knots has slope at most 1.5 x 0.5 (value) x 1.5 Hz per second.
  EXPECT_LT(largest_change, 1.5f * 0.5f * 1.5f / 60.0f + 1e-6f);
  EXPECT_TRUE(seeds_differ);
}

TEST(Wind, OffByDefaultAndAZeroWindChangesNoBit) {
  const auto rig = hangingChain();
  for (Path path : {Path::kLanes, Path::kGeneral, Path::kXpbd}) {
    auto plain = instanceOn(rig, path), calm = instanceOn(rig, path);
    EXPECT_EQ(plain->wind().strength, 0.0f);
    Wind zero = breeze();
    zero.strength = 0.0f;
    calm->setWind(zero);
    run(*plain, 90);
    run(*calm, 90);
    EXPECT_TRUE(sameRotations(*plain, *calm)) << static_cast<int>(path);
  }
}

TEST(Wind, BlowsTheChainDownwindOnEveryPath) {
  const auto rig = hangingChain();
  for (Path path : {Path::kLanes, Path::kGeneral, Path::kXpbd}) {
    auto still = instanceOn(rig, path), blown = instanceOn(rig, path);
    blown->setWind(breeze(7, 0.0f));
    run(*still, 180);
    run(*blown, 180);
    // Steady pull 1 against stiffness 1 and gravity 0.5: the chain leans well over toward +x.
    EXPECT_GT(lastTail(*blown).x - lastTail(*still).x, 0.03f) << static_cast<int>(path);
  }
}

TEST(Wind, TheSameSeedGivesTheSameBitsAnotherSeedOtherMotion) {
  const auto rig = hangingChain();
  for (Path path : {Path::kLanes, Path::kGeneral, Path::kXpbd}) {
    auto a = instanceOn(rig, path), b = instanceOn(rig, path), c = instanceOn(rig, path);
    a->setWind(breeze(7));
    b->setWind(breeze(7));
    c->setWind(breeze(99));
    run(*a, 200);
    run(*b, 200);
    run(*c, 200);
    EXPECT_TRUE(sameRotations(*a, *b)) << static_cast<int>(path);
    EXPECT_FALSE(sameRotations(*a, *c)) << static_cast<int>(path);
  }
}

TEST(Wind, ASceneSetsEveryMemberAndStepsThemAsIfAlone) {
  const auto rig = hangingChain();
  Scene scene;
  auto first = instanceOn(rig, Path::kLanes), second = instanceOn(rig, Path::kLanes);
  auto own = instanceOn(rig, Path::kLanes);
  auto twin_first = instanceOn(rig, Path::kLanes), twin_own = instanceOn(rig, Path::kLanes);
  scene.add(first.get());
  scene.setWind(breeze(3));
  scene.add(second.get());  // added after: takes the scene's wind
  scene.add(own.get());
  own->setWind(breeze(4));  // its own wind overrides the scene's
  twin_first->setWind(breeze(3));
  twin_own->setWind(breeze(4));
  EXPECT_EQ(second->wind().seed, 3u);
  for (int f = 0; f < 150; ++f) {
    scene.step(1.0 / 60.0);
    twin_first->step(1.0 / 60.0);
    twin_own->step(1.0 / 60.0);
  }
  EXPECT_TRUE(sameRotations(*first, *twin_first));
  EXPECT_TRUE(sameRotations(*second, *twin_first));
  EXPECT_TRUE(sameRotations(*own, *twin_own));
  EXPECT_FALSE(sameRotations(*own, *first));
}

TEST(Wind, OutOfRangeValuesAreClamped) {
  auto instance = instanceOn(hangingChain(), Path::kLanes);
  Wind wind = breeze();
  wind.direction = Vec3{0.0f, 0.0f, 2.0f};
  wind.strength = 1e9f;
  wind.gust_frequency = NAN;
  instance->setWind(wind);
  EXPECT_TRUE(vecNear(instance->wind().direction, glm::vec3(0.0f, 0.0f, 1.0f), 0.0f));
  EXPECT_EQ(instance->wind().strength, kMaxWindStrength);
  EXPECT_EQ(instance->wind().gust_frequency, 0.0f);
  wind.strength = NAN;
  instance->setWind(wind);
  EXPECT_EQ(instance->wind().strength, 0.0f);
  wind.strength = 1.0f;
  wind.direction = Vec3{NAN, 0.0f, 0.0f};
  instance->setWind(wind);
  EXPECT_EQ(instance->wind().strength, 0.0f);  // no usable direction: no wind
  wind.direction = Vec3{};
  instance->setWind(wind);
  EXPECT_EQ(instance->wind().strength, 0.0f);
  // The strongest wind with the fastest gusts for a long time: still finite.
  wind = breeze(1, kMaxGustFrequency);
  wind.strength = kMaxWindStrength;
  instance->setWind(wind);
  run(*instance, 600);
  for (std::size_t i = 0; i < 4 * instance->jointCount(); ++i) ASSERT_TRUE(std::isfinite(instance->rotations()[i]));
}

}  // namespace
}  // namespace springbones
