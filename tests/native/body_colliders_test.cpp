// The 'dcl-body' collider preset (src/loading/body_colliders.cpp): shapes measured from the armature of
// tests/fixtures/avatar_hair.glb (neck 10.05 cm, Spine2 -> Neck 16.03 cm, Spine1 -> Spine2 12 cm,
// Shoulder -> Arm 12 cm, Arm -> ForeArm 27 cm; the Armature's scale 0.01 makes bone space
// centimetres), how they scale with the avatar, and what happens when bones are missing.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/transform_math.h"
#include "loading/body_colliders.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using namespace test;

const ColliderSpec* findSpec(const std::vector<ColliderSpec>& specs, const std::string& node) {
  for (const ColliderSpec& s : specs) {
    if (s.node == node) return &s;
  }
  return nullptr;
}

// World position of a point in a node's rest space.
glm::vec3 worldOf(const Skeleton& skeleton, const std::string& node, const Vec3& local) {
  return glm::vec3(toGlm(skeleton.nodes[nodeIndex(skeleton, node)].rest_world) * glm::vec4(toGlm(local), 1.0f));
}

// The skeleton with its root scaled by `factor` (rest_world recomputed parents first).
Skeleton scaled(Skeleton skeleton, float factor) {
  skeleton.nodes[nodeIndex(skeleton, "Armature")].rest_local.scale =
      fromGlm(toGlm(skeleton.nodes[nodeIndex(skeleton, "Armature")].rest_local.scale) * factor);
  for (int n : skeleton.parents_first) {
    SkeletonNode& node = skeleton.nodes[n];
    const glm::mat4 local = composeTransform(node.rest_local);
    node.rest_world = fromGlm(node.parent >= 0 ? toGlm(skeleton.nodes[node.parent].rest_world) * local : local);
  }
  return skeleton;
}

TEST(BodyColliders, EightShapesFromTheFullArmatureWithSizesFromRestLengths) {
  const Skeleton skeleton = loadFixtureSkeleton("avatar_hair.glb");
  std::vector<Warning> warnings;
  const std::vector<ColliderSpec> specs = dclBodyColliders(skeleton, {}, warnings);
  EXPECT_TRUE(warnings.empty());
  ASSERT_EQ(specs.size(), 8u);

  // Head: neck (0, 1.5, -0.01) -> head (0, 1.6, 0), L = sqrt(0.1^2 + 0.01^2) = 0.100499 m; the
  // centre 0.9 L past the head along it, (0, 1.69, 0.009), radius 0.94 L = 9.447 cm in bone space.
  const ColliderSpec* head = findSpec(specs, "Avatar_Head");
  ASSERT_NE(head, nullptr);
  EXPECT_EQ(head->shape, Collider::Shape::kSphere);
  EXPECT_TRUE(vecNear(worldOf(skeleton, "Avatar_Head", head->offset), glm::vec3(0.0f, 1.69f, 0.009f), 1e-5f));
  EXPECT_NEAR(head->radius, 0.94f * 10.0499f, 1e-3f);

  // Neck: a capsule from the neck to the head, radius 0.45 L.
  const ColliderSpec* neck = findSpec(specs, "Avatar_Neck");
  ASSERT_NE(neck, nullptr);
  EXPECT_EQ(neck->shape, Collider::Shape::kCapsule);
  EXPECT_TRUE(vecNear(worldOf(skeleton, "Avatar_Neck", neck->offset), glm::vec3(0.0f, 1.5f, -0.01f), 1e-5f));
  EXPECT_TRUE(vecNear(worldOf(skeleton, "Avatar_Neck", neck->tail), glm::vec3(0.0f, 1.6f, 0.0f), 1e-5f));
  EXPECT_NEAR(neck->radius, 0.45f * 10.0499f, 1e-3f);

  // Chest on Spine2 (1.34 m): L = |(0, 0.16, -0.01)| = 0.160312; centre 0.31 L up the segment,
  // ends 0.375 L to either side along X (square to the segment), radius 0.69 L.
  const ColliderSpec* chest = findSpec(specs, "Avatar_Spine2");
  ASSERT_NE(chest, nullptr);
  const float chest_length = 0.160312f;
  const glm::vec3 up = glm::vec3(0.0f, 0.16f, -0.01f) / chest_length;
  const glm::vec3 centre = glm::vec3(0.0f, 1.34f, 0.0f) + up * (0.31f * chest_length);
  EXPECT_TRUE(vecNear(worldOf(skeleton, "Avatar_Spine2", chest->offset),
                      centre - glm::vec3(0.375f * chest_length, 0.0f, 0.0f), 1e-5f));
  EXPECT_TRUE(vecNear(worldOf(skeleton, "Avatar_Spine2", chest->tail),
                      centre + glm::vec3(0.375f * chest_length, 0.0f, 0.0f), 1e-5f));
  EXPECT_NEAR(chest->radius, 0.69f * 16.0312f, 1e-3f);

  // The left upper arm: Arm (0.15, 1.45, -0.01) to ForeArm (0.42, 1.45, -0.01), radius 0.17 x 27 cm.
  const ColliderSpec* arm = findSpec(specs, "Avatar_LeftArm");
  ASSERT_NE(arm, nullptr);
  EXPECT_TRUE(vecNear(worldOf(skeleton, "Avatar_LeftArm", arm->tail), glm::vec3(0.42f, 1.45f, -0.01f), 1e-5f));
  EXPECT_NEAR(arm->radius, 0.17f * 27.0f, 1e-3f);
  ASSERT_NE(findSpec(specs, "Avatar_RightShoulder"), nullptr);
}

TEST(BodyColliders, ScaleWithTheAvatarInWorldAndStayTheSameInBoneSpace) {
  const Skeleton skeleton = loadFixtureSkeleton("avatar_hair.glb");
  const Skeleton big = scaled(skeleton, 1.5f);
  std::vector<Warning> warnings;
  const std::vector<ColliderSpec> normal = dclBodyColliders(skeleton, {}, warnings);
  const std::vector<ColliderSpec> larger = dclBodyColliders(big, {}, warnings);
  ASSERT_EQ(normal.size(), larger.size());
  for (std::size_t i = 0; i < normal.size(); ++i) {
    // Bone space is the same: the world sizes grow with the bones' scale.
    EXPECT_TRUE(vecNear(larger[i].offset, normal[i].offset, 1e-3f)) << normal[i].node;
    EXPECT_NEAR(larger[i].radius, normal[i].radius, 1e-3f) << normal[i].node;
  }
  const ColliderSpec* head = findSpec(larger, "Avatar_Head");
  ASSERT_NE(head, nullptr);
  // The head is 1.5 x as far above the origin, its centre 1.5 x 1.69 m up.
  EXPECT_TRUE(vecNear(worldOf(big, "Avatar_Head", head->offset), glm::vec3(0.0f, 1.5f * 1.69f, 1.5f * 0.009f), 1e-4f));
}

TEST(BodyColliders, ShapesWhoseBonesTheGlbLacksAreLeftOutWithOneWarning) {
  // Hips -> Spine -> Spine1 -> Spine2 -> Neck -> Head and a hair chain, as the demo's wearable
  // carries them: no shoulders or arms.
  const nlohmann::json nodes = nlohmann::json::array(
      {node("Avatar_Hips", {1}, {0, 1.0, 0}), node("Avatar_Spine", {2}, {0, 0.1, 0}),
       node("Avatar_Spine1", {3}, {0, 0.12, 0}), node("Avatar_Spine2", {4}, {0, 0.12, 0}),
       node("Avatar_Neck", {5}, {0, 0.16, -0.01}), node("Avatar_Head", {6}, {0, 0.1, 0.01}),
       node("SpringBone_hair", {7}, {0, 0.05, -0.1}), node("SpringBone_hair_tip", {}, {0, -0.1, 0})});
  RigOptions options;
  options.preset = ColliderPreset::kDclBody;
  const auto rig = rigFromJson(nodes, {{"SpringBone_hair", {{"isRoot", true}}}}, options);
  ASSERT_EQ(rig->colliders.size(), 4u);  // head, neck, chest, upper belly
  int skipped = 0;
  for (const Warning& w : rig->warnings) {
    if (w.code != "body-collider-skipped") continue;
    ++skipped;
    EXPECT_NE(w.message.find("left-upper-arm"), std::string::npos) << w.message;
    EXPECT_NE(w.message.find("Avatar_RightForeArm"), std::string::npos) << w.message;
  }
  EXPECT_EQ(skipped, 1);
  ASSERT_EQ(rig->joints.size(), 1u);
  EXPECT_EQ(rig->joints[0].colliders.size(), 4u);
  // Unscaled bones: the sizes are metres. Head radius 0.94 x |(0, 0.1, 0.01)|.
  EXPECT_NEAR(rig->colliders[0].radius, 0.94f * 0.100499f, 1e-5f);
}

// The demo's case: the wearable carries Hips to Head, the avatar it is worn on all 62 bones. Given
// the avatar's bones, every shape is measured on them and the ones the GLB lacks ride on the
// avatar's bone by name (an external driver); only a bone the avatar lacks leaves a shape out.
TEST(BodyColliders, TheAvatarsBonesGiveEveryShapeToAWearableThatLacksThem) {
  const nlohmann::json nodes = nlohmann::json::array(
      {node("Avatar_Hips", {1}, {0, 1.0, 0}), node("Avatar_Spine", {2}, {0, 0.1, 0}),
       node("Avatar_Spine1", {3}, {0, 0.12, 0}), node("Avatar_Spine2", {4}, {0, 0.12, 0}),
       node("Avatar_Neck", {5}, {0, 0.16, -0.01}), node("Avatar_Head", {6}, {0, 0.1, 0.01}),
       node("SpringBone_hair", {7}, {0, 0.05, -0.1}), node("SpringBone_hair_tip", {}, {0, -0.1, 0})});
  const Skeleton avatar = loadFixtureSkeleton("avatar_hair.glb");
  std::vector<AvatarBone> bones;
  for (const SkeletonNode& n : avatar.nodes) bones.push_back(AvatarBone{n.name, n.rest_world});
  RigOptions options;
  options.preset = ColliderPreset::kDclBody;
  options.avatar_bones = bones;
  const auto rig = rigFromJson(nodes, {{"SpringBone_hair", {{"isRoot", true}}}}, options);
  EXPECT_FALSE(hasWarning(rig->warnings, "body-collider-skipped")) << describeWarnings(rig->warnings);
  ASSERT_EQ(rig->colliders.size(), 8u);
  // The same shapes as the full armature's own, in each bone's space.
  std::vector<Warning> warnings;
  const std::vector<ColliderSpec> own = dclBodyColliders(avatar, {}, warnings);
  ASSERT_EQ(own.size(), 8u);
  for (std::size_t i = 0; i < own.size(); ++i) {
    const Collider& c = rig->colliders[i];
    EXPECT_EQ(rig->drivers[c.driver].name, own[i].node);
    EXPECT_TRUE(vecNear(c.offset, own[i].offset, 1e-4f)) << own[i].node;
    EXPECT_TRUE(vecNear(c.tail, own[i].tail, 1e-4f)) << own[i].node;
    EXPECT_NEAR(c.radius, own[i].radius, 1e-4f) << own[i].node;
  }
  // The arms are not in the wearable: the page supplies them by name.
  for (const Collider& c : rig->colliders) {
    const Driver& d = rig->drivers[c.driver];
    const bool in_glb = d.name.find("Shoulder") == std::string::npos && d.name.find("Arm") == std::string::npos;
    EXPECT_EQ(d.node >= 0, in_glb) << d.name;
  }

  // An avatar without a left forearm: the left upper arm alone is left out, and the warning says
  // the avatar lacks it.
  std::vector<AvatarBone> no_forearm;
  for (const AvatarBone& b : bones) {
    if (b.name != "Avatar_LeftForeArm") no_forearm.push_back(b);
  }
  options.avatar_bones = no_forearm;
  const auto partial = rigFromJson(nodes, {{"SpringBone_hair", {{"isRoot", true}}}}, options);
  EXPECT_EQ(partial->colliders.size(), 7u);
  const Warning* skipped = findWarning(partial->warnings, "body-collider-skipped", "");
  ASSERT_NE(skipped, nullptr);
  EXPECT_NE(skipped->message.find("left out left-upper-arm (the avatar lacks Avatar_LeftForeArm)"), std::string::npos)
      << skipped->message;
}

TEST(BodyColliders, NoArmatureNoShapes) {
  const nlohmann::json nodes = nlohmann::json::array(
      {node("Root", {1}), node("SpringBone_a", {2}, {0, 1, 0}), node("SpringBone_a_tip", {}, {0, -0.1, 0})});
  RigOptions options;
  options.preset = ColliderPreset::kDclBody;
  const auto rig = rigFromJson(nodes, {{"SpringBone_a", {{"isRoot", true}}}}, options);
  EXPECT_TRUE(rig->colliders.empty());
  const Warning* skipped = findWarning(rig->warnings, "body-collider-skipped", "");
  ASSERT_NE(skipped, nullptr);
  EXPECT_NE(skipped->message.find("head, neck, chest"), std::string::npos) << skipped->message;
  EXPECT_NE(skipped->message.find("the GLB lacks Avatar_Spine1, Avatar_Spine2, Avatar_Neck, Avatar_Head,"),
            std::string::npos)
      << skipped->message;
}

TEST(BodyColliders, OffUnlessAsked) {
  const Skeleton skeleton = loadFixtureSkeleton("avatar_hair.glb");
  ModelEntry model;
  std::vector<Warning> warnings;
  ASSERT_FALSE(parseSpringBonesText(readFixtureText("avatar_hair.metadata.json"), metadataKeyOf("avatar_hair.glb"),
                                    model, warnings));
  EXPECT_TRUE(buildRig(skeleton, model, warnings)->colliders.empty());
  RigOptions options;
  options.preset = ColliderPreset::kDclBody;
  EXPECT_EQ(buildRig(skeleton, model, warnings, options)->colliders.size(), 8u);
}

}  // namespace
}  // namespace springbones
