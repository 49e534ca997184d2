// Angle limits (VRMC_springBone_limit 1.0-draft): the three shapes and their singular directions
// against the draft's definitions, the limit space, reading them from a VRM file and from
// RigOptions with their warnings, and that no limited joint leaves its limit under shaking, wind
// and colliders, with either integrator (docs/semantics.md, "Angle limits").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "simulation/joint_limits.h"
#include "springbones/springbones.h"
#include "springbones/vrm.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using nlohmann::json;
using test::vecNear;

constexpr float kPi = 3.14159265f;

JointLimit cone(float angle, Quat rotation = {}) {
  JointLimit l;
  l.kind = JointLimit::Kind::kCone;
  l.angle = angle;
  l.rotation = rotation;
  return l;
}

JointLimit hinge(float angle, Quat rotation = {}) {
  JointLimit l = cone(angle, rotation);
  l.kind = JointLimit::Kind::kHinge;
  return l;
}

JointLimit spherical(float pitch, float yaw, Quat rotation = {}) {
  JointLimit l;
  l.kind = JointLimit::Kind::kSpherical;
  l.pitch = pitch;
  l.yaw = yaw;
  l.rotation = rotation;
  return l;
}

glm::vec3 limited(const JointLimit& limit, glm::vec3 d, bool* moved = nullptr) {
  d = glm::normalize(d);
  const bool m = limitDirection(limit, d);
  if (moved) *moved = m;
  return d;
}

TEST(JointLimitShapes, ConeKeepsDirectionsWithinItsAngleAndMovesOthersToTheBoundaryInTheirPlane) {
  bool moved = true;
  EXPECT_TRUE(vecNear(limited(cone(kPi / 4), {0.3f, 1.0f, 0.2f}, &moved), glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f))));
  EXPECT_FALSE(moved);
  // Outside: the same azimuth, at the cone's angle from +Y.
  const glm::vec3 d = limited(cone(kPi / 6), {1.0f, -0.5f, 1.0f}, &moved);
  EXPECT_TRUE(moved);
  EXPECT_NEAR(std::acos(d.y), kPi / 6, 1e-5f);
  EXPECT_NEAR(d.x, d.z, 1e-6f);
  EXPECT_GT(d.x, 0.0f);
  // -Y has no azimuth: the draft's boundary on the +Z side.
  EXPECT_TRUE(vecNear(limited(cone(kPi / 3), {0, -1, 0}), {0.0f, std::cos(kPi / 3), std::sin(kPi / 3)}));
  // pi is the whole sphere.
  EXPECT_TRUE(vecNear(limited(cone(kPi), {0, -1, 0}, &moved), {0, -1, 0}));
  EXPECT_FALSE(moved);
}

TEST(JointLimitShapes, HingeKeepsTheYZPlaneAndItsAngle) {
  // Out of the plane: projected onto it.
  EXPECT_TRUE(vecNear(limited(hinge(kPi / 2), {0.5f, 1.0f, 1.0f}), glm::normalize(glm::vec3(0.0f, 1.0f, 1.0f))));
  // Beyond the angle on either side: the boundary on that side.
  EXPECT_TRUE(vecNear(limited(hinge(kPi / 4), {0, 0, -1}), {0.0f, std::cos(kPi / 4), -std::sin(kPi / 4)}));
  EXPECT_TRUE(vecNear(limited(hinge(kPi / 4), {0.2f, -1.0f, 0.0f}), {0.0f, std::cos(kPi / 4), std::sin(kPi / 4)}));
  // +-X has no projection: +Y.
  EXPECT_TRUE(vecNear(limited(hinge(kPi), {1, 0, 0}), {0, 1, 0}));
  EXPECT_TRUE(vecNear(limited(hinge(kPi), {-1, 0, 0}), {0, 1, 0}));
}

TEST(JointLimitShapes, SphericalBoundsPitchAboutXAndYawTowardX) {
  bool moved = true;
  const glm::vec3 inside = glm::normalize(glm::vec3(0.2f, 1.0f, 0.3f));
  EXPECT_TRUE(vecNear(limited(spherical(kPi / 4, kPi / 4), inside, &moved), inside));
  EXPECT_FALSE(moved);
  // (sqrt(1/2), 0, -sqrt(1/2)): yaw pi/4 > pi/6, pitch -pi/2 < -pi/4 -> (sin 30, cos 30 cos 45, -cos 30 sin 45).
  const glm::vec3 d = limited(spherical(kPi / 4, kPi / 6), {1, 0, -1});
  EXPECT_TRUE(vecNear(d, {0.5f, 0.8660254f * 0.7071068f, -0.8660254f * 0.7071068f}));
  // +X: pitch 0, yaw at its bound (the +Y side); -Y: pitch pi, on the +Z side.
  EXPECT_TRUE(vecNear(limited(spherical(kPi / 4, kPi / 4), {1, 0, 0}), {0.7071068f, 0.7071068f, 0.0f}));
  EXPECT_TRUE(vecNear(limited(spherical(kPi / 3, kPi / 2), {0, -1, 0}), {0.0f, std::cos(kPi / 3), std::sin(kPi / 3)}));
}

TEST(JointLimitSpace, TakesPlusYOntoTheBoneAxisThenTheLimitRotation) {
  const glm::vec3 axis = glm::normalize(glm::vec3(1.0f, 2.0f, -0.5f));
  EXPECT_TRUE(vecNear(limitFrameLocal(axis, Quat{}) * glm::vec3(0, 1, 0), axis));
  // Exactly -Y: half a turn about X (so +Z goes to -Z), as the draft requires.
  const glm::quat down = limitFrameLocal({0, -1, 0}, Quat{});
  EXPECT_TRUE(vecNear(down * glm::vec3(0, 1, 0), {0, -1, 0}));
  EXPECT_TRUE(vecNear(down * glm::vec3(0, 0, 1), {0, 0, -1}));
  EXPECT_TRUE(vecNear(down * glm::vec3(1, 0, 0), {1, 0, 0}));
  // The limit's rotation comes after: a quarter turn about Z leans the limit's +Y toward -X.
  const float h = std::sqrt(0.5f);
  EXPECT_TRUE(vecNear(limitFrameLocal({0, 1, 0}, Quat{0, 0, h, h}) * glm::vec3(0, 1, 0), {-1, 0, 0}));
}

// ---------------------------------------------------------------------------------------------
// Reading

json gnode(const std::string& name, std::vector<int> children, glm::vec3 t) {
  json n = {{"name", name}, {"translation", {t.x, t.y, t.z}}};
  if (!children.empty()) n["children"] = children;
  return n;
}

// body -> root -> j2 -> j3 -> tip, 10 cm bones along `bone` (local translation of each child).
json chainNodes(glm::vec3 bone) {
  return json::array({gnode("body", {1}, {0, 1.5f, 0}), gnode("root", {2}, {0, 0, 0}), gnode("j2", {3}, bone),
                      gnode("j3", {4}, bone), gnode("tip", {}, bone)});
}

json limitExtension(json limit, std::string version = "1.0-draft") {
  return {{"VRMC_springBone_limit", {{"specVersion", version}, {"limit", limit}}}};
}

std::shared_ptr<const Rig> loadVrmDoc(const json& nodes, const json& joint_list, const json& colliders = json::array(),
                                      const json& groups = json::array(), json spring_groups = json::array()) {
  json spring = {{"joints", joint_list}};
  if (!spring_groups.empty()) spring["colliderGroups"] = spring_groups;
  const json doc = {{"asset", {{"version", "2.0"}}},
                    {"nodes", nodes},
                    {"extensions",
                     {{"VRMC_springBone",
                       {{"specVersion", "1.0"},
                        {"springs", json::array({spring})},
                        {"colliders", colliders},
                        {"colliderGroups", groups}}}}}};
  const std::string text = doc.dump();
  std::shared_ptr<const Rig> rig;
  const Error e = loadVrm(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), rig);
  EXPECT_FALSE(e) << e.message;
  return rig ? rig : std::make_shared<const Rig>();
}

json limitedJoint(int node, json limit, json params = json::object()) {
  json j = params;
  j["node"] = node;
  j["extensions"] = limitExtension(std::move(limit));
  return j;
}

TEST(JointLimitReading, VrmJointsCarryTheirLimitsInBothSphericalSpellings) {
  const json limits =
      json::array({limitedJoint(1, {{"cone", {{"angle", 0.5}, {"rotation", {0, 0, 0.258819, 0.965926}}}}}),
                   limitedJoint(2, {{"spherical", {{"phi", 0.4}, {"theta", 0.2}}}}),
                   limitedJoint(3, {{"spherical", {{"pitch", 0.6}, {"yaw", 0.3}}}}),
                   {{"node", 4}}});
  const auto rig = loadVrmDoc(chainNodes({0, -0.1f, 0}), limits);
  ASSERT_EQ(rig->joints.size(), 3u);
  const JointLimit& c = rig->joints[0].limit;
  EXPECT_EQ(c.kind, JointLimit::Kind::kCone);
  EXPECT_FLOAT_EQ(c.angle, 0.5f);
  EXPECT_TRUE(test::quatNear(c.rotation, glm::normalize(glm::quat(0.965926f, 0, 0, 0.258819f))));
  EXPECT_EQ(rig->joints[1].limit.kind, JointLimit::Kind::kSpherical);
  EXPECT_FLOAT_EQ(rig->joints[1].limit.pitch, 0.4f);  // phi is the older name of pitch
  EXPECT_FLOAT_EQ(rig->joints[1].limit.yaw, 0.2f);    // theta of yaw
  EXPECT_FLOAT_EQ(rig->joints[2].limit.pitch, 0.6f);
  EXPECT_FLOAT_EQ(rig->joints[2].limit.yaw, 0.3f);
  EXPECT_TRUE(rig->warnings.empty()) << test::describeWarnings(rig->warnings);
}

TEST(JointLimitReading, BadValuesAreClampedOrDroppedWithWarnings) {
  const std::string base = "/extensions/VRMC_springBone/springs/0/joints/";
  const json list = json::array({
      limitedJoint(1, {{"cone", {{"angle", -0.2}}}}),                                                // negative: 0
      limitedJoint(2, {{"spherical", {{"pitch", 4.0}, {"yaw", 2.0}, {"rotation", {0, 0, 0, 2}}}}}),  // beyond: pi, pi/2
      {{"node", 3}, {"extensions", limitExtension({{"hinge", {{"angle", 0.3}}}}, "2.0")}},           // unknown version
      {{"node", 4}, {"extensions", limitExtension({{"cone", {{"angle", 0.3}}}})}},                   // on the end joint
  });
  const auto rig = loadVrmDoc(chainNodes({0.02f, -0.1f, 0}), list);
  ASSERT_EQ(rig->joints.size(), 3u);
  EXPECT_EQ(rig->joints[0].limit.angle, 0.0f);
  ASSERT_TRUE(test::findWarning(rig->warnings, "limit-clamped", base + "0/extensions/VRMC_springBone_limit/limit"));
  EXPECT_FLOAT_EQ(rig->joints[1].limit.pitch, kPi);
  EXPECT_FLOAT_EQ(rig->joints[1].limit.yaw, kPi / 2);
  EXPECT_TRUE(test::quatNear(rig->joints[1].limit.rotation, glm::quat(1, 0, 0, 0)));  // made unit
  EXPECT_EQ(test::countWarnings(rig->warnings, "limit-clamped"), 3);
  EXPECT_EQ(test::countWarnings(rig->warnings, "limit-rotation-invalid"), 1);
  EXPECT_EQ(rig->joints[2].limit.kind, JointLimit::Kind::kNone);
  EXPECT_TRUE(
      test::findWarning(rig->warnings, "limit-spec-version", base + "2/extensions/VRMC_springBone_limit/specVersion"));
  EXPECT_TRUE(test::findWarning(rig->warnings, "limit-on-end-joint", base + "3/extensions/VRMC_springBone_limit"));

  // A limit object without a shape, or a missing angle (the maximum, with a warning).
  const auto shapeless = loadVrmDoc(
      chainNodes({0, -0.1f, 0}),
      json::array({limitedJoint(1, {{"box", 1}}), limitedJoint(2, {{"cone", json::object()}}), {{"node", 3}}}));
  EXPECT_EQ(shapeless->joints[0].limit.kind, JointLimit::Kind::kNone);
  EXPECT_TRUE(
      test::findWarning(shapeless->warnings, "limit-invalid", base + "0/extensions/VRMC_springBone_limit/limit"));
  EXPECT_EQ(shapeless->joints[1].limit.kind, JointLimit::Kind::kCone);
  EXPECT_FLOAT_EQ(shapeless->joints[1].limit.angle, kPi);
}

// UniVRM's import rule (its issue #2828): a limit with two shapes is ignored with a warning rather
// than read as one of them; a limit with one shape beside it still applies.
TEST(JointLimitReading, ALimitWithTwoShapesIsIgnored) {
  const std::string base = "/extensions/VRMC_springBone/springs/0/joints/";
  const auto rig = loadVrmDoc(chainNodes({0, -0.1f, 0}),
                              json::array({limitedJoint(1, {{"cone", {{"angle", 0.5}}}, {"hinge", {{"angle", 0.3}}}}),
                                           limitedJoint(2, {{"hinge", {{"angle", 0.3}}}}),
                                           {{"node", 3}},
                                           {{"node", 4}}}));
  ASSERT_EQ(rig->joints.size(), 3u);
  EXPECT_EQ(rig->joints[0].limit.kind, JointLimit::Kind::kNone);
  const Warning* w =
      test::findWarning(rig->warnings, "limit-invalid", base + "0/extensions/VRMC_springBone_limit/limit");
  ASSERT_NE(w, nullptr);
  EXPECT_NE(w->message.find("more than one"), std::string::npos) << w->message;
  EXPECT_EQ(rig->joints[1].limit.kind, JointLimit::Kind::kHinge);
}

// Hostile values: numbers beyond float's range, strings, arrays of the wrong size load with
// warnings, never a NaN in the rig.
TEST(JointLimitReading, HostileValuesLoadAsFiniteLimitsWithWarnings) {
  const json list =
      json::array({limitedJoint(1, {{"cone", {{"angle", 1e300}, {"rotation", {1e300, 0, 0, 1}}}}}),
                   limitedJoint(2, {{"spherical", {{"pitch", "wide"}, {"yaw", -1e300}, {"rotation", {0, 0, 1}}}}}),
                   limitedJoint(3, {{"hinge", json::array()}}),
                   {{"node", 4}}});
  const auto rig = loadVrmDoc(chainNodes({0, -0.1f, 0}), list);
  ASSERT_EQ(rig->joints.size(), 3u);
  for (const Joint& j : rig->joints) {
    for (float v : {j.limit.angle, j.limit.pitch, j.limit.yaw, j.limit.rotation.x, j.limit.rotation.y,
                    j.limit.rotation.z, j.limit.rotation.w}) {
      EXPECT_TRUE(std::isfinite(v));
    }
  }
  EXPECT_FLOAT_EQ(rig->joints[0].limit.angle, kPi);
  EXPECT_TRUE(test::quatNear(rig->joints[0].limit.rotation, glm::quat(1, 0, 0, 0)));
  EXPECT_FLOAT_EQ(rig->joints[1].limit.pitch, kPi);
  EXPECT_FLOAT_EQ(rig->joints[1].limit.yaw, 0.0f);
  EXPECT_EQ(rig->joints[2].limit.kind, JointLimit::Kind::kNone);
  EXPECT_EQ(test::countWarnings(rig->warnings, "limit-clamped"), 3) << test::describeWarnings(rig->warnings);
  EXPECT_EQ(test::countWarnings(rig->warnings, "limit-rotation-invalid"), 2);
  EXPECT_EQ(test::countWarnings(rig->warnings, "limit-invalid"), 1);
}

// A rotation of any finite size within float's range is a direction: [1e20, 0, 0, 1e20] squares past
// float's range and [1e-25, 0, 0, 1e-25] to zero, yet both are half a turn about X made unit, in a
// file and through the option alike; the warning names the length, not a non-finite number.
TEST(JointLimitReading, RotationsOfExtremeFiniteSizeAreMadeUnitInBothPaths) {
  const float h = std::sqrt(0.5f);
  const glm::quat expected(h, h, 0, 0);  // glm: w first
  const json list = json::array({limitedJoint(1, {{"cone", {{"angle", 0.5}, {"rotation", {1e20, 0, 0, 1e20}}}}}),
                                 limitedJoint(2, {{"cone", {{"angle", 0.5}, {"rotation", {1e-25, 0, 0, 1e-25}}}}}),
                                 {{"node", 3}},
                                 {{"node", 4}}});
  const auto rig = loadVrmDoc(chainNodes({0, -0.1f, 0}), list);
  ASSERT_EQ(rig->joints.size(), 3u);
  for (int j = 0; j < 2; ++j) { EXPECT_TRUE(test::quatNear(rig->joints[j].limit.rotation, expected)) << "joint " << j; }
  EXPECT_EQ(test::countWarnings(rig->warnings, "limit-rotation-invalid"), 2);
  EXPECT_TRUE(test::hasWarning(rig->warnings, "limit-rotation-invalid", "length 1.41421e+20"))
      << test::describeWarnings(rig->warnings);
  EXPECT_TRUE(test::hasWarning(rig->warnings, "limit-rotation-invalid", "length 1.41421e-25"));
  EXPECT_FALSE(test::hasWarning(rig->warnings, "limit-rotation-invalid", "finite"));

  const json nodes = json::array({test::node("Avatar_Head", {1}), test::node("hair_springbone_1", {2}, {0, -0.1, 0}),
                                  test::node("hair_springbone_2", {3}, {0, -0.1, 0}),
                                  test::node("hair_springbone_end", {}, {0, -0.1, 0})});
  RigOptions options;
  options.limits["hair_springbone_1"] = cone(0.5f, Quat{1e20f, 0, 0, 1e20f});
  options.limits["hair_springbone_2"] = cone(0.5f, Quat{1e-25f, 0, 0, 1e-25f});
  const auto from_options = test::rigFromJson(nodes, {{"hair_springbone_1", {{"isRoot", true}}}}, options);
  ASSERT_EQ(from_options->joints.size(), 2u);
  for (int j = 0; j < 2; ++j) {
    EXPECT_TRUE(test::quatNear(from_options->joints[j].limit.rotation, expected)) << "joint " << j;
  }
  EXPECT_EQ(test::countWarnings(from_options->warnings, "limit-rotation-invalid"), 2);
  EXPECT_FALSE(test::hasWarning(from_options->warnings, "limit-rotation-invalid", "finite"));
}

TEST(JointLimitReading, RigOptionsPutLimitsOnJointsByNameAndWarnAboutOthers) {
  const json nodes = json::array({test::node("Avatar_Head", {1}), test::node("hair_springbone_1", {2}, {0, -0.1, 0}),
                                  test::node("hair_springbone_2", {3}, {0, -0.1, 0}),
                                  test::node("hair_springbone_end", {}, {0, -0.1, 0})});
  const json bones = {{"hair_springbone_1", {{"isRoot", true}}}};
  RigOptions options;
  options.limits["hair_springbone_2"] = cone(7.0f);  // beyond pi: clamped
  options.limits["hair_springbone_end"] = cone(0.5f);
  options.limits["no_such_bone"] = hinge(0.5f);
  JointLimit nan_yaw = spherical(0.5f, NAN);
  options.limits["hair_springbone_1"] = nan_yaw;
  const auto rig = test::rigFromJson(nodes, bones, options);
  ASSERT_EQ(rig->joints.size(), 2u);
  EXPECT_EQ(rig->joints[0].limit.kind, JointLimit::Kind::kSpherical);
  EXPECT_FLOAT_EQ(rig->joints[0].limit.yaw, kPi / 2);
  EXPECT_FLOAT_EQ(rig->joints[1].limit.angle, kPi);
  EXPECT_EQ(test::countWarnings(rig->warnings, "limit-clamped"), 2);
  EXPECT_TRUE(test::hasWarning(rig->warnings, "limit-on-end-joint", "hair_springbone_end"));
  EXPECT_TRUE(test::hasWarning(rig->warnings, "limit-joint-not-found", "no_such_bone"));
}

// ---------------------------------------------------------------------------------------------
// No limited joint leaves its limit

// The limit space of joint j after a step, computed from the instance's world matrices and the
// rig (the parent's world matrix, the rest rotation, the bone axis) and the limit's rotation, as the
// draft defines it.
glm::quat limitSpaceOf(const Rig& rig, const Instance& instance, std::size_t j, const std::vector<glm::mat4>& drivers,
                       const JointLimit& limit) {
  const Joint& joint = rig.joints[j];
  const float* world = instance.worldMatrices();
  const glm::mat4 parent =
      joint.parent_joint >= 0 ? glm::make_mat4(world + 16 * joint.parent_joint) : drivers[joint.parent_driver];
  const glm::mat3 linear(parent);
  const glm::quat parent_rotation =
      glm::quat_cast(glm::mat3(glm::normalize(linear[0]), glm::normalize(linear[1]), glm::normalize(linear[2])));
  const glm::vec3 axis = glm::normalize(toGlm(joint.tail_local));
  const glm::vec3 up(0, 1, 0);
  const glm::quat to_axis = axis == -up ? glm::angleAxis(kPi, glm::vec3(1, 0, 0))
                            : axis == up
                                ? glm::quat(1, 0, 0, 0)
                                : glm::angleAxis(std::acos(glm::dot(up, axis)), glm::normalize(glm::cross(up, axis)));
  return glm::normalize(parent_rotation * toGlm(joint.rest_local.rotation) * to_axis * toGlm(limit.rotation));
}

// How far a unit direction in limit space is outside the limit, radians (0 or less inside).
float beyond(const JointLimit& limit, const glm::vec3& d) {
  const auto clamp1 = [](float v) { return std::clamp(v, -1.0f, 1.0f); };
  switch (limit.kind) {
    case JointLimit::Kind::kCone: return std::acos(clamp1(d.y)) - limit.angle;
    case JointLimit::Kind::kHinge:
      return std::max(std::asin(std::fabs(clamp1(d.x))), std::acos(clamp1(d.y / std::hypot(d.y, d.z))) - limit.angle);
    case JointLimit::Kind::kSpherical:
      return std::max(std::fabs(std::atan2(d.z, d.y)) - limit.pitch, std::fabs(std::asin(clamp1(d.x))) - limit.yaw);
    case JointLimit::Kind::kNone: break;
  }
  return -1.0f;
}

// Shakes and turns the body for 6 s at 60 fps under a gusty side wind, with a sphere the chain
// swings into, and returns the largest angle any joint went beyond `measured` (radians). Every joint
// carries `applied` (kNone: no limit, to show the motion needs one).
float worstExcess(Integrator integrator, const JointLimit& applied, const JointLimit& measured, glm::vec3 bone) {
  json list = json::array();
  for (int n = 1; n <= 3; ++n) {
    list.push_back({{"node", n}, {"stiffness", 0.3}, {"dragForce", 0.2}, {"gravityPower", 0.5}, {"hitRadius", 0.01}});
  }
  list.push_back({{"node", 4}});
  const json colliders =
      json::array({{{"node", 0}, {"shape", {{"sphere", {{"offset", {0.12, -0.15, 0}}, {"radius", 0.06}}}}}}});
  const auto loaded =
      loadVrmDoc(chainNodes(bone), list, colliders, json::array({{{"colliders", {0}}}}), json::array({0}));
  auto rig = std::make_shared<Rig>(*loaded);
  for (Joint& j : rig->joints) j.limit = applied;
  InstanceOptions options;
  options.integrator = integrator;
  Instance instance(rig, options);
  Wind wind;
  wind.direction = Vec3{1, 0, 0.3f};
  wind.strength = 3.0f;
  wind.gust_frequency = 2.0f;
  wind.seed = 7;
  instance.setWind(wind);
  std::vector<glm::mat4> drivers(rig->drivers.size());
  float worst = -10.0f;
  for (int f = 0; f < 360; ++f) {
    const float t = f / 60.0f;
    const glm::mat4 shake =
        glm::translate(glm::mat4(1.0f),
                       glm::vec3(0.4f * std::sin(9.0f * t), 0.2f * std::sin(13.0f * t), 0.3f * std::sin(7.0f * t))) *
        glm::rotate(glm::mat4(1.0f), 1.2f * std::sin(5.0f * t), glm::vec3(0, 0, 1)) *
        glm::rotate(glm::mat4(1.0f), 2.0f * std::sin(3.0f * t), glm::vec3(0, 1, 0));
    for (std::size_t d = 0; d < rig->drivers.size(); ++d) {
      drivers[d] = shake * toGlm(rig->skeleton.nodes[rig->drivers[d].node].rest_world);
      std::memcpy(instance.driverMatrices() + 16 * d, &drivers[d][0][0], 16 * sizeof(float));
    }
    instance.step(1.0 / 60.0);
    const float* world = instance.worldMatrices();
    for (std::size_t j = 0; j < rig->joints.size(); ++j) {
      const glm::vec3 offset = glm::mat3(glm::make_mat4(world + 16 * j)) * toGlm(rig->joints[j].tail_local);
      const glm::vec3 d = glm::conjugate(limitSpaceOf(*rig, instance, j, drivers, measured)) * glm::normalize(offset);
      worst = std::max(worst, beyond(measured, d));
    }
  }
  return worst;
}

struct LimitCase {
  const char* name;
  JointLimit limit;
  glm::vec3 bone;
};

TEST(JointLimitMotion, NoLimitedJointLeavesItsLimitUnderShakingWindAndColliders) {
  const float h = std::sqrt(0.5f);
  const LimitCase cases[] = {
      {"cone 30 degrees, bone straight down (-Y)", cone(kPi / 6), {0, -0.1f, 0}},
      {"cone 20 degrees turned, slanted bone", cone(kPi / 9, Quat{0, 0, 0.258819f, 0.965926f}), {0.03f, -0.1f, 0.02f}},
      {"hinge 45 degrees turned about Y", hinge(kPi / 4, Quat{0, 0.382683f, 0, 0.92388f}), {0, -0.1f, 0}},
      {"spherical pitch 30, yaw 11 degrees",
       spherical(kPi / 6, kPi / 16, Quat{0, 0.258819f, 0, 0.965926f}),
       {0.02f, -0.1f, 0}},
      {"hinge 90 degrees turned about X", hinge(kPi / 2, Quat{h, 0, 0, h}), {0, -0.1f, 0.01f}},
  };
  for (const LimitCase& c : cases) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      const char* which = integrator == Integrator::kXpbd ? "xpbd" : "vrm";
      const float free = worstExcess(integrator, JointLimit{}, c.limit, c.bone);
      const float held = worstExcess(integrator, c.limit, c.limit, c.bone);
      // Without the limit the same motion goes well past it, so the check below can fail.
      EXPECT_GT(free, 0.1f) << c.name << ", " << which;
      EXPECT_LT(held, 1e-3f) << c.name << ", " << which << ": " << held << " rad beyond (free: " << free << ")";
      std::printf("[          ] %s, %s: %.3g rad beyond without the limit, %.3g with it\n", c.name, which, free, held);
    }
  }
}

}  // namespace
}  // namespace springbones
