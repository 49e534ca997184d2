// Chain building tests (src/loading/rig_builder.cpp): the ADR's naming table and Full Example, the chain
// rules of docs/semantics.md, and the avatar fixture (tests/fixtures/avatar_hair.glb, laid out in
// scripts/generate/make_fixtures.mjs, whose comments give every offset used below).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "readers/json_values.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using nlohmann::json;
using test::findWarning;
using test::gltfWithNodes;
using test::node;
using test::vecNear;

const std::string kHash = "h";

json entry(double stiffness, double gravity_power, double drag, json extra = json::object()) {
  json e = {{"stiffness", stiffness}, {"gravityPower", gravity_power}, {"gravityDir", {0, -1, 0}}, {"drag", drag}};
  e.update(extra);
  return e;
}

json rootEntry(double stiffness = 1.0, json extra = json::object()) {
  extra["isRoot"] = true;
  return entry(stiffness, 0.5, 0.4, extra);
}

std::shared_ptr<const Rig> buildFromSpringBones(const json& nodes, const json& springBones) {
  Skeleton skeleton;
  const Error e = test::loadText(gltfWithNodes(nodes), skeleton);
  EXPECT_FALSE(e) << e.message;
  ModelEntry model;
  std::vector<Warning> warnings;
  const Error m = parseSpringBones(springBones, kHash, model, warnings);
  EXPECT_FALSE(m) << m.message;
  return buildRig(std::move(skeleton), model, std::move(warnings));
}

std::shared_ptr<const Rig> build(const json& nodes, const json& bones) {
  return buildFromSpringBones(nodes, {{"version", 1}, {"models", {{kHash, bones}}}});
}

std::shared_ptr<const Rig> buildFixture(const std::string& glb, const std::string& metadata, const std::string& key) {
  Skeleton skeleton = test::loadFixtureSkeleton(glb);
  ModelEntry model;
  std::vector<Warning> warnings;
  const Error e = parseSpringBonesText(test::readFixtureText(metadata), key, model, warnings);
  EXPECT_FALSE(e) << e.message;
  EXPECT_TRUE(model.enabled);
  return buildRig(std::move(skeleton), model, std::move(warnings));
}

std::shared_ptr<const Rig> avatarRig() {
  return buildFixture("avatar_hair.glb", "avatar_hair.metadata.json", test::metadataKeyOf("avatar_hair.glb"));
}

const std::string& nodeName(const Rig& rig, int node) { return rig.skeleton.nodes.at(node).name; }

/// Joint index of the node with that name, -1 when the node is not a joint.
int jointOf(const Rig& rig, const std::string& name) {
  for (std::size_t j = 0; j < rig.joints.size(); ++j) {
    if (nodeName(rig, rig.joints[j].node) == name) return static_cast<int>(j);
  }
  return -1;
}

const Joint& joint(const Rig& rig, const std::string& name) {
  const int j = jointOf(rig, name);
  EXPECT_GE(j, 0) << name << " is not a joint";
  static const Joint kNone;
  return j >= 0 ? rig.joints[j] : kNone;
}

std::vector<std::string> jointNames(const Rig& rig) {
  std::vector<std::string> names;
  for (const Joint& j : rig.joints) names.push_back(nodeName(rig, j.node));
  return names;
}

std::vector<std::string> driverNames(const Rig& rig) {
  std::vector<std::string> names;
  for (const Driver& d : rig.drivers) names.push_back(d.name);
  return names;
}

int driverOf(const Rig& rig, const std::string& name) {
  for (std::size_t d = 0; d < rig.drivers.size(); ++d) {
    if (rig.drivers[d].name == name) return static_cast<int>(d);
  }
  return -2;  // distinct from -1 (world space / no driver)
}

// Head at the origin, `name` 10 cm below the head side, its tip 5 cm lower.
json strandNodes(const std::string& name) {
  return {node("Avatar_Head", {1}), node(name, {2}, {0.08, -0.1, 0}), node(name + "_tip", {}, {0, -0.05, 0})};
}

// ---------------------------------------------------------------------------------------------
// The ADR's naming table

TEST(RigBuilder, DetectsCandidatesExactlyAsTheAdrNamingTable) {
  // | SpringBone_hair_left ✓ | hair_springbone_l ✓ | springbone_earring_r ✓ |
  // | ponytail_SPRINGBONE ✓ | skirt_1 ✗ | SpringBoneCollider ✓ (root only with isRoot) |
  EXPECT_TRUE(isSpringBoneName("SpringBone_hair_left"));
  EXPECT_TRUE(isSpringBoneName("hair_springbone_l"));
  EXPECT_TRUE(isSpringBoneName("springbone_earring_r"));
  EXPECT_TRUE(isSpringBoneName("ponytail_SPRINGBONE"));
  EXPECT_FALSE(isSpringBoneName("skirt_1"));
  EXPECT_TRUE(isSpringBoneName("SpringBoneCollider"));
}

TEST(RigBuilder, MatchesTheTokenAnywhereAsciiCaseInsensitively) {
  EXPECT_TRUE(isSpringBoneName("springbone"));
  EXPECT_TRUE(isSpringBoneName("sPrInGbOnE"));
  EXPECT_TRUE(isSpringBoneName("xxspringbonexx"));
  EXPECT_TRUE(isSpringBoneName("sprinspringbone"));  // a partial match just before the token
  EXPECT_FALSE(isSpringBoneName(""));
  EXPECT_FALSE(isSpringBoneName("springbon"));
  EXPECT_FALSE(isSpringBoneName("spring_bone"));
  EXPECT_FALSE(isSpringBoneName("spring bone"));
  EXPECT_FALSE(isSpringBoneName("Hair_001"));
  // Only ASCII letters fold: U+0130 (capital I with dot, UTF-8 C4 B0) is not 'i'.
  EXPECT_FALSE(isSpringBoneName("SPR\xC4\xB0NGBONE"));
}

TEST(RigBuilder, BuildsARootForEveryValidNameInTheNamingTable) {
  for (const char* name :
       {"SpringBone_hair_left", "hair_springbone_l", "springbone_earring_r", "ponytail_SPRINGBONE"}) {
    SCOPED_TRACE(name);
    const auto rig = build(strandNodes(name), {{name, rootEntry()}});
    ASSERT_EQ(jointNames(*rig), std::vector<std::string>{name});
    EXPECT_EQ(rig->chain_roots, std::vector<int>{0});
    EXPECT_TRUE(rig->warnings.empty()) << test::describeWarnings(rig->warnings);
  }
}

TEST(RigBuilder, NeverBuildsAChainFromANameWithoutTheToken) {
  // skirt_1 with an isRoot entry: the entry is reported (the catalyst would reject it) and ignored.
  const auto rig = build(strandNodes("skirt_1"), {{"skirt_1", rootEntry()}});
  EXPECT_TRUE(rig->joints.empty());
  EXPECT_TRUE(rig->chain_roots.empty());
  EXPECT_TRUE(rig->drivers.empty());
  findWarning(rig->warnings, "bone-not-spring", "/models/h/skirt_1");
}

TEST(RigBuilder, SpringBoneColliderIsARootOnlyWhenItsEntrySaysIsRootTrue) {
  const json nodes = strandNodes("SpringBoneCollider");
  EXPECT_TRUE(build(nodes, {{"SpringBoneCollider", entry(1, 0, 0.5)}})->joints.empty());
  EXPECT_TRUE(build(nodes, {{"SpringBoneCollider", entry(1, 0, 0.5, {{"isRoot", false}})}})->joints.empty());
  EXPECT_TRUE(build(nodes, {{"SpringBoneCollider", entry(1, 0, 0.5, {{"isRoot", nullptr}})}})->joints.empty());
  EXPECT_EQ(build(nodes, {{"SpringBoneCollider", entry(1, 0, 0.5, {{"isRoot", true}})}})->joints.size(), 1u);
}

TEST(RigBuilder, CandidateWithoutAnyEntryIsNotARoot) {
  const auto rig = build(strandNodes("SpringBone_hair_left"), json::object());
  EXPECT_TRUE(rig->joints.empty());
}

TEST(RigBuilder, MatchesEntriesToNodeNamesCaseSensitively) {
  // The ADR: "case-sensitive match against the GLB node name".
  const auto rig = build(strandNodes("SpringBone_hair_left"), {{"springbone_hair_left", rootEntry()}});
  EXPECT_TRUE(rig->joints.empty());
  findWarning(rig->warnings, "bone-not-found", "/models/h/springbone_hair_left");
}

// ---------------------------------------------------------------------------------------------
// The ADR's Full Example, end to end from the fixture files

TEST(RigBuilder, BuildsTheAdrFullExample) {
  const std::string key = test::metadataKeyOf("adr_example.glb");
  ASSERT_EQ(key, "bafkreialsvt77jvpy673cnugp5ggnxfaalfncufweayuk3jbxskh3pelkm");
  const auto rig = buildFixture("adr_example.glb", "adr_example.metadata.json", key);
  // Two chains, earring (node 1, tail node 3) and hair (node 2, tail node 4). The _tip nodes
  // only end their bones: not joints.
  ASSERT_EQ(jointNames(*rig), (std::vector<std::string>{"SpringBone_earring_r", "SpringBone_hair_left"}));
  EXPECT_EQ(rig->chain_roots, (std::vector<int>{0, 1}));
  const Joint& earring = rig->joints[0];
  const Joint& hair = rig->joints[1];
  EXPECT_EQ(earring.tail_node, 3);
  EXPECT_EQ(hair.tail_node, 4);
  EXPECT_EQ(earring.chain, 0);
  EXPECT_EQ(hair.chain, 1);
  EXPECT_EQ(earring.parent_joint, -1);
  // Both roots hang from Avatar_Head, the one driver; Avatar_Hips is not in this file.
  EXPECT_EQ(driverNames(*rig), std::vector<std::string>{"Avatar_Head"});
  EXPECT_EQ(earring.parent_driver, 0);
  EXPECT_EQ(hair.parent_driver, 0);
  // Parameters straight from the ADR's metadata.
  EXPECT_FLOAT_EQ(earring.params.stiffness, 0.5f);
  EXPECT_FLOAT_EQ(earring.params.gravity_power, 1.0f);
  EXPECT_FLOAT_EQ(earring.params.drag, 0.6f);
  EXPECT_FLOAT_EQ(hair.params.stiffness, 2.0f);
  EXPECT_FLOAT_EQ(hair.params.gravity_power, 0.8f);
  EXPECT_FLOAT_EQ(hair.params.drag, 0.4f);
  EXPECT_TRUE(vecNear(hair.params.gravity_dir, {0, -1, 0}, 0));
  // center "Avatar_Hips" does not exist here: a warning and world space (the ADR's SHOULD/MUST).
  EXPECT_EQ(earring.center_driver, -1);
  findWarning(rig->warnings, "center-not-found", "/models/" + key + "/SpringBone_earring_r/center");
  // No transforms in the example: both bones have zero length, each reported once.
  EXPECT_FLOAT_EQ(earring.rest_length, 0.0f);
  EXPECT_EQ(test::countWarnings(rig->warnings, "zero-length-bone"), 2);
  EXPECT_TRUE(test::hasWarning(rig->warnings, "zero-length-bone", "SpringBone_earring_r"));
  EXPECT_TRUE(test::hasWarning(rig->warnings, "zero-length-bone", "SpringBone_hair_left"));
  EXPECT_EQ(rig->warnings.size(), 3u) << test::describeWarnings(rig->warnings);
}

TEST(RigBuilder, BuildsTheSameAdrExampleFromGltfText) {
  const std::string key = test::metadataKeyOf("adr_example.gltf");
  const auto glb = buildFixture("adr_example.glb", "adr_example.metadata.json", key);
  const auto text = buildFixture("adr_example.gltf", "adr_example.metadata.json", key);
  EXPECT_EQ(jointNames(*glb), jointNames(*text));
  EXPECT_EQ(driverNames(*glb), driverNames(*text));
  EXPECT_EQ(glb->warnings.size(), text->warnings.size());
}

TEST(RigBuilder, MeasuresBoneLengthsOfThePosedAdrExample) {
  // adr_example_posed.glb: the earring tip 4 cm below the earring, the hair tip 10 cm below.
  const auto rig =
      buildFixture("adr_example_posed.glb", "adr_example.metadata.json", test::metadataKeyOf("adr_example_posed.glb"));
  ASSERT_EQ(rig->joints.size(), 2u);
  EXPECT_NEAR(joint(*rig, "SpringBone_earring_r").rest_length, 0.04f, 1e-6f);
  EXPECT_NEAR(joint(*rig, "SpringBone_hair_left").rest_length, 0.10f, 1e-6f);
  EXPECT_TRUE(vecNear(joint(*rig, "SpringBone_hair_left").tail_local, {0, -0.1f, 0}, 1e-7f));
  EXPECT_EQ(test::countWarnings(rig->warnings, "zero-length-bone"), 0);
  EXPECT_EQ(test::countWarnings(rig->warnings, "center-not-found"), 1);
}

// ---------------------------------------------------------------------------------------------
// Chain shape

TEST(RigBuilder, ChainTakesEveryDescendantIncludingNodesWithoutTheToken) {
  // root -> a (no token) -> b (no token) -> tip: three joints, one chain.
  const json nodes = {node("Avatar_Head", {1}), node("hair_springbone_l", {2}, {0, -0.1, 0}),
                      node("strand_a", {3}, {0, -0.1, 0}), node("strand_b", {4}, {0, -0.1, 0}),
                      node("strand_tip", {}, {0, -0.1, 0})};
  const auto rig = build(nodes, {{"hair_springbone_l", rootEntry()}});
  EXPECT_EQ(jointNames(*rig), (std::vector<std::string>{"hair_springbone_l", "strand_a", "strand_b"}));
  for (const Joint& j : rig->joints) EXPECT_EQ(j.chain, 0);
  EXPECT_EQ(rig->joints[1].parent_joint, 0);
  EXPECT_EQ(rig->joints[2].parent_joint, 1);
  EXPECT_EQ(rig->chain_roots, std::vector<int>{0});
}

TEST(RigBuilder, FirstChildIsTheTailAndOtherChildrenStartSimulatedBranches) {
  // fork has children a (listed first) and b; each continues to a tip.
  const json nodes = {node("Avatar_Head", {1}),          node("SpringBone_fork", {2, 4}, {0, -0.1, 0}),
                      node("a", {3}, {0.02, -0.05, 0}),  node("a_tip", {}, {0, -0.05, 0}),
                      node("b", {5}, {-0.02, -0.05, 0}), node("b_tip", {}, {0, -0.05, 0})};
  const auto rig = build(nodes, {{"SpringBone_fork", rootEntry()}});
  ASSERT_EQ(rig->joints.size(), 3u);
  const Joint& fork = joint(*rig, "SpringBone_fork");
  EXPECT_EQ(fork.tail_node, 2);  // a, the first child
  EXPECT_TRUE(vecNear(fork.tail_local, {0.02f, -0.05f, 0}, 1e-7f));
  EXPECT_EQ(joint(*rig, "a").parent_joint, jointOf(*rig, "SpringBone_fork"));
  EXPECT_EQ(joint(*rig, "b").parent_joint, jointOf(*rig, "SpringBone_fork"));
  EXPECT_EQ(joint(*rig, "b").tail_node, 5);
  EXPECT_EQ(joint(*rig, "b").chain, 0);
}

TEST(RigBuilder, LeavesAreNotSimulated) {
  const auto rig = build(strandNodes("SpringBone_x"), {{"SpringBone_x", rootEntry()}});
  EXPECT_EQ(jointOf(*rig, "SpringBone_x_tip"), -1);
  EXPECT_EQ(rig->joints.size(), 1u);
}

TEST(RigBuilder, IgnoresParametersOfAChainTipWithAWarning) {
  json nodes = strandNodes("SpringBone_x");
  nodes[2]["name"] = "SpringBone_x_tip";
  const auto rig = build(nodes, {{"SpringBone_x", rootEntry(1.0)}, {"SpringBone_x_tip", entry(3, 0, 0.5)}});
  EXPECT_EQ(rig->joints.size(), 1u);
  EXPECT_FLOAT_EQ(rig->joints[0].params.stiffness, 1.0f);
  findWarning(rig->warnings, "tip-entry-ignored", "/models/h/SpringBone_x_tip");
}

TEST(RigBuilder, RootWithoutChildrenIsReportedAndSimulatesNothing) {
  const auto rig = build({node("Avatar_Head", {1}), node("SpringBone_alone", {}, {0, -0.1, 0})},
                         {{"SpringBone_alone", rootEntry()}});
  EXPECT_TRUE(rig->joints.empty());
  EXPECT_TRUE(rig->chain_roots.empty());
  EXPECT_TRUE(test::hasWarning(rig->warnings, "root-without-tail", "SpringBone_alone"));
}

TEST(RigBuilder, WarnsAboutZeroLengthBones) {
  const auto rig = build(
      {node("Avatar_Head", {1}), node("SpringBone_z", {2}, {0, -0.1, 0}), node("SpringBone_z_tip", {}, {0, 0, 0})},
      {{"SpringBone_z", rootEntry()}});
  ASSERT_EQ(rig->joints.size(), 1u);  // still a joint: it keeps its rest rotation
  EXPECT_EQ(rig->joints[0].rest_length, 0.0f);
  EXPECT_TRUE(test::hasWarning(rig->warnings, "zero-length-bone", "SpringBone_z"));
}

TEST(RigBuilder, RootAtTheSceneRootHasNoParentDriver) {
  const auto rig = build({node("SpringBone_top", {1}), node("SpringBone_top_tip", {}, {0, -0.1, 0})},
                         {{"SpringBone_top", rootEntry()}});
  ASSERT_EQ(rig->joints.size(), 1u);
  EXPECT_EQ(rig->joints[0].parent_driver, -1);
  EXPECT_TRUE(rig->drivers.empty());
}

TEST(RigBuilder, CopiesTheRestLocalTransformOfEachJoint) {
  json nodes = strandNodes("SpringBone_r");
  nodes[1]["rotation"] = {0, 0, std::sqrt(0.5), std::sqrt(0.5)};  // 90 degrees about Z
  nodes[1]["scale"] = {2, 2, 2};
  const auto rig = build(nodes, {{"SpringBone_r", rootEntry()}});
  ASSERT_EQ(rig->joints.size(), 1u);
  const Transform& t = rig->joints[0].rest_local;
  EXPECT_TRUE(vecNear(t.translation, {0.08f, -0.1f, 0}, 1e-7f));
  EXPECT_TRUE(test::quatNear(t.rotation, glm::quat(std::sqrt(0.5f), 0, 0, std::sqrt(0.5f))));
  EXPECT_TRUE(vecNear(t.scale, {2, 2, 2}, 0));
  // The tip is 5 cm along the joint's local -Y; in the world that is scaled by 2 (10 cm).
  EXPECT_NEAR(rig->joints[0].rest_length, 0.1f, 1e-6f);
}

// ---------------------------------------------------------------------------------------------
// Parameters

TEST(RigBuilder, MembersTakeTheirOwnEntryElseTheNearestAncestorsInTheChain) {
  // root(1.0) -> m1 (no entry) -> m2 (entry 3.0, isRoot false) -> m3 (no entry) -> tip
  const json nodes = {node("Avatar_Head", {1}),
                      node("SpringBone_root", {2}, {0, -0.1, 0}),
                      node("SpringBone_m1", {3}, {0, -0.1, 0}),
                      node("SpringBone_m2", {4}, {0, -0.1, 0}),
                      node("SpringBone_m3", {5}, {0, -0.1, 0}),
                      node("SpringBone_tip", {}, {0, -0.1, 0})};
  const auto rig =
      build(nodes, {{"SpringBone_root", rootEntry(1.0)}, {"SpringBone_m2", entry(3.0, 1.5, 0.9, {{"isRoot", false}})}});
  ASSERT_EQ(rig->joints.size(), 4u);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_root").params.stiffness, 1.0f);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_m1").params.stiffness, 1.0f);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_m2").params.stiffness, 3.0f);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_m2").params.gravity_power, 1.5f);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_m3").params.stiffness, 3.0f);  // from m2, not the root
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_m3").params.drag, 0.9f);
  EXPECT_EQ(rig->chain_roots, std::vector<int>{0});
}

TEST(RigBuilder, AMemberEntryWithoutTheTokenIsIgnored) {
  // Entries apply only to candidate nodes (every metadata bone name must carry the token).
  const json nodes = {node("Avatar_Head", {1}), node("SpringBone_root", {2}, {0, -0.1, 0}),
                      node("plain", {3}, {0, -0.1, 0}), node("plain_tip", {}, {0, -0.1, 0})};
  const auto rig = build(nodes, {{"SpringBone_root", rootEntry(1.0)}, {"plain", entry(3.0, 0, 0.5)}});
  EXPECT_FLOAT_EQ(joint(*rig, "plain").params.stiffness, 1.0f);
  findWarning(rig->warnings, "bone-not-spring", "/models/h/plain");
}

TEST(RigBuilder, NestedRootBecomesAMemberWithItsOwnParametersAndAWarning) {
  const json nodes = {node("Avatar_Head", {1}), node("SpringBone_outer", {2}, {0, -0.1, 0}),
                      node("SpringBone_inner", {3}, {0, -0.1, 0}), node("after", {4}, {0, -0.1, 0}),
                      node("tip", {}, {0, -0.1, 0})};
  const auto rig = build(nodes, {{"SpringBone_outer", rootEntry(1.0)}, {"SpringBone_inner", rootEntry(3.5)}});
  ASSERT_EQ(rig->chain_roots, std::vector<int>{0});  // one chain, not two
  const Joint& inner = joint(*rig, "SpringBone_inner");
  EXPECT_EQ(inner.chain, 0);
  EXPECT_EQ(inner.parent_joint, jointOf(*rig, "SpringBone_outer"));
  EXPECT_EQ(inner.parent_driver, -1);  // its parent is a joint, not a driver
  EXPECT_FLOAT_EQ(inner.params.stiffness, 3.5f);
  EXPECT_FLOAT_EQ(joint(*rig, "after").params.stiffness, 3.5f);
  findWarning(rig->warnings, "nested-root", "/models/h/SpringBone_inner");
  EXPECT_EQ(driverNames(*rig), std::vector<std::string>{"Avatar_Head"});
}

// ---------------------------------------------------------------------------------------------
// center

json centerNodes() {
  // Hips -> {Head -> {SpringBone_c -> {SpringBone_c_1 -> tip}}, SpringBoneCollider, plain}
  return {node("Avatar_Hips", {1, 5, 6}),
          node("Avatar_Head", {2}, {0, 0.6, 0}),
          node("SpringBone_c", {3}, {0.08, 0, 0}),
          node("SpringBone_c_1", {4}, {0, -0.05, 0}),
          node("SpringBone_c_tip", {}, {0, -0.05, 0}),
          node("SpringBoneCollider", {}, {0, 0.3, 0.1}),
          node("Avatar_Spine", {}, {0, 0.1, 0})};
}

TEST(RigBuilder, ResolvesCenterByNameToADriver) {
  const auto rig = build(centerNodes(), {{"SpringBone_c", rootEntry(1.0, {{"center", "Avatar_Hips"}})}});
  EXPECT_EQ(driverNames(*rig), (std::vector<std::string>{"Avatar_Head", "Avatar_Hips"}));
  EXPECT_EQ(rig->drivers[1].node, 0);
  EXPECT_EQ(joint(*rig, "SpringBone_c").center_driver, 1);
  EXPECT_EQ(joint(*rig, "SpringBone_c").parent_driver, 0);
  EXPECT_EQ(joint(*rig, "SpringBone_c_1").center_driver, 1);  // members share the chain's center
  EXPECT_TRUE(rig->warnings.empty()) << test::describeWarnings(rig->warnings);
}

TEST(RigBuilder, FallsBackToWorldSpaceWhenTheCenterDoesNotExist) {
  const auto rig = build(centerNodes(), {{"SpringBone_c", rootEntry(1.0, {{"center", "Avatar_Pelvis"}})}});
  EXPECT_EQ(joint(*rig, "SpringBone_c").center_driver, -1);
  EXPECT_EQ(joint(*rig, "SpringBone_c_1").center_driver, -1);
  EXPECT_EQ(driverNames(*rig), std::vector<std::string>{"Avatar_Head"});
  const Warning* w = findWarning(rig->warnings, "center-not-found", "/models/h/SpringBone_c/center");
  if (w) { EXPECT_NE(w->message.find("Avatar_Pelvis"), std::string::npos); }
}

TEST(RigBuilder, FallsBackToWorldSpaceWhenTheCenterIsASpringBone) {
  // A candidate outside any chain, a chain's own node, and a chain node without the token are all
  // "spring bone nodes" the ADR forbids as centers.
  for (const char* center : {"SpringBoneCollider", "SpringBone_c_1", "SpringBone_c"}) {
    SCOPED_TRACE(center);
    const auto rig = build(centerNodes(), {{"SpringBone_c", rootEntry(1.0, {{"center", center}})}});
    EXPECT_EQ(joint(*rig, "SpringBone_c").center_driver, -1);
    EXPECT_EQ(driverNames(*rig), std::vector<std::string>{"Avatar_Head"});
    findWarning(rig->warnings, "center-is-spring-bone", "/models/h/SpringBone_c/center");
  }
  json nodes = centerNodes();
  nodes[3]["name"] = "strand";  // a chain member without the token
  const auto rig = build(nodes, {{"SpringBone_c", rootEntry(1.0, {{"center", "strand"}})}});
  EXPECT_EQ(joint(*rig, "SpringBone_c").center_driver, -1);
  findWarning(rig->warnings, "center-is-spring-bone", "/models/h/SpringBone_c/center");
}

TEST(RigBuilder, MemberCenterOverridesTheInheritedOneAndNullMeansWorldSpace) {
  json nodes = centerNodes();
  nodes[4]["children"] = {7};
  nodes[4]["name"] = "SpringBone_c_2";
  nodes.push_back(node("SpringBone_c_tip", {}, {0, -0.05, 0}));
  // root center Hips; c_1 center null (world); c_2 no center key: inherits c_1's world space.
  const auto rig = build(nodes, {{"SpringBone_c", rootEntry(1.0, {{"center", "Avatar_Hips"}})},
                                 {"SpringBone_c_1", entry(1, 0, 0.5, {{"center", nullptr}})},
                                 {"SpringBone_c_2", entry(2, 0, 0.5)}});
  EXPECT_EQ(joint(*rig, "SpringBone_c").center_driver, driverOf(*rig, "Avatar_Hips"));
  EXPECT_EQ(joint(*rig, "SpringBone_c_1").center_driver, -1);
  EXPECT_EQ(joint(*rig, "SpringBone_c_2").center_driver, -1);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_c_2").params.stiffness, 2.0f);
}

// ---------------------------------------------------------------------------------------------
// Entries that match nothing, duplicates, disabled models

TEST(RigBuilder, WarnsAboutAnEntryNamingANodeThatDoesNotExist) {
  const auto rig =
      build(strandNodes("SpringBone_x"), {{"SpringBone_x", rootEntry()}, {"SpringBone_ghost", rootEntry()}});
  EXPECT_EQ(rig->joints.size(), 1u);
  const Warning* w = findWarning(rig->warnings, "bone-not-found", "/models/h/SpringBone_ghost");
  if (w) { EXPECT_NE(w->message.find("SpringBone_ghost"), std::string::npos); }
}

TEST(RigBuilder, AppliesAnEntryToEveryNodeOfADuplicatedNameWithAWarning) {
  const json nodes = {node("Avatar_Head", {1, 3}), node("SpringBone_dup", {2}, {0.05, 0, 0}),
                      node("tip_a", {}, {0, -0.1, 0}), node("SpringBone_dup", {4}, {-0.05, 0, 0}),
                      node("tip_b", {}, {0, -0.1, 0})};
  const auto rig = build(nodes, {{"SpringBone_dup", rootEntry()}});
  EXPECT_EQ(rig->chain_roots.size(), 2u);
  findWarning(rig->warnings, "duplicate-node-name", "/models/h/SpringBone_dup");
}

TEST(RigBuilder, DisabledModelBuildsNoJointsAndKeepsTheWarnings) {
  Skeleton skeleton;
  ASSERT_FALSE(test::loadText(gltfWithNodes(strandNodes("SpringBone_x")), skeleton));
  ModelEntry disabled;  // enabled = false
  const auto rig = buildRig(std::move(skeleton), disabled, {Warning{"earlier", "kept", ""}});
  EXPECT_TRUE(rig->joints.empty());
  EXPECT_TRUE(rig->drivers.empty());
  EXPECT_TRUE(rig->chain_roots.empty());
  EXPECT_EQ(rig->skeleton.nodes.size(), 3u);  // the hierarchy is still there
  ASSERT_EQ(rig->warnings.size(), 1u);
  EXPECT_EQ(rig->warnings[0].code, "earlier");
}

TEST(RigBuilder, VersionOtherThan1BuildsNoChains) {
  const auto rig = buildFromSpringBones(strandNodes("SpringBone_x"),
                                        {{"version", 2}, {"models", {{kHash, {{"SpringBone_x", rootEntry()}}}}}});
  EXPECT_TRUE(rig->joints.empty());
  findWarning(rig->warnings, "unsupported-version", "/version");
}

TEST(RigBuilder, MissingModelEntryBuildsNoChains) {
  const auto rig = buildFromSpringBones(strandNodes("SpringBone_x"),
                                        {{"version", 1}, {"models", {{"other", {{"SpringBone_x", rootEntry()}}}}}});
  EXPECT_TRUE(rig->joints.empty());
  findWarning(rig->warnings, "model-not-found", "/models/h");
}

// ---------------------------------------------------------------------------------------------
// The avatar fixture (Decentraland-like armature, scale 0.01, hair on the head)

TEST(RigBuilder, BuildsEveryChainOfTheAvatarFixture) {
  const auto rig = avatarRig();
  // Roots in hierarchy order under Avatar_Head; skirt_1 (no token), SpringBoneCollider (no
  // isRoot) and SpringBone_bangs_1 (nested) are not roots.
  std::vector<std::string> roots;
  for (int j : rig->chain_roots) roots.push_back(nodeName(*rig, rig->joints[j].node));
  EXPECT_EQ(roots, (std::vector<std::string>{"SpringBone_hair_left", "hair_springbone_r", "springbone_earring_r",
                                             "SpringBone_braid", "SpringBone_bangs", "SpringBone_ribbon",
                                             "SpringBone_tassel", "ponytail_SPRINGBONE"}));
  // Joints: hair_left 4 (root, _1, _2, _3), hair_r 3 (root, _1, hair_r_bead), earring 1,
  // braid 4 (root, _1, _a, _b), bangs 3 (root, _1, _2), ribbon 1, tassel 1, ponytail 2.
  EXPECT_EQ(rig->joints.size(), 19u);
  EXPECT_EQ(jointOf(*rig, "skirt_1"), -1);
  EXPECT_EQ(jointOf(*rig, "SpringBoneCollider"), -1);
  EXPECT_GE(jointOf(*rig, "hair_r_bead"), 0);  // in the chain without the token
  for (const char* tip : {"SpringBone_hair_left_tip", "hair_r_bead_tip", "springbone_earring_r_tip",
                          "SpringBone_braid_a_tip", "SpringBone_braid_b_tip", "ponytail_SPRINGBONE_tip"}) {
    EXPECT_EQ(jointOf(*rig, tip), -1) << tip;
  }
}

TEST(RigBuilder, ReportsEachProblemOfTheAvatarFixtureOnce) {
  const auto rig = avatarRig();
  const std::string m = "/models/" + test::metadataKeyOf("avatar_hair.glb");
  findWarning(rig->warnings, "bone-not-found", m + "/SpringBone_missing_node");
  findWarning(rig->warnings, "bone-not-spring", m + "/skirt_1");
  findWarning(rig->warnings, "nested-root", m + "/SpringBone_bangs_1");
  findWarning(rig->warnings, "center-not-found", m + "/SpringBone_ribbon/center");
  findWarning(rig->warnings, "center-is-spring-bone", m + "/SpringBone_tassel/center");
  EXPECT_EQ(rig->warnings.size(), 5u) << test::describeWarnings(rig->warnings);
}

TEST(RigBuilder, OrdersAvatarJointsParentsBeforeChildren) {
  const auto rig = avatarRig();
  std::set<int> chain_roots(rig->chain_roots.begin(), rig->chain_roots.end());
  for (std::size_t j = 0; j < rig->joints.size(); ++j) {
    const Joint& joint = rig->joints[j];
    SCOPED_TRACE(nodeName(*rig, joint.node));
    if (joint.parent_joint >= 0) {
      EXPECT_LT(joint.parent_joint, static_cast<int>(j));
      // The parent joint is the glTF parent of the node.
      EXPECT_EQ(rig->joints[joint.parent_joint].node, rig->skeleton.nodes[joint.node].parent);
      EXPECT_EQ(joint.chain, rig->joints[joint.parent_joint].chain);
      EXPECT_EQ(joint.parent_driver, -1);
    } else {
      EXPECT_EQ(chain_roots.count(static_cast<int>(j)), 1u);
      EXPECT_EQ(joint.chain, static_cast<int>(j));
      EXPECT_EQ(rig->drivers.at(joint.parent_driver).node, rig->skeleton.nodes[joint.node].parent);
    }
    EXPECT_EQ(joint.tail_node, rig->skeleton.nodes[joint.node].children.front());
  }
}

TEST(RigBuilder, AvatarDriversAreRootParentsAndCentersWithoutDuplicates) {
  // Every root hangs from Avatar_Head; centers: earring -> Avatar_Hips, braid -> Avatar_Head
  // (already a driver), ribbon/tassel unusable. So exactly two drivers, in first-use order.
  const auto rig = avatarRig();
  EXPECT_EQ(driverNames(*rig), (std::vector<std::string>{"Avatar_Head", "Avatar_Hips"}));
  for (const Driver& d : rig->drivers) EXPECT_EQ(nodeName(*rig, d.node), d.name);
  EXPECT_EQ(joint(*rig, "springbone_earring_r").center_driver, driverOf(*rig, "Avatar_Hips"));
  EXPECT_EQ(joint(*rig, "SpringBone_braid").center_driver, driverOf(*rig, "Avatar_Head"));
  EXPECT_EQ(joint(*rig, "SpringBone_braid_b").center_driver, driverOf(*rig, "Avatar_Head"));
  EXPECT_EQ(joint(*rig, "SpringBone_ribbon").center_driver, -1);
  EXPECT_EQ(joint(*rig, "SpringBone_tassel").center_driver, -1);
  EXPECT_EQ(joint(*rig, "SpringBone_hair_left").center_driver, -1);  // no center: world
}

TEST(RigBuilder, MeasuresAvatarBoneLengthsInMetresThroughTheScaledArmature) {
  // Offsets are centimetres under Armature's scale 0.01: lengths come out in metres, while
  // tail_local stays in the joint's own (centimetre) space.
  const auto rig = avatarRig();
  EXPECT_NEAR(joint(*rig, "SpringBone_hair_left").rest_length, 0.05f, 1e-6f);
  EXPECT_TRUE(vecNear(joint(*rig, "SpringBone_hair_left").tail_local, {0, -5, 0}, 1e-5f));
  EXPECT_NEAR(joint(*rig, "SpringBone_hair_left_3").rest_length, 0.04f, 1e-6f);
  EXPECT_NEAR(joint(*rig, "springbone_earring_r").rest_length, 0.04f, 1e-6f);
  // ponytail root -> _1 is (0,-8,-2) cm: sqrt(64 + 4) = 8.246 cm; _1 -> tip is 10 cm.
  EXPECT_NEAR(joint(*rig, "ponytail_SPRINGBONE").rest_length, std::sqrt(68.0f) / 100, 1e-6f);
  EXPECT_NEAR(joint(*rig, "ponytail_SPRINGBONE_1").rest_length, 0.10f, 1e-6f);
  // braid_b is (-2,-6,0) cm from braid_1 and its tip 5 cm below: braid_b's own length is 5 cm.
  EXPECT_NEAR(joint(*rig, "SpringBone_braid_b").rest_length, 0.05f, 1e-6f);
  // braid_1's tail is braid_a at (2,-6,0) cm: sqrt(4 + 36) = 6.325 cm.
  EXPECT_NEAR(joint(*rig, "SpringBone_braid_1").rest_length, std::sqrt(40.0f) / 100, 1e-6f);
}

TEST(RigBuilder, AppliesAvatarParametersByNearestEntry) {
  const auto rig = avatarRig();
  // SpringBone_hair_left 1.5; _2 overrides with 0.8 (isRoot false); _3 inherits from _2.
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_hair_left").params.stiffness, 1.5f);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_hair_left_1").params.stiffness, 1.5f);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_hair_left_2").params.stiffness, 0.8f);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_hair_left_3").params.stiffness, 0.8f);
  // Nested root SpringBone_bangs_1 (stiffness 0.5, gravityDir [0,-1,-1]) inside bangs (3.0):
  // its own parameters, normalized direction (0, -0.7071, -0.7071), passed down to bangs_2.
  const float d = 1.0f / std::sqrt(2.0f);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_bangs").params.stiffness, 3.0f);
  EXPECT_FLOAT_EQ(joint(*rig, "SpringBone_bangs_1").params.stiffness, 0.5f);
  EXPECT_TRUE(vecNear(joint(*rig, "SpringBone_bangs_2").params.gravity_dir, {0, -d, -d}, 1e-6f));
  EXPECT_EQ(joint(*rig, "SpringBone_bangs_1").chain, jointOf(*rig, "SpringBone_bangs"));
  // hair_r_bead (no token, no entry) takes hair_springbone_r's parameters.
  EXPECT_FLOAT_EQ(joint(*rig, "hair_r_bead").params.drag, 0.4f);
  EXPECT_FLOAT_EQ(joint(*rig, "springbone_earring_r").params.gravity_power, 1.0f);
}

}  // namespace
}  // namespace springbones
