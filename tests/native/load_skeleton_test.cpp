// loadSkeleton on GLB and glTF input (the readers' src/readers/glb_container.cpp, the node table's
// src/loading/gltf_nodes.cpp): what loads, the rest pose it yields, and one test per class of
// malformed input with the ErrorCode it must produce.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/transform_math.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using nlohmann::json;
using test::gltfWithNodes;
using test::loadBytes;
using test::loadText;
using test::makeGlb;
using test::node;
using test::quatNear;
using test::vecNear;

const float kHalfSqrt2 = std::sqrt(0.5f);

// The message of the last loadCode() failure, so a test can check it failed for its own reason.
std::string g_last_message;

// Loads and returns the error code; the skeleton must be empty whenever loading fails.
ErrorCode loadCode(const std::vector<std::uint8_t>& bytes) {
  Skeleton skeleton;
  skeleton.nodes.resize(3);  // stale content that a failed load must clear
  skeleton.parents_first = {0, 1, 2};
  const Error e = loadBytes(bytes, skeleton);
  g_last_message = e.message;
  if (e) {
    EXPECT_FALSE(e.message.empty());
    EXPECT_TRUE(skeleton.nodes.empty()) << "a failed load left nodes behind";
    EXPECT_TRUE(skeleton.parents_first.empty());
  }
  return e.code;
}

ErrorCode loadCode(const std::string& text) { return loadCode(std::vector<std::uint8_t>(text.begin(), text.end())); }

std::vector<std::uint8_t> bytesOf(const std::string& s) { return {s.begin(), s.end()}; }

::testing::AssertionResult lastMessageMentions(const std::string& part) {
  if (g_last_message.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "message \"" << g_last_message << "\" does not mention \"" << part << "\"";
}

// A minimal valid document: one node.
const std::string kOneNode = R"({"asset":{"version":"2.0"},"nodes":[{"name":"A"}]})";

// ---------------------------------------------------------------------------------------------
// What loads

void expectAdrExampleHierarchy(const Skeleton& s) {
  // The ADR's Full Example: 0 Avatar_Head {1, 2}, 1 earring {3}, 2 hair {4}, 3 and 4 tips.
  ASSERT_EQ(s.nodes.size(), 5u);
  const char* names[] = {"Avatar_Head", "SpringBone_earring_r", "SpringBone_hair_left", "springbone_earring_r_tip",
                         "SpringBone_hair_left_tip"};
  const int parents[] = {-1, 0, 0, 1, 2};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(s.nodes[i].name, names[i]);
    EXPECT_EQ(s.nodes[i].parent, parents[i]) << names[i];
  }
  EXPECT_EQ(s.nodes[0].children, (std::vector<int>{1, 2}));
  EXPECT_EQ(s.nodes[1].children, (std::vector<int>{3}));
  EXPECT_EQ(s.nodes[2].children, (std::vector<int>{4}));
  EXPECT_TRUE(s.nodes[3].children.empty());
  // No transforms in the file: every rest transform is the identity.
  for (const SkeletonNode& n : s.nodes) {
    EXPECT_TRUE(vecNear(n.rest_local.translation, glm::vec3(0)));
    EXPECT_TRUE(quatNear(n.rest_local.rotation, glm::quat(1, 0, 0, 0)));
    EXPECT_TRUE(vecNear(n.rest_local.scale, glm::vec3(1)));
    EXPECT_EQ(toGlm(n.rest_world), glm::mat4(1.0f));
  }
}

TEST(GlbLoader, LoadsAdrExampleGlb) { expectAdrExampleHierarchy(test::loadFixtureSkeleton("adr_example.glb")); }

TEST(GlbLoader, LoadsAdrExampleGltfTextWithTheSameHierarchy) {
  expectAdrExampleHierarchy(test::loadFixtureSkeleton("adr_example.gltf"));
}

TEST(GlbLoader, LoadsGltfTextWithByteOrderMarkAndLeadingWhitespace) {
  Skeleton s;
  const Error e = loadText("\xEF\xBB\xBF \n\t" + kOneNode, s);
  ASSERT_FALSE(e) << e.message;
  ASSERT_EQ(s.nodes.size(), 1u);
  EXPECT_EQ(s.nodes[0].name, "A");
}

TEST(GlbLoader, LoadsGlbWithBinChunkAndMeshWithoutDecodingIt) {
  // avatar_hair.glb has a BIN chunk holding a skinned mesh; only the nodes matter.
  const Skeleton s = test::loadFixtureSkeleton("avatar_hair.glb");
  // 95 skeleton nodes (Armature, the 62 Avatar_* bones, 32 wearable nodes) + HairMesh.
  EXPECT_EQ(s.nodes.size(), 96u);
  EXPECT_EQ(s.nodes.back().name, "HairMesh");
  EXPECT_EQ(s.nodes.back().parent, -1);
}

TEST(GlbLoader, HasEveryAvatarBoneInTheAvatarFixture) {
  const Skeleton s = test::loadFixtureSkeleton("avatar_hair.glb");
  std::vector<std::string> bones = {"Hips", "Spine", "Spine1", "Spine2", "Neck", "Head"};
  for (const char* side : {"Left", "Right"}) {
    for (const char* b : {"Shoulder", "Arm", "ForeArm", "Hand", "UpLeg", "Leg", "Foot", "ToeBase"}) {
      bones.push_back(std::string(side) + b);
    }
    for (const char* f : {"Thumb", "Index", "Middle", "Ring", "Pinky"}) {
      for (int j = 1; j <= 4; ++j) bones.push_back(std::string(side) + "Hand" + f + std::to_string(j));
    }
  }
  ASSERT_EQ(bones.size(), 62u);
  int found = 0;
  for (const std::string& b : bones) {
    for (const SkeletonNode& n : s.nodes) found += n.name == "Avatar_" + b ? 1 : 0;
  }
  EXPECT_EQ(found, 62);
  const int hips = test::nodeIndex(s, "Avatar_Hips");
  const int armature = test::nodeIndex(s, "Armature");
  EXPECT_EQ(s.nodes[hips].parent, armature);
  EXPECT_EQ(s.nodes[test::nodeIndex(s, "Avatar_Head")].parent, test::nodeIndex(s, "Avatar_Neck"));
  EXPECT_EQ(s.nodes[test::nodeIndex(s, "Avatar_LeftHandPinky4")].parent, test::nodeIndex(s, "Avatar_LeftHandPinky3"));
}

TEST(GlbLoader, ReadsTranslationRotationAndScale) {
  json n = node("A");
  n["translation"] = {1.5, -2, 3};
  n["rotation"] = {0, kHalfSqrt2, 0, kHalfSqrt2};  // glTF order x, y, z, w: 90 degrees about Y
  n["scale"] = {2, 3, 4};
  Skeleton s;
  ASSERT_FALSE(loadText(gltfWithNodes(json::array({n})), s));
  const Transform& t = s.nodes[0].rest_local;
  EXPECT_TRUE(vecNear(t.translation, {1.5f, -2, 3}));
  EXPECT_TRUE(quatNear(t.rotation, glm::quat(kHalfSqrt2, 0, kHalfSqrt2, 0)));  // glm: w, x, y, z
  EXPECT_TRUE(vecNear(t.scale, {2, 3, 4}));
}

TEST(GlbLoader, RenormalizesRotationAndTreatsZeroQuaternionAsIdentity) {
  json a = node("A");
  a["rotation"] = {0, 0, 2, 0};  // length 2: the unit quaternion (0,0,1,0), 180 degrees about Z
  json b = node("B");
  b["rotation"] = {0, 0, 0, 0};
  Skeleton s;
  ASSERT_FALSE(loadText(gltfWithNodes({a, b}), s));
  EXPECT_TRUE(quatNear(s.nodes[0].rest_local.rotation, glm::quat(0, 0, 0, 1)));
  EXPECT_TRUE(quatNear(s.nodes[1].rest_local.rotation, glm::quat(1, 0, 0, 0)));
}

TEST(GlbLoader, DecomposesNodeMatrixIntoTranslationRotationScale) {
  // M = T(1,2,3) * Rz(90) * S(2,3,4), column-major. Rz(90) takes x to y and y to -x, so the
  // columns are Rz*(2,0,0) = (0,2,0), Rz*(0,3,0) = (-3,0,0), (0,0,4), and (1,2,3,1).
  json n = node("M");
  n["matrix"] = {0, 2, 0, 0, -3, 0, 0, 0, 0, 0, 4, 0, 1, 2, 3, 1};
  Skeleton s;
  ASSERT_FALSE(loadText(gltfWithNodes(json::array({n})), s));
  const Transform& t = s.nodes[0].rest_local;
  EXPECT_TRUE(vecNear(t.translation, {1, 2, 3}));
  EXPECT_TRUE(vecNear(t.scale, {2, 3, 4}));
  EXPECT_TRUE(quatNear(t.rotation, glm::quat(kHalfSqrt2, 0, 0, kHalfSqrt2)));  // 90 deg about Z
  // The world matrix of a root is its local matrix: (1,0,0) lands at T + Rz*S*(1,0,0) = (1,4,3).
  EXPECT_TRUE(vecNear(glm::vec3(toGlm(s.nodes[0].rest_world) * glm::vec4(1, 0, 0, 1)), {1, 4, 3}));
}

TEST(GlbLoader, DecomposesMirroredMatrixIntoNegativeScale) {
  // diag(-1, 1, 1): a mirror, not a rotation. One scale component goes negative and the rotation
  // stays the identity, so composing again gives back the same matrix.
  json n = node("Mirror");
  n["matrix"] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  Skeleton s;
  ASSERT_FALSE(loadText(gltfWithNodes(json::array({n})), s));
  const Transform& t = s.nodes[0].rest_local;
  EXPECT_TRUE(vecNear(t.scale, {-1, 1, 1}));
  EXPECT_TRUE(quatNear(t.rotation, glm::quat(1, 0, 0, 0)));
  EXPECT_TRUE(vecNear(glm::vec3(toGlm(s.nodes[0].rest_world) * glm::vec4(2, 3, 4, 1)), {-2, 3, 4}));
}

TEST(GlbLoader, ComputesRestWorldTransformsFromTheRootDown) {
  // Parent: T(1,0,0), 90 degrees about Y, uniform scale 2. Child: T(0,0,1).
  // Child origin in world = (1,0,0) + Ry(90) * 2 * (0,0,1); Ry(90) takes z to x, so (3,0,0).
  // Grandchild T(0,1,0) under an identity child: (3,0,0) + Ry(90) * 2 * (0,1,0) = (3,2,0).
  json parent = node("P", {1});
  parent["translation"] = {1, 0, 0};
  parent["rotation"] = {0, kHalfSqrt2, 0, kHalfSqrt2};
  parent["scale"] = {2, 2, 2};
  Skeleton s;
  ASSERT_FALSE(loadText(gltfWithNodes({parent, node("C", {2}, {0, 0, 1}), node("G", {}, {0, 1, 0})}), s));
  EXPECT_TRUE(vecNear(glm::vec3(toGlm(s.nodes[1].rest_world)[3]), {3, 0, 0}));
  EXPECT_TRUE(vecNear(glm::vec3(toGlm(s.nodes[2].rest_world)[3]), {3, 2, 0}));
  // The child's x axis is the parent's: Ry(90) * 2 * (1,0,0) = (0,0,-2).
  EXPECT_TRUE(vecNear(glm::vec3(toGlm(s.nodes[1].rest_world)[0]), {0, 0, -2}));
}

TEST(GlbLoader, ComputesWorldPositionsOfTheScaledRotatedAvatarArmature) {
  // Armature: +90 deg about X, scale 0.01; Avatar_Hips at (0,0,-100) with -90 deg about X.
  // Rx(90) takes z to -y... applied to (0,0,-100) gives (0,100,0), times 0.01: hips at 1 m.
  // The two rotations cancel, so below the hips offsets are centimetres along world axes:
  // Head = hips + Spine(0,10,0) + Spine1(0,12,0) + Spine2(0,12,0) + Neck(0,16,-1) + Head(0,10,1)
  //      = (0, 100+60, 0) cm = (0, 1.6, 0) m.
  // LeftUpLeg at (9,-6,0) is turned 180 deg about Z, so its children's +Y points down:
  // LeftToeBase = (9, 94, 0) - (0, 44.89, 0) - (0, 41, 0) + (0, -6, 12) = (9, 2.11, 12) cm.
  const Skeleton s = test::loadFixtureSkeleton("avatar_hair.glb");
  EXPECT_TRUE(vecNear(test::worldPosition(s, "Avatar_Hips"), {0, 1.0f, 0}));
  EXPECT_TRUE(vecNear(test::worldPosition(s, "Avatar_Head"), {0, 1.6f, 0}));
  EXPECT_TRUE(vecNear(test::worldPosition(s, "Avatar_LeftToeBase"), {0.09f, 0.0211f, 0.12f}));
  // SpringBone_hair_left at head + (7,8,-2) cm; its tip 5+5+5+4 = 19 cm lower.
  EXPECT_TRUE(vecNear(test::worldPosition(s, "SpringBone_hair_left"), {0.07f, 1.68f, -0.02f}));
  EXPECT_TRUE(vecNear(test::worldPosition(s, "SpringBone_hair_left_tip"), {0.07f, 1.49f, -0.02f}));
  // Left hand in T-pose: Spine2 (0,134,0) + Shoulder (3,11,-1) + Arm 12 + ForeArm 27 + Hand 25.
  EXPECT_TRUE(vecNear(test::worldPosition(s, "Avatar_LeftHand"), {0.67f, 1.45f, -0.01f}));
}

TEST(GlbLoader, OrdersEveryNodeAfterItsParentEvenWhenChildrenComeFirstInTheFile) {
  // Node 0 is a leaf whose parent (2) is listed after it; node 1 is another root.
  json nodes = {node("leaf"), node("root2"), node("mid", {0}), node("root", {2})};
  Skeleton s;
  ASSERT_FALSE(loadText(gltfWithNodes(nodes), s));
  EXPECT_EQ(s.nodes[0].parent, 2);
  EXPECT_EQ(s.nodes[2].parent, 3);
  EXPECT_EQ(s.nodes[1].parent, -1);
  EXPECT_EQ(s.nodes[3].parent, -1);
  ASSERT_EQ(s.parents_first.size(), 4u);
  std::vector<int> position(4, -1);
  for (std::size_t k = 0; k < s.parents_first.size(); ++k) position[s.parents_first[k]] = int(k);
  for (int i = 0; i < 4; ++i) {
    ASSERT_GE(position[i], 0) << "node " << i << " missing from parents_first";
    if (s.nodes[i].parent >= 0) { EXPECT_LT(position[s.nodes[i].parent], position[i]); }
  }
}

TEST(GlbLoader, LoadsDocumentWithoutNodesAsEmptySkeleton) {
  Skeleton s;
  const Error e = loadText(R"({"asset":{"version":"2.0"}})", s);
  EXPECT_FALSE(e) << e.message;
  EXPECT_TRUE(s.nodes.empty());
}

TEST(GlbLoader, DoesNotDecodeBuffersImagesOrMeshes) {
  // A bogus base64 buffer, an image that is not an image, a mesh pointing at accessors that do
  // not exist, and nested extras: none of it is needed for the hierarchy, so the file loads.
  json doc = json::parse(gltfWithNodes({node("Root", {1}), node("SpringBone_a")}));
  doc["buffers"] = {{{"uri", "data:application/octet-stream;base64,@@@not base64@@@"}, {"byteLength", 1000}}};
  doc["images"] = {{{"uri", "data:image/png;base64,AAAA"}}, {{"uri", "missing.png"}}};
  doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 42}}}}}}}};
  doc["accessors"] = {{{"bufferView", 7}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}}};
  doc["nodes"][0]["mesh"] = 0;
  doc["nodes"][0]["extras"] = {{"deep", {{"er", {1, 2, {{"x", nullptr}}}}}}};
  doc["nodes"][1]["extensions"] = {{"DCL_spring_bone_joint", {{"stiffness", "bogus"}}}};
  Skeleton s;
  const Error e = loadText(doc.dump(), s);
  ASSERT_FALSE(e) << e.message;
  ASSERT_EQ(s.nodes.size(), 2u);
  EXPECT_EQ(s.nodes[1].parent, 0);
}

TEST(GlbLoader, LoadsTenThousandDeepHierarchyWithoutRecursion) {
  // Node i has child i+1 and translation (0,1,0): node i sits at y = i + 1, exactly
  // representable in float, so the last one is at 10000.
  constexpr int kDepth = 10000;
  json nodes = json::array();
  for (int i = 0; i < kDepth; ++i) {
    json n = {{"name", "n" + std::to_string(i)}, {"translation", {0, 1, 0}}};
    if (i + 1 < kDepth) n["children"] = {i + 1};
    nodes.push_back(std::move(n));
  }
  Skeleton s;
  const Error e = loadBytes(makeGlb(gltfWithNodes(nodes)), s);
  ASSERT_FALSE(e) << e.message;
  ASSERT_EQ(s.nodes.size(), std::size_t(kDepth));
  EXPECT_EQ(s.nodes.back().parent, kDepth - 2);
  EXPECT_EQ(s.parents_first.front(), 0);
  EXPECT_EQ(s.parents_first.back(), kDepth - 1);
  EXPECT_EQ(glm::vec3(toGlm(s.nodes.back().rest_world)[3]), glm::vec3(0, float(kDepth), 0));
}

TEST(GlbLoader, LoadsDeeplyNestedExtrasWithoutRecursion) {
  // 200,000 nested arrays in a node's extras: a recursive parser, copier or printer would run
  // out of stack. The loader drops extras before anything walks them.
  constexpr int kDepth = 200000;
  std::string text = R"({"asset":{"version":"2.0"},"nodes":[{"name":"A","extras":)";
  text += std::string(kDepth, '[') + std::string(kDepth, ']') + "}]}";
  Skeleton s;
  const Error e = loadText(text, s);
  ASSERT_FALSE(e) << e.message;
  EXPECT_EQ(s.nodes.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// Container errors

TEST(GlbLoader, RejectsEmptyInput) {
  Skeleton s;
  const std::uint8_t byte = 0;
  EXPECT_EQ(loadSkeleton(&byte, 0, s).code, ErrorCode::kGlbTruncated);
  EXPECT_EQ(loadSkeleton(nullptr, 0, s).code, ErrorCode::kGlbTruncated);
}

TEST(GlbLoader, RejectsNullBufferWithNonZeroSize) {
  Skeleton s;
  EXPECT_EQ(loadSkeleton(nullptr, 16, s).code, ErrorCode::kInvalidArgument);
}

TEST(GlbLoader, RejectsInputTooShortToIdentify) { EXPECT_EQ(loadCode(bytesOf("gl")), ErrorCode::kGlbTruncated); }

TEST(GlbLoader, RejectsTruncatedGlbHeader) {
  // The magic is there but the 12-byte header and the first 8-byte chunk header are not.
  const std::vector<std::uint8_t> glb = makeGlb(kOneNode);
  for (std::size_t size : {4u, 11u, 12u, 19u}) {
    EXPECT_EQ(loadCode(std::vector<std::uint8_t>(glb.begin(), glb.begin() + size)), ErrorCode::kGlbTruncated)
        << size << " bytes";
  }
}

TEST(GlbLoader, RejectsHeaderLengthBeyondTheBuffer) {
  std::vector<std::uint8_t> glb = makeGlb(kOneNode);
  test::writeU32(glb, 8, static_cast<std::uint32_t>(glb.size() + 4));
  EXPECT_EQ(loadCode(glb), ErrorCode::kGlbTruncated);
}

TEST(GlbLoader, RejectsFileCutShortOfItsDeclaredLength) {
  std::vector<std::uint8_t> glb = makeGlb(kOneNode);
  glb.resize(glb.size() - 8);
  EXPECT_EQ(loadCode(glb), ErrorCode::kGlbTruncated);
}

TEST(GlbLoader, RejectsHeaderLengthShorterThanTheHeaders) {
  std::vector<std::uint8_t> glb = makeGlb(kOneNode);
  test::writeU32(glb, 8, 16);
  EXPECT_EQ(loadCode(glb), ErrorCode::kGlbBadChunk);
}

TEST(GlbLoader, RejectsWrongMagic) {
  std::vector<std::uint8_t> glb = makeGlb(kOneNode);
  glb[3] = 'X';  // "glTX"
  EXPECT_EQ(loadCode(glb), ErrorCode::kGlbBadMagic);
  EXPECT_EQ(loadCode(bytesOf("PK\x03\x04 not a model at all")), ErrorCode::kGlbBadMagic);
}

TEST(GlbLoader, RejectsGlbVersionOtherThanTwo) {
  std::vector<std::uint8_t> glb = makeGlb(kOneNode);
  test::writeU32(glb, 4, 1);
  EXPECT_EQ(loadCode(glb), ErrorCode::kGlbBadChunk);
  test::writeU32(glb, 4, 3);
  EXPECT_EQ(loadCode(glb), ErrorCode::kGlbBadChunk);
}

TEST(GlbLoader, RejectsFirstChunkThatIsNotJson) {
  std::vector<std::uint8_t> glb = makeGlb(kOneNode);
  test::writeU32(glb, 16, test::kChunkBin);
  EXPECT_EQ(loadCode(glb), ErrorCode::kGlbBadChunk);
}

TEST(GlbLoader, RejectsJsonChunkLengthBeyondTheFile) {
  std::vector<std::uint8_t> glb = makeGlb(kOneNode);
  // Chunk data may span at most declared length - 12 (header) - 8 (chunk header) bytes.
  const std::uint32_t available = static_cast<std::uint32_t>(glb.size() - 20);
  test::writeU32(glb, 12, available + 1);
  EXPECT_EQ(loadCode(glb), ErrorCode::kGlbTruncated);
  test::writeU32(glb, 12, 0xFFFFFFFFu);
  EXPECT_EQ(loadCode(glb), ErrorCode::kGlbTruncated);
  test::writeU32(glb, 12, available);  // exactly fits again
  EXPECT_EQ(loadCode(glb), ErrorCode::kOk);
}

TEST(GlbLoader, RejectsTruncatedJsonChunk) {
  // The container is consistent but the JSON chunk ends mid-document: the header and chunk
  // lengths were rewritten to the cut size.
  const std::string text = kOneNode;
  std::vector<std::uint8_t> glb = makeGlb(text.substr(0, text.size() - 8));
  EXPECT_EQ(loadCode(glb), ErrorCode::kGltfBadJson);
}

// ---------------------------------------------------------------------------------------------
// Document errors

TEST(GlbLoader, RejectsJsonThatDoesNotParse) {
  EXPECT_EQ(loadCode(makeGlb(R"({"asset": {"version": "2.0"}, "nodes": [)")), ErrorCode::kGltfBadJson);
  EXPECT_EQ(loadCode(std::string(R"({"asset": {"version": "2.0"},})")), ErrorCode::kGltfBadJson);
  EXPECT_EQ(loadCode(std::string("{ nodes: [] }")), ErrorCode::kGltfBadJson);
  // NaN is not JSON.
  EXPECT_EQ(loadCode(std::string(R"({"asset":{"version":"2.0"},"nodes":[{"translation":[NaN,0,0]}]})")),
            ErrorCode::kGltfBadJson);
}

TEST(GlbLoader, RejectsJsonThatIsNotAnObject) {
  // Inside a GLB the chunk is taken as JSON whatever it holds.
  EXPECT_EQ(loadCode(makeGlb("[1, 2, 3]")), ErrorCode::kGltfInvalid);
  EXPECT_EQ(loadCode(makeGlb("\"glTF\"")), ErrorCode::kGltfInvalid);
  EXPECT_EQ(loadCode(makeGlb("null")), ErrorCode::kGltfInvalid);
  // Bare text must start with '{' to be taken for glTF at all.
  EXPECT_EQ(loadCode(std::string("[1, 2, 3]")), ErrorCode::kGlbBadMagic);
}

TEST(GlbLoader, RejectsMissingAssetVersion) {
  EXPECT_EQ(loadCode(std::string(R"({"nodes":[]})")), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("asset"));
  EXPECT_EQ(loadCode(std::string(R"({"asset":{},"nodes":[]})")), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("asset"));
  EXPECT_EQ(loadCode(std::string(R"({"asset":{"version":2.0},"nodes":[]})")), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("asset"));
  EXPECT_EQ(loadCode(std::string(R"({"asset":"2.0","nodes":[]})")), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("asset"));
  EXPECT_EQ(loadCode(makeGlb(R"({"asset":{"generator":"x"}})")), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("asset"));
}

TEST(GlbLoader, RejectsNodesThatAreNotAnArray) {
  EXPECT_EQ(loadCode(std::string(R"({"asset":{"version":"2.0"},"nodes":{"0":{}}})")), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("not an array"));
}

TEST(GlbLoader, RejectsNodeThatIsNotAnObject) {
  EXPECT_EQ(loadCode(gltfWithNodes({node("A"), 5})), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("node 1 is not an object"));
  EXPECT_EQ(loadCode(gltfWithNodes(json::array({nullptr}))), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("node 0 is not an object"));
}

TEST(GlbLoader, RejectsTransformArraysOfTheWrongLength) {
  const std::pair<const char*, json> cases[] = {
      {"translation", {0, 1}},                    // 2 numbers
      {"translation", {0, 1, 2, 3}},              // 4 numbers
      {"rotation", {0, 0, 1}},                    // 3 numbers
      {"scale", json::array()},                   // empty
      {"matrix", json(std::vector<int>(15, 0))},  // 15 numbers
  };
  for (const auto& [field, value] : cases) {
    json n = node("A");
    n[field] = value;
    EXPECT_EQ(loadCode(gltfWithNodes(json::array({n}))), ErrorCode::kGltfInvalid) << field << " " << value;
    EXPECT_TRUE(lastMessageMentions(field));
  }
}

TEST(GlbLoader, RejectsTransformsThatAreNotNumbers) {
  const std::pair<const char*, json> cases[] = {
      {"translation", {0, "1", 2}}, {"rotation", {0, 0, 0, nullptr}}, {"scale", "1 1 1"},
      {"scale", {true, 1, 1}},      {"translation", {{0}, 1, 2}},     {"translation", 3},
  };
  for (const auto& [field, value] : cases) {
    json n = node("A");
    n[field] = value;
    EXPECT_EQ(loadCode(gltfWithNodes(json::array({n}))), ErrorCode::kGltfInvalid) << field << " " << value;
    EXPECT_TRUE(lastMessageMentions(field));
  }
}

TEST(GlbLoader, RejectsNameThatIsNotAString) {
  for (json name : {json(5), json(nullptr), json({"A"}), json({{"text", "A"}})}) {
    EXPECT_EQ(loadCode(gltfWithNodes(json::array({{{"name", name}}}))), ErrorCode::kGltfInvalid) << name;
    EXPECT_TRUE(lastMessageMentions("name"));
  }
}

TEST(GlbLoader, RejectsChildIndexOutOfRange) {
  EXPECT_EQ(loadCode(gltfWithNodes(json::array({node("A", {1})}))), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("child"));
  EXPECT_EQ(loadCode(gltfWithNodes({node("A", {2}), node("B")})), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("child"));
  EXPECT_EQ(loadCode(gltfWithNodes(json::array({{{"name", "A"}, {"children", {10000000000LL}}}}))),
            ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("child"));
}

TEST(GlbLoader, RejectsNegativeChildIndex) {
  EXPECT_EQ(loadCode(gltfWithNodes({{{"name", "A"}, {"children", {-1}}}, node("B")})), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("child"));
}

TEST(GlbLoader, RejectsChildIndexThatIsNotAnInteger) {
  EXPECT_EQ(loadCode(gltfWithNodes({{{"name", "A"}, {"children", {0.5}}}, node("B")})), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("child"));
  // 1.0 is the number 1: a page's JSON.parse cannot tell them apart, so neither does the reader
  // (as JSON Schema since draft 6 counts 1.0 an integer).
  EXPECT_EQ(loadCode(std::string(R"({"asset":{"version":"2.0"},"nodes":[{"children":[1.0]},{}]})")), ErrorCode::kOk);
  EXPECT_EQ(loadCode(gltfWithNodes({{{"name", "A"}, {"children", {"1"}}}, node("B")})), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("child"));
  EXPECT_EQ(loadCode(gltfWithNodes({{{"name", "A"}, {"children", 1}}, node("B")})), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("child"));
}

TEST(GlbLoader, RejectsTransformValuesBeyondFloatRange) {
  // Finite doubles that a float (what the rest pose is stored in) turns into infinity.
  const std::pair<const char*, json> cases[] = {
      {"translation", {1e39, 0, 0}},
      {"scale", {1, -1e300, 1}},
      {"rotation", {0, 0, 0, 1e39}},
      {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5e38, 0, 0, 1}},
  };
  for (const auto& [field, value] : cases) {
    json n = node("A");
    n[field] = value;
    EXPECT_EQ(loadCode(gltfWithNodes(json::array({n}))), ErrorCode::kGltfInvalid) << field << " " << value;
    EXPECT_TRUE(lastMessageMentions(field));
  }
}

TEST(GlbLoader, NormalizesQuaternionWithHugeComponents) {
  // (1e30, 0, 0, 1e30) is float-representable; its squared length is not, so it must be
  // normalized in double: 90 degrees about X, (x, w) = (0.7071, 0.7071).
  json n = node("A");
  n["rotation"] = {1e30, 0, 0, 1e30};
  Skeleton s;
  const Error e = loadText(gltfWithNodes(json::array({n})), s);
  ASSERT_FALSE(e) << e.message;
  EXPECT_TRUE(quatNear(s.nodes[0].rest_local.rotation, glm::quat(kHalfSqrt2, kHalfSqrt2, 0, 0)));
}

TEST(GlbLoader, RejectsRestPoseThatOverflowsFloat) {
  // Each scale 1e30 is a valid float; two levels multiply to 1e60, which is not.
  json a = node("A", {1});
  a["scale"] = {1e30, 1e30, 1e30};
  json b = node("B", {}, {1, 0, 0});
  b["scale"] = {1e30, 1e30, 1e30};
  EXPECT_EQ(loadCode(gltfWithNodes({a, b})), ErrorCode::kGltfInvalid);
  EXPECT_TRUE(lastMessageMentions("overflow"));
  // A matrix whose column lengths overflow while decomposing.
  json m = node("M");
  m["matrix"] = {3e38, 3e38, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_EQ(loadCode(gltfWithNodes(json::array({m}))), ErrorCode::kGltfInvalid);
  // Large but representable stays accepted: a node at 1e20 m.
  json far = node("Far", {}, {1e20, 0, 0});
  EXPECT_EQ(loadCode(gltfWithNodes(json::array({far}))), ErrorCode::kOk);
}

// ---------------------------------------------------------------------------------------------
// Hierarchy errors

TEST(GlbLoader, RejectsNodeListedAsChildOfTwoParents) {
  EXPECT_EQ(loadCode(test::readFixture("two_parents.gltf")), ErrorCode::kHierarchyMultipleParents);
  // The same child twice in one parent's list is also a second parent link.
  EXPECT_EQ(loadCode(gltfWithNodes({node("A", {1, 1}), node("B")})), ErrorCode::kHierarchyMultipleParents);
}

TEST(GlbLoader, RejectsNodeThatIsItsOwnChild) {
  EXPECT_EQ(loadCode(gltfWithNodes({node("Root", {1}), node("Self", {1})})), ErrorCode::kHierarchyCycle);
}

TEST(GlbLoader, RejectsCycleThatNoRootLeadsTo) {
  // cycle.gltf: node 0 is a root; nodes 1 and 2 are each other's parent.
  EXPECT_EQ(loadCode(test::readFixture("cycle.gltf")), ErrorCode::kHierarchyCycle);
  // Every node in the cycle, no root at all: 0 -> 1 -> 2 -> 0.
  EXPECT_EQ(loadCode(gltfWithNodes({node("A", {1}), node("B", {2}), node("C", {0})})), ErrorCode::kHierarchyCycle);
}

// ---------------------------------------------------------------------------------------------
// Limits

TEST(GlbLoader, RejectsMoreThanMaxNodes) {
  std::string text = R"({"asset":{"version":"2.0"},"nodes":[)";
  text.reserve(text.size() + 3 * (kMaxNodes + 1) + 4);
  for (std::size_t i = 0; i <= kMaxNodes; ++i) text += i == 0 ? "{}" : ",{}";
  text += "]}";
  EXPECT_EQ(loadCode(text), ErrorCode::kLimitExceeded);
}

TEST(GlbLoader, AcceptsExactlyMaxNodes) {
  std::string text = R"({"asset":{"version":"2.0"},"nodes":[)";
  text.reserve(text.size() + 3 * kMaxNodes + 4);
  for (std::size_t i = 0; i < kMaxNodes; ++i) text += i == 0 ? "{}" : ",{}";
  text += "]}";
  Skeleton s;
  const Error e = loadText(text, s);
  ASSERT_FALSE(e) << e.message;
  EXPECT_EQ(s.nodes.size(), kMaxNodes);
  EXPECT_EQ(s.parents_first.size(), kMaxNodes);
}

TEST(GlbLoader, RejectsGltfJsonLargerThanTheLimit) {
  // Valid JSON (an object followed by whitespace) one byte over the limit: the size decides,
  // before anything parses it.
  std::string text = kOneNode;
  text.resize(kMaxGltfJsonBytes + 1, ' ');
  EXPECT_EQ(loadCode(text), ErrorCode::kLimitExceeded);
  EXPECT_EQ(loadCode(makeGlb(text)), ErrorCode::kLimitExceeded);
  text.resize(kMaxGltfJsonBytes);  // at the limit: loads
  EXPECT_EQ(loadCode(text), ErrorCode::kOk);
}

// linkHierarchy multiplies the rest matrices with its own scalar code (no out-of-line glm calls
// in WebAssembly); it must give glm's product bit for bit, zero signs included.
TEST(GlbLoader, RestWorldIsGlmsProductToTheBit) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::string text = R"({"asset":{"version":"2.0"},"nodes":[)";
  const int count = 200;
  for (int i = 0; i < count; ++i) {
    char node[512];
    if (i % 7 == 3) {
      std::snprintf(node, sizeof node, R"({"matrix":[%.9g,%.9g,0,0,%.9g,%.9g,0,0,0,0,-0.0,1,%.9g,%.9g,%.9g,1])", u(rng),
                    u(rng), u(rng), u(rng), u(rng), u(rng), u(rng));
    } else {
      std::snprintf(node, sizeof node,
                    R"({"translation":[%.9g,%.9g,-0.0],"rotation":[%.9g,%.9g,%.9g,%.9g],"scale":[%.9g,1,%.9g])", u(rng),
                    u(rng), u(rng), u(rng), u(rng), u(rng), u(rng), u(rng));
    }
    text += (i ? "," : "") + std::string(node);
    // A chain with side branches: node i's parent is i - 1 or i - 2.
    const int child_a = i + 1, child_b = i + 2;
    if (i % 2 == 0 && child_b < count) {
      text += ",\"children\":[" + std::to_string(child_a) + "," + std::to_string(child_b) + "]}";
    } else if (i % 2 == 0 && child_a < count) {
      text += ",\"children\":[" + std::to_string(child_a) + "]}";
    } else {
      text += "}";
    }
  }
  text += "]}";
  Skeleton s;
  ASSERT_FALSE(test::loadText(text, s)) << text.substr(0, 200);
  int checked = 0;
  for (int i : s.parents_first) {
    const SkeletonNode& n = s.nodes[i];
    const glm::mat4 local = composeTransform(n.rest_local);
    const glm::mat4 expected = n.parent < 0 ? local : toGlm(s.nodes[n.parent].rest_world) * local;
    EXPECT_TRUE(std::memcmp(&expected, &n.rest_world, sizeof(glm::mat4)) == 0) << "node " << i;
    checked += n.parent >= 0;
  }
  EXPECT_GT(checked, 50);
}

}  // namespace
}  // namespace springbones
