// Instance::setColliders: colliders changed at run time, on every integrator (the general path,
// the lanes alone and in a scene's batch, XPBD), resized, removed, following a frame the caller
// writes, the 'dcl-body' preset's scale and omissions, and hostile values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "loading/body_colliders.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using nlohmann::json;

// A two-joint strand under Avatar_Neck, swinging beside a head sphere on Avatar_Head (a driver the
// caller supplies). `z_scale` off 1 sends the instance down the general path; `xpbd` picks XPBD.
struct Strand {
  std::shared_ptr<const Rig> rig;
  InstanceOptions options;
};

Strand strand(float radius, float z_scale = 1.0f, bool xpbd = false) {
  const json nodes = {
      {{"name", "Avatar_Neck"}, {"children", {1}}},
      {{"name", "springbone_hair"}, {"translation", {0, 0.25, 0}}, {"children", {2}}, {"scale", {1.0, 1.0, z_scale}}},
      {{"name", "springbone_hair_1"}, {"translation", {0.12, 0, 0}}, {"children", {3}}},
      {{"name", "springbone_hair_tip"}, {"translation", {0.12, 0, 0}}}};
  const json bones = {
      {"springbone_hair",
       {{"isRoot", true}, {"stiffness", 0.2}, {"gravityPower", 2}, {"gravityDir", {-0.3, -1, 0}}, {"drag", 0.2}}}};
  RigOptions options;
  options.colliders = {test::sphereSpec("Avatar_Head", {0, 0.12f, 0}, radius)};
  options.hit_radius = 0.01f;
  Strand s{test::rigFromJson(nodes, bones, options), {}};
  if (xpbd) s.options.integrator = Integrator::kXpbd;
  return s;
}

ColliderOptions headSphere(float radius, const std::string& node = "Avatar_Head") {
  ColliderOptions options;
  options.colliders = {test::sphereSpec(node, {0, 0.12f, 0}, radius)};
  return options;
}

int driverNamed(const Rig& rig, const std::string& name) {
  for (std::size_t d = 0; d < rig.drivers.size(); ++d) {
    if (rig.drivers[d].name == name) return static_cast<int>(d);
  }
  return -1;
}

// The avatar swaying sideways: every driver of the instance moved by the same translation.
void sway(Instance& instance, int frame) {
  const glm::mat4 m = glm::translate(glm::mat4(1), glm::vec3(0.15f * std::sin(0.11f * frame), 0, 0));
  for (std::size_t d = 0; d < instance.driverCount(); ++d)
    std::memcpy(instance.driverMatrices() + 16 * d, &m[0][0], sizeof(float) * 16);
}

std::vector<float> rotationsOf(const Instance& instance) {
  return std::vector<float>(instance.rotations(), instance.rotations() + 4 * instance.jointCount());
}

std::vector<glm::vec3> tailsOf(const Instance& instance) {
  std::vector<glm::vec3> tails;
  for (std::size_t j = 0; j < instance.jointCount(); ++j) {
    glm::mat4 m;
    std::memcpy(&m[0][0], instance.worldMatrices() + 16 * j, sizeof(float) * 16);
    tails.emplace_back(m * glm::vec4(toGlm(instance.rig().joints[j].tail_local), 1.0f));
  }
  return tails;
}

// Steps `a` and `b` frame by frame (alone, or together in a scene) and calls `change` on `b`
// before frame `at`; returns the first frame whose rotations differ (-1: none in `frames`).
template <typename Change>
int firstDifference(Instance& a, Instance& b, int at, int frames, bool in_scene, Change change) {
  Scene scene;
  if (in_scene) {
    scene.add(&a);
    scene.add(&b);
  }
  for (int f = 0; f < frames; ++f) {
    if (f == at) change(b);
    sway(a, f);
    sway(b, f);
    if (in_scene) {
      scene.step(1.0 / 60);
    } else {
      a.step(1.0 / 60);
      b.step(1.0 / 60);
    }
    if (rotationsOf(a) != rotationsOf(b)) return f;
  }
  return -1;
}

struct Path {
  const char* name;
  float z_scale;
  bool xpbd;
  bool in_scene;
};
const Path kPaths[] = {{"lanes", 1.0f, false, false},
                       {"lanes in a scene", 1.0f, false, true},
                       {"general", 1.0f + 1e-7f, false, false},
                       {"xpbd", 1.0f, true, false}};

TEST(SetColliders, TheRigsOwnCollidersGivenAgainMoveBitForBit) {
  for (const Path& path : kPaths) {
    const Strand s = strand(0.1f, path.z_scale, path.xpbd);
    Instance a(s.rig, s.options), b(s.rig, s.options);
    const int differs = firstDifference(a, b, 40, 200, path.in_scene, [](Instance& i) {
      EXPECT_TRUE(i.setColliders(headSphere(0.1f)).empty());
      EXPECT_TRUE(i.frameNames().empty());
    });
    EXPECT_EQ(differs, -1) << path.name;
  }
}

TEST(SetColliders, AResizedColliderChangesTheMotionFromTheNextStepOn) {
  for (const Path& path : kPaths) {
    const Strand s = strand(0.1f, path.z_scale, path.xpbd);
    Instance a(s.rig, s.options), b(s.rig, s.options);
    std::vector<float> before;
    const int differs = firstDifference(a, b, 40, 200, path.in_scene, [&](Instance& i) {
      before = rotationsOf(i);
      i.setColliders(headSphere(0.13f));
      EXPECT_EQ(rotationsOf(i), before) << "setColliders itself moves nothing";
    });
    EXPECT_EQ(differs, 40) << path.name;
    // The bigger sphere holds from then on: no tail sinks more than a little into it (the length
    // restored after a push may re-enter it a little, as with any collider).
    for (int f = 200; f < 400; ++f) {
      sway(b, f);
      b.step(1.0 / 60);
      const glm::vec3 head(0.15f * std::sin(0.11f * f), 0.12f, 0);
      for (const glm::vec3& tail : tailsOf(b)) EXPECT_GT(glm::length(tail - head), 0.13f - 0.015f) << path.name;
    }
  }
}

TEST(SetColliders, SameLayoutOnTheLanesMovesAsARigLoadedWithIt) {
  // b's rig has the small sphere, a's the big one; b resized to the big one moves as a does.
  for (const Path& path : kPaths) {
    const Strand big = strand(0.13f, path.z_scale, path.xpbd), small = strand(0.1f, path.z_scale, path.xpbd);
    Instance a(big.rig, big.options), b(small.rig, small.options);
    b.setColliders(headSphere(0.13f));
    EXPECT_EQ(firstDifference(a, b, -1, 200, path.in_scene, [](Instance&) {}), -1) << path.name;
  }
}

TEST(SetColliders, NoneLeavesTheTailsFree) {
  for (const Path& path : kPaths) {
    const Strand with = strand(0.1f, path.z_scale, path.xpbd), without = strand(0.0f, path.z_scale, path.xpbd);
    Instance a(without.rig, without.options), b(with.rig, with.options);
    a.setColliders({});
    b.setColliders({});
    EXPECT_EQ(firstDifference(a, b, -1, 200, path.in_scene, [](Instance&) {}), -1) << path.name;
  }
}

TEST(SetColliders, AColliderOnAFramePushesTheTailOutOfWhereTheFrameIs) {
  for (const Path& path : kPaths) {
    const Strand s = strand(0.1f, path.z_scale, path.xpbd);
    Instance instance(s.rig, s.options);
    // A sphere of radius 0.1 on "hat", a name that is no driver of the rig: a frame.
    ColliderOptions options = headSphere(0.1f, "hat");
    options.colliders[0].offset = Vec3{0, 0, 0};
    EXPECT_TRUE(instance.setColliders(options).empty());
    ASSERT_EQ(instance.frameNames(), std::vector<std::string>{"hat"}) << path.name;
    for (int f = 0; f < 240; ++f) {
      // The hat moves onto where the strand hangs, and stays.
      const glm::vec3 at = f < 60 ? glm::vec3(5, 5, 5) : glm::vec3(0.18f, 0.2f, 0);
      const glm::mat4 m = glm::translate(glm::mat4(1), at);
      std::memcpy(instance.frameMatrices(), &m[0][0], sizeof(float) * 16);
      instance.step(1.0 / 60);
      if (f < 120) continue;
      for (const glm::vec3& tail : tailsOf(instance)) EXPECT_GT(glm::length(tail - at), 0.1f) << path.name;
    }
  }
}

TEST(SetColliders, AFrameMatrixThatIsNoNumberKeepsTheLastGoodOne) {
  const Strand s = strand(0.1f);
  Instance a(s.rig), b(s.rig);
  for (Instance* i : {&a, &b}) i->setColliders(headSphere(0.1f, "hat"));
  const glm::mat4 m = glm::translate(glm::mat4(1), glm::vec3(0.1f, 0.1f, 0));
  for (int f = 0; f < 120; ++f) {
    for (Instance* i : {&a, &b}) std::memcpy(i->frameMatrices(), &m[0][0], sizeof(float) * 16);
    if (f > 30) b.frameMatrices()[12] = f % 2 ? std::numeric_limits<float>::quiet_NaN() : 1e13f;
    a.step(1.0 / 60);
    b.step(1.0 / 60);
    ASSERT_EQ(rotationsOf(a), rotationsOf(b)) << "frame " << f;
  }
}

TEST(SetColliders, AFrameStartsAtItsAvatarBonesRestMatrix) {
  const Strand s = strand(0.1f);
  Instance instance(s.rig);
  ColliderOptions options = headSphere(0.1f, "Avatar_Hat");
  AvatarBone bone{"Avatar_Hat", {}};
  bone.rest_world.m[13] = 2.0f;
  options.avatar_bones = {bone};
  instance.setColliders(options);
  ASSERT_EQ(instance.frameNames().size(), 1u);
  EXPECT_EQ(instance.frameMatrices()[13], 2.0f);
  EXPECT_EQ(instance.frameMatrices()[0], 1.0f);
}

TEST(SetColliders, ARigDriverIsFollowedByName) {
  const Strand s = strand(0.1f);
  Instance instance(s.rig);
  ColliderOptions options = headSphere(0.1f, "Avatar_Neck");  // the chain's parent: a driver
  instance.setColliders(options);
  EXPECT_TRUE(instance.frameNames().empty());
  EXPECT_GE(driverNamed(*s.rig, "Avatar_Neck"), 0);
}

TEST(SetColliders, BadShapesAreIgnoredWithTheRigsWarnings) {
  for (const Path& path : kPaths) {
    const Strand s = strand(0.1f, path.z_scale, path.xpbd);
    Instance instance(s.rig, s.options);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    ColliderOptions options;
    for (float radius : {nan, inf, -1.0f, 2e6f}) options.colliders.push_back(test::sphereSpec("hat", {}, radius));
    options.colliders.push_back(test::sphereSpec("springbone_hair_1", {}, 0.1f));
    ColliderSpec plane = test::sphereSpec("hat", {}, 0.0f);
    plane.shape = Collider::Shape::kPlane;
    plane.normal = Vec3{0, 0, 0};
    options.colliders.push_back(plane);
    const std::vector<Warning> warnings = instance.setColliders(options);
    EXPECT_EQ(test::countWarnings(warnings, "collider-invalid"), 5) << test::describeWarnings(warnings);
    EXPECT_EQ(test::countWarnings(warnings, "collider-on-spring-bone"), 1) << test::describeWarnings(warnings);
    EXPECT_TRUE(instance.frameNames().empty()) << "no collider made a frame";
    for (int f = 0; f < 60; ++f) {
      sway(instance, f);
      instance.step(1.0 / 60);
    }
    for (float r : rotationsOf(instance)) EXPECT_TRUE(std::isfinite(r)) << path.name;
  }
}

// ---------------------------------------------------------------------------------------------
// The 'dcl-body' preset per instance

TEST(SetColliders, BodyScaleMultipliesEveryRadiusAndOmitLeavesShapesOut) {
  const Skeleton skeleton = test::loadFixtureSkeleton("avatar_hair.glb");
  std::vector<Warning> warnings;
  const std::vector<ColliderSpec> full = dclBodyColliders(skeleton, {}, warnings);
  BodyColliderOptions body;
  body.scale = 0.5f;
  body.omit = {"head", "left-upper-arm"};
  const std::vector<ColliderSpec> half = dclBodyColliders(skeleton, {}, warnings, body);
  EXPECT_TRUE(warnings.empty()) << test::describeWarnings(warnings);
  ASSERT_EQ(full.size(), 8u);
  ASSERT_EQ(half.size(), 6u);
  // full: head, neck, chest, upper-belly, left-shoulder, right-shoulder, left-upper-arm, right-upper-arm
  const std::size_t kept[] = {1, 2, 3, 4, 5, 7};
  for (std::size_t i = 0; i < half.size(); ++i) {
    const ColliderSpec& f = full[kept[i]];
    EXPECT_EQ(half[i].node, f.node);
    EXPECT_EQ(half[i].radius, f.radius * 0.5f);
    EXPECT_TRUE(test::vecNear(half[i].offset, f.offset, 0.0f));  // lengths are the avatar's
    EXPECT_TRUE(test::vecNear(half[i].tail, f.tail, 0.0f));
  }
  EXPECT_EQ(dclBodyShapeNames(), (std::vector<std::string>{"head", "neck", "chest", "upper-belly", "left-shoulder",
                                                           "right-shoulder", "left-upper-arm", "right-upper-arm"}));
}

// The avatar fixture's hair with the body preset, and the same preset given per instance.
std::shared_ptr<const Rig> hairWithBody() {
  const std::vector<std::uint8_t> glb = test::readFixture("avatar_hair.glb");
  Skeleton skeleton;
  EXPECT_FALSE(test::loadBytes(glb, skeleton));
  ModelEntry model;
  std::vector<Warning> warnings;
  const std::string key = test::metadataKeyOf("avatar_hair.glb");
  EXPECT_FALSE(parseSpringBonesText(test::readFixtureText("avatar_hair.metadata.json"), key, model, warnings));
  RigOptions options;
  options.preset = ColliderPreset::kDclBody;
  options.hit_radius = 0.01f;
  return buildRig(std::move(skeleton), model, warnings, options);
}

TEST(SetColliders, TheBodyPresetGivenAgainMovesBitForBitAndItsScaleChangesIt) {
  const auto rig = hairWithBody();
  ASSERT_EQ(rig->colliders.size(), 8u);
  for (bool xpbd : {false, true}) {
    InstanceOptions options;
    if (xpbd) options.integrator = Integrator::kXpbd;
    Instance a(rig, options), b(rig, options), c(rig, options);
    ColliderOptions body;
    body.preset = ColliderPreset::kDclBody;
    EXPECT_TRUE(b.setColliders(body).empty());
    body.body.scale = 2.0f;
    body.body.omit = {"left-shoulder"};
    c.setColliders(body);
    EXPECT_EQ(firstDifference(a, b, -1, 200, false, [](Instance&) {}), -1) << (xpbd ? "xpbd" : "vrm");
    Instance d(rig, options);
    EXPECT_NE(firstDifference(d, c, -1, 200, false, [](Instance&) {}), -1) << (xpbd ? "xpbd" : "vrm");
  }
}

}  // namespace
}  // namespace springbones
