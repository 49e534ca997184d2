// Extreme finite values, the classes of defects adversarial testing found (issue 31, "Never silent,
// everywhere" item 7): a vector whose float32 squared length overflows or underflows still has
// its direction; a value the core would zero or ignore because it is out of range is clamped or
// refused with a warning; huge or degenerate finite drivers never make a world matrix
// non-finite; the scene budget tells huge and tiny distances apart.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "loading/metadata.h"
#include "springbones/springbones.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using nlohmann::json;
constexpr char kHash[] = "bafkreiextremes";
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Avatar_Head driving a hair chain of two joints and a tip, and an earring of one.
std::shared_ptr<const Rig> hairRig(const RigOptions& options = {}, float gravity_power = 0.0f) {
  const json nodes = json::array({
      {{"name", "Avatar_Head"}, {"children", {1, 4}}, {"translation", {0, 1.6, 0}}},
      {{"name", "SpringBone_hair"}, {"children", {2}}, {"translation", {0.1, 0, 0}}},
      {{"name", "SpringBone_hair_1"}, {"children", {3}}, {"translation", {0, -0.1, 0}}},
      {{"name", "SpringBone_hair_tip"}, {"translation", {0, -0.1, 0}}},
      {{"name", "SpringBone_earring"}, {"children", {5}}, {"translation", {-0.1, 0, 0}}},
      {{"name", "SpringBone_earring_tip"}, {"translation", {0, -0.05, 0.01}}},
  });
  const std::vector<std::uint8_t> glb = test::makeGlb(json{{"asset", {{"version", "2.0"}}}, {"nodes", nodes}}.dump());
  Skeleton skeleton;
  EXPECT_FALSE(loadSkeleton(glb.data(), glb.size(), skeleton));
  const json entry = {
      {"stiffness", 0.2}, {"gravityPower", gravity_power}, {"gravityDir", {0, -1, 0}}, {"drag", 0.4}, {"isRoot", true}};
  const json metadata = {{"version", 1},
                         {"models", {{kHash, {{"SpringBone_hair", entry}, {"SpringBone_earring", entry}}}}}};
  ModelEntry model;
  std::vector<Warning> warnings;
  EXPECT_FALSE(parseSpringBones(metadata, kHash, model, warnings));
  return buildRig(std::move(skeleton), model, std::move(warnings), options);
}

const Warning* findWarning(const Rig& rig, const std::string& code) {
  for (const Warning& w : rig.warnings) {
    if (w.code == code) return &w;
  }
  return nullptr;
}

std::vector<float> rotationsAfter(Instance& instance, int frames) {
  for (int i = 0; i < frames; ++i) instance.step(1.0 / 60);
  return std::vector<float>(instance.rotations(), instance.rotations() + 4 * instance.jointCount());
}

Wind windAlong(Vec3 direction) {
  Wind wind;
  wind.direction = direction;
  wind.strength = 2.0f;
  return wind;
}

// ---------------------------------------------------------------------------------------------
// Directions

TEST(FiniteExtremes, WindDirectionsWhoseFloatLengthOverflowsOrUnderflowsStillBlow) {
  const auto rig = hairRig();
  Instance calm(rig);
  Instance reference(rig);
  reference.setWind(windAlong({1.0f, 0.0f, 0.0f}));
  const std::vector<float> still = rotationsAfter(calm, 60);
  const std::vector<float> blown = rotationsAfter(reference, 60);
  ASSERT_NE(blown, still) << "the wind moves the chains";
  // x^2 overflows (1e20, 3e38) or underflows (1e-25; 1e-44 is a denormal) in float.
  for (float size : {1e20f, 3e38f, 1e-25f, 1e-44f, -1e20f}) {
    Instance instance(rig);
    instance.setWind(windAlong({size, 0.0f, 0.0f}));
    EXPECT_EQ(instance.wind().strength, 2.0f) << size;
    EXPECT_EQ(instance.wind().direction.x, size > 0 ? 1.0f : -1.0f) << size;
    EXPECT_EQ(instance.wind().direction.y, 0.0f) << size;
    if (size > 0) { EXPECT_EQ(rotationsAfter(instance, 60), blown) << "direction (" << size << ", 0, 0)"; }
  }
  // Mixed sizes keep their ratio: (3e38, 0, 3e38) is the diagonal.
  Instance diagonal(rig);
  diagonal.setWind(windAlong({3e38f, 0.0f, 3e38f}));
  EXPECT_NEAR(diagonal.wind().direction.x, std::sqrt(0.5f), 1e-7f);
  EXPECT_NEAR(diagonal.wind().direction.z, std::sqrt(0.5f), 1e-7f);
  // Through a scene alike.
  Scene scene;
  Instance member(rig);
  scene.add(&member);
  scene.setWind(windAlong({1e-30f, 0.0f, 0.0f}));
  for (int i = 0; i < 60; ++i) scene.step(1.0 / 60);
  EXPECT_EQ(std::vector<float>(member.rotations(), member.rotations() + 4 * member.jointCount()), blown);
  // Zero and non-finite directions are still no wind (documented).
  for (Vec3 none : {Vec3{0, 0, 0}, Vec3{kNaN, 0, 0}, Vec3{kInf, 0, 0}}) {
    Instance instance(rig);
    instance.setWind(windAlong(none));
    EXPECT_EQ(instance.wind().strength, 0.0f);
  }
}

TEST(FiniteExtremes, PlaneNormalsWhoseFloatLengthOverflowsOrUnderflowsAreMadeUnit) {
  for (float size : {1e20f, 3e38f, 1e-25f, 1e-44f}) {
    RigOptions options;
    ColliderSpec plane;
    plane.node = "Avatar_Head";
    plane.shape = Collider::Shape::kPlane;
    plane.normal = Vec3{0.0f, size, 0.0f};
    options.colliders.push_back(plane);
    const auto rig = hairRig(options);
    ASSERT_EQ(rig->colliders.size(), 1u) << size;
    EXPECT_EQ(rig->colliders[0].normal.y, 1.0f) << size;
    EXPECT_EQ(findWarning(*rig, "collider-invalid"), nullptr) << size;
  }
}

// ---------------------------------------------------------------------------------------------
// Values out of range warn

TEST(FiniteExtremes, AHitRadiusOutOfRangeIsClampedWithAWarning) {
  struct Case {
    float given, used;
  };
  for (const Case c : {Case{1e30f, kMaxHitRadius}, Case{kInf, kMaxHitRadius}, Case{kNaN, 0.0f}, Case{-1.0f, 0.0f},
                       Case{-kInf, 0.0f}}) {
    RigOptions options;
    ColliderSpec sphere;
    sphere.node = "Avatar_Head";
    sphere.radius = 0.1f;
    options.colliders.push_back(sphere);
    options.hit_radius = c.given;
    const auto rig = hairRig(options);
    const Warning* w = findWarning(*rig, "hit-radius-out-of-range");
    ASSERT_NE(w, nullptr) << c.given;
    EXPECT_NE(w->message.find("hitRadius"), std::string::npos) << w->message;
    for (const Joint& joint : rig->joints) EXPECT_EQ(joint.hit_radius, c.used) << c.given;
  }
  // In range: used as given, no warning.
  RigOptions options;
  ColliderSpec sphere;
  sphere.node = "Avatar_Head";
  sphere.radius = 0.1f;
  options.colliders.push_back(sphere);
  options.hit_radius = kMaxHitRadius;
  const auto rig = hairRig(options);
  EXPECT_EQ(findWarning(*rig, "hit-radius-out-of-range"), nullptr);
  EXPECT_EQ(rig->joints[0].hit_radius, kMaxHitRadius);
}

TEST(FiniteExtremes, AClampedHitRadiusPushesTailsAwayWithFiniteRotations) {
  RigOptions options;
  ColliderSpec sphere;
  sphere.node = "Avatar_Head";
  sphere.radius = 0.1f;
  options.colliders.push_back(sphere);
  options.hit_radius = 1e30f;
  Instance instance(hairRig(options));
  const std::vector<float> rotations = rotationsAfter(instance, 30);
  for (float v : rotations) ASSERT_TRUE(std::isfinite(v));
  // Every tail is inside the huge hit radius: each bone is pushed to point away from the head's
  // center, so none stays at rest.
  Instance at_rest(hairRig());
  EXPECT_NE(rotations, rotationsAfter(at_rest, 30));
}

TEST(FiniteExtremes, ColliderSizesBeyondTheLimitAreIgnoredWithAWarning) {
  const auto make = [](auto change) {
    RigOptions options;
    ColliderSpec spec;
    spec.node = "Avatar_Head";
    spec.radius = 0.1f;
    change(spec);
    options.colliders.push_back(spec);
    return hairRig(options);
  };
  const auto huge_radius = make([](ColliderSpec& s) { s.radius = 1e30f; });
  const auto far_offset = make([](ColliderSpec& s) { s.offset = Vec3{0.0f, -1e30f, 0.0f}; });
  const auto far_tail = make([](ColliderSpec& s) {
    s.shape = Collider::Shape::kCapsule;
    s.tail = Vec3{1e30f, 0.0f, 0.0f};
  });
  for (const auto& rig : {huge_radius, far_offset, far_tail}) {
    EXPECT_TRUE(rig->colliders.empty());
    const Warning* w = findWarning(*rig, "collider-invalid");
    ASSERT_NE(w, nullptr);
    EXPECT_NE(w->message.find("Avatar_Head"), std::string::npos) << w->message;
  }
  const auto at_limit = make([](ColliderSpec& s) {
    s.radius = kMaxColliderSize;
    s.offset = Vec3{-kMaxColliderSize, 0.0f, 0.0f};
  });
  EXPECT_EQ(at_limit->colliders.size(), 1u);
  EXPECT_EQ(findWarning(*at_limit, "collider-invalid"), nullptr);
}

// ---------------------------------------------------------------------------------------------
// World matrices under extreme drivers

::testing::AssertionResult finiteOutputs(const Instance& instance) {
  const float* world = instance.worldMatrices();
  for (std::size_t k = 0; k < 16 * instance.jointCount(); ++k) {
    if (!std::isfinite(world[k]))
      return ::testing::AssertionFailure() << "world matrix entry " << k << " is " << world[k];
  }
  const float* r = instance.rotations();
  for (std::size_t j = 0; j < instance.jointCount(); ++j) {
    const double len = std::hypot(std::hypot(r[4 * j], r[4 * j + 1]), std::hypot(r[4 * j + 2], r[4 * j + 3]));
    if (!(std::fabs(len - 1.0) < 1e-4))
      return ::testing::AssertionFailure() << "rotation " << j << " has length " << len;
  }
  return ::testing::AssertionSuccess();
}

TEST(FiniteExtremes, WorldMatricesStayFiniteUnderHugeOrDegenerateFiniteDrivers) {
  RigOptions with_collider;
  ColliderSpec sphere;
  sphere.node = "Avatar_Head";
  sphere.radius = 0.05f;
  sphere.offset = Vec3{0.0f, 0.05f, 0.0f};
  with_collider.colliders.push_back(sphere);
  with_collider.hit_radius = 0.01f;
  // A driver: rest is the head at (0, 1.6, 0).
  const auto scaled = [](float sx, float sy, float sz, float tx, float ty, float tz) {
    std::vector<float> m(16, 0.0f);
    m[0] = sx;
    m[5] = sy;
    m[10] = sz;
    m[12] = tx;
    m[13] = ty;
    m[14] = tz;
    m[15] = 1.0f;
    return m;
  };
  struct Driver {
    const char* what;
    std::vector<float> m;
  };
  std::vector<Driver> drivers = {
      {"scale 1e30", scaled(1e30f, 1e30f, 1e30f, 0, 1.6f, 0)},
      {"scale 3e38", scaled(3e38f, 3e38f, 3e38f, 0, 1.6f, 0)},
      {"scale 1e19 (squares overflow)", scaled(1e19f, 1e19f, 1e19f, 0, 1.6f, 0)},
      {"scale 0", scaled(0, 0, 0, 0, 1.6f, 0)},
      {"scale 1e-30", scaled(1e-30f, 1e-30f, 1e-30f, 0, 1.6f, 0)},
      {"scale 1e-45 (denormal)", scaled(1e-45f, 1e-45f, 1e-45f, 0, 1.6f, 0)},
      {"translation 1e30", scaled(1, 1, 1, 1e30f, 1e30f, -1e30f)},
      {"translation 3e38", scaled(1, 1, 1, 3e38f, 0, 0)},
      {"non-uniform 1e30", scaled(1e30f, 1, 1, 0, 1.6f, 0)},
      {"non-uniform 1e-30", scaled(1, 1e-30f, 1, 0, 1.6f, 0)},
      {"scale 1e30, translation 3e38", scaled(1e30f, 1e30f, 1e30f, 3e38f, 3e38f, 3e38f)},
      {"scale 1e-30, translation 1e30", scaled(1e-30f, 1e-30f, 1e-30f, 1e30f, 0, 0)},
      // At the bound (kMaxDriverEntry), where drivers are still taken.
      {"scale at the bound", scaled(kMaxDriverEntry, kMaxDriverEntry, kMaxDriverEntry, 0, 1.6f, 0)},
      {"non-uniform at the bound", scaled(kMaxDriverEntry, 1, 1, 0, 1.6f, 0)},
      {"non-uniform at the bound, tiny", scaled(kMaxDriverEntry, 1e-30f, 1, 0, 1.6f, 0)},
      {"translation at the bound", scaled(1, 1, 1, kMaxDriverEntry, -kMaxDriverEntry, kMaxDriverEntry)},
      {"scale and translation at the bound",
       scaled(kMaxDriverEntry, kMaxDriverEntry, kMaxDriverEntry, kMaxDriverEntry, kMaxDriverEntry, kMaxDriverEntry)},
      {"mirrored at the bound", scaled(-kMaxDriverEntry, kMaxDriverEntry, kMaxDriverEntry, 0, 1.6f, 0)},
  };
  for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
    for (const RigOptions& options : {RigOptions{}, with_collider}) {
      const auto rig = hairRig(options, 1.0f);
      for (const Driver& d : drivers) {
        InstanceOptions instance_options;
        instance_options.integrator = integrator;
        Instance instance(rig, instance_options);
        Wind wind = windAlong({1, 0, 0});
        instance.setWind(wind);
        float* m = instance.driverMatrices();
        const std::vector<float> rest(m, m + 16);
        for (int frame = 0; frame < 20; ++frame) {
          // Half the frames at rest, then the extreme driver, then back: every transition.
          const bool extreme = frame >= 5 && frame < 15;
          std::memcpy(m, extreme ? d.m.data() : rest.data(), sizeof(float) * 16);
          instance.step(1.0 / 60);
          ASSERT_TRUE(finiteOutputs(instance))
              << d.what << ", frame " << frame << ", " << (integrator == Integrator::kXpbd ? "xpbd" : "vrm") << ", "
              << options.colliders.size() << " colliders";
        }
        // Seeded under the extreme driver too.
        std::memcpy(m, d.m.data(), sizeof(float) * 16);
        instance.reset();
        instance.step(1.0 / 60);
        ASSERT_TRUE(finiteOutputs(instance)) << d.what << " after reset";
      }
    }
  }
}

TEST(FiniteExtremes, ADriverBeyondTheBoundKeepsItsLastGoodPose) {
  const auto rig = hairRig({}, 1.0f);
  for (float beyond : {2.0f * kMaxDriverEntry, 3e38f}) {
    Instance held(rig), moved(rig);
    float* m = moved.driverMatrices();
    const std::vector<float> rest(m, m + 16);
    for (int frame = 0; frame < 20; ++frame) {
      if (frame == 5) m[12] = beyond;  // stays there: ignored every frame
      held.step(1.0 / 60);
      moved.step(1.0 / 60);
    }
    EXPECT_EQ(std::vector<float>(moved.rotations(), moved.rotations() + 4 * moved.jointCount()),
              std::vector<float>(held.rotations(), held.rotations() + 4 * held.jointCount()))
        << beyond;
    const float* a = moved.worldMatrices();
    const std::vector<float> world(a, a + 16 * moved.jointCount());
    const float* b = held.worldMatrices();
    EXPECT_EQ(world, std::vector<float>(b, b + 16 * held.jointCount())) << beyond;
    EXPECT_EQ(moved.jumps(), 0) << "an ignored matrix is no jump";
  }
}

// ---------------------------------------------------------------------------------------------
// The scene budget

TEST(FiniteExtremes, TheSceneBudgetTellsHugeAndTinyDistancesApart) {
  const auto rig = hairRig();
  for (float unit : {1e20f, 1e-25f, 1e-40f}) {
    Scene scene;
    Instance far(rig), near(rig);
    scene.add(&far);
    scene.add(&near);
    float* p = scene.positions();
    p[0] = 3.0f * unit;  // far first: a tie would keep the first slot
    p[3] = 1.0f * unit;
    scene.setBudget(1, Vec3{0, 0, 0});
    scene.step(1.0 / 60);
    EXPECT_FALSE(scene.isActive(0)) << unit;
    EXPECT_TRUE(scene.isActive(1)) << unit;
    scene.remove(&far);
    scene.remove(&near);
  }
}

}  // namespace
}  // namespace springbones
