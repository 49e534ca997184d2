// Builder edits: candidate detection with prefill values, and writing parameters under the hash
// of the representation's main file (ADR-316, "Builder").
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "creator_tools/builder_edits.h"
#include "readers/json_values.h"
#include "springbones/readers.h"

namespace springbones {
namespace {

using nlohmann::json;

const char* kMale = "urn:decentraland:off-chain:base-avatars:BaseMale";
const char* kFemale = "urn:decentraland:off-chain:base-avatars:BaseFemale";

json entityWith(const std::string& male_file, const std::string& female_file, json springBones = nullptr) {
  return {{"content",
           {{{"file", "male/hair.glb"}, {"hash", "bafyMALE"}},
            {{"file", "female/hair.glb"}, {"hash", "bafyFEMALE"}},
            {{"file", "shared.glb"}, {"hash", "bafySHARED"}},
            {{"file", "thumbnail.png"}, {"hash", "bafyTHUMB"}}}},
          {"metadata",
           {{"data",
             {{"representations",
               {{{"bodyShapes", {kMale}}, {"mainFile", male_file}, {"contents", {male_file}}},
                {{"bodyShapes", {kFemale}}, {"mainFile", female_file}, {"contents", {female_file}}}}},
              {"springBones", springBones}}}}}};
}

json paramsWith(double stiffness) {
  return {{"stiffness", stiffness}, {"gravityPower", 0.5}, {"gravityDir", {0, -1, 0}}, {"drag", 0.4}, {"isRoot", true}};
}

Skeleton skeletonOf(const json& nodes) {
  const std::string text = json{{"asset", {{"version", "2.0"}}}, {"nodes", nodes}}.dump();
  Skeleton s;
  EXPECT_FALSE(loadSkeleton(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), s));
  return s;
}

TEST(BuilderEdits, DetectListsEveryCandidateParentsFirstWithDefaults) {
  const Skeleton s = skeletonOf(json::array({{{"name", "Avatar_Head"}, {"children", {1, 3}}},
                                             {{"name", "SpringBone_hair"}, {"children", {2}}},
                                             {{"name", "springbone_hair_tip"}},
                                             {{"name", "skirt_1"}}}));
  const auto c = detectSpringBones(s, ModelEntry{});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].name, "SpringBone_hair");
  EXPECT_TRUE(c[0].is_root);  // top-most candidate
  EXPECT_FALSE(c[0].has_entry);
  EXPECT_FLOAT_EQ(c[0].params.stiffness, 2.0f);
  EXPECT_FLOAT_EQ(c[0].params.drag, 0.5f);
  EXPECT_EQ(c[1].name, "springbone_hair_tip");
  EXPECT_EQ(c[1].parent_candidate, 0);
  EXPECT_FALSE(c[1].is_root);
}

TEST(BuilderEdits, DetectPrefillsFromExistingEntries) {
  const Skeleton s =
      skeletonOf(json::array({{{"name", "SpringBone_a"}, {"children", {1}}}, {{"name", "SpringBone_b"}}}));
  ModelEntry existing;
  std::vector<Warning> warnings;
  ASSERT_FALSE(parseSpringBones(json{{"version", 1}, {"models", {{"h", {{"SpringBone_a", paramsWith(3.5)}}}}}}, "h",
                                existing, warnings));
  const auto c = detectSpringBones(s, existing);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_TRUE(c[0].has_entry);
  EXPECT_FLOAT_EQ(c[0].params.stiffness, 3.5f);
  EXPECT_FLOAT_EQ(c[0].params.gravity_power, 0.5f);
}

TEST(BuilderEdits, WritesUnderTheMainFileHashOfTheBodyShape) {
  json out;
  ASSERT_FALSE(setSpringBoneParams(nullptr, entityWith("male/hair.glb", "female/hair.glb"), kFemale, "SpringBone_hair",
                                   paramsWith(1.0), out));
  EXPECT_EQ(out["version"], 1);
  ASSERT_TRUE(out["models"].contains("bafyFEMALE"));
  EXPECT_EQ(out["models"]["bafyFEMALE"]["SpringBone_hair"]["stiffness"], 1.0);
  EXPECT_EQ(out["models"].size(), 1u);
}

TEST(BuilderEdits, SharedGlbForBothBodyShapesGetsOneEntry) {
  const json entity = entityWith("shared.glb", "shared.glb");
  json once, twice;
  ASSERT_FALSE(setSpringBoneParams(nullptr, entity, kMale, "SpringBone_hair", paramsWith(1.0), once));
  ASSERT_FALSE(setSpringBoneParams(once, entity, "BaseFemale", "SpringBone_hair", paramsWith(3.0), twice));
  ASSERT_EQ(twice["models"].size(), 1u);
  EXPECT_EQ(twice["models"]["bafySHARED"]["SpringBone_hair"]["stiffness"], 3.0);
}

TEST(BuilderEdits, DropsEntriesOfHashesNoRepresentationUses) {
  const json old = {{"version", 1},
                    {"models",
                     {{"bafySTALE", {{"SpringBone_hair", paramsWith(2)}}},
                      {"bafyTHUMB", {{"SpringBone_hair", paramsWith(2)}}},
                      {"bafyMALE", {{"SpringBone_other", paramsWith(2)}}}}}};
  json out;
  ASSERT_FALSE(setSpringBoneParams(old, entityWith("male/hair.glb", "female/hair.glb"), kMale, "SpringBone_hair",
                                   paramsWith(1.0), out));
  EXPECT_FALSE(out["models"].contains("bafySTALE"));
  EXPECT_FALSE(out["models"].contains("bafyTHUMB"));                         // a non-main file is not a model
  EXPECT_EQ(out["models"]["bafyMALE"]["SpringBone_other"]["stiffness"], 2);  // kept, still current
  EXPECT_EQ(out["models"]["bafyMALE"]["SpringBone_hair"]["stiffness"], 1.0);
}

// Every representation's main file is looked up in the content list, and every models key in the
// active hashes: by name, not by scanning the lists, which made this quadratic (40,000 x 40,000
// string comparisons here). A large instance, to keep it linear; no timer.
TEST(BuilderEdits, ManyRepresentationsAndStaleModelsStayLinear) {
  constexpr int kCount = 40000;
  json content = json::array(), representations = json::array(), models = json::object();
  for (int i = 0; i < kCount; ++i) {
    const std::string n = std::to_string(i);
    content.push_back({{"file", "f" + n + ".glb"}, {"hash", "bafy" + n}});
    // Only the last representation is for the male body shape.
    representations.push_back({{"bodyShapes", {i + 1 == kCount ? kMale : kFemale}}, {"mainFile", "f" + n + ".glb"}});
    models["stale" + n] = {{"SpringBone_hair", paramsWith(2)}};
    if (i % 2 == 0) models["bafy" + n] = json::object();
  }
  const json entity = {{"content", content}, {"metadata", {{"data", {{"representations", representations}}}}}};
  json out;
  ASSERT_FALSE(setSpringBoneParams({{"version", 1}, {"models", models}}, entity, kMale, "SpringBone_hair",
                                   paramsWith(1.0), out));
  // The stale keys are gone, the active ones kept, and the entry written under the male GLB's hash.
  EXPECT_EQ(out["models"].size(), std::size_t(kCount / 2 + 1));
  EXPECT_FALSE(out["models"].contains("stale0"));
  EXPECT_TRUE(out["models"].contains("bafy0"));
  EXPECT_EQ(out["models"]["bafy" + std::to_string(kCount - 1)]["SpringBone_hair"]["stiffness"], 1.0);
}

TEST(BuilderEdits, NullParamsRemoveTheEntry) {
  const json old = {{"version", 1}, {"models", {{"bafyMALE", {{"SpringBone_hair", paramsWith(2)}}}}}};
  json out;
  ASSERT_FALSE(
      setSpringBoneParams(old, entityWith("male/hair.glb", "female/hair.glb"), kMale, "SpringBone_hair", nullptr, out));
  EXPECT_FALSE(out["models"]["bafyMALE"].contains("SpringBone_hair"));
}

TEST(BuilderEdits, DoesNotModifyItsInputs) {
  const json old = {{"version", 1}, {"models", {{"bafySTALE", {{"SpringBone_hair", paramsWith(2)}}}}}};
  const json before = old;
  json out;
  ASSERT_FALSE(setSpringBoneParams(old, entityWith("male/hair.glb", "female/hair.glb"), kMale, "SpringBone_x",
                                   paramsWith(1), out));
  EXPECT_EQ(old, before);
}

TEST(BuilderEdits, RejectsNamesWithoutTheToken) {
  json out;
  const Error e = setSpringBoneParams(nullptr, entityWith("male/hair.glb", "female/hair.glb"), kMale, "Hair_001",
                                      paramsWith(1), out);
  EXPECT_EQ(e.code, ErrorCode::kInvalidArgument);
  EXPECT_NE(e.message.find("springbone"), std::string::npos);
}

TEST(BuilderEdits, RejectsAnUnknownBodyShape) {
  json out;
  const Error e = setSpringBoneParams(nullptr, entityWith("male/hair.glb", "female/hair.glb"), "BaseAlien",
                                      "SpringBone_x", paramsWith(1), out);
  EXPECT_EQ(e.code, ErrorCode::kInvalidArgument);
  EXPECT_NE(e.message.find("BaseAlien"), std::string::npos);
}

TEST(BuilderEdits, RejectsAMainFileMissingFromTheContentList) {
  json out;
  const Error e = setSpringBoneParams(nullptr, entityWith("male/missing.glb", "female/hair.glb"), kMale, "SpringBone_x",
                                      paramsWith(1), out);
  EXPECT_EQ(e.code, ErrorCode::kInvalidArgument);
  EXPECT_NE(e.message.find("male/missing.glb"), std::string::npos);
}

TEST(BuilderEdits, AcceptsABuilderItemWithAContentsMap) {
  const json item = {{"contents", {{"male/hair.glb", "bafyITEM"}}},
                     {"data", {{"representations", {{{"bodyShapes", {kMale}}, {"mainFile", "male/hair.glb"}}}}}}};
  json out;
  ASSERT_FALSE(setSpringBoneParams(nullptr, item, kMale, "SpringBone_x", paramsWith(1), out));
  EXPECT_TRUE(out["models"].contains("bafyITEM"));
}

TEST(BuilderEdits, RejectsParamsThatAreNotAnObject) {
  json out;
  EXPECT_EQ(
      setSpringBoneParams(nullptr, entityWith("male/hair.glb", "female/hair.glb"), kMale, "SpringBone_x", 5, out).code,
      ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace springbones
