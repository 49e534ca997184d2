// Colliders (VRMC_springBone spheres and capsules, and the extended collider's plane, inside sphere
// and inside capsule): results derived by hand, the driver list, agreement of the lane kernel with
// the general matrix path, both integrators, and hostile values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "readers/json_values.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "test_helpers.h"

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
  const json bones = {
      {"springbone_a",
       {{"isRoot", true}, {"stiffness", 0}, {"gravityPower", 0}, {"gravityDir", {0, -1, 0}}, {"drag", 1}}}};
  RigOptions options;
  options.colliders = colliders;
  options.hit_radius = hit_radius;
  return test::rigFromJson(nodes, bones, options);
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
  return glm::vec3(world * glm::vec4(toGlm(instance.rig().joints[0].tail_local), 1.0f));
}

TEST(Colliders, ExternalColliderNodesJoinTheDriverList) {
  auto rig = hangingJoint({test::sphereSpec("Avatar_Head", {0, 0, 0}, 0.1f)}, 0.0f);
  ASSERT_EQ(rig->colliders.size(), 1u);
  const int head = driverNamed(*rig, "Avatar_Head");
  ASSERT_GE(head, 0);
  EXPECT_EQ(rig->drivers[head].node, -1);  // not in the GLB: the caller supplies it by name
  EXPECT_EQ(rig->colliders[0].driver, head);
  EXPECT_EQ(rig->joints[0].colliders, std::vector<int>{0});
}

TEST(Colliders, ColliderOnASpringBoneIsIgnoredWithAWarning) {
  auto rig = hangingJoint({test::sphereSpec("springbone_a_tip", {0, 0, 0}, 0.1f)}, 0.0f);
  EXPECT_TRUE(rig->colliders.empty());
  bool warned = false;
  for (const Warning& w : rig->warnings) warned = warned || w.code == "collider-on-spring-bone";
  EXPECT_TRUE(warned);
}

TEST(Colliders, SpherePushesTheTailOutThenTheLengthIsRestored) {
  // Sphere of radius 0.1 at (0.05, -0.3, 0), joint radius 0.02: the rest tail (0, -0.3, 0) is
  // 0.05 from the center, 0.07 inside. Pushed along (-1, 0, 0) to (-0.07, -0.3, 0), then back to
  // length 0.3: (-0.07, -0.3, 0) * 0.3 / sqrt(0.07^2 + 0.3^2).
  auto rig = hangingJoint({test::sphereSpec("Avatar_Head", {0, 0, 0}, 0.1f)}, 0.02f);
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
  auto rig = hangingJoint({test::sphereSpec("Avatar_Head", {0, 0, 0}, 10.0f)}, 0.02f);
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
  const ColliderSpec capsule = test::capsuleSpec("Avatar_Spine", {0.05f, -0.3f, 0.1f}, {0.05f, -0.3f, 0.5f}, 0.1f);
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
  const ColliderSpec capsule = test::capsuleSpec("Avatar_Spine", {0.05f, -0.3f, -0.4f}, {0.05f, -0.3f, 0.4f}, 0.1f);
  auto rig = hangingJoint({capsule}, 0.02f);
  Instance instance(rig);
  instance.step(1.0 / 60);
  const double k = 0.3 / std::sqrt(0.07 * 0.07 + 0.3 * 0.3);
  EXPECT_NEAR(tailOf(instance).x, -0.07 * k, 1e-6);
  EXPECT_NEAR(tailOf(instance).y, -0.3 * k, 1e-6);
}

TEST(Colliders, ATailOutsideEveryShapeIsNotMoved) {
  auto rig = hangingJoint({test::sphereSpec("Avatar_Head", {1, 0, 0}, 0.1f)}, 0.02f);
  Instance instance(rig);
  instance.step(1.0 / 60);
  EXPECT_NEAR(tailOf(instance).x, 0.0, 1e-7);
  EXPECT_NEAR(tailOf(instance).y, -0.3, 1e-7);
}

TEST(Colliders, GeneralPathPushesLikeTheLaneKernel) {
  // A rest scale off uniform by 1e-7 sends the instance down the general matrix path.
  for (float z_scale : {1.0f, 1.0f + 1e-7f}) {
    auto rig = hangingJoint({test::sphereSpec("Avatar_Head", {0, 0, 0}, 0.1f)}, 0.02f, z_scale);
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
    const json bones = {
        {"springbone_hair",
         {{"isRoot", true}, {"stiffness", 0.2}, {"gravityPower", 2}, {"gravityDir", {-0.3, -1, 0}}, {"drag", 0.2}}}};
    RigOptions options;
    if (with_collider) options.colliders = {test::sphereSpec("Avatar_Neck", {0, 0.12f, 0}, 0.1f)};
    options.hit_radius = 0.01f;
    Instance instance(test::rigFromJson(nodes, bones, options));
    float deepest = 0.0f;
    for (int i = 0; i < 600; ++i) {
      instance.step(1.0 / 60);
      std::vector<float> world(instance.worldMatrices(), instance.worldMatrices() + 16 * instance.jointCount());
      for (std::size_t j = 0; j < instance.jointCount(); ++j) {
        glm::mat4 m;
        std::memcpy(&m[0][0], world.data() + 16 * j, sizeof(float) * 16);
        const glm::vec3 tail(m * glm::vec4(toGlm(instance.rig().joints[j].tail_local), 1.0f));
        deepest = std::max(deepest, 0.11f - glm::length(tail - glm::vec3(0, 0.12f, 0)));
      }
    }
    return deepest;
  };
  EXPECT_LT(run(true), 0.015f);  // the length constraint after a push may re-enter a little
  EXPECT_GT(run(false), 0.05f);
}

// ---------------------------------------------------------------------------------------------
// Extended shapes

ColliderSpec insideSphere(Vec3 offset, float radius) {
  ColliderSpec c = test::sphereSpec("Avatar_Head", offset, radius);
  c.inside = true;
  return c;
}

ColliderSpec insideCapsule(Vec3 offset, Vec3 tail, float radius) {
  ColliderSpec c = insideSphere(offset, radius);
  c.shape = Collider::Shape::kCapsule;
  c.tail = tail;
  return c;
}

ColliderSpec plane(Vec3 offset, Vec3 normal) {
  ColliderSpec c;
  c.node = "Avatar_Head";
  c.shape = Collider::Shape::kPlane;
  c.offset = offset;
  c.normal = normal;
  return c;
}

// A point moved by a collider, then put back at length 0.3 from the head at the origin.
glm::dvec3 atBoneLength(const glm::dvec3& p) { return p * (0.3 / glm::length(p)); }

// The three shapes on the hanging joint (rest tail (0, -0.3, 0), joint radius 0.02), each placed
// so its move is off the bone's line, with the tail the VRM update leaves: derived by hand.
struct ShapeCase {
  const char* name;
  ColliderSpec spec;
  glm::dvec3 expected;
};

std::vector<ShapeCase> shapeCases() {
  // Inside sphere around (0.1, -0.2, 0), radius 0.1: the tail, 0.1414 away, is pulled to
  // 0.1 - 0.02 = 0.08 from the center along (-1, -1, 0) / sqrt(2).
  const double s = 0.08 / std::sqrt(2.0);
  // Inside capsule along Y at x = 0.1, radius 0.06: the closest point is (0.1, -0.3, 0), the tail
  // is pulled to 0.06 - 0.02 = 0.04 from it: (0.06, -0.3, 0).
  // Plane through (0, -0.25, 0) with normal (1, 1, 0) / sqrt(2): the tail is -0.05 / sqrt(2) from
  // it, so it moves along the normal by 0.02 + 0.05 / sqrt(2).
  const double n = 1.0 / std::sqrt(2.0), depth = 0.02 + 0.05 * n;
  return {
      {"inside sphere", insideSphere({0.1f, -0.2f, 0}, 0.1f), atBoneLength({0.1 - s, -0.2 - s, 0})},
      {"inside capsule", insideCapsule({0.1f, 0, 0}, {0.1f, -0.5f, 0}, 0.06f), atBoneLength({0.06, -0.3, 0})},
      {"plane", plane({0, -0.25f, 0}, {1, 1, 0}), atBoneLength({depth * n, -0.3 + depth * n, 0})},
  };
}

TEST(ExtendedColliders, EachShapeMovesTheTailAsDerivedOnBothPaths) {
  for (const ShapeCase& shape : shapeCases()) {
    // A rest scale off uniform by 1e-7 sends the instance down the general matrix path.
    for (float z_scale : {1.0f, 1.0f + 1e-7f}) {
      auto rig = hangingJoint({shape.spec}, 0.02f, z_scale);
      ASSERT_EQ(rig->colliders.size(), 1u) << shape.name;
      Instance instance(rig);
      instance.step(1.0 / 60);
      const glm::vec3 tail = tailOf(instance);
      EXPECT_NEAR(tail.x, shape.expected.x, 1e-6) << shape.name << ", z scale " << z_scale;
      EXPECT_NEAR(tail.y, shape.expected.y, 1e-6) << shape.name << ", z scale " << z_scale;
      EXPECT_NEAR(tail.z, shape.expected.z, 1e-6) << shape.name << ", z scale " << z_scale;
    }
  }
}

TEST(ExtendedColliders, ATailOnTheAllowedSideIsNotMoved) {
  for (const ColliderSpec& spec : {insideSphere({0, -0.3f, 0}, 0.1f), insideCapsule({0, 0, 0}, {0, -1, 0}, 0.05f),
                                   plane({0, -0.5f, 0}, {0, 1, 0})}) {
    Instance instance(hangingJoint({spec}, 0.02f));
    instance.step(1.0 / 60);
    EXPECT_NEAR(tailOf(instance).x, 0.0, 1e-7);
    EXPECT_NEAR(tailOf(instance).y, -0.3, 1e-7);
  }
}

TEST(ExtendedColliders, ThePlaneTurnsAndScalesWithItsNode) {
  // The normal (0, 1, 0) under a driver turned -45 degrees about Z is (1, 1, 0) / sqrt(2): the
  // plane case above, on the lane path.
  const ShapeCase turned = shapeCases()[2];
  auto rig = hangingJoint({plane({0, 0, 0}, {0, 1, 0})}, 0.02f);
  Instance instance(rig);
  setDriver(
      instance, driverNamed(*rig, "Avatar_Head"),
      glm::rotate(glm::translate(glm::mat4(1), glm::vec3(0, -0.25f, 0)), -glm::pi<float>() / 4, glm::vec3(0, 0, 1)));
  instance.step(1.0 / 60);
  EXPECT_NEAR(tailOf(instance).x, turned.expected.x, 1e-6);
  EXPECT_NEAR(tailOf(instance).y, turned.expected.y, 1e-6);
  // Under a scale of (0.5, 1, 1) (the general path) the plane of normal (1, 2, 0) is the plane of
  // normal (2, 2, 0) in the world: normals turn with the inverse transpose (a plain transform
  // would give (0.5, 2, 0)).
  auto scaled_rig = hangingJoint({plane({0, 0, 0}, {1, 2, 0})}, 0.02f);
  Instance scaled(scaled_rig);
  setDriver(scaled, driverNamed(*scaled_rig, "Avatar_Head"),
            glm::scale(glm::translate(glm::mat4(1), glm::vec3(0, -0.25f, 0)), glm::vec3(0.5f, 1, 1)));
  scaled.step(1.0 / 60);
  EXPECT_NEAR(tailOf(scaled).x, turned.expected.x, 1e-6);
  EXPECT_NEAR(tailOf(scaled).y, turned.expected.y, 1e-6);
}

TEST(ExtendedColliders, InsideRadiusScalesWithItsNode) {
  // The inside sphere case given as radius 10 under a 0.01-scaled node.
  const ShapeCase inside = shapeCases()[0];
  auto rig = hangingJoint({insideSphere({0, 0, 0}, 10.0f)}, 0.02f);
  Instance instance(rig);
  setDriver(instance, driverNamed(*rig, "Avatar_Head"),
            glm::scale(glm::translate(glm::mat4(1), glm::vec3(0.1f, -0.2f, 0)), glm::vec3(0.01f)));
  instance.step(1.0 / 60);
  EXPECT_NEAR(tailOf(instance).x, inside.expected.x, 1e-6);
  EXPECT_NEAR(tailOf(instance).y, inside.expected.y, 1e-6);
}

// A swinging strand under each shape for ten seconds, with both integrators: its tails end where
// the shape allows (within the give of the length constraint), and without the collider they do
// not, so the shape did the work.
TEST(ExtendedColliders, KeepASwingingStrandOnTheAllowedSideWithBothIntegrators) {
  // Violation of the shape by a tail (world): > 0 on the forbidden side.
  struct Case {
    const char* name;
    ColliderSpec spec;
    float (*violation)(const glm::vec3&);
  };
  const Case cases[] = {
      {"inside sphere", insideSphere({0.1f, -0.1f, 0}, 0.16f),
       [](const glm::vec3& t) { return glm::length(t - glm::vec3(0.1f, -0.1f, 0)) - (0.16f - 0.01f); }},
      {"inside capsule", insideCapsule({0.05f, 0, 0}, {0.05f, -0.4f, 0}, 0.1f),
       [](const glm::vec3& t) {
         return std::hypot(t.x - 0.05f, t.z) - (0.1f - 0.01f);
       }},  // tails stay within its length
      {"plane", plane({-0.05f, 0, 0}, {1, 0, 0}), [](const glm::vec3& t) { return 0.01f - (t.x + 0.05f); }},
  };
  for (const Case& shape : cases) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      auto run = [&](bool with_collider) {
        json nodes = {{{"name", "Avatar_Head"}, {"children", {1}}},
                      {{"name", "springbone_s"}, {"children", {2}}},
                      {{"name", "springbone_s_1"}, {"translation", {0, -0.12, 0}}, {"children", {3}}},
                      {{"name", "springbone_s_tip"}, {"translation", {0, -0.12, 0}}}};
        const json bones = {{"springbone_s",
                             {{"isRoot", true},
                              {"stiffness", 0.1},
                              {"gravityPower", 1},
                              {"gravityDir", {-1, -0.2, 0}},
                              {"drag", 0.1}}}};
        RigOptions options;
        if (with_collider) options.colliders = {shape.spec};
        options.hit_radius = 0.01f;
        InstanceOptions instance_options;
        instance_options.integrator = integrator;
        Instance instance(test::rigFromJson(nodes, bones, options), instance_options);
        const int head_driver = driverNamed(instance.rig(), "Avatar_Head");
        float worst_end = -1.0f;
        for (int i = 0; i < 600; ++i) {
          // The head swings along X, so the strand is thrown both ways.
          const glm::mat4 head = glm::translate(glm::mat4(1), glm::vec3(0.06f * std::sin(i * 0.1f), 0, 0));
          setDriver(instance, head_driver, head);
          instance.step(1.0 / 60);
          if (i < 540) continue;
          for (std::size_t j = 0; j < instance.jointCount(); ++j) {
            glm::mat4 m;
            std::memcpy(&m[0][0], instance.worldMatrices() + 16 * j, sizeof(float) * 16);
            const glm::vec3 tail(m * glm::vec4(toGlm(instance.rig().joints[j].tail_local), 1.0f));
            EXPECT_TRUE(std::isfinite(tail.x) && std::isfinite(tail.y) && std::isfinite(tail.z));
            worst_end = std::max(worst_end, shape.violation(tail - glm::vec3(head[3])));
          }
        }
        return worst_end;
      };
      const char* which = integrator == Integrator::kXpbd ? "xpbd" : "vrm";
      EXPECT_LT(run(true), 0.01f) << shape.name << ", " << which;
      EXPECT_GT(run(false), 0.03f) << shape.name << ", " << which;
    }
  }
}

TEST(ExtendedColliders, RigReportsAndBadSpecsAreSkippedWithWarnings) {
  ColliderSpec zero_normal = plane({0, 0, 0}, {0, 0, 0});
  ColliderSpec nan_normal = plane({0, 0, 0}, {std::nanf(""), 1, 0});
  ColliderSpec huge_normal = plane({0, 0, 0}, {3e38f, 3e38f, 0});
  ColliderSpec inside_plane = plane({0, 0, 0}, {0, 2, 0});
  inside_plane.inside = true;  // has no meaning for a plane: dropped
  inside_plane.radius = 0.5f;  // nor has a radius
  auto rig = hangingJoint({zero_normal, nan_normal, huge_normal, inside_plane}, 0.02f);
  ASSERT_EQ(rig->colliders.size(), 2u);
  EXPECT_TRUE(test::vecNear(rig->colliders[0].normal, glm::vec3(1, 1, 0) / std::sqrt(2.0f), 1e-6f));
  EXPECT_TRUE(test::vecNear(rig->colliders[1].normal, {0, 1, 0}, 0.0f));
  EXPECT_FALSE(rig->colliders[1].inside);
  EXPECT_EQ(rig->colliders[1].radius, 0.0f);
  EXPECT_EQ(test::countWarnings(rig->warnings, "collider-invalid"), 2);
}

// Huge, tiny and non-finite driver matrices and shapes: every rotation stays a finite unit
// quaternion, on both paths and with both integrators, and more colliders than the lane kernel's
// mask (the general path) behave the same.
TEST(ExtendedColliders, HostileValuesStayBounded) {
  std::vector<ColliderSpec> specs;
  for (int k = 0; k < 40; ++k) {
    const float f = static_cast<float>(k);
    switch (k % 3) {
      case 0: specs.push_back(insideSphere({0.01f * f, -0.2f, 0}, k == 3 ? 0.0f : 1e30f * (k % 2))); break;
      case 1: specs.push_back(insideCapsule({0, 0, 0}, {0, -1e30f, 0.001f * f}, 0.05f)); break;
      default: specs.push_back(plane({0, -1e30f * (k % 2), 0}, {std::sin(f), std::cos(f), 1e-30f})); break;
    }
  }
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t count : {std::size_t(3), specs.size()}) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      for (float z_scale : {1.0f, 1.0f + 1e-7f}) {
        auto rig = hangingJoint(std::vector<ColliderSpec>(specs.begin(), specs.begin() + count), 0.02f, z_scale);
        InstanceOptions options;
        options.integrator = integrator;
        Instance instance(rig, options);
        const int head = driverNamed(*rig, "Avatar_Head");
        for (const glm::mat4& m :
             {glm::scale(glm::mat4(1), glm::vec3(1e-30f)), glm::scale(glm::mat4(1), glm::vec3(1e30f)), glm::mat4(0.0f),
              glm::mat4(nan), glm::mat4(inf), glm::scale(glm::mat4(1), glm::vec3(1, 0, 1)), glm::mat4(1.0f)}) {
          setDriver(instance, head, m);
          for (int i = 0; i < 5; ++i) instance.step(1.0 / 60);
          const float* q = instance.rotations();
          const float norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
          EXPECT_NEAR(norm, 1.0f, 1e-5f) << count << " colliders";
        }
      }
    }
  }
}

}  // namespace
}  // namespace springbones
