// Hostile input, end to end: every named case goes through the whole path a wearable
// takes (GLB bytes -> loadSkeleton -> springBones -> buildRig -> Instance -> step) and must end in
// a clear Error or in a documented clamp with a warning, never in a crash, a hang or a NaN. The
// loader's and the reader's own unit tests (load_skeleton_test.cpp, metadata_test.cpp) check each
// rule in isolation; here the point is that nothing downstream breaks. Inputs that a fuzzer found
// are replayed by fuzz_regressions_test.cpp and named here (RegressionFuzz*).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/typed_value.h"
#include "creator_tools/builder_edits.h"
#include "creator_tools/validation.h"
#include "readers/json_values.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "springbones/typed_input.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using nlohmann::json;
using test::makeGlb;
using test::readFixture;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr char kHash[] = "bafkreihostile";

std::vector<std::uint8_t> bytesOf(const std::string& s) { return {s.begin(), s.end()}; }

// What a preview gets from a wearable: an error, or a rig with warnings.
struct Loaded {
  Error error;
  std::shared_ptr<const Rig> rig;
};

Loaded loadWearable(const std::vector<std::uint8_t>& glb, const std::string& metadata_text,
                    const std::string& hash = kHash) {
  Loaded out;
  Skeleton skeleton;
  out.error = loadSkeleton(glb.data(), glb.size(), skeleton);
  if (out.error) {
    EXPECT_FALSE(out.error.message.empty());
    EXPECT_TRUE(skeleton.nodes.empty());
    return out;
  }
  ModelEntry model;
  std::vector<Warning> warnings;
  out.error = parseSpringBonesText(metadata_text, hash, model, warnings);
  if (out.error) {
    EXPECT_FALSE(out.error.message.empty());
    return out;
  }
  out.rig = buildRig(std::move(skeleton), model, std::move(warnings));
  return out;
}

Loaded loadWearableValue(const std::vector<std::uint8_t>& glb, const json& springBones) {
  Loaded out;
  Skeleton skeleton;
  out.error = loadSkeleton(glb.data(), glb.size(), skeleton);
  if (out.error) return out;
  ModelEntry model;
  std::vector<Warning> warnings;
  out.error = parseSpringBones(springBones, kHash, model, warnings);
  if (out.error) return out;
  out.rig = buildRig(std::move(skeleton), model, std::move(warnings));
  return out;
}

::testing::AssertionResult finiteUnitRotations(const Instance& instance) {
  const float* r = instance.rotations();
  for (std::size_t j = 0; j < instance.jointCount(); ++j) {
    const float x = r[4 * j], y = r[4 * j + 1], z = r[4 * j + 2], w = r[4 * j + 3];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(w)) {
      return ::testing::AssertionFailure() << "joint " << j << " has a non-finite rotation";
    }
    const double len = std::sqrt(double(x) * x + double(y) * y + double(z) * z + double(w) * w);
    if (std::fabs(len - 1.0) > 1e-4) {
      return ::testing::AssertionFailure() << "joint " << j << " rotation has length " << len;
    }
  }
  return ::testing::AssertionSuccess();
}

// Steps a few ordinary frames and checks the output after each.
void stepAndCheck(Instance& instance, int frames = 10, double dt = 1.0 / 60) {
  ASSERT_TRUE(finiteUnitRotations(instance)) << "before stepping";
  for (int i = 0; i < frames; ++i) {
    instance.step(dt);
    ASSERT_TRUE(finiteUnitRotations(instance)) << "after frame " << i;
  }
}

// A wearable like the ADR example: Avatar_Head driving two chains of three bones each.
json hairNodes() {
  return json::array({
      {{"name", "Avatar_Head"}, {"children", {1, 4}}, {"translation", {0, 1.6, 0}}},
      {{"name", "SpringBone_hair"}, {"children", {2}}, {"translation", {0.1, 0, 0}}},
      {{"name", "SpringBone_hair_1"}, {"children", {3}}, {"translation", {0, -0.1, 0}}},
      {{"name", "SpringBone_hair_tip"}, {"translation", {0, -0.1, 0}}},
      {{"name", "SpringBone_earring"}, {"children", {5}}, {"translation", {-0.1, 0, 0}}},
      {{"name", "SpringBone_earring_tip"}, {"translation", {0, -0.05, 0.01}}},
  });
}

std::vector<std::uint8_t> hairGlb() {
  return makeGlb(json{{"asset", {{"version", "2.0"}}}, {"nodes", hairNodes()}}.dump());
}

json entry(json stiffness, json gravity_power, json gravity_dir, json drag) {
  return {{"stiffness", std::move(stiffness)},
          {"gravityPower", std::move(gravity_power)},
          {"gravityDir", std::move(gravity_dir)},
          {"drag", std::move(drag)},
          {"isRoot", true}};
}

json hairMetadata(const json& hair_entry) {
  return {{"version", 1},
          {"models",
           {{kHash, {{"SpringBone_hair", hair_entry}, {"SpringBone_earring", entry(1.0, 1.0, {0, -1, 0}, 0.4)}}}}}};
}

// ---------------------------------------------------------------------------------------------
// The GLB container

TEST(HostileInput, TruncatedGlbHeaderAtEveryLengthIsAGlbTruncatedError) {
  const std::vector<std::uint8_t> glb = readFixture("adr_example.glb");
  ASSERT_GT(glb.size(), 20u);
  for (std::size_t size = 0; size < 20; ++size) {
    const std::vector<std::uint8_t> cut(glb.begin(), glb.begin() + size);
    Skeleton s;
    const Error e = loadSkeleton(cut.data(), cut.size(), s);
    EXPECT_EQ(e.code, ErrorCode::kGlbTruncated) << size << " bytes: " << e.message;
  }
  // Cut anywhere inside the JSON chunk: still truncated, never read past the end.
  for (std::size_t size = 20; size < glb.size(); size += 7) {
    const std::vector<std::uint8_t> cut(glb.begin(), glb.begin() + size);
    Skeleton s;
    EXPECT_EQ(loadSkeleton(cut.data(), cut.size(), s).code, ErrorCode::kGlbTruncated) << size;
  }
}

TEST(HostileInput, OversizedGlbLengthsAreErrorsNotReadsPastTheBuffer) {
  const std::vector<std::uint8_t> glb = readFixture("adr_example.glb");
  const std::uint32_t lengths[] = {std::uint32_t(glb.size() + 1), 0x7FFFFFFFu, 0xFFFFFFFFu};
  for (std::uint32_t declared : lengths) {
    std::vector<std::uint8_t> bad = glb;
    test::writeU32(bad, 8, declared);
    Skeleton s;
    EXPECT_EQ(loadSkeleton(bad.data(), bad.size(), s).code, ErrorCode::kGlbTruncated) << declared;
  }
  for (std::uint32_t chunk : lengths) {
    std::vector<std::uint8_t> bad = glb;
    test::writeU32(bad, 12, chunk);
    Skeleton s;
    EXPECT_EQ(loadSkeleton(bad.data(), bad.size(), s).code, ErrorCode::kGlbTruncated) << chunk;
  }
  std::vector<std::uint8_t> tiny = glb;
  test::writeU32(tiny, 8, 12);  // shorter than its own headers
  Skeleton s;
  EXPECT_EQ(loadSkeleton(tiny.data(), tiny.size(), s).code, ErrorCode::kGlbBadChunk);
}

TEST(HostileInput, WrongMagicIsAGlbBadMagicError) {
  std::vector<std::uint8_t> glb = readFixture("adr_example.glb");
  glb[0] = 'x';
  const Loaded l = loadWearable(glb, "null");
  EXPECT_EQ(l.error.code, ErrorCode::kGlbBadMagic) << l.error.message;
  const Loaded png = loadWearable({0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A}, "null");
  EXPECT_EQ(png.error.code, ErrorCode::kGlbBadMagic);
}

TEST(HostileInput, JsonChunkThatIsNotJsonIsAGltfBadJsonError) {
  const std::vector<std::string> texts = {"{not json at all", R"({"asset":{"version":"2.0"},"nodes":[)",
                                          std::string("{\"a\":\"\0\"}", 9), "{}}"};
  for (const std::string& text : texts) {
    const Loaded l = loadWearable(makeGlb(text), "null");
    EXPECT_EQ(l.error.code, ErrorCode::kGltfBadJson) << text << ": " << l.error.message;
  }
  // Binary garbage in a well-formed container.
  std::string garbage;
  for (int i = 0; i < 256; ++i) garbage.push_back(static_cast<char>(i));
  EXPECT_EQ(loadWearable(makeGlb(garbage), "null").error.code, ErrorCode::kGltfBadJson);
}

// ---------------------------------------------------------------------------------------------
// The hierarchy

TEST(HostileInput, NodeThatIsItsOwnAncestorIsAHierarchyCycleError) {
  const Loaded fixture = loadWearable(readFixture("cycle.gltf"), "null");
  EXPECT_EQ(fixture.error.code, ErrorCode::kHierarchyCycle) << fixture.error.message;
  // Own child, and a three-node loop that no root leads to next to a healthy tree.
  const json self = {{"asset", {{"version", "2.0"}}}, {"nodes", {{{"name", "springbone_a"}, {"children", {0}}}}}};
  EXPECT_EQ(loadWearable(bytesOf(self.dump()), "null").error.code, ErrorCode::kHierarchyCycle);
  json loop = {{"asset", {{"version", "2.0"}}},
               {"nodes", json::array({{{"name", "root"}},
                                      {{"name", "a"}, {"children", {2}}},
                                      {{"name", "b"}, {"children", {3}}},
                                      {{"name", "c"}, {"children", {1}}}})}};
  const Loaded l = loadWearable(bytesOf(loop.dump()), "null");
  EXPECT_EQ(l.error.code, ErrorCode::kHierarchyCycle);
  EXPECT_NE(l.error.message.find("ancestor"), std::string::npos) << l.error.message;
}

TEST(HostileInput, NodeWithTwoParentsIsAHierarchyMultipleParentsError) {
  const Loaded l = loadWearable(readFixture("two_parents.gltf"), "null");
  EXPECT_EQ(l.error.code, ErrorCode::kHierarchyMultipleParents) << l.error.message;
  // Listed twice by the same parent counts as two parents too.
  const json twice = {{"asset", {{"version", "2.0"}}},
                      {"nodes", json::array({{{"name", "p"}, {"children", {1, 1}}}, {{"name", "c"}}})}};
  EXPECT_EQ(loadWearable(bytesOf(twice.dump()), "null").error.code, ErrorCode::kHierarchyMultipleParents);
}

TEST(HostileInput, HundredThousandNodesLoadBuildAndStep) {
  // 100,000 flat nodes under one root, all spring-bone candidates: loads, builds (no root, so
  // no joints) and steps. kMaxNodes + 1 nodes is a limit-exceeded error
  // (GlbLoader.RejectsMoreThanMaxNodes).
  constexpr int kCount = 100000;
  json nodes = json::array();
  std::vector<int> children;
  for (int i = 1; i < kCount; ++i) children.push_back(i);
  nodes.push_back({{"name", "Avatar_Hips"}, {"children", children}});
  for (int i = 1; i < kCount; ++i) nodes.push_back({{"name", "springbone_" + std::to_string(i)}});
  const Loaded l = loadWearable(makeGlb(json{{"asset", {{"version", "2.0"}}}, {"nodes", nodes}}.dump()),
                                hairMetadata(entry(1, 1, {0, -1, 0}, 0.5)).dump());
  ASSERT_FALSE(l.error) << l.error.message;
  EXPECT_EQ(l.rig->skeleton.nodes.size(), std::size_t(kCount));
  Instance instance(l.rig);
  stepAndCheck(instance, 2);
}

// One chain of `depth` spring bones hanging from Avatar_Hips, each 1 cm below its parent.
std::vector<std::uint8_t> deepChainGlb(int depth, const std::string& extras = {}) {
  std::string text = R"({"asset":{"version":"2.0"},"nodes":[{"name":"Avatar_Hips","children":[1]})";
  for (int i = 1; i <= depth; ++i) {
    text += R"(,{"name":"springbone_)" + std::to_string(i) + R"(","translation":[0,-0.01,0])";
    if (i < depth) text += R"(,"children":[)" + std::to_string(i + 1) + "]";
    if (!extras.empty()) text += R"(,"extras":)" + extras;
    text += "}";
  }
  text += "]}";
  return makeGlb(text);
}

TEST(HostileInput, TenThousandDeepHierarchyLoadsBuildsStepsAndDestroysWithoutRecursion) {
  constexpr int kDepth = 10000;
  const json springBones = {{"version", 1}, {"models", {{kHash, {{"springbone_1", entry(0.5, 2.0, {1, 0, 0}, 0.1)}}}}}};
  const Loaded l = loadWearable(deepChainGlb(kDepth), springBones.dump());
  ASSERT_FALSE(l.error) << l.error.message;
  ASSERT_EQ(l.rig->joints.size(), std::size_t(kDepth - 1));  // the last node is the tip
  EXPECT_EQ(l.rig->joints.back().parent_joint, kDepth - 3);
  {
    Instance instance(l.rig);
    stepAndCheck(instance, 30);
    instance.reset();
    stepAndCheck(instance, 2, 1e9);
  }
  // Builder edits and the validator walk the same hierarchy.
  ModelEntry model;
  std::vector<Warning> warnings;
  ASSERT_FALSE(parseSpringBones(springBones, kHash, model, warnings));
  EXPECT_EQ(detectSpringBones(l.rig->skeleton, model).size(), std::size_t(kDepth));
}

TEST(HostileInput, DeeplyNestedExtrasAreDroppedBeforeAnythingRecursesIntoThem) {
  // 100,000 levels in one node's extras and 10 levels in each of 1,000 nodes: the readers keep only
  // the fields the runtime reads of each node and of the root, so nothing converts, copies or
  // compares the nested values recursively.
  constexpr int kDepth = 100000;
  const std::string deep = std::string(kDepth, '[') + std::string(kDepth, ']');
  std::string text = R"({"asset":{"version":"2.0","extras":)" + deep + R"(},"extensions":{"X":)" + deep +
                     R"(},"nodes":[{"name":"Avatar_Hips","children":[1],"extras":)" + deep +
                     R"(},{"name":"springbone_a","children":[2],"translation":[0,-0.1,0],"extensions":{"KHR_x":)" +
                     deep + R"(}},{"name":"springbone_b","translation":[0,-0.1,0]}],"extras":{"a":)" + deep + "}}";
  const json springBones = {{"version", 1}, {"models", {{kHash, {{"springbone_a", entry(1, 1, {0, -1, 0}, 0.5)}}}}}};
  const Loaded l = loadWearable(bytesOf(text), springBones.dump());
  ASSERT_FALSE(l.error) << l.error.message;
  ASSERT_EQ(l.rig->joints.size(), 1u);
  Instance instance(l.rig);
  stepAndCheck(instance);

  const Loaded many = loadWearable(deepChainGlb(1000, std::string(10, '[') + std::string(10, ']')), springBones.dump());
  EXPECT_FALSE(many.error) << many.error.message;
}

TEST(HostileInput, DeeplyNestedMetadataIsReadValidatedAndEditedWithoutRecursion) {
  // springBones text nested 200,000 deep, as the whole value, as a parameter and as an unknown
  // key inside a bone entry (which the schema allows and the Builder must carry over).
  constexpr int kDepth = 200000;
  const std::string deep = std::string(kDepth, '[') + std::string(kDepth, ']');
  ModelEntry model;
  std::vector<Warning> warnings;
  EXPECT_EQ(parseSpringBonesText(deep, kHash, model, warnings).code, ErrorCode::kMetadataInvalid);

  const std::string text =
      R"({"version":1,"models":{")" + std::string(kHash) + R"(":{"SpringBone_hair":{"stiffness":)" + deep +
      R"(,"gravityPower":1,"gravityDir":[0,-1,0],"drag":0.5,"isRoot":true,"custom":)" + deep + "}}}}";
  const Loaded l = loadWearable(hairGlb(), text);
  ASSERT_FALSE(l.error) << l.error.message;
  EXPECT_TRUE(test::hasWarning(l.rig->warnings, "param-not-number"));
  Instance instance(l.rig);
  stepAndCheck(instance);

  const json value = json::parse(text);
  const std::vector<ValidationError> errors = validateSpringBonesSchema(value);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].message, "must be number");
}

TEST(HostileInput, BuilderEditsRefuseMetadataNestedDeeperThanTheyCanCopy) {
  // setSpringBoneParams copies springBones into its result; nlohmann's copy recurses once per
  // level. A bone entry with an unknown key nested 200,000 deep overflowed the stack (found
  // writing this test, ASan: stack-overflow in basic_json's copy constructor); it is now an
  // error, like params nested that deep. 64 levels are allowed.
  constexpr int kDepth = 200000;
  const std::string deep = std::string(kDepth, '[') + std::string(kDepth, ']');
  const json entity = {
      {"content", {{{"file", "a.glb"}, {"hash", kHash}}}},
      {"metadata",
       {{"data",
         {{"representations",
           {{{"bodyShapes", {"urn:decentraland:off-chain:base-avatars:BaseMale"}}, {"mainFile", "a.glb"}}}}}}}}};
  const json spring_bones = json::parse(R"({"version":1,"models":{")" + std::string(kHash) +
                                        R"(":{"SpringBone_hair":{"custom":)" + deep + "}}}}");
  json out;
  const Error e = setSpringBoneParams(spring_bones, entity, "BaseMale", "SpringBone_hair", json{{"stiffness", 1}}, out);
  EXPECT_EQ(e.code, ErrorCode::kMetadataInvalid) << e.message;
  const json deep_params = json::parse(R"({"custom":)" + deep + "}");
  EXPECT_EQ(setSpringBoneParams(nullptr, entity, "BaseMale", "SpringBone_hair", deep_params, out).code,
            ErrorCode::kInvalidArgument);
  // The limit: params plus 63 nested arrays (64 levels) pass, one more does not.
  const json at_limit = json::parse(R"({"custom":)" + std::string(63, '[') + std::string(63, ']') + "}");
  EXPECT_FALSE(setSpringBoneParams(nullptr, entity, "BaseMale", "SpringBone_hair", at_limit, out));
  const json over_limit = json::parse(R"({"custom":)" + std::string(64, '[') + std::string(64, ']') + "}");
  EXPECT_TRUE(setSpringBoneParams(nullptr, entity, "BaseMale", "SpringBone_hair", over_limit, out));
  // Shallow documents still go through.
  EXPECT_FALSE(setSpringBoneParams(nullptr, entity, "BaseMale", "SpringBone_hair",
                                   json{{"stiffness", 1}, {"custom", {{"a", {1, 2, {3}}}}}}, out));
}

// ---------------------------------------------------------------------------------------------
// Names

TEST(HostileInput, InvalidUtf8InNodeNamesBecomesReplacementCharactersAsThePageDecodesIt) {
  // The page decodes the JSON chunk with TextDecoder: each ill-formed sequence is one U+FFFD (EF BF
  // BD), so the name is valid UTF-8 and the readers give the same (docs/input.md).
  const std::string fffd = "\xef\xbf\xbd";
  const std::vector<std::pair<std::string, std::string>> names = {
      {"springbone_\xff\xfe", "springbone_" + fffd + fffd},
      {"springbone_\xc3", "springbone_" + fffd},
      {"springbone_\xed\xa0\x80", "springbone_" + fffd + fffd + fffd},
      {"\xc0\xaf", fffd + fffd},
      {"\xe2\x82"
       "A",
       fffd + "A"},
  };
  for (const auto& [bytes, decoded] : names) {
    const std::string text = R"({"asset":{"version":"2.0"},"nodes":[{"name":")" + bytes + R"("}]})";
    const std::vector<std::uint8_t> glb = makeGlb(text);
    Skeleton skeleton;
    ASSERT_FALSE(loadSkeleton(glb.data(), glb.size(), skeleton)) << decoded;
    EXPECT_EQ(skeleton.nodes[0].name, decoded);
  }
  // An escaped lone surrogate in a name the runtime reads: the page's encoder refuses it, so do the
  // readers, with the path.
  const std::string escaped = R"({"asset":{"version":"2.0"},"nodes":[{"name":"springbone_\ud800"}]})";
  const Loaded lone = loadWearable(makeGlb(escaped), "null");
  EXPECT_EQ(lone.error.code, ErrorCode::kGltfInvalid);
  EXPECT_EQ(lone.error.path, "/nodes/0/name");
  // Well-formed but odd names load: NUL, escapes, astral characters.
  const std::string odd = R"({"asset":{"version":"2.0"},"nodes":[{"name":"springbone_\u0000\ud83d\ude00/~\"\\"}]})";
  EXPECT_FALSE(loadWearable(makeGlb(odd), "null").error);
}

TEST(HostileInput, WhatJsonParseRefusesTheReadersRefuseAndWhatItAcceptsInUnreadMembersTheyNeverCheck) {
  const std::string head = R"({"asset":{"version":"2.0"},"nodes":[{"name":"a","rotation":[-0,0,0,1]}])";
  const auto load = [](const std::string& text, Skeleton& skeleton) {
    return loadSkeleton(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), skeleton);
  };
  Skeleton skeleton;
  for (const std::string& refused :
       {head + "}" + std::string(3, '\0'), head + "}" + std::string("\0garbage", 8), head + "} x", head + ",}",
        head + R"(,"a":01})", head + R"(,"a":"\x"})", head + ",\"a\":\"\t\"}", head}) {
    EXPECT_EQ(load(refused, skeleton).code, ErrorCode::kGltfBadJson) << refused;
  }
  for (const std::string& accepted :
       {head + R"(,"accessors":[{"max":[1e400]}]})", head + R"(,"meshes":[{"name":"\ud800\udc00\udfff"}]})",
        head + ",\"meshes\":[{\"name\":\"\xff\xc0\"}]}", head + ",\"extras\":[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]}"}) {
    ASSERT_FALSE(load(accepted, skeleton)) << accepted;
    // -0 keeps its sign through to the rest rotation, as JSON.parse keeps it.
    EXPECT_TRUE(std::signbit(skeleton.nodes[0].rest_local.rotation.x));
  }
}

TEST(HostileInput, InvalidUtf8InMetadataIsAnErrorAsTextAndHarmlessAsAJsonValue) {
  ModelEntry model;
  std::vector<Warning> warnings;
  const std::string text = "{\"version\":1,\"models\":{\"h\":{\"springbone_\xff\":{}}}}";
  EXPECT_EQ(parseSpringBonesText(text, "h", model, warnings).code, ErrorCode::kMetadataBadJson);
  // A json built in C++ (or by a binding) can hold any bytes; every message that quotes them
  // goes through dump(..., error_handler_t::replace) or the validator's own UTF-16 conversion.
  const std::string bad = "springbone_\xff\xc3(";
  json value = {{"version", 1},
                {"models",
                 {{"h",
                   {{bad,
                     {{"stiffness", bad},
                      {"gravityDir", {bad}},
                      {"center", bad},
                      {"isRoot", bad},
                      {"drag", 0.5},
                      {"gravityPower", 0}}},
                    {"springbone_ok", bad}}}}}};
  ASSERT_FALSE(parseSpringBones(value, "h", model, warnings));
  EXPECT_TRUE(test::hasWarning(warnings, "param-not-number"));
  EXPECT_TRUE(test::hasWarning(warnings, "bone-entry-invalid"));
  EXPECT_FALSE(validateSpringBonesSchema(value).empty());
  value["models"][bad] = value["models"]["h"];
  const json entity = {{"content", {{{"file", bad}, {"hash", bad}}}},
                       {"metadata", {{"data", {{"representations", {{{"mainFile", bad}}}}, {"springBones", value}}}}}};
  std::vector<ValidationError> entity_errors;
  ASSERT_FALSE(validateSpringBones(entity, entity_errors));
  EXPECT_FALSE(entity_errors.empty());
  // The loader: a node named with invalid UTF-8 (as a Skeleton built in C++ could be) matched
  // by an entry with the same bytes builds and steps.
  const Loaded l = loadWearableValue(hairGlb(), hairMetadata(entry(1, 1, {0, -1, 0}, 0.5)));
  ASSERT_FALSE(l.error);
  Skeleton skeleton = l.rig->skeleton;
  skeleton.nodes[1].name = bad;
  ModelEntry m;
  std::vector<Warning> w;
  ASSERT_FALSE(
      parseSpringBones(json{{"version", 1}, {"models", {{"h", {{bad, entry(1, 1, {0, -1, 0}, 0.5)}}}}}}, "h", m, w));
  Instance instance(buildRig(std::move(skeleton), m, std::move(w)));
  EXPECT_EQ(instance.jointCount(), 2u);
  stepAndCheck(instance);
}

// ---------------------------------------------------------------------------------------------
// Metadata

TEST(HostileInput, TenMegabyteMetadataIsReadAndSixteenMegabytesPlusOneIsRejected) {
  // 10 MB of bone entries for one model (names that match no node) plus the real ones.
  json model = hairMetadata(entry(1, 1, {0, -1, 0}, 0.5))["models"][kHash];
  std::string text = R"({"version":1,"models":{")" + std::string(kHash) + R"(":{)";
  const std::string filler =
      R"({"stiffness":1,"gravityPower":1,"gravityDir":[0,-1,0],"drag":0.5,"pad":")" + std::string(900, 'x') + R"("})";
  int count = 0;
  while (text.size() < (10u << 20)) { text += "\"springbone_unused_" + std::to_string(count++) + "\":" + filler + ","; }
  text += "\"SpringBone_hair\":" + model["SpringBone_hair"].dump() + "}}}";
  ASSERT_GE(text.size(), 10u << 20);
  const Loaded l = loadWearable(hairGlb(), text);
  ASSERT_FALSE(l.error) << l.error.message;
  EXPECT_EQ(l.rig->joints.size(), 2u);
  EXPECT_EQ(test::countWarnings(l.rig->warnings, "bone-not-found"), count);
  Instance instance(l.rig);
  stepAndCheck(instance);

  std::string over(kMaxMetadataBytes + 1, ' ');
  over[0] = '{';
  over.back() = '}';
  EXPECT_EQ(loadWearable(hairGlb(), over).error.code, ErrorCode::kLimitExceeded);
}

TEST(HostileInput, ParametersAsStringsNullNaNAndHugeNumbersAreReplacedOrClampedWithWarnings) {
  // What is not a finite number takes the ADR default (stiffness 2, gravityPower 0, drag 0.5);
  // out-of-range values clamp to [0,4] / [0,2] / [0,1]. One warning per field, at its path.
  struct Case {
    json value;
    const char* warning;
    float stiffness, gravity_power, drag;
  };
  const Case cases[] = {
      {"2", "param-not-number", 2, 0, 0.5f},
      {nullptr, "param-not-number", 2, 0, 0.5f},
      {json::array({1}), "param-not-number", 2, 0, 0.5f},
      {true, "param-not-number", 2, 0, 0.5f},
      {std::numeric_limits<double>::quiet_NaN(), "param-not-finite", 2, 0, 0.5f},  // only a C++ json holds it
      {std::numeric_limits<double>::infinity(), "param-not-finite", 2, 0, 0.5f},
      {1e308, "param-out-of-range", 4, 2, 1},
      {-1e308, "param-out-of-range", 0, 0, 0},
      {std::numeric_limits<double>::denorm_min(), "", 0, 0, 0},
  };
  const std::string prefix = std::string("/models/") + kHash + "/SpringBone_hair/";
  for (const Case& c : cases) {
    const Loaded l = loadWearableValue(hairGlb(), hairMetadata(entry(c.value, c.value, {0, -1, 0}, c.value)));
    ASSERT_FALSE(l.error) << c.value;
    const std::vector<Warning>& w = l.rig->warnings;
    if (*c.warning) {
      ASSERT_EQ(w.size(), 3u) << c.value << test::describeWarnings(w);
      std::vector<std::string> paths;
      for (const Warning& warning : w) {
        EXPECT_EQ(warning.code, c.warning) << c.value;
        EXPECT_FALSE(warning.message.empty());
        paths.push_back(warning.path);
      }
      std::sort(paths.begin(), paths.end());
      EXPECT_EQ(paths, (std::vector<std::string>{prefix + "drag", prefix + "gravityPower", prefix + "stiffness"}));
    } else {
      EXPECT_TRUE(w.empty()) << c.value << test::describeWarnings(w);
    }
    const BoneParams& p = l.rig->joints[0].params;
    EXPECT_EQ(p.stiffness, c.stiffness) << c.value;
    EXPECT_EQ(p.gravity_power, c.gravity_power) << c.value;
    EXPECT_EQ(p.drag, c.drag) << c.value;
    Instance instance(l.rig);
    stepAndCheck(instance, 20);
  }
  // 1e308 as text is a number; 1e309 does not fit a double and the text does not parse.
  std::string text = hairMetadata(entry("@", 1, {0, -1, 0}, 0.5)).dump();
  text.replace(text.find("\"@\""), 3, "1e308");
  const Loaded l = loadWearable(hairGlb(), text);
  ASSERT_FALSE(l.error) << l.error.message;
  EXPECT_FLOAT_EQ(l.rig->joints[0].params.stiffness, 4.0f);
  text.replace(text.find("1e308"), 5, "1e309");
  EXPECT_EQ(loadWearable(hairGlb(), text).error.code, ErrorCode::kMetadataBadJson);
}

TEST(HostileInput, GravityDirOfLengthTwoOrFourFallsBackToDownWithAWarning) {
  // What is not 3 finite numbers is the default [0,-1,0]; a huge vector keeps its direction
  // (normalized without overflowing); each case is exactly one warning at the field's path.
  struct Case {
    json dir;
    const char* warning;
    glm::vec3 expected;
  };
  const glm::vec3 down(0, -1, 0);
  const float diagonal = float(1 / std::sqrt(3.0));
  const Case cases[] = {
      {{0, -1}, "param-not-vector", down},
      {{0, -1, 0, 0}, "param-not-vector", down},
      {json::array(), "param-not-vector", down},
      {{1e308, 1e308, 1e308}, "param-out-of-range", glm::vec3(diagonal)},
      {{std::numeric_limits<double>::quiet_NaN(), 0, 0}, "param-not-vector", down},
      {{0, -1, "0"}, "param-not-vector", down},
      {{0, 0, 0}, "gravity-dir-zero", down},
      {"down", "param-not-vector", down},
      {nullptr, "param-not-vector", down},
  };
  for (const Case& c : cases) {
    const Loaded l = loadWearableValue(hairGlb(), hairMetadata(entry(1, 2, c.dir, 0.5)));
    ASSERT_FALSE(l.error) << c.dir;
    const glm::vec3 g = toGlm(l.rig->joints[0].params.gravity_dir);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(g[k], c.expected[k], 1e-6f) << c.dir;
    ASSERT_EQ(l.rig->warnings.size(), 1u) << c.dir << test::describeWarnings(l.rig->warnings);
    EXPECT_EQ(l.rig->warnings[0].code, c.warning) << c.dir;
    EXPECT_EQ(l.rig->warnings[0].path, std::string("/models/") + kHash + "/SpringBone_hair/gravityDir");
    Instance instance(l.rig);
    stepAndCheck(instance, 20);
  }
}

// ---------------------------------------------------------------------------------------------
// Driver matrices and frame times

TEST(HostileInput, NaNInfiniteAndSingularDriverMatricesKeepRotationsFiniteUnit) {
  const Loaded l = loadWearableValue(hairGlb(), hairMetadata(entry(1, 1, {0, -1, 0}, 0.5)));
  ASSERT_FALSE(l.error);
  Instance instance(l.rig);
  ASSERT_EQ(instance.driverCount(), 1u);
  float* m = instance.driverMatrices();
  const std::vector<float> rest(m, m + 16);
  stepAndCheck(instance, 5);

  std::vector<std::vector<float>> bad;
  bad.push_back(std::vector<float>(16, kNaN));
  bad.push_back(std::vector<float>(16, kInf));
  bad.push_back(std::vector<float>(16, 0.0f));  // all zero, even w
  std::vector<float> singular(16, 0.0f);
  singular[15] = 1.0f;  // zero scale, at the origin
  bad.push_back(singular);
  std::vector<float> flat = rest;
  flat[5] = 0.0f;  // y axis collapsed
  bad.push_back(flat);
  std::vector<float> one_nan = rest;
  one_nan[13] = kNaN;
  bad.push_back(one_nan);
  std::vector<float> projective = rest;
  projective[3] = 1.0f;
  bad.push_back(projective);
  std::vector<float> huge = rest;
  for (int k = 0; k < 12; ++k) huge[k] *= 3e38f;
  bad.push_back(huge);
  std::vector<float> tiny = rest;
  for (int k = 0; k < 12; ++k) tiny[k] *= 1e-40f;  // denormal scale
  bad.push_back(tiny);
  std::vector<float> mirrored = rest;
  for (int k = 0; k < 4; ++k) mirrored[k] = -mirrored[k];
  bad.push_back(mirrored);
  std::vector<float> far = rest;
  far[12] = 3e38f;
  bad.push_back(far);

  for (std::size_t b = 0; b < bad.size(); ++b) {
    std::memcpy(m, bad[b].data(), sizeof(float) * 16);
    for (int i = 0; i < 5; ++i) {
      instance.step(1.0 / 60);
      ASSERT_TRUE(finiteUnitRotations(instance)) << "bad matrix " << b << ", frame " << i;
    }
    // Back to a good pose: the motion recovers, also after a reset under a bad matrix.
    std::memcpy(m, rest.data(), sizeof(float) * 16);
    stepAndCheck(instance, 5);
    std::memcpy(m, bad[b].data(), sizeof(float) * 16);
    instance.reset();
    instance.step(1.0 / 60);
    ASSERT_TRUE(finiteUnitRotations(instance)) << "reset under bad matrix " << b;
    std::memcpy(m, rest.data(), sizeof(float) * 16);
    stepAndCheck(instance, 3);
  }
}

TEST(HostileInput, FrameTimesOfABillionSecondsAndNegativeOrNonFiniteAreHarmless) {
  const Loaded l = loadWearableValue(hairGlb(), hairMetadata(entry(1, 1, {0, -1, 0}, 0.5)));
  ASSERT_FALSE(l.error);
  Instance instance(l.rig);
  stepAndCheck(instance, 10);
  // A huge frame runs maxSubsteps steps and drops the rest (RegressionFuzzSimulationHugeDt).
  instance.step(1e9);
  EXPECT_TRUE(finiteUnitRotations(instance));
  instance.step(std::numeric_limits<double>::max());
  EXPECT_TRUE(finiteUnitRotations(instance));
  // Non-positive and non-finite frames change nothing at all.
  const std::vector<float> before(instance.rotations(), instance.rotations() + 4 * instance.jointCount());
  for (double dt : {-1.0, 0.0, -0.0, -1e9, std::numeric_limits<double>::quiet_NaN(),
                    std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}) {
    instance.step(dt);
    EXPECT_EQ(std::vector<float>(instance.rotations(), instance.rotations() + 4 * instance.jointCount()), before) << dt;
  }
  // Tiny frames accumulate without stepping and without drift into NaN.
  for (int i = 0; i < 1000; ++i) instance.step(1e-300);
  EXPECT_TRUE(finiteUnitRotations(instance));
  // Options out of range are clamped, never divide by zero.
  for (double hz : {0.0, -1.0, 1e-300, 1e300, double(std::numeric_limits<float>::quiet_NaN())}) {
    for (int substeps : {-5, 0, 1, 1000000}) {
      InstanceOptions options;
      options.step_hz = hz;
      options.max_substeps = substeps;
      Instance clamped(l.rig, options);
      EXPECT_GE(clamped.options().step_hz, 1.0);
      EXPECT_LE(clamped.options().step_hz, 1000.0);
      clamped.step(1e9);
      EXPECT_TRUE(finiteUnitRotations(clamped)) << hz << " Hz, " << substeps << " substeps";
    }
  }
}

TEST(HostileInput, RegressionFuzzSimulationHugeDtOverflowedTheStepCount) {
  // Found by fuzz_simulation (tests/fuzz/regressions/simulation/crash-9c1f87cf...): a frame of
  // 1e9 s at 1000 Hz is 1e12 steps, converted to int before the substep cap was applied
  // (undefined behaviour; UBSan: "1e+12 is outside the range of representable values of type
  // 'int'"). The count is now capped in double.
  const Loaded l = loadWearableValue(hairGlb(), hairMetadata(entry(1, 1, {0, -1, 0}, 0.5)));
  ASSERT_FALSE(l.error);
  InstanceOptions options;
  options.step_hz = 1000;
  Instance instance(l.rig, options);
  for (double dt : {1e9, 1e12, 1e300, std::numeric_limits<double>::max()}) {
    instance.step(dt);
    ASSERT_TRUE(finiteUnitRotations(instance)) << dt;
  }
}

TEST(HostileInput, RegressionFuzzSimulationHugeQuaternionComponentsMadeNaNRestRotations) {
  // Found by fuzz_simulation (tests/fuzz/regressions/simulation/crash-bf45c5eb...): a node
  // rotation with a 1e39 component became a float infinity, and normalizing it gave NaN rest
  // rotations (output before the first step). Components are now normalized in double and
  // transforms beyond the float range are a gltf-invalid error.
  const std::string big = R"({"asset":{"version":"2.0"},"nodes":[{"name":"Avatar_Hips","children":[1]},
      {"name":"springbone_a","children":[2],"rotation":[0.85,0.87,3e38,-3.4e38]},
      {"name":"springbone_b","translation":[0,-0.1,0]}]})";
  const json springBones = {{"version", 1}, {"models", {{kHash, {{"springbone_a", entry(1, 1, {0, -1, 0}, 0.5)}}}}}};
  const Loaded l = loadWearable(bytesOf(big), springBones.dump());
  ASSERT_FALSE(l.error) << l.error.message;
  Instance instance(l.rig);
  stepAndCheck(instance);
  std::string beyond = big;
  beyond.replace(beyond.find("3e38"), 4, "1e39");
  EXPECT_EQ(loadWearable(bytesOf(beyond), springBones.dump()).error.code, ErrorCode::kGltfInvalid);
}

// ---------------------------------------------------------------------------------------------
// Size

// Sanitized builds run the size tests smaller: they look for memory errors, which do not need
// the full size, and a Debug + ASan load is 20x slower than a release one.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kSizeDivisor = 10;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr int kSizeDivisor = 10;
#else
constexpr int kSizeDivisor = 1;
#endif
#else
constexpr int kSizeDivisor = 1;
#endif

TEST(HostileInput, RigOfHundredThousandJointsLoadsAndSteps) {
  // 1,000 chains of 100 joints (+ a tip each) under Avatar_Hips: 101,001 nodes, 100,000 joints
  // (a tenth under ASan). Speed is the benchmarks' (springbones_load_report, scripts/bench).
  constexpr int kChains = 1000 / kSizeDivisor, kJoints = 100;
  std::string text = R"({"asset":{"version":"2.0"},"nodes":[{"name":"Avatar_Hips","children":[)";
  for (int c = 0; c < kChains; ++c) text += (c ? "," : "") + std::to_string(1 + c * (kJoints + 1));
  text += "]}";
  std::string bones;
  for (int c = 0; c < kChains; ++c) {
    for (int j = 0; j <= kJoints; ++j) {
      const int index = 1 + c * (kJoints + 1) + j;
      const std::string name = "springbone_" + std::to_string(c) + "_" + std::to_string(j);
      text += R"(,{"name":")" + name + R"(","translation":[)" + (j == 0 ? "0.001" : "0") + ",-0.01,0]";
      if (j < kJoints) text += R"(,"children":[)" + std::to_string(index + 1) + "]";
      text += "}";
      if (j == 0) {
        bones += std::string(bones.empty() ? "" : ",") + "\"" + name +
                 R"(":{"stiffness":1,"gravityPower":1,"gravityDir":[0,-1,0],"drag":0.4,"isRoot":true})";
      }
    }
  }
  text += "]}";
  const std::string metadata = R"({"version":1,"models":{")" + std::string(kHash) + "\":{" + bones + "}}}";
  const Loaded l = loadWearable(makeGlb(text), metadata);
  ASSERT_FALSE(l.error) << l.error.message;
  ASSERT_EQ(l.rig->joints.size(), std::size_t(kChains * kJoints));
  Instance instance(l.rig);
  constexpr int kFrames = 10;
  for (int i = 0; i < kFrames; ++i) instance.step(1.0 / 60);
  EXPECT_TRUE(finiteUnitRotations(instance));
}

// ---------------------------------------------------------------------------------------------
// Bounded by its input (docs/input.md, the limits table): each bound of the typed input is checked
// before the work it bounds, and is limit-exceeded with the limit in the message and the path.

// {"asset": {"version": "2.0"}, "nodes": [{"name": <name>}]} with the name's bytes given.
std::vector<std::uint8_t> typedGltfWithName(const std::string& name) {
  TypedWriter w;
  w.object(2);
  w.key("asset");
  w.object(1);
  w.key("version");
  w.string("2.0");
  w.key("nodes");
  w.array(1);
  w.object(1);
  w.key("name");
  w.string(name);
  return w.bytes();
}

Error loadTyped(const std::vector<std::uint8_t>& typed) {
  Skeleton skeleton;
  return loadSkeleton(TypedBytes{typed.data(), typed.size()}, skeleton);
}

TEST(HostileInput, TypedStringPastItsBoundIsLimitExceededWithItsPath) {
  EXPECT_FALSE(loadTyped(typedGltfWithName(std::string(kTypedMaxStringBytes, 'a'))));
  const Error e = loadTyped(typedGltfWithName(std::string(kTypedMaxStringBytes + 1, 'a')));
  EXPECT_EQ(e.code, ErrorCode::kLimitExceeded);
  EXPECT_EQ(e.path, "/nodes/0/name");
  EXPECT_NE(e.message.find(std::to_string(kTypedMaxStringBytes)), std::string::npos) << e.message;
}

TEST(HostileInput, TypedKeyPastItsBoundIsLimitExceededAndThePathQuotesAPrefixOfIt) {
  TypedWriter w;
  w.object(1);
  w.key("models");
  w.object(1);
  w.key(std::string(kTypedMaxStringBytes + 1, 'k'));
  w.null();
  ModelEntry model;
  std::vector<Warning> warnings;
  const Error e = parseSpringBones(TypedBytes{w.bytes().data(), w.bytes().size()}, "h", model, warnings);
  EXPECT_EQ(e.code, ErrorCode::kLimitExceeded);
  // The path names the member by a bounded prefix of its key, as a message quotes a name.
  EXPECT_EQ(e.path, "/models/" + std::string(kTypedMaxNameBytesInMessage, 'k') + "...");
  EXPECT_LT(e.message.size(), 200u) << e.message;
}

TEST(HostileInput, TypedContainerCountPastItsBoundIsRefusedBeforeItsElementsAreRead) {
  // The count alone: no element follows, and the bound is what is reported, not the short input.
  for (const bool object : {false, true}) {
    TypedWriter w;
    w.object(1);
    w.key("nodes");
    if (object) {
      w.object(static_cast<std::uint32_t>(kTypedMaxContainerSize + 1));
    } else {
      w.array(static_cast<std::uint32_t>(kTypedMaxContainerSize + 1));
    }
    const Error e = loadTyped(w.bytes());
    EXPECT_EQ(e.code, ErrorCode::kLimitExceeded);
    EXPECT_EQ(e.path, "/nodes");
    EXPECT_NE(e.message.find(std::to_string(kTypedMaxContainerSize)), std::string::npos) << e.message;
  }
}

TEST(HostileInput, TypedInputOfMoreValuesThanTheBoundIsRefused) {
  // Nine arrays of a million nulls: 9 MiB, within the glTF's bytes, past the values.
  TypedWriter w;
  w.object(1);
  w.key("extensions");
  const std::size_t arrays = kTypedMaxValues / kTypedMaxContainerSize + 1;
  w.array(static_cast<std::uint32_t>(arrays));
  for (std::size_t a = 0; a < arrays; ++a) {
    w.array(static_cast<std::uint32_t>(kTypedMaxContainerSize));
    w.bytes().insert(w.bytes().end(), kTypedMaxContainerSize, std::uint8_t(kTypedTagNull));
  }
  std::shared_ptr<const Rig> rig;
  const Error e = loadVrm(TypedBytes{w.bytes().data(), w.bytes().size()}, rig);
  EXPECT_EQ(e.code, ErrorCode::kLimitExceeded);
  EXPECT_NE(e.message.find(std::to_string(kTypedMaxValues)), std::string::npos) << e.message;
}

TEST(HostileInput, TypedInputPastItsKindsBytesIsRefusedBeforeDecoding) {
  // springBones as typed input has the bound of its text; a glTF document that of its JSON chunk.
  std::vector<std::uint8_t> big(kMaxMetadataBytes + 1, 0);
  ModelEntry model;
  std::vector<Warning> warnings;
  EXPECT_EQ(parseSpringBones(TypedBytes{big.data(), big.size()}, "h", model, warnings).code, ErrorCode::kLimitExceeded);
  std::string hash;
  EXPECT_EQ(mainFileHashFor(TypedBytes{big.data(), big.size()}, "BaseMale", hash).code, ErrorCode::kLimitExceeded);
  // The same bytes are within a glTF's bound: malformed, not too large.
  EXPECT_EQ(loadTyped(big).code, ErrorCode::kInvalidArgument);
}

TEST(HostileInput, HashAndBodyShapePastTheStringBoundAreRefusedBeforeUse) {
  const std::vector<std::uint8_t> null_value{kTypedTagNull};
  ModelEntry model;
  std::vector<Warning> warnings;
  const std::string long_text(kTypedMaxStringBytes + 1, 'Q');
  EXPECT_EQ(parseSpringBones(TypedBytes{null_value.data(), null_value.size()}, long_text, model, warnings).code,
            ErrorCode::kLimitExceeded);
  std::string hash;
  EXPECT_EQ(mainFileHashFor(TypedBytes{null_value.data(), null_value.size()}, long_text, hash).code,
            ErrorCode::kLimitExceeded);
}

TEST(HostileInput, MessagesQuoteABoundedPrefixOfALongName) {
  // A node that is its own child, named with 60,000 bytes: the error names it by its first bytes.
  const std::string name(60000, 'n');
  const json doc = {{"asset", {{"version", "2.0"}}}, {"nodes", json::array({{{"name", name}, {"children", {0}}}})}};
  const std::string text = doc.dump();
  Skeleton skeleton;
  const Error e = loadSkeleton(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), skeleton);
  EXPECT_EQ(e.code, ErrorCode::kHierarchyCycle);
  EXPECT_NE(e.message.find(std::string(kTypedMaxNameBytesInMessage, 'n') + "..."), std::string::npos);
  EXPECT_LT(e.message.size(), 200u);
}

TEST(HostileInput, ReadersRefuseMoreNodesThanTheLimitBeforeWritingAny) {
  std::string text = R"({"asset":{"version":"2.0"},"nodes":[)";
  for (std::size_t i = 0; i <= kMaxNodes; ++i) text += i == 0 ? "0" : ",0";
  text += "]}";
  std::vector<std::uint8_t> typed;
  const Error e = readGltf(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), GltfPart::kNodes, typed);
  EXPECT_EQ(e.code, ErrorCode::kLimitExceeded);
  EXPECT_EQ(e.path, "/nodes");
  EXPECT_TRUE(typed.empty());
}

}  // namespace
}  // namespace springbones
