// VRM spring bones (src/loading/vrm_loader.cpp): the mapping of VRMC_springBone 1.0 and VRM 0.x
// secondaryAnimation onto a Rig, checked on the fixtures of scripts/generate/make_vrm_fixtures.mjs and on
// small documents built here; agreement of the simulation with @pixiv/three-vrm-springbone 3.5.5
// (tests/fixtures/vrm_trajectories.json, scripts/generate/make_vrm_trajectories.mjs); and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "common/typed_encoding.h"
#include "readers/glb_container.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "springbones/vrm.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using nlohmann::json;
using test::describeWarnings;
using test::quatNear;
using test::vecNear;

// Agreement with three-vrm per quaternion component over every frame (see VrmTrajectories).
constexpr double kThreeVrmTolerance = 1e-5;

std::shared_ptr<const Rig> loadFixtureRig(const std::string& name, VrmSpringFormat* format = nullptr) {
  const std::vector<std::uint8_t> bytes = test::readFixture(name);
  std::shared_ptr<const Rig> rig;
  const Error e = loadVrm(bytes.data(), bytes.size(), rig, format);
  EXPECT_FALSE(e) << name << ": " << e.message;
  return rig;
}

// Loads glTF JSON text (a document with the given nodes and extensions) through loadVrm.
Error loadDoc(const json& nodes, const json& extensions, std::shared_ptr<const Rig>& rig,
              VrmSpringFormat* format = nullptr) {
  json doc = {{"asset", {{"version", "2.0"}}}, {"nodes", nodes}};
  if (!extensions.is_null()) doc["extensions"] = extensions;
  const std::string text = doc.dump();
  return loadVrm(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), rig, format);
}

std::shared_ptr<const Rig> mustLoad(const json& nodes, const json& extensions) {
  std::shared_ptr<const Rig> rig;
  const Error e = loadDoc(nodes, extensions, rig);
  EXPECT_FALSE(e) << e.message;
  return rig ? rig : std::make_shared<const Rig>();
}

json gnode(const std::string& name, std::vector<int> children = {}, glm::vec3 t = glm::vec3(0.0f),
           glm::quat r = glm::quat(1, 0, 0, 0), glm::vec3 s = glm::vec3(1.0f)) {
  json n = {{"name", name}, {"translation", {t.x, t.y, t.z}}, {"rotation", {r.x, r.y, r.z, r.w}}};
  if (s != glm::vec3(1.0f)) n["scale"] = {s.x, s.y, s.z};
  if (!children.empty()) n["children"] = children;
  return n;
}

json vrmc(json springs, json colliders = json::array(), json groups = json::array()) {
  return {{"VRMC_springBone",
           {{"specVersion", "1.0"}, {"springs", springs}, {"colliders", colliders}, {"colliderGroups", groups}}}};
}

json vrm0(json bone_groups, json collider_groups = json::array()) {
  return {{"VRM", {{"secondaryAnimation", {{"boneGroups", bone_groups}, {"colliderGroups", collider_groups}}}}}};
}

json joints(std::vector<int> nodes) {
  json out = json::array();
  for (int n : nodes) out.push_back({{"node", n}});
  return out;
}

int jointOfNode(const Rig& rig, int node) {
  for (std::size_t j = 0; j < rig.joints.size(); ++j) {
    if (rig.joints[j].node == node) return static_cast<int>(j);
  }
  return -1;
}

int jointNamed(const Rig& rig, const std::string& name) {
  for (std::size_t j = 0; j < rig.joints.size(); ++j) {
    if (rig.skeleton.nodes[rig.joints[j].node].name == name) return static_cast<int>(j);
  }
  ADD_FAILURE() << "no joint on a node named " << name;
  return -1;
}

const Joint& joint(const Rig& rig, const std::string& name) {
  static const Joint kNone;
  const int j = jointNamed(rig, name);
  return j >= 0 ? rig.joints[j] : kNone;
}

std::string driverName(const Rig& rig, int driver) {
  return driver >= 0 && driver < static_cast<int>(rig.drivers.size()) ? rig.drivers[driver].name : "<none>";
}

// What the solver relies on: joints parents first, parent_joint = the joint of the glTF parent
// whenever that parent is a joint, otherwise a chain root hanging from a driver on that parent; one
// joint per node; chain and chain_roots consistent; indices in range.
void expectRigInvariants(const Rig& rig) {
  const auto& nodes = rig.skeleton.nodes;
  std::set<int> seen_nodes;
  std::set<int> roots(rig.chain_roots.begin(), rig.chain_roots.end());
  for (std::size_t j = 0; j < rig.joints.size(); ++j) {
    const Joint& joint = rig.joints[j];
    ASSERT_GE(joint.node, 0);
    ASSERT_LT(joint.node, static_cast<int>(nodes.size()));
    EXPECT_TRUE(seen_nodes.insert(joint.node).second) << "node " << joint.node << " has two joints";
    const int parent = nodes[joint.node].parent;
    const int parent_joint = parent >= 0 ? jointOfNode(rig, parent) : -1;
    EXPECT_EQ(joint.parent_joint, parent_joint) << nodes[joint.node].name;
    if (joint.parent_joint >= 0) {
      EXPECT_LT(joint.parent_joint, static_cast<int>(j)) << "parents first";
      EXPECT_EQ(joint.parent_driver, -1);
      EXPECT_EQ(joint.chain, rig.joints[joint.parent_joint].chain);
      EXPECT_EQ(roots.count(static_cast<int>(j)), 0u);
    } else {
      EXPECT_EQ(joint.chain, static_cast<int>(j));
      EXPECT_EQ(roots.count(static_cast<int>(j)), 1u);
      if (parent >= 0) {
        ASSERT_GE(joint.parent_driver, 0);
        EXPECT_EQ(rig.drivers[joint.parent_driver].node, parent);
      } else {
        EXPECT_EQ(joint.parent_driver, -1);
      }
    }
    EXPECT_GE(joint.tail_node, -1);
    EXPECT_LT(joint.tail_node, static_cast<int>(nodes.size()));
    EXPECT_GE(joint.center_driver, -1);
    EXPECT_LT(joint.center_driver, static_cast<int>(rig.drivers.size()));
    // In the order the spring lists its groups, a collider of two groups twice (not sorted).
    for (int c : joint.colliders) {
      EXPECT_GE(c, 0);
      EXPECT_LT(c, static_cast<int>(rig.colliders.size()));
    }
    EXPECT_TRUE(std::isfinite(joint.params.stiffness) && joint.params.stiffness >= 0.0f);
    EXPECT_TRUE(std::isfinite(joint.params.gravity_power) && joint.params.gravity_power >= 0.0f);
    EXPECT_TRUE(joint.params.drag >= 0.0f && joint.params.drag <= 1.0f);
    EXPECT_NEAR(glm::length(toGlm(joint.params.gravity_dir)), 1.0f, 1e-5f);
    EXPECT_TRUE(std::isfinite(joint.hit_radius) && joint.hit_radius >= 0.0f);
  }
  EXPECT_EQ(rig.chain_roots.size(), roots.size());
  for (const Collider& c : rig.colliders) {
    ASSERT_GE(c.driver, 0);
    ASSERT_LT(c.driver, static_cast<int>(rig.drivers.size()));
    EXPECT_GE(rig.drivers[c.driver].node, 0);
    EXPECT_GE(c.radius, 0.0f);
  }
  for (const Driver& d : rig.drivers) {
    ASSERT_GE(d.node, 0);
    EXPECT_EQ(d.name, nodes[d.node].name);
    EXPECT_EQ(jointOfNode(rig, d.node), -1) << "a driver on a joint: " << d.name;
  }
}

glm::quat rotationOf(const Instance& instance, std::size_t j) {
  const float* r = instance.rotations() + 4 * j;
  return glm::quat(r[3], r[0], r[1], r[2]);
}

glm::mat4 worldOf(const Instance& instance, std::size_t j) {
  glm::mat4 m;
  std::memcpy(&m[0][0], instance.worldMatrices() + 16 * j, sizeof(float) * 16);
  return m;
}

// ---------------------------------------------------------------------------------------------
// The VRM 1.0 fixture

TEST(VrmLoader, Vrm10FixtureMapsSpringsJointsAndTails) {
  VrmSpringFormat format = VrmSpringFormat::kNone;
  auto rig = loadFixtureRig("vrm10_springs.vrm", &format);
  ASSERT_TRUE(rig);
  EXPECT_EQ(format, VrmSpringFormat::kVrmcSpringBone1);
  expectRigInvariants(*rig);
  // Two springs of 5 and 4 listed joints: the last of each is only a tail.
  ASSERT_EQ(rig->joints.size(), 7u) << describeWarnings(rig->warnings);
  const auto& nodes = rig->skeleton.nodes;
  EXPECT_EQ(jointOfNode(*rig, test::nodeIndex(rig->skeleton, "Hair_Back_End")), -1);
  EXPECT_EQ(jointOfNode(*rig, test::nodeIndex(rig->skeleton, "Skirt_L_End")), -1);
  const char* const hair[] = {"Hair_Back_1", "Hair_Back_2", "Hair_Back_3", "Hair_Back_4", "Hair_Back_End"};
  for (int k = 0; k < 4; ++k) {
    const Joint& j = joint(*rig, hair[k]);
    EXPECT_EQ(nodes[j.tail_node].name, hair[k + 1]);
    EXPECT_TRUE(vecNear(j.tail_local, nodes[j.tail_node].rest_local.translation, 0.0f));
    EXPECT_NEAR(
        j.rest_length,
        glm::length(glm::vec3(toGlm(nodes[j.tail_node].rest_world)[3]) - glm::vec3(toGlm(nodes[j.node].rest_world)[3])),
        1e-6f);
    EXPECT_TRUE(quatNear(j.rest_local.rotation, nodes[j.node].rest_local.rotation, 0.0f));
    if (k > 0) { EXPECT_EQ(j.parent_joint, jointNamed(*rig, hair[k - 1])); }
  }
  EXPECT_EQ(nodes[joint(*rig, "Skirt_L_3").tail_node].name, "Skirt_L_End");
  ASSERT_EQ(rig->chain_roots.size(), 2u);
  EXPECT_EQ(driverName(*rig, joint(*rig, "Hair_Back_1").parent_driver), "J_Head");
  EXPECT_EQ(driverName(*rig, joint(*rig, "Skirt_L_1").parent_driver), "J_Hips");
  // Only the intended warning: Hair_Back_4's gravityDir (0, -1.5, 0.5) is not unit.
  ASSERT_EQ(rig->warnings.size(), 1u) << describeWarnings(rig->warnings);
  EXPECT_EQ(rig->warnings[0].code, "vrm-gravity-dir-scaled");
  EXPECT_EQ(rig->warnings[0].path, "/extensions/VRMC_springBone/springs/0/joints/3/gravityDir");
}

TEST(VrmLoader, Vrm10FixtureReadsPerJointParametersCentersAndColliders) {
  auto rig = loadFixtureRig("vrm10_springs.vrm");
  ASSERT_TRUE(rig);
  const Joint& h1 = joint(*rig, "Hair_Back_1");
  EXPECT_FLOAT_EQ(h1.params.stiffness, 1.2f);
  EXPECT_FLOAT_EQ(h1.params.gravity_power, 0.4f);
  EXPECT_FLOAT_EQ(h1.params.drag, 0.35f);
  EXPECT_FLOAT_EQ(h1.hit_radius, 0.02f);
  EXPECT_TRUE(vecNear(h1.params.gravity_dir, {0, -1, 0}, 0.0f));
  EXPECT_FLOAT_EQ(joint(*rig, "Hair_Back_3").hit_radius, 0.015f);
  // A joint's own parameters, not the next one's (Hair_Back_End's are unused).
  const Joint& h4 = joint(*rig, "Hair_Back_4");
  EXPECT_FLOAT_EQ(h4.params.stiffness, 0.5f);
  EXPECT_FLOAT_EQ(h4.params.drag, 0.25f);
  // gravityDir (0, -1.5, 0.5) x 0.3: unit direction, the length folded into the power.
  const float len = std::sqrt(1.5f * 1.5f + 0.5f * 0.5f);
  EXPECT_TRUE(vecNear(h4.params.gravity_dir, glm::vec3(0, -1.5f, 0.5f) / len, 1e-6f));
  EXPECT_NEAR(h4.params.gravity_power, 0.3f * len, 1e-6f);
  EXPECT_TRUE(vecNear(toGlm(h4.params.gravity_dir) * h4.params.gravity_power, glm::vec3(0, -1.5f, 0.5f) * 0.3f, 1e-6f));

  // Centers: the skirt's is J_Hips (also its root's parent driver), the hair has none.
  EXPECT_EQ(h1.center_driver, -1);
  for (const char* s : {"Skirt_L_1", "Skirt_L_2", "Skirt_L_3"}) {
    EXPECT_EQ(driverName(*rig, joint(*rig, s).center_driver), "J_Hips") << s;
  }
  EXPECT_EQ(joint(*rig, "Skirt_L_1").center_driver, joint(*rig, "Skirt_L_1").parent_driver);

  // Colliders in file order: head sphere, two leg capsules, chest sphere.
  ASSERT_EQ(rig->colliders.size(), 4u);
  const Collider& head = rig->colliders[0];
  EXPECT_EQ(head.shape, Collider::Shape::kSphere);
  EXPECT_EQ(driverName(*rig, head.driver), "J_Head");
  EXPECT_TRUE(vecNear(head.offset, {0, 0.07f, -0.01f}, 0.0f));
  EXPECT_TRUE(vecNear(head.tail, head.offset, 0.0f));
  EXPECT_FLOAT_EQ(head.radius, 0.115f);
  const Collider& leg = rig->colliders[1];
  EXPECT_EQ(leg.shape, Collider::Shape::kCapsule);
  EXPECT_EQ(driverName(*rig, leg.driver), "J_UpperLeg_L");
  EXPECT_TRUE(vecNear(leg.offset, {0, 0, 0}, 0.0f));
  EXPECT_TRUE(vecNear(leg.tail, {0, -0.4f, 0.02f}, 0.0f));
  EXPECT_FLOAT_EQ(leg.radius, 0.07f);
  EXPECT_EQ(driverName(*rig, rig->colliders[2].driver), "J_UpperLeg_R");
  EXPECT_EQ(driverName(*rig, rig->colliders[3].driver), "J_Chest");
  // Groups: hair -> head + chest, skirt -> both legs.
  EXPECT_EQ(h1.colliders, (std::vector<int>{0, 3}));
  EXPECT_EQ(joint(*rig, "Hair_Back_4").colliders, (std::vector<int>{0, 3}));
  EXPECT_EQ(joint(*rig, "Skirt_L_2").colliders, (std::vector<int>{1, 2}));
  std::set<std::string> drivers;
  for (const Driver& d : rig->drivers) drivers.insert(d.name);
  EXPECT_EQ(drivers, (std::set<std::string>{"J_Head", "J_Hips", "J_UpperLeg_L", "J_UpperLeg_R", "J_Chest"}));
}

// ---------------------------------------------------------------------------------------------
// The VRM 0.x fixture

TEST(VrmLoader, ExtendedColliderFixtureReadsPlaneInsideShapesAndAFallback) {
  auto rig = loadFixtureRig("vrm10_extended_colliders.vrm");
  ASSERT_TRUE(rig);
  expectRigInvariants(*rig);
  ASSERT_EQ(rig->colliders.size(), 4u) << describeWarnings(rig->warnings);
  const auto& c = rig->colliders;
  EXPECT_EQ(c[0].shape, Collider::Shape::kPlane);
  EXPECT_TRUE(vecNear(c[0].offset, {0, 0, -0.1f}, 0.0f));
  EXPECT_TRUE(vecNear(c[0].normal, {0, 0, -1}, 0.0f));
  EXPECT_EQ(c[1].shape, Collider::Shape::kSphere);
  EXPECT_TRUE(c[1].inside);
  EXPECT_FLOAT_EQ(c[1].radius, 0.045f);
  EXPECT_EQ(c[2].shape, Collider::Shape::kCapsule);
  EXPECT_TRUE(c[2].inside);
  EXPECT_TRUE(vecNear(c[2].tail, {0, -0.35f, -0.22f}, 0.0f));
  EXPECT_EQ(c[3].shape, Collider::Shape::kSphere);  // the unknown version's base sphere
  EXPECT_FALSE(c[3].inside);
  EXPECT_EQ(driverName(*rig, c[3].driver), "J_Chest");
  EXPECT_EQ(test::countWarnings(rig->warnings, "vrm-extended-collider"), 1) << describeWarnings(rig->warnings);
  EXPECT_EQ(joint(*rig, "Hair_Back_1").colliders, (std::vector<int>{0, 3}));
  EXPECT_EQ(joint(*rig, "Ear_L_2").colliders, (std::vector<int>{1}));
  EXPECT_EQ(joint(*rig, "Tail_3").colliders, (std::vector<int>{2}));
}

TEST(VrmLoader, Vrm0FixtureMapsBoneGroupsToEveryDescendant) {
  VrmSpringFormat format = VrmSpringFormat::kNone;
  auto rig = loadFixtureRig("vrm0_springs.vrm", &format);
  ASSERT_TRUE(rig);
  EXPECT_EQ(format, VrmSpringFormat::kVrm0);
  expectRigInvariants(*rig);
  EXPECT_TRUE(rig->warnings.size() == 1u && rig->warnings[0].code == "vrm-gravity-dir-scaled")
      << describeWarnings(rig->warnings);
  ASSERT_EQ(rig->joints.size(), 8u);
  const auto& nodes = rig->skeleton.nodes;
  // The branching root: first child is the tail, the second child is a joint of its own.
  const Joint& hair = joint(*rig, "Hair_1");
  EXPECT_EQ(nodes[hair.tail_node].name, "Hair_1_a");
  EXPECT_EQ(joint(*rig, "Hair_1_side").parent_joint, jointNamed(*rig, "Hair_1"));
  EXPECT_EQ(joint(*rig, "Hair_1_a").parent_joint, jointNamed(*rig, "Hair_1"));
  // Leaves: a virtual tail 7 cm along the leaf's own translation, in its own frame.
  for (const char* leaf : {"Hair_1_a_b", "Hair_1_side", "Ear_L", "Tail_3"}) {
    const Joint& j = joint(*rig, leaf);
    EXPECT_EQ(j.tail_node, -1) << leaf;
    const glm::vec3 t = toGlm(nodes[j.node].rest_local.translation);
    EXPECT_TRUE(vecNear(j.tail_local, glm::normalize(t) * 0.07f, 1e-7f)) << leaf;
    EXPECT_NEAR(j.rest_length, 0.07f, 1e-6f) << leaf;
  }
  // Ear_L is a root that is itself a leaf: one joint hanging from J_Head.
  EXPECT_EQ(driverName(*rig, joint(*rig, "Ear_L").parent_driver), "J_Head");
  // Group parameters on every joint of the group.
  for (const char* name : {"Hair_1", "Hair_1_a", "Hair_1_a_b", "Hair_1_side", "Ear_L"}) {
    const Joint& j = joint(*rig, name);
    EXPECT_FLOAT_EQ(j.params.stiffness, 1.1f) << name;
    EXPECT_FLOAT_EQ(j.params.gravity_power, 0.3f) << name;
    EXPECT_FLOAT_EQ(j.params.drag, 0.3f) << name;
    EXPECT_FLOAT_EQ(j.hit_radius, 0.015f) << name;
    EXPECT_EQ(j.center_driver, -1) << name;  // center -1: none, and no warning
    EXPECT_EQ(j.colliders, (std::vector<int>{0, 1})) << name;
  }
  const float len = std::sqrt(0.3f * 0.3f + 1.2f * 1.2f);
  for (const char* name : {"Tail_1", "Tail_2", "Tail_3"}) {
    const Joint& j = joint(*rig, name);
    EXPECT_FLOAT_EQ(j.params.stiffness, 0.7f) << name;
    EXPECT_FLOAT_EQ(j.params.drag, 0.2f) << name;
    EXPECT_TRUE(vecNear(j.params.gravity_dir, glm::vec3(0.3f, -1.2f, 0) / len, 1e-6f)) << name;
    EXPECT_NEAR(j.params.gravity_power, 0.5f * len, 1e-6f) << name;
    EXPECT_EQ(driverName(*rig, j.center_driver), "J_Hips") << name;
    EXPECT_EQ(j.colliders, (std::vector<int>{2})) << name;
  }
  // Sphere colliders, offsets converted from Unity's axes (z negated).
  ASSERT_EQ(rig->colliders.size(), 3u);
  EXPECT_TRUE(vecNear(rig->colliders[0].offset, {0, 0.07f, -0.01f}, 0.0f));
  EXPECT_FLOAT_EQ(rig->colliders[0].radius, 0.1f);
  EXPECT_TRUE(vecNear(rig->colliders[1].offset, {0, -0.02f, -0.06f}, 0.0f));
  EXPECT_TRUE(vecNear(rig->colliders[2].offset, {0, -0.16f, -0.14f}, 0.0f));
  EXPECT_EQ(driverName(*rig, rig->colliders[2].driver), "J_Hips");
  for (const Collider& c : rig->colliders) EXPECT_EQ(c.shape, Collider::Shape::kSphere);
}

// ---------------------------------------------------------------------------------------------
// Simulation against three-vrm 3.5.5

TEST(VrmTrajectories, AgreeWithThreeVrmOnEveryFixture) {
  const json reference = json::parse(test::readFixtureText("vrm_trajectories.json"));
  ASSERT_EQ(reference["models"].size(), 3u);
  const double fps = reference["fps"].get<double>();
  for (const json& model : reference["models"]) {
    const std::string file = model["file"];
    auto rig = loadFixtureRig(file);
    ASSERT_TRUE(rig);
    Instance instance(rig, InstanceOptions{fps, 4});
    // Every driver's matrices are recorded, every joint's rotations too.
    for (const Driver& d : rig->drivers) {
      ASSERT_TRUE(model["drivers"].contains(std::to_string(d.node))) << file << ": driver " << d.name;
    }
    ASSERT_EQ(model["rotations"].size(), rig->joints.size()) << file;
    const std::size_t frames = reference["frames"].get<std::size_t>();
    double worst = 0.0, worst_stock = 0.0;
    std::size_t worst_frame = 0;
    std::string worst_joint;
    for (std::size_t f = 0; f < frames; ++f) {
      for (std::size_t d = 0; d < rig->drivers.size(); ++d) {
        const json& m = model["drivers"][std::to_string(rig->drivers[d].node)][f];
        for (int i = 0; i < 16; ++i) instance.driverMatrices()[16 * d + i] = m[i].get<float>();
      }
      instance.step(1.0 / fps);
      for (std::size_t j = 0; j < rig->joints.size(); ++j) {
        const std::string key = std::to_string(rig->joints[j].node);
        ASSERT_TRUE(model["rotations"].contains(key)) << file << ": joint node " << key;
        const glm::quat got = rotationOf(instance, j);
        auto difference = [&](const json& q) {
          const glm::quat want(q[3].get<float>(), q[0].get<float>(), q[1].get<float>(), q[2].get<float>());
          const float sign = glm::dot(got, want) < 0.0f ? -1.0f : 1.0f;
          double d = 0.0;
          for (int i = 0; i < 4; ++i) d = std::max(d, double(std::fabs(got[i] - sign * want[i])));
          return d;
        };
        const double d = difference(model["rotations"][key][f]);
        if (d > worst) {
          worst = d;
          worst_frame = f + 1;
          worst_joint = rig->skeleton.nodes[rig->joints[j].node].name;
        }
        worst_stock = std::max(worst_stock, difference(model["stockRotations"][key][f]));
      }
    }
    EXPECT_LT(worst, kThreeVrmTolerance) << file << ": worst at frame " << worst_frame << ", joint " << worst_joint;
    // Unmodified three-vrm (bone length from the previous frame) is measurably elsewhere: the
    // comparison above is sensitive to the bone length.
    EXPECT_GT(worst_stock, 100 * kThreeVrmTolerance) << file;
    std::cout << "[          ] " << file << ": max |dq| " << worst << " (frame " << worst_frame << ", " << worst_joint
              << "); stock three-vrm " << worst_stock << "\n";
  }
}

// ---------------------------------------------------------------------------------------------
// VRMC_springBone mapping details

// Root(0) -> Head(1) -> A(2) -> B(3, rotated, scaled) -> C(4) -> D(5) -> E(6)
json chainNodes(glm::vec3 b_scale = glm::vec3(1.0f)) {
  const glm::quat b_rotation = glm::angleAxis(0.4f, glm::normalize(glm::vec3(1, 0, 1)));
  return json::array({gnode("Root", {1}), gnode("Head", {2}, {0, 1.5f, 0}), gnode("A", {3}, {0, 0.1f, -0.1f}),
                      gnode("B", {4}, {0, -0.05f, 0}, b_rotation, b_scale), gnode("C", {5}, {0.01f, -0.06f, 0}),
                      gnode("D", {6}, {0, -0.05f, 0}), gnode("E", {}, {0, -0.05f, 0})});
}

TEST(VrmLoader, SkippedNodesBetweenJointsAreHeldAtRest) {
  auto rig = mustLoad(chainNodes(), vrmc(json::array({{{"joints", joints({2, 4, 6})}}})));
  expectRigInvariants(*rig);
  // A (tail C), B fixed, C (tail E), D fixed.
  ASSERT_EQ(rig->joints.size(), 4u) << describeWarnings(rig->warnings);
  const auto& nodes = rig->skeleton.nodes;
  const Joint& a = joint(*rig, "A");
  EXPECT_EQ(a.tail_node, 4);
  // C in A's frame: B's local transform applied to C's translation.
  const glm::vec3 expected = toGlm(nodes[3].rest_local.translation) +
                             toGlm(nodes[3].rest_local.rotation) * toGlm(nodes[4].rest_local.translation);
  EXPECT_TRUE(vecNear(a.tail_local, expected, 1e-6f));
  EXPECT_NEAR(a.rest_length,
              glm::length(glm::vec3(toGlm(nodes[4].rest_world)[3]) - glm::vec3(toGlm(nodes[2].rest_world)[3])), 1e-6f);
  const Joint& b = joint(*rig, "B");
  EXPECT_EQ(b.tail_node, 4);
  EXPECT_TRUE(vecNear(b.tail_local, glm::vec3(0.0f), 0.0f));
  EXPECT_EQ(b.rest_length, 0.0f);
  EXPECT_TRUE(b.colliders.empty());
  EXPECT_EQ(joint(*rig, "C").parent_joint, jointNamed(*rig, "B"));
  EXPECT_EQ(joint(*rig, "C").tail_node, 6);
  EXPECT_EQ(test::countWarnings(rig->warnings, "vrm-fixed-nodes"), 2) << describeWarnings(rig->warnings);
  EXPECT_EQ(rig->warnings.size(), 2u) << describeWarnings(rig->warnings);
}

// Fixed joints keep their rest rotation and carry the chain: the listed next joint sits exactly
// where the simulated bone points, on the fast path and on the general one (non-uniform scale).
TEST(VrmLoader, SkippedNodesComposeThroughTheSolverOnBothPaths) {
  for (glm::vec3 scale : {glm::vec3(1.0f), glm::vec3(1.0f, 1.6f, 0.8f)}) {
    json ext = vrmc(json::array({{{"joints", joints({2, 4, 6})}}}));
    for (auto& j : ext["VRMC_springBone"]["springs"][0]["joints"]) {
      j["gravityPower"] = 1.0;
      j["stiffness"] = 0.3;
      j["dragForce"] = 0.1;
    }
    auto rig = mustLoad(chainNodes(scale), ext);
    ASSERT_EQ(rig->joints.size(), 4u);
    Instance instance(rig, InstanceOptions{60, 4});
    const int head = 0;  // driver: Head
    ASSERT_EQ(rig->drivers[head].name, "Head");
    const int a = jointNamed(*rig, "A"), b = jointNamed(*rig, "B"), c = jointNamed(*rig, "C");
    for (int f = 0; f < 90; ++f) {
      const glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(0.2f * std::sin(f * 0.1f), 1.5f, 0)) *
                          glm::rotate(glm::mat4(1.0f), 0.8f * std::sin(f * 0.07f), glm::vec3(0, 0, 1));
      std::memcpy(instance.driverMatrices() + 16 * head, &m[0][0], sizeof(float) * 16);
      instance.step(1.0 / 60.0);
      EXPECT_TRUE(quatNear(rotationOf(instance, b), rig->joints[b].rest_local.rotation, 1e-6f));
      const glm::vec3 aimed = glm::vec3(worldOf(instance, a) * glm::vec4(toGlm(rig->joints[a].tail_local), 1.0f));
      EXPECT_TRUE(vecNear(glm::vec3(worldOf(instance, c)[3]), aimed, 1e-5f)) << "frame " << f;
    }
    // The joints did move.
    EXPECT_FALSE(quatNear(rotationOf(instance, a), rig->joints[a].rest_local.rotation, 1e-3f));
  }
}

TEST(VrmLoader, SpringsEndAtAJointThatIsNotADescendant) {
  // Joints A, C, E, B: B lies above E, so the spring ends with the pair C -> E (E only a tail).
  auto rig = mustLoad(chainNodes(), vrmc(json::array({{{"joints", joints({2, 4, 6, 3})}}})));
  expectRigInvariants(*rig);
  const Warning* w =
      test::findWarning(rig->warnings, "vrm-joint-not-descendant", "/extensions/VRMC_springBone/springs/0/joints/3");
  ASSERT_NE(w, nullptr);
  EXPECT_NE(w->message.find("'B'"), std::string::npos) << w->message;
  EXPECT_EQ(jointNamed(*rig, "C") >= 0, true);
  EXPECT_EQ(jointOfNode(*rig, 6), -1);  // E only a tail
  // A sibling as next joint.
  json nodes = json::array({gnode("R", {1, 2}), gnode("X", {}, {0, 1, 0}), gnode("Y", {}, {1, 0, 0})});
  auto sibling = mustLoad(nodes, vrmc(json::array({{{"joints", joints({1, 2})}}})));
  EXPECT_TRUE(sibling->joints.empty());
  EXPECT_EQ(test::countWarnings(sibling->warnings, "vrm-joint-not-descendant"), 1);
}

TEST(VrmLoader, ANodeIsSimulatedByTheFirstSpringOnly) {
  // Spring 0: A, B, C (B simulated). Spring 1: B, C, D: B is taken, the whole spring 1 is dropped
  // at its first pair. Spring 2: D, E works (D under C, C is spring 0's tail only: held at rest).
  auto rig =
      mustLoad(chainNodes(),
               vrmc(json::array(
                   {{{"joints", joints({2, 3, 4})}}, {{"joints", joints({3, 4, 5})}}, {{"joints", joints({5, 6})}}})));
  expectRigInvariants(*rig);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-joint-conflict", "/extensions/VRMC_springBone/springs/1/joints/0"),
            nullptr);
  ASSERT_NE(test::findWarning(rig->warnings, "vrm-fixed-nodes", "/extensions/VRMC_springBone/springs/2"), nullptr);
  // A, B simulated; C fixed (it is between B's joint and D's); D simulated.
  ASSERT_EQ(rig->joints.size(), 4u) << describeWarnings(rig->warnings);
  EXPECT_EQ(joint(*rig, "C").tail_node, 5);
  EXPECT_TRUE(vecNear(joint(*rig, "C").tail_local, glm::vec3(0.0f), 0.0f));
  EXPECT_EQ(joint(*rig, "D").parent_joint, jointNamed(*rig, "C"));
  EXPECT_EQ(joint(*rig, "D").tail_node, 6);
  EXPECT_EQ(rig->chain_roots.size(), 1u);
  // A later spring whose pair passes through a simulated node is cut there as well.
  auto through =
      mustLoad(chainNodes(), vrmc(json::array({{{"joints", joints({3, 4})}}, {{"joints", joints({2, 5})}}})));
  EXPECT_EQ(test::countWarnings(through->warnings, "vrm-joint-conflict"), 1);
  EXPECT_EQ(jointNamed(*through, "B"), 0);
  EXPECT_EQ(through->joints.size(), 1u);
}

TEST(VrmLoader, MissingParametersGetTheSpecDefaults) {
  auto rig = mustLoad(chainNodes(), vrmc(json::array({{{"joints", joints({2, 3})}}})));
  ASSERT_EQ(rig->joints.size(), 1u);
  const Joint& a = rig->joints[0];
  EXPECT_FLOAT_EQ(a.params.stiffness, 1.0f);
  EXPECT_FLOAT_EQ(a.params.gravity_power, 0.0f);
  EXPECT_TRUE(vecNear(a.params.gravity_dir, {0, -1, 0}, 0.0f));
  EXPECT_FLOAT_EQ(a.params.drag, 0.5f);  // spec; three-vrm would use 0.4
  EXPECT_FLOAT_EQ(a.hit_radius, 0.0f);
  EXPECT_EQ(a.center_driver, -1);
  EXPECT_TRUE(a.colliders.empty());
  EXPECT_TRUE(rig->warnings.empty()) << describeWarnings(rig->warnings);
}

TEST(VrmLoader, BadParametersAreClampedOrReplacedWithWarnings) {
  json j0 = {{"node", 2},        {"stiffness", -1},    {"gravityPower", "heavy"},
             {"dragForce", 1.5}, {"hitRadius", 1e300}, {"gravityDir", {0, 0, 0}}};
  json j1 = {{"node", 3},         {"stiffness", 1e30}, {"gravityPower", 2}, {"gravityDir", {1, "x", 0}},
             {"dragForce", -0.5}, {"hitRadius", 1e30}};
  const std::string p = "/extensions/VRMC_springBone/springs/0/joints/";
  auto rig = mustLoad(chainNodes(), vrmc(json::array({{{"joints", {j0, j1, {{"node", 4}}}}}})));
  expectRigInvariants(*rig);
  const Joint& a = joint(*rig, "A");
  EXPECT_EQ(a.params.stiffness, 0.0f);
  EXPECT_EQ(a.params.gravity_power, 0.0f);
  EXPECT_EQ(a.params.drag, 1.0f);
  EXPECT_EQ(a.hit_radius, 0.0f);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-param-clamped", p + "0/stiffness"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-param-invalid", p + "0/gravityPower"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-param-clamped", p + "0/dragForce"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-param-invalid", p + "0/hitRadius"), nullptr);
  // Zero gravityDir with zero power: no gravity, nothing to say.
  EXPECT_EQ(test::countWarnings(rig->warnings, "vrm-gravity-dir-zero"), 0);
  const Joint& b = joint(*rig, "B");
  EXPECT_EQ(b.params.stiffness, 1e30f);  // no upper bound in the VRMC_springBone schema
  EXPECT_TRUE(vecNear(b.params.gravity_dir, {0, -1, 0}, 0.0f));
  EXPECT_EQ(b.params.gravity_power, 2.0f);
  EXPECT_EQ(b.params.drag, 0.0f);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-param-invalid", p + "1/gravityDir"), nullptr);
  // hitRadius is bounded like every rig's (kMaxHitRadius): beyond it a collider would move nothing.
  EXPECT_EQ(b.hit_radius, kMaxHitRadius);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-param-clamped", p + "1/hitRadius"), nullptr);
  // Zero direction with a power: no gravity, with a warning.
  json j2 = {{"node", 2}, {"gravityPower", 1}, {"gravityDir", {0, 0, 0}}};
  auto zero = mustLoad(chainNodes(), vrmc(json::array({{{"joints", {j2, {{"node", 3}}}}}})));
  ASSERT_EQ(zero->joints.size(), 1u);
  EXPECT_EQ(zero->joints[0].params.gravity_power, 0.0f);
  EXPECT_EQ(test::countWarnings(zero->warnings, "vrm-gravity-dir-zero"), 1);
  // The simulation stays finite with the extreme stiffness.
  Instance instance(rig, InstanceOptions{60, 4});
  for (int f = 0; f < 30; ++f) instance.step(1.0 / 60.0);
  for (std::size_t j = 0; j < instance.jointCount(); ++j) {
    const glm::quat q = rotationOf(instance, j);
    EXPECT_TRUE(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w));
  }
}

TEST(VrmLoader, CentersResolveToDriversOrFallBackToWorldSpace) {
  auto spring = [](json center) {
    json s = {{"joints", joints({2, 3, 4})}};
    if (!center.is_null()) s["center"] = center;
    return s;
  };
  auto head = mustLoad(chainNodes(), vrmc(json::array({spring(1)})));
  for (const Joint& j : head->joints) EXPECT_EQ(driverName(*head, j.center_driver), "Head");
  EXPECT_EQ(head->drivers.size(), 1u);  // parent and center share the driver
  EXPECT_TRUE(head->warnings.empty()) << describeWarnings(head->warnings);
  // The spring's own first joint: it moves with the simulation, so world space.
  auto self = mustLoad(chainNodes(), vrmc(json::array({spring(2)})));
  for (const Joint& j : self->joints) EXPECT_EQ(j.center_driver, -1);
  EXPECT_NE(test::findWarning(self->warnings, "center-is-spring-bone", "/extensions/VRMC_springBone/springs/0/center"),
            nullptr);
  // Below a joint (E under D under C...): world space too.
  auto below = mustLoad(chainNodes(),
                        vrmc(json::array({{{"joints", joints({2, 3})}}, {{"joints", joints({4, 5})}, {"center", 3}}})));
  EXPECT_EQ(joint(*below, "C").center_driver, -1);
  EXPECT_EQ(test::countWarnings(below->warnings, "center-is-spring-bone"), 1);
  for (json bad : {json(99), json(-1), json("Head"), json(1.5)}) {
    auto rig = mustLoad(chainNodes(), vrmc(json::array({spring(bad)})));
    for (const Joint& j : rig->joints) EXPECT_EQ(j.center_driver, -1);
    EXPECT_EQ(test::countWarnings(rig->warnings, "center-not-found"), 1) << bad.dump();
  }
}

TEST(VrmLoader, CollidersShapesGroupsAndSkips) {
  json nodes = chainNodes();
  json colliders = json::array({
      {{"node", 1}, {"shape", {{"sphere", {{"offset", {0, 0.1, 0}}, {"radius", 0.1}}}}}},                       // 0 ok
      {{"node", 0}, {"shape", {{"capsule", {{"offset", {0, 0, 0}}, {"radius", 0.05}, {"tail", {0, 1, 0}}}}}}},  // 1 ok
      {{"node", 3}, {"shape", {{"sphere", {{"radius", 0.1}}}}}},  // 2 on joint B
      {{"node", 1}, {"shape", {{"sphere", {{"radius", -1}}}}}},   // 3 invalid
      {{"node", 1}, {"shape", {{"plane", {}}}}},                  // 4 no base shape
      {{"node", 1},
       {"shape", {{"sphere", {{"radius", 0.02}}}}},
       {"extensions",
        {{"VRMC_springBone_extended_collider",
          {{"specVersion", "1.0"}, {"shape", {{"plane", json::object()}}}}}}}},  // 5 plane
      {{"node", 42}, {"shape", {{"sphere", {{"radius", 0.1}}}}}},                // 6 no such node
      {{"node", 0}, {"shape", {{"sphere", {{"radius", 0.3}}}}}},                 // 7 unused by any spring
  });
  json groups = json::array({{{"colliders", {1, 0}}}, {{"colliders", {2, 3, 4, 5, 6, 99}}}, {{"colliders", {7}}}});
  json springs = json::array({{{"joints", joints({2, 3, 4})}, {"colliderGroups", {1, 0, 0, 7}}}});
  auto rig = mustLoad(nodes, vrmc(springs, colliders, groups));
  expectRigInvariants(*rig);
  // Kept, in file order: 0 (sphere on Head), 1 (capsule on Root), 5 (a plane on Head, the
  // extension's default normal).
  ASSERT_EQ(rig->colliders.size(), 3u) << describeWarnings(rig->warnings);
  EXPECT_EQ(rig->colliders[0].shape, Collider::Shape::kSphere);
  EXPECT_EQ(rig->colliders[1].shape, Collider::Shape::kCapsule);
  EXPECT_TRUE(vecNear(rig->colliders[1].tail, {0, 1, 0}, 0.0f));
  EXPECT_EQ(rig->colliders[2].shape, Collider::Shape::kPlane);
  EXPECT_TRUE(vecNear(rig->colliders[2].normal, {0, 0, 1}, 0.0f));
  EXPECT_EQ(rig->colliders[2].radius, 0.0f);
  // A joint tests them in the order the spring lists its groups (1, then 0), as three-vrm does.
  for (const Joint& j : rig->joints) EXPECT_EQ(j.colliders, (std::vector<int>{2, 1, 0}));
  const std::string p = "/extensions/VRMC_springBone/";
  EXPECT_NE(test::findWarning(rig->warnings, "collider-on-spring-bone", p + "colliders/2"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-invalid", p + "colliders/3"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-invalid", p + "colliders/4"), nullptr);
  EXPECT_EQ(test::countWarnings(rig->warnings, "vrm-extended-collider"), 0) << describeWarnings(rig->warnings);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-invalid", p + "colliders/6"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-group-invalid", p + "colliderGroups/1/colliders/5"),
            nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-group-invalid", p + "springs/0/colliderGroups/3"), nullptr);
  // Root and Head are drivers (Head: parent of A and collider node), nothing for collider 7.
  EXPECT_EQ(rig->drivers.size(), 2u);
}

// Sizes beyond kMaxColliderSize (1e6) would make the squared distances overflow in float and the
// collider move nothing: left out with a warning, as for loadRig's colliders.
TEST(VrmLoader, CollidersBeyondTheSizeLimitAreIgnoredWithAWarning) {
  json colliders = json::array({
      {{"node", 1}, {"shape", {{"sphere", {{"offset", {0, 0.1, 0}}, {"radius", 1e30}}}}}},  // 0 radius
      {{"node", 1}, {"shape", {{"capsule", {{"radius", 0.05}, {"tail", {0, -1e7, 0}}}}}}},  // 1 tail
      {{"node", 1},
       {"shape", {{"sphere", {{"radius", 0.02}}}}},
       {"extensions",
        {{"VRMC_springBone_extended_collider",
          {{"specVersion", "1.0"}, {"shape", {{"plane", {{"offset", {3e38, 0, 0}}}}}}}}}}},  // 2 plane offset
      {{"node", 1},
       {"shape",
        {{"sphere", {{"offset", {kMaxColliderSize, 0, 0}}, {"radius", kMaxColliderSize}}}}}},  // 3 at the limit
  });
  json groups = json::array({{{"colliders", {0, 1, 2, 3}}}});
  json springs = json::array({{{"joints", joints({2, 3, 4})}, {"colliderGroups", {0}}}});
  auto rig = mustLoad(chainNodes(), vrmc(springs, colliders, groups));
  expectRigInvariants(*rig);
  ASSERT_EQ(rig->colliders.size(), 1u) << describeWarnings(rig->warnings);
  EXPECT_EQ(rig->colliders[0].radius, kMaxColliderSize);
  const std::string p = "/extensions/VRMC_springBone/colliders/";
  for (int c : {0, 1, 2}) {
    EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-invalid", p + std::to_string(c)), nullptr) << c;
  }
}

// VRMC_springBone_extended_collider: a readable shape of a known version replaces the base
// shape; anything else falls back to the base shape with a warning.
TEST(VrmLoader, ExtendedCollidersReplaceTheBaseShapeOrFallBack) {
  const json base = {{"sphere", {{"offset", {0, 0.2, 0}}, {"radius", 0.3}}}};
  auto extended = [&](json ext) {
    return json{{"node", 1}, {"shape", base}, {"extensions", {{"VRMC_springBone_extended_collider", ext}}}};
  };
  auto known = [](json shape, const std::string& version = "1.0") {
    return json{{"specVersion", version}, {"shape", shape}};
  };
  json colliders = json::array({
      extended(known({{"sphere", {{"offset", {1, 2, 3}}, {"radius", 0.5}, {"inside", true}}}})),  // 0
      extended(known(
          {{"capsule", {{"offset", {0, 0, 0}}, {"tail", {0, -1, 0}}, {"radius", 0.25}, {"inside", true}}}})),  // 1
      extended(known({{"plane", {{"offset", {0, -0.5, 0}}, {"normal", {0, 2, 0}}}}}, "1.0-draft")),            // 2
      extended(known({{"sphere", {{"radius", 0.1}}}})),                             // 3 outside
      extended(known({{"plane", json::object()}}, "2.0")),                          // 4 unknown version
      extended({{"shape", {{"plane", json::object()}}}}),                           // 5 no version
      extended(known({{"cone", json::object()}})),                                  // 6 unknown shape
      extended(known({{"plane", {{"normal", {0, 0, 0}}}}})),                        // 7 zero normal
      extended(known({{"sphere", {{"radius", -1}}}})),                              // 8 negative radius
      extended(known({{"capsule", {{"inside", "yes"}}}})),                          // 9 inside not a bool
      extended("plane"),                                                            // 10 not an object
      {{"node", 1}, {"shape", {{"sphere", {{"radius", 0.1}, {"inside", true}}}}}},  // 11 base shapes have no inside
      {{"node", 1},
       {"extensions",
        {{"VRMC_springBone_extended_collider", known({{"plane", json::object()}})}}}},  // 12 no base needed
  });
  std::vector<int> all(colliders.size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  auto rig = mustLoad(chainNodes(), vrmc(json::array({{{"joints", joints({2, 3, 4})}, {"colliderGroups", {0}}}}),
                                         colliders, json::array({{{"colliders", all}}})));
  expectRigInvariants(*rig);
  ASSERT_EQ(rig->colliders.size(), colliders.size()) << describeWarnings(rig->warnings);
  const auto& c = rig->colliders;
  EXPECT_EQ(c[0].shape, Collider::Shape::kSphere);
  EXPECT_TRUE(c[0].inside);
  EXPECT_TRUE(vecNear(c[0].offset, {1, 2, 3}, 0.0f));
  EXPECT_EQ(c[0].radius, 0.5f);
  EXPECT_EQ(c[1].shape, Collider::Shape::kCapsule);
  EXPECT_TRUE(c[1].inside);
  EXPECT_TRUE(vecNear(c[1].tail, {0, -1, 0}, 0.0f));
  EXPECT_EQ(c[2].shape, Collider::Shape::kPlane);  // the draft's version is read too
  EXPECT_FALSE(c[2].inside);
  EXPECT_TRUE(vecNear(c[2].offset, {0, -0.5f, 0}, 0.0f));
  EXPECT_TRUE(vecNear(c[2].normal, {0, 1, 0}, 0.0f));  // made unit
  EXPECT_EQ(c[3].shape, Collider::Shape::kSphere);
  EXPECT_FALSE(c[3].inside);
  EXPECT_EQ(c[3].radius, 0.1f);
  for (std::size_t k = 4; k <= 11; ++k) {  // the base sphere
    EXPECT_EQ(c[k].shape, Collider::Shape::kSphere) << k;
    EXPECT_FALSE(c[k].inside) << k;
    EXPECT_TRUE(vecNear(c[k].offset, k == 11 ? glm::vec3(0.0f) : glm::vec3(0, 0.2f, 0), 0.0f)) << k;
  }
  EXPECT_EQ(c[12].shape, Collider::Shape::kPlane);
  const std::string p = "/extensions/VRMC_springBone/colliders/";
  for (int k : {4, 5, 6, 7, 8, 9, 10}) {
    EXPECT_NE(test::findWarning(rig->warnings, "vrm-extended-collider",
                                p + std::to_string(k) + "/extensions/VRMC_springBone_extended_collider"),
              nullptr)
        << k << describeWarnings(rig->warnings);
  }
  EXPECT_EQ(test::countWarnings(rig->warnings, "vrm-extended-collider"), 7) << describeWarnings(rig->warnings);
}

TEST(VrmLoader, ShortOrBrokenSpringsAreSkippedWithWarnings) {
  const std::string p = "/extensions/VRMC_springBone/springs/";
  json springs = json::array({
      {{"joints", joints({2})}},                        // 0: one joint, nothing to simulate
      "spring",                                         // 1: not an object
      {{"joints", "A"}},                                // 2: joints not an array
      {{"joints", {{{"node", 2}}, {{"node", 77}}}}},    // 3: second joint names no node
      {{"joints", {{{"node", 2}}, 5, {{"node", 4}}}}},  // 4: second joint not an object
  });
  auto rig = mustLoad(chainNodes(), vrmc(springs));
  expectRigInvariants(*rig);
  EXPECT_TRUE(rig->joints.empty()) << describeWarnings(rig->warnings);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-spring-invalid", p + "0/joints"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-spring-invalid", p + "1"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-spring-invalid", p + "2/joints"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-joint-invalid", p + "3/joints/1"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-joint-invalid", p + "4/joints/1"), nullptr);
}

TEST(VrmLoader, SpecVersionAndFormatSelection) {
  json ext = vrmc(json::array({{{"joints", joints({2, 3})}}}));
  ext["VRMC_springBone"]["specVersion"] = "2.5";
  ext.update(vrm0(json::array({{{"bones", {5}}}})));
  std::shared_ptr<const Rig> rig;
  VrmSpringFormat format = VrmSpringFormat::kNone;
  ASSERT_FALSE(loadDoc(chainNodes(), ext, rig, &format));
  EXPECT_EQ(format, VrmSpringFormat::kVrmcSpringBone1);
  EXPECT_EQ(rig->joints.size(), 1u);  // only A: the VRM 0.x group is ignored
  EXPECT_EQ(test::countWarnings(rig->warnings, "vrm-spec-version"), 1);
  EXPECT_EQ(test::countWarnings(rig->warnings, "vrm-both-formats"), 1);
  // Neither: an empty rig.
  ASSERT_FALSE(loadDoc(chainNodes(), nullptr, rig, &format));
  EXPECT_EQ(format, VrmSpringFormat::kNone);
  EXPECT_TRUE(rig->joints.empty());
  EXPECT_EQ(test::countWarnings(rig->warnings, "vrm-no-springs"), 1);
  ASSERT_FALSE(loadDoc(chainNodes(), json{{"VRM", {{"meta", {}}}}}, rig, &format));
  EXPECT_EQ(format, VrmSpringFormat::kNone);
  EXPECT_EQ(test::countWarnings(rig->warnings, "vrm-no-springs"), 1);
}

// ---------------------------------------------------------------------------------------------
// VRM 0.x mapping details

TEST(VrmLoader, Vrm0OverlappingRootsAndZeroLengthLeaves) {
  // Group 0 root B (B, C, D, E), group 1 roots A (takes only A: B's subtree is group 0's) and C
  // (taken). The leaf E gets the virtual tail; a leaf at its parent's origin has no direction.
  json nodes = chainNodes();
  nodes[6]["translation"] = {0, 0, 0};
  json groups = json::array({{{"stiffiness", 2.0}, {"dragForce", 0.1}, {"bones", {3}}},
                             {{"stiffiness", 0.5}, {"bones", {2, 4, -3, "x"}}, {"center", -1}}});
  auto rig = mustLoad(nodes, vrm0(groups));
  expectRigInvariants(*rig);
  ASSERT_EQ(rig->joints.size(), 5u) << describeWarnings(rig->warnings);
  EXPECT_FLOAT_EQ(joint(*rig, "B").params.stiffness, 2.0f);
  EXPECT_FLOAT_EQ(joint(*rig, "E").params.stiffness, 2.0f);
  EXPECT_FLOAT_EQ(joint(*rig, "A").params.stiffness, 0.5f);
  EXPECT_FLOAT_EQ(joint(*rig, "A").params.drag, 0.5f);  // missing: the VRMC_springBone schema's default
  EXPECT_EQ(joint(*rig, "B").parent_joint, jointNamed(*rig, "A"));
  const std::string p = "/extensions/VRM/secondaryAnimation/boneGroups/1/bones/";
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-joint-conflict", p + "0"), nullptr);  // A's subtree
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-joint-conflict", p + "1"), nullptr);  // C
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-joint-invalid", p + "2"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-joint-invalid", p + "3"), nullptr);
  // E sits on D's origin: D's bone has no length, nor has E's virtual tail a direction.
  EXPECT_EQ(test::countWarnings(rig->warnings, "zero-length-bone"), 2);
  EXPECT_TRUE(vecNear(joint(*rig, "E").tail_local, glm::vec3(0.0f), 0.0f));
  EXPECT_EQ(test::countWarnings(rig->warnings, "center-not-found"), 0);
}

TEST(VrmLoader, Vrm0CollidersCentersAndVectors) {
  json colliders = json::array({
      {{"node", 1},
       {"colliders",
        {{{"offset", {{"x", 0.1}, {"y", 0.2}, {"z", 0.3}}}, {"radius", 0.05}},
         {{"radius", 0.04}},                               // offset missing: origin
         {{"offset", {{"x", "a"}}}, {"radius", 0.1}},      // invalid
         {{"offset", {{"y", 1}}}, {"radius", -0.1}}}}},    // invalid
      {{"node", 99}, {"colliders", {{{"radius", 0.1}}}}},  // no node
      {{"node", 5}, {"colliders", {{{"radius", 0.1}}}}},   // on joint D
  });
  json groups = json::array({{{"bones", {2}},
                              {"colliderGroups", {0, 1, 2, 5}},
                              {"center", 0},
                              {"gravityDir", {{"x", 0.6}, {"y", -0.8}, {"z", 0.5}}},
                              {"gravityPower", 0.2}}});
  auto rig = mustLoad(chainNodes(), vrm0(groups, colliders));
  expectRigInvariants(*rig);
  ASSERT_EQ(rig->colliders.size(), 2u) << describeWarnings(rig->warnings);
  EXPECT_TRUE(vecNear(rig->colliders[0].offset, {0.1f, 0.2f, -0.3f}, 0.0f));
  EXPECT_TRUE(vecNear(rig->colliders[0].tail, rig->colliders[0].offset, 0.0f));
  EXPECT_TRUE(vecNear(rig->colliders[1].offset, {0, 0, 0}, 0.0f));
  const std::string p = "/extensions/VRM/secondaryAnimation/";
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-invalid", p + "colliderGroups/0/colliders/2"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-invalid", p + "colliderGroups/0/colliders/3"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-group-invalid", p + "colliderGroups/1"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "collider-on-spring-bone", p + "colliderGroups/2/colliders/0"), nullptr);
  EXPECT_NE(test::findWarning(rig->warnings, "vrm-collider-group-invalid", p + "boneGroups/0/colliderGroups/3"),
            nullptr);
  // gravityDir in Unity's axes: z negated, then normalized with the length in the power.
  const glm::vec3 dir(0.6f, -0.8f, -0.5f);
  for (const Joint& j : rig->joints) {
    EXPECT_TRUE(vecNear(j.params.gravity_dir, glm::normalize(dir), 1e-6f));
    EXPECT_NEAR(j.params.gravity_power, 0.2f * glm::length(dir), 1e-6f);
    EXPECT_EQ(driverName(*rig, j.center_driver), "Root");
    EXPECT_EQ(j.colliders, (std::vector<int>{0, 1}));
  }
  // Every descendant of A is a joint; E, the leaf, has a virtual tail.
  EXPECT_EQ(rig->joints.size(), 5u);
  EXPECT_EQ(joint(*rig, "E").tail_node, -1);
}

// ---------------------------------------------------------------------------------------------
// Bad input

TEST(VrmLoader, ContainerAndJsonErrorsComeFromTheLoader) {
  std::shared_ptr<const Rig> rig = std::make_shared<const Rig>();
  const std::uint8_t byte = 0;
  EXPECT_EQ(loadVrm(nullptr, 10, rig).code, ErrorCode::kInvalidArgument);
  EXPECT_FALSE(rig);
  EXPECT_EQ(loadVrm(&byte, 0, rig).code, ErrorCode::kGlbTruncated);
  const std::string garbage = "not a model at all";
  EXPECT_EQ(loadVrm(reinterpret_cast<const std::uint8_t*>(garbage.data()), garbage.size(), rig).code,
            ErrorCode::kGlbBadMagic);
  const std::string broken = R"({"asset": {"version": "2.0"}, "extensions": {)";
  EXPECT_EQ(loadVrm(reinterpret_cast<const std::uint8_t*>(broken.data()), broken.size(), rig).code,
            ErrorCode::kGltfBadJson);
  EXPECT_FALSE(rig);
}

TEST(VrmLoader, UnreadableExtensionShapesAreErrorsWithPaths) {
  struct Case {
    json extensions;
    ErrorCode code;
    std::string path;
  };
  const Case cases[] = {
      {json{{"VRMC_springBone", 5}}, ErrorCode::kMetadataInvalid, "/extensions/VRMC_springBone"},
      {json{{"VRMC_springBone", {{"specVersion", "1.0"}, {"springs", 5}}}}, ErrorCode::kMetadataInvalid,
       "/extensions/VRMC_springBone/springs"},
      {json{{"VRMC_springBone", {{"specVersion", "1.0"}, {"colliders", "x"}}}}, ErrorCode::kMetadataInvalid,
       "/extensions/VRMC_springBone/colliders"},
      {json{{"VRMC_springBone", {{"specVersion", "1.0"}, {"colliderGroups", {{"a", 1}}}}}}, ErrorCode::kMetadataInvalid,
       "/extensions/VRMC_springBone/colliderGroups"},
      {json{{"VRM", "x"}}, ErrorCode::kMetadataInvalid, "/extensions/VRM"},
      {json{{"VRM", {{"secondaryAnimation", 1}}}}, ErrorCode::kMetadataInvalid, "/extensions/VRM/secondaryAnimation"},
      {json{{"VRM", {{"secondaryAnimation", {{"boneGroups", 1}}}}}}, ErrorCode::kMetadataInvalid,
       "/extensions/VRM/secondaryAnimation/boneGroups"},
      {json::array({1}), ErrorCode::kGltfInvalid, "/extensions"},
  };
  for (const Case& c : cases) {
    std::shared_ptr<const Rig> rig;
    const Error e = loadDoc(chainNodes(), c.extensions, rig);
    EXPECT_EQ(e.code, c.code) << c.extensions.dump() << ": " << e.message;
    EXPECT_EQ(e.path, c.path) << c.extensions.dump();
    EXPECT_FALSE(e.message.empty());
    EXPECT_FALSE(rig);
  }
}

TEST(VrmLoader, WrongTypesEverywhereNeverCrash) {
  const json values[] = {nullptr,
                         true,
                         -1,
                         0,
                         1,
                         2.5,
                         1e300,
                         -1e300,
                         "x",
                         json::array(),
                         json::object(),
                         json::array({1, 2, 3}),
                         json::array({0, -1, 0}),
                         json{{"x", 1}, {"y", "z"}},
                         4294967296.0,
                         18446744073709551615ull};
  for (const json& v : values) {
    for (const char* key : {"node", "stiffness", "gravityPower", "gravityDir", "dragForce", "hitRadius"}) {
      json bad = {{"node", 2}};
      bad[key] = v;
      json spring = {{"joints", {bad, {{"node", 3}}, {{"node", 4}}}}, {"center", v}, {"colliderGroups", v}};
      std::shared_ptr<const Rig> rig;
      loadDoc(
          chainNodes(),
          vrmc(json::array({spring}), json::array({{{"node", v}, {"shape", v}}}), json::array({{{"colliders", v}}})),
          rig);
      if (rig) expectRigInvariants(*rig);
      json group = {{"bones", v}, {"stiffiness", v}, {"gravityDir", v}, {"center", v}, {"colliderGroups", v}};
      group[key] = v;
      loadDoc(
          chainNodes(),
          vrm0(json::array({group, {{"bones", {2}}, {"center", v}}}), json::array({{{"node", v}, {"colliders", v}}})),
          rig);
      if (rig) expectRigInvariants(*rig);
    }
  }
}

TEST(VrmLoader, TruncatedAndCorruptedFixturesNeverCrash) {
  for (const char* name : {"vrm10_springs.vrm", "vrm0_springs.vrm"}) {
    const std::vector<std::uint8_t> bytes = test::readFixture(name);
    ASSERT_FALSE(bytes.empty());
    for (std::size_t n = 0; n < bytes.size(); n += 7) {
      std::shared_ptr<const Rig> rig;
      const Error e = loadVrm(bytes.data(), n, rig);
      EXPECT_TRUE(e) << name << " truncated to " << n;
      EXPECT_FALSE(rig);
    }
    // Flip bytes inside the JSON chunk: parse errors or a (possibly smaller) valid rig.
    std::vector<std::uint8_t> copy = bytes;
    for (std::size_t at = 20; at < copy.size(); at += 13) {
      const std::uint8_t saved = copy[at];
      for (std::uint8_t replacement : {std::uint8_t('9'), std::uint8_t('-'), std::uint8_t('"'), std::uint8_t('[')}) {
        copy[at] = replacement;
        std::shared_ptr<const Rig> rig;
        if (!loadVrm(copy.data(), copy.size(), rig)) {
          ASSERT_TRUE(rig);
          expectRigInvariants(*rig);
          Instance instance(rig);
          instance.step(1.0 / 60.0);
        }
      }
      copy[at] = saved;
    }
  }
}

TEST(VrmLoader, FindGltfJsonAgreesWithTheLoaderOnContainers) {
  const std::vector<std::uint8_t> bytes = test::readFixture("vrm10_springs.vrm");
  const char* begin = nullptr;
  std::size_t size = 0;
  ASSERT_FALSE(findGltfJson(bytes.data(), bytes.size(), begin, size));
  const json doc = json::parse(begin, begin + size);
  EXPECT_TRUE(doc.contains("extensions"));
  const std::string text = "\xEF\xBB\xBF  {\"asset\": {}}";
  ASSERT_FALSE(findGltfJson(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), begin, size));
  EXPECT_EQ(size, text.size());
  std::vector<std::uint8_t> bad = bytes;
  test::writeU32(bad, 12, 1u << 30);  // JSON chunk longer than the file
  Skeleton skeleton;
  const Error mine = findGltfJson(bad.data(), bad.size(), begin, size);
  const Error loader = loadSkeleton(bad.data(), bad.size(), skeleton);
  EXPECT_EQ(mine.code, ErrorCode::kGlbTruncated);
  EXPECT_EQ(mine.code, loader.code);
  EXPECT_EQ(mine.message, loader.message);
}

// Springs whose pairs skip long runs of nodes and then fail: the walk over skipped nodes has a
// budget of twice the node count for the whole file, so a hostile file costs linear time.
TEST(VrmLoader, LongSkippedRunsAreBounded) {
  constexpr int kDepth = 3000;
  constexpr int kSprings = 2000;
  json nodes = json::array();
  for (int i = 0; i < kDepth; ++i) {
    nodes.push_back(
        gnode("n" + std::to_string(i), i + 1 < kDepth ? std::vector<int>{i + 1} : std::vector<int>{}, {0, -0.01f, 0}));
  }
  // Spring 0 simulates n1; every other spring pairs n0 with the deepest node, which passes n1.
  json springs = json::array({{{"joints", joints({1, 2})}}});
  for (int k = 0; k < kSprings; ++k) springs.push_back({{"joints", joints({0, kDepth - 1})}});
  auto rig = mustLoad(nodes, vrmc(springs));
  expectRigInvariants(*rig);
  ASSERT_EQ(rig->joints.size(), 1u);
  EXPECT_EQ(rig->joints[0].node, 1);
  const int conflicts = test::countWarnings(rig->warnings, "vrm-joint-conflict");
  const int limited = test::countWarnings(rig->warnings, "vrm-limit");
  EXPECT_EQ(conflicts + limited, kSprings);
  EXPECT_LE(conflicts, 3);  // the budget (2 x 3000 + 64 steps) runs out after two full walks
}

// Joints x colliders is bounded (kMaxVrmColliderReferences); repeated groups and colliders count once.
TEST(VrmLoader, ColliderReferencesAreLimited) {
  auto file = [](int joint_count, int collider_count, int repeats) {
    json nodes = json::array();
    for (int i = 0; i <= joint_count; ++i) {
      nodes.push_back(gnode("n" + std::to_string(i), i < joint_count ? std::vector<int>{i + 1} : std::vector<int>{},
                            {0, -0.01f, 0}));
    }
    json colliders = json::array();
    // Extended shapes count like the others: every third collider a plane, every third an inside sphere.
    for (int c = 0; c < collider_count; ++c) {
      json collider = {{"node", 0}, {"shape", {{"sphere", {{"radius", 0.01}}}}}};
      const json extended =
          c % 3 == 1 ? json{{"plane", {{"normal", {0, 1, 0}}}}} : json{{"sphere", {{"radius", 0.5}, {"inside", true}}}};
      if (c % 3 != 0)
        collider["extensions"] = {{"VRMC_springBone_extended_collider", {{"specVersion", "1.0"}, {"shape", extended}}}};
      colliders.push_back(collider);
    }
    json ids = json::array();
    for (int r = 0; r < repeats; ++r) {
      for (int c = 0; c < collider_count; ++c) ids.push_back(c);
    }
    std::vector<int> listed;
    for (int i = 1; i <= joint_count; ++i) listed.push_back(i);
    json group_refs = json::array();
    for (int r = 0; r < repeats; ++r) group_refs.push_back(0);
    return std::make_pair(nodes, vrmc(json::array({{{"joints", joints(listed)}, {"colliderGroups", group_refs}}}),
                                      colliders, json::array({{{"colliders", ids}}})));
  };
  std::shared_ptr<const Rig> rig;
  const int side = static_cast<int>(std::sqrt(double(kMaxVrmColliderReferences))) + 2;
  auto [big_nodes, big_ext] = file(side + 1, side, 1);
  const Error e = loadDoc(big_nodes, big_ext, rig);
  EXPECT_EQ(e.code, ErrorCode::kLimitExceeded) << e.message;
  EXPECT_FALSE(rig);
  // Repeats do not count: 20 joints x 50 colliders, each listed 200 times in 200 group references.
  auto [nodes, ext] = file(21, 50, 200);
  ASSERT_FALSE(loadDoc(nodes, ext, rig));
  ASSERT_EQ(rig->joints.size(), 20u);
  for (const Joint& j : rig->joints) EXPECT_EQ(j.colliders.size(), 50u);
  EXPECT_EQ(std::count_if(rig->colliders.begin(), rig->colliders.end(), [](const Collider& c) { return c.inside; }),
            16);
  EXPECT_EQ(std::count_if(rig->colliders.begin(), rig->colliders.end(),
                          [](const Collider& c) { return c.shape == Collider::Shape::kPlane; }),
            17);
}

}  // namespace
}  // namespace springbones

namespace springbones {
namespace {

// Shapes that took superlinear time. Each runs an instance large enough that the old quadratic
// behaviour would take minutes (or run out of memory); no timer, the assertions are about results.

// `n` copies of `item`, comma-separated.
std::string repeated(const std::string& item, std::size_t n) {
  std::string out;
  out.reserve(n * (item.size() + 1));
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) out += ',';
    out += item;
  }
  return out;
}

Error loadText(const std::string& text, std::shared_ptr<const Rig>& rig) {
  return loadVrm(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), rig);
}

// The JSON was parsed with nlohmann's callback parser, which scans a container's elements each
// time one of them ends: quadratic in the length of every array and object, kept or dropped.
TEST(VrmLoaderScaling, LongArraysOfSmallObjectsAnywhereLoadInLinearTime) {
  constexpr std::size_t kCount = 400000;  // 8e10 element visits when quadratic
  constexpr std::size_t kNodes = 200000;
  const std::string text = R"({"asset":{"version":"2.0"},"nodes":[{"name":"root","children":[1]},)"
                           R"({"name":"tip","translation":[0,-0.1,0]},)" +
                           repeated("{}", kNodes) + R"(],"accessors":[)" + repeated(R"({"count":1})", kCount) +
                           R"(],"extensions":{"VRMC_springBone":{"specVersion":"1.0","springs":[{"joints":[{"node":0},)"
                           R"({"node":1}]}],"extras":[)" +
                           repeated("[{}]", kCount) + "]}}}";
  std::shared_ptr<const Rig> rig;
  const Error e = loadText(text, rig);
  ASSERT_FALSE(e) << e.message;
  EXPECT_EQ(rig->skeleton.nodes.size(), kNodes + 2);
  ASSERT_EQ(rig->joints.size(), 1u);
  EXPECT_EQ(rig->joints[0].node, 0);
}

// Each spring's collider list was built from its groups while reading, before the limit was
// checked: springs x colliders of work and memory (here 4e8 ids, 1.6 GB). Now the count comes
// first, from the group sizes.
TEST(VrmLoaderScaling, ManySpringsSharingALargeColliderGroupHitTheLimitBeforeBuildingLists) {
  constexpr int kSprings = 20000, kColliders = 20000;
  std::string nodes = R"([{"name":"body"})";
  std::string springs;
  for (int s = 0; s < kSprings; ++s) {
    const int head = 1 + 2 * s;
    nodes += R"(,{"children":[)" + std::to_string(head + 1) + R"(]},{"translation":[0,-0.1,0]})";
    springs += (s ? "," : "") + std::string(R"({"joints":[{"node":)") + std::to_string(head) + R"(},{"node":)" +
               std::to_string(head + 1) + R"(}],"colliderGroups":[0,0]})";
  }
  std::string ids;
  for (int c = 0; c < kColliders; ++c) ids += (c ? "," : "") + std::to_string(c);
  const std::string text =
      R"({"asset":{"version":"2.0"},"nodes":)" + nodes + R"(],"extensions":{"VRMC_springBone":{"colliders":[)" +
      repeated(R"({"node":0,"shape":{"sphere":{"radius":0.1}}})", kColliders) +
      R"(],"colliderGroups":[{"colliders":[)" + ids + "," + ids + R"(]}],"springs":[)" + springs + "]}}}";
  std::shared_ptr<const Rig> rig;
  const Error e = loadText(text, rig);
  EXPECT_EQ(e.code, ErrorCode::kLimitExceeded) << e.message;
  EXPECT_NE(e.message.find("400000000 times"), std::string::npos) << e.message;  // repeats count once
  EXPECT_FALSE(rig);
}

// A collider listed by two of a spring's groups counts twice toward the limit (the count is taken
// from the group sizes), and the joint tests it twice, once per group, as three-vrm and UniVRM do
// (with a warning).
TEST(VrmLoaderScaling, OverlappingGroupsCountTwiceTowardTheLimitAndOnTheJoint) {
  json nodes = json::array({gnode("body", {1}), gnode("root", {2}), gnode("tip", {}, {0, -0.1f, 0})});
  json colliders = json::array();
  for (int c = 0; c < 3; ++c) colliders.push_back({{"node", 0}, {"shape", {{"sphere", {{"radius", 0.01}}}}}});
  json groups = json::array({{{"colliders", {0, 1}}}, {{"colliders", {1, 2}}}});
  json springs = json::array({{{"joints", joints({1, 2})}, {"colliderGroups", {0, 1}}}});
  const auto rig = mustLoad(nodes, vrmc(springs, colliders, groups));
  ASSERT_EQ(rig->joints.size(), 1u);
  EXPECT_EQ(rig->joints[0].colliders, (std::vector<int>{0, 1, 1, 2}));
  EXPECT_NE(
      test::findWarning(rig->warnings, "vrm-collider-repeated", "/extensions/VRMC_springBone/springs/0/colliderGroups"),
      nullptr);

  // 1,000 joints x two groups of the same 2,100 colliders: 4.2 million references, 2.1 million distinct.
  constexpr int kJoints = 1000, kColliders = 2100;
  json chain = json::array({gnode("body", {1})});
  std::vector<int> listed;
  for (int i = 1; i <= kJoints + 1; ++i) {
    chain.push_back(
        gnode("n" + std::to_string(i), i <= kJoints ? std::vector<int>{i + 1} : std::vector<int>{}, {0, -0.01f, 0}));
    listed.push_back(i);
  }
  json many = json::array();
  std::vector<int> ids;
  for (int c = 0; c < kColliders; ++c) {
    many.push_back({{"node", 0}, {"shape", {{"sphere", {{"radius", 0.01}}}}}});
    ids.push_back(c);
  }
  std::shared_ptr<const Rig> limited;
  const Error e = loadDoc(chain,
                          vrmc(json::array({{{"joints", joints(listed)}, {"colliderGroups", {0, 1}}}}), many,
                               json::array({{{"colliders", ids}}, {{"colliders", ids}}})),
                          limited);
  EXPECT_EQ(e.code, ErrorCode::kLimitExceeded) << e.message;
  EXPECT_NE(e.message.find("4200000 times"), std::string::npos) << e.message;
}

// Warnings named the node with its whole name: one 1 MB name in a warning per spring made the
// warnings springs x 1 MB (here 100 GB). A name is now at most kTypedMaxStringBytes (a longer one
// is limit-exceeded); one of that size, in a warning per spring, would still be 6.5 GB.
TEST(VrmLoaderScaling, ALongNodeNameRepeatedInManyWarningsIsShortened) {
  constexpr int kSprings = 100000;
  const std::string name = "\xc3\xa9" + std::string(kTypedMaxStringBytes - 2, 'x');  // a two-byte character first
  const std::string text =
      R"({"asset":{"version":"2.0"},"nodes":[{"name":")" + name +
      R"(","children":[1]},{"translation":[0,-0.1,0]}],"extensions":{"VRMC_springBone":{"springs":[)" +
      repeated(R"({"joints":[{"node":0},{"node":1}]})", kSprings) + "]}}}";
  std::shared_ptr<const Rig> rig;
  ASSERT_FALSE(loadText(text, rig));
  ASSERT_EQ(test::countWarnings(rig->warnings, "vrm-joint-conflict"), kSprings - 1);
  for (const Warning& w : rig->warnings) {
    if (w.code != "vrm-joint-conflict") continue;
    EXPECT_LT(w.message.size(), 200u);
    EXPECT_NE(w.message.find("node 0 ('" + name.substr(0, 64) + "...')"), std::string::npos) << w.message;
  }
  // A cut inside a UTF-8 sequence moves back to its start.
  std::string one = text;
  one.replace(one.find(name), name.size(), std::string(63, 'y') + "\xc3\xa9" + "tail");
  ASSERT_FALSE(loadText(one, rig));
  EXPECT_NE(rig->warnings.back().message.find("('" + std::string(63, 'y') + "...')"), std::string::npos)
      << rig->warnings.back().message;
}

}  // namespace
}  // namespace springbones
