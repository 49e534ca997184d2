// Colliders (VRMC_springBone spheres and capsules): push-out results derived by hand, the driver
// list, and agreement of the lane kernel with the general matrix path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "loading/metadata.h"
#include "springbones/springbones.h"

namespace springbones {
namespace {

using nlohmann::json;

// One joint at the origin under Avatar_Hips whose 0.3 m bone hangs straight down, with no
// stiffness, gravity or velocity (drag 1), so only colliders can move its tail.
std::shared_ptr<const Rig> hangingJoint(const std::vector<ColliderSpec>& colliders, float hit_radius,
                                        float z_scale = 1.0f) {
  json nodes = {{{"name", "Avatar_Hips"}, {"children", {1}}},
                {{"name", "springbone_a"}, {"children", {2}}, {"scale", {1.0, 1.0, z_scale}}},
                {{"name", "springbone_a_tip"}, {"translation", {0, -0.3, 0}}}};
  const std::string gltf = json{{"asset", {{"version", "2.0"}}}, {"nodes", nodes}}.dump();
  Skeleton skeleton;
  EXPECT_FALSE(loadSkeleton(reinterpret_cast<const std::uint8_t*>(gltf.data()), gltf.size(), skeleton));
  ModelEntry model;
  std::vector<Warning> warnings;
  EXPECT_FALSE(parseSpringBones(json{{"version", 1},
                                     {"models", {{"h", {{"springbone_a", {{"isRoot", true}, {"stiffness", 0},
                                                                          {"gravityPower", 0}, {"gravityDir", {0, -1, 0}},
                                                                          {"drag", 1}}}}}}}},
                                "h", model, warnings));
  RigOptions options;
  options.colliders = colliders;
  options.hit_radius = hit_radius;
  return buildRig(std::move(skeleton), model, warnings, options);
}

int driverNamed(const Rig& rig, const std::string& name) {
  for (std::size_t d = 0; d < rig.drivers.size(); ++d) {
    if (rig.drivers[d].name == name) return static_cast<int>(d);
  }
  return -1;
}

void setDriver(Instance& instance, int driver, const glm::mat4& m) {
  std::memcpy(instance.driverMatrices() + 16 * driver, &m[0][0], sizeof(float) * 16);
}

glm::vec3 tailOf(const Instance& instance) {
  glm::mat4 world;
  std::memcpy(&world[0][0], instance.worldMatrices(), sizeof(float) * 16);
  return glm::vec3(world * glm::vec4(instance.rig().joints[0].tail_local, 1.0f));
}

ColliderSpec sphere(const std::string& node, glm::vec3 offset, float radius) {
  ColliderSpec c;
  c.node = node;
  c.offset = offset;
  c.radius = radius;
  return c;
}

TEST(Colliders, ExternalColliderNodesJoinTheDriverList) {
  auto rig = hangingJoint({sphere("Avatar_Head", {0, 0, 0}, 0.1f)}, 0.0f);
  ASSERT_EQ(rig->colliders.size(), 1u);
  const int head = driverNamed(*rig, "Avatar_Head");
  ASSERT_GE(head, 0);
  EXPECT_EQ(rig->drivers[head].node, -1);  // not in the GLB: the caller supplies it by name
  EXPECT_EQ(rig->colliders[0].driver, head);
  EXPECT_EQ(rig->joints[0].colliders, std::vector<int>{0});
}

TEST(Colliders, ColliderOnASpringBoneIsIgnoredWithAWarning) {
  auto rig = hangingJoint({sphere("springbone_a_tip", {0, 0, 0}, 0.1f)}, 0.0f);
  EXPECT_TRUE(rig->colliders.empty());
  bool warned = false;
  for (const Warning& w : rig->warnings) warned = warned || w.code == "collider-on-spring-bone";
  EXPECT_TRUE(warned);
}

TEST(Colliders, SpherePushesTheTailOutThenTheLengthIsRestored) {
  // Sphere of radius 0.1 at (0.05, -0.3, 0), joint radius 0.02: the rest tail (0, -0.3, 0) is
  // 0.05 from the center, 0.07 inside. Pushed along (-1, 0, 0) to (-0.07, -0.3, 0), then back to
  // length 0.3: (-0.07, -0.3, 0) * 0.3 / sqrt(0.07^2 + 0.3^2).
  auto rig = hangingJoint({sphere("Avatar_Head", {0, 0, 0}, 0.1f)}, 0.02f);
  Instance instance(rig);
  setDriver(instance, driverNamed(*rig, "Avatar_Head"), glm::translate(glm::mat4(1), glm::vec3(0.05f, -0.3f, 0)));
  instance.step(1.0 / 60);
  const double k = 0.3 / std::sqrt(0.07 * 0.07 + 0.3 * 0.3);
  const glm::vec3 tail = tailOf(instance);
  EXPECT_NEAR(tail.x, -0.07 * k, 1e-6);
  EXPECT_NEAR(tail.y, -0.3 * k, 1e-6);
  EXPECT_NEAR(tail.z, 0.0, 1e-6);
}

TEST(Colliders, SphereRadiusScalesWithItsNode) {
  // The same sphere given as radius 10 under a 0.01-scaled node behaves as radius 0.1.
  auto rig = hangingJoint({sphere("Avatar_Head", {0, 0, 0}, 10.0f)}, 0.02f);
  Instance instance(rig);
  setDriver(instance, driverNamed(*rig, "Avatar_Head"),
            glm::scale(glm::translate(glm::mat4(1), glm::vec3(0.05f, -0.3f, 0)), glm::vec3(0.01f)));
  instance.step(1.0 / 60);
  const double k = 0.3 / std::sqrt(0.07 * 0.07 + 0.3 * 0.3);
  EXPECT_NEAR(tailOf(instance).x, -0.07 * k, 1e-6);
}

TEST(Colliders, CapsulePushesFromItsClosestPoint) {
  // Capsule from (0.05, -0.3, 0.1) to (0.05, -0.3, 0.5), radius 0.1, joint radius 0.02. The rest
  // tail (0, -0.3, 0) projects before the start, so the closest point is the start: away =
  // (-0.05, 0, -0.1), distance d = sqrt(0.0125); pushed by (0.12 - d) / d along it, then back to
  // length 0.3.
  ColliderSpec capsule;
  capsule.node = "Avatar_Spine";
  capsule.shape = Collider::Shape::kCapsule;
  capsule.offset = {0.05f, -0.3f, 0.1f};
  capsule.tail = {0.05f, -0.3f, 0.5f};
  capsule.radius = 0.1f;
  auto rig = hangingJoint({capsule}, 0.02f);
  Instance instance(rig);
  instance.step(1.0 / 60);
  const double d = std::sqrt(0.05 * 0.05 + 0.1 * 0.1);
  const double push = (0.12 - d) / d;
  const glm::dvec3 pushed(-0.05 * push, -0.3, -0.1 * push);
  const glm::dvec3 expected = pushed * (0.3 / glm::length(pushed));
  const glm::vec3 tail = tailOf(instance);
  EXPECT_NEAR(tail.x, expected.x, 1e-6);
  EXPECT_NEAR(tail.y, expected.y, 1e-6);
  EXPECT_NEAR(tail.z, expected.z, 1e-6);
}

TEST(Colliders, CapsuleSideProjectsOntoTheSegment) {
  // Capsule along Z through (0.05, -0.3, *): the tail's closest point is (0.05, -0.3, 0), the same
  // geometry as the sphere case.
  ColliderSpec capsule;
  capsule.node = "Avatar_Spine";
  capsule.shape = Collider::Shape::kCapsule;
  capsule.offset = {0.05f, -0.3f, -0.4f};
  capsule.tail = {0.05f, -0.3f, 0.4f};
  capsule.radius = 0.1f;
  auto rig = hangingJoint({capsule}, 0.02f);
  Instance instance(rig);
  instance.step(1.0 / 60);
  const double k = 0.3 / std::sqrt(0.07 * 0.07 + 0.3 * 0.3);
  EXPECT_NEAR(tailOf(instance).x, -0.07 * k, 1e-6);
  EXPECT_NEAR(tailOf(instance).y, -0.3 * k, 1e-6);
}

TEST(Colliders, ATailOutsideEveryShapeIsNotMoved) {
  auto rig = hangingJoint({sphere("Avatar_Head", {1, 0, 0}, 0.1f)}, 0.02f);
  Instance instance(rig);
  instance.step(1.0 / 60);
  EXPECT_NEAR(tailOf(instance).x, 0.0, 1e-7);
  EXPECT_NEAR(tailOf(instance).y, -0.3, 1e-7);
}

TEST(Colliders, GeneralPathPushesLikeTheLaneKernel) {
  // A rest scale off uniform by 1e-7 sends the instance down the general matrix path.
  for (float z_scale : {1.0f, 1.0f + 1e-7f}) {
    auto rig = hangingJoint({sphere("Avatar_Head", {0, 0, 0}, 0.1f)}, 0.02f, z_scale);
    Instance instance(rig);
    setDriver(instance, driverNamed(*rig, "Avatar_Head"), glm::translate(glm::mat4(1), glm::vec3(0.05f, -0.3f, 0)));
    instance.step(1.0 / 60);
    const double k = 0.3 / std::sqrt(0.07 * 0.07 + 0.3 * 0.3);
    EXPECT_NEAR(tailOf(instance).x, -0.07 * k, 1e-6) << "z scale " << z_scale;
  }
}

TEST(Colliders, HeadSphereKeepsASwingingStrandOutside) {
  // A strand rooted above a head sphere, pulled by gravity and swung sideways: with the collider
  // its tails never sink more than about a centimetre into the sphere; without it they go through.
  auto run = [](bool with_collider) {
    json nodes = {{{"name", "Avatar_Neck"}, {"children", {1}}},
                  {{"name", "springbone_hair"}, {"translation", {0, 0.25, 0}}, {"children", {2}}},
                  {{"name", "springbone_hair_1"}, {"translation", {0.12, 0, 0}}, {"children", {3}}},
                  {{"name", "springbone_hair_tip"}, {"translation", {0.12, 0, 0}}}};
    const std::string gltf = json{{"asset", {{"version", "2.0"}}}, {"nodes", nodes}}.dump();
    Skeleton skeleton;
    loadSkeleton(reinterpret_cast<const std::uint8_t*>(gltf.data()), gltf.size(), skeleton);
    ModelEntry model;
    std::vector<Warning> warnings;
    parseSpringBones(json{{"version", 1},
                          {"models", {{"h", {{"springbone_hair", {{"isRoot", true}, {"stiffness", 0.2},
                                                                  {"gravityPower", 2}, {"gravityDir", {-0.3, -1, 0}},
                                                                  {"drag", 0.2}}}}}}}},
                     "h", model, warnings);
    RigOptions options;
    if (with_collider) options.colliders = {sphere("Avatar_Neck", {0, 0.12f, 0}, 0.1f)};
    options.hit_radius = 0.01f;
    Instance instance(buildRig(std::move(skeleton), model, warnings, options));
    float deepest = 0.0f;
    for (int i = 0; i < 600; ++i) {
      instance.step(1.0 / 60);
      std::vector<float> world(instance.worldMatrices(), instance.worldMatrices() + 16 * instance.jointCount());
      for (std::size_t j = 0; j < instance.jointCount(); ++j) {
        glm::mat4 m;
        std::memcpy(&m[0][0], world.data() + 16 * j, sizeof(float) * 16);
        const glm::vec3 tail(m * glm::vec4(instance.rig().joints[j].tail_local, 1.0f));
        deepest = std::max(deepest, 0.11f - glm::length(tail - glm::vec3(0, 0.12f, 0)));
      }
    }
    return deepest;
  };
  EXPECT_LT(run(true), 0.015f);  // the length constraint after a push may re-enter a little
  EXPECT_GT(run(false), 0.05f);
}

}  // namespace
}  // namespace springbones
