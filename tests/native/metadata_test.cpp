// data.springBones reader tests (src/loading/metadata.cpp): the runtime's forgiving rules — defaults,
// clamping, normalization, each with a warning at a JSON pointer — and the few shapes that are
// errors. Expected values come from the ADR's parameter table (defaults 2.0 / 0 / [0,-1,0] / 0.5,
// ranges [0,4], [0,2], [0,1]).
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <limits>
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
using test::vecNear;

const std::string kHash = "bafkreialsvt77jvpy673cnugp5ggnxfaalfncufweayuk3jbxskh3pelkm";
const std::string kBone = "SpringBone_hair_left";
const std::string kBonePath = "/models/" + kHash + "/" + kBone;

json fullEntry() {
  return {{"stiffness", 1.25}, {"gravityPower", 0.75}, {"gravityDir", {0, -1, 0}}, {"drag", 0.25}, {"isRoot", true}};
}

json springBonesWith(const json& entry) { return {{"version", 1}, {"models", {{kHash, {{kBone, entry}}}}}}; }

struct Parsed {
  Error error;
  ModelEntry model;
  std::vector<Warning> warnings;
};

Parsed parse(const json& springBones, const std::string& hash = kHash) {
  Parsed p;
  p.error = parseSpringBones(springBones, hash, p.model, p.warnings);
  return p;
}

Parsed parseText(const std::string& text, const std::string& hash = kHash) {
  Parsed p;
  p.error = parseSpringBonesText(text, hash, p.model, p.warnings);
  return p;
}

// Parses one entry that must come back as the single bone.
Parsed parseEntry(const json& entry) {
  Parsed p = parse(springBonesWith(entry));
  EXPECT_FALSE(p.error) << p.error.message;
  EXPECT_TRUE(p.model.enabled);
  EXPECT_EQ(p.model.bones.size(), 1u);
  return p;
}

const BoneParams& paramsOf(const Parsed& p) { return p.model.bones.at(0).params; }

json without(json entry, const char* key) {
  entry.erase(key);
  return entry;
}

json with(json entry, const char* key, json value) {
  entry[key] = std::move(value);
  return entry;
}

// ---------------------------------------------------------------------------------------------
// Reading well-formed metadata

TEST(Metadata, ReadsEveryFieldOfACompleteEntryWithoutWarnings) {
  const Parsed p = parseEntry(with(fullEntry(), "center", "Avatar_Hips"));
  EXPECT_TRUE(p.warnings.empty()) << test::describeWarnings(p.warnings);
  const BoneEntry& b = p.model.bones[0];
  EXPECT_EQ(b.name, kBone);
  EXPECT_EQ(p.model.entryPath(b), kBonePath);
  EXPECT_FLOAT_EQ(b.params.stiffness, 1.25f);
  EXPECT_FLOAT_EQ(b.params.gravity_power, 0.75f);
  EXPECT_TRUE(vecNear(b.params.gravity_dir, {0, -1, 0}, 0));
  EXPECT_FLOAT_EQ(b.params.drag, 0.25f);
  EXPECT_TRUE(b.is_root);
  EXPECT_TRUE(b.has_center);
  EXPECT_EQ(b.center, "Avatar_Hips");
}

TEST(Metadata, ReadsTheAdrFullExampleFixture) {
  const Parsed p =
      parseText(test::readFixtureText("adr_example.metadata.json"), test::metadataKeyOf("adr_example.glb"));
  ASSERT_FALSE(p.error) << p.error.message;
  EXPECT_TRUE(p.warnings.empty()) << test::describeWarnings(p.warnings);
  ASSERT_TRUE(p.model.enabled);
  ASSERT_EQ(p.model.bones.size(), 2u);
  // nlohmann::json objects are ordered by key; find each entry by name.
  const BoneEntry* earring = nullptr;
  const BoneEntry* hair = nullptr;
  for (const BoneEntry& b : p.model.bones) {
    if (b.name == "SpringBone_earring_r") earring = &b;
    if (b.name == "SpringBone_hair_left") hair = &b;
  }
  ASSERT_TRUE(earring && hair);
  // The ADR: earring {0.5, 1.0, [0,-1,0], 0.6, isRoot, center Avatar_Hips},
  //          hair {2.0, 0.8, [0,-1,0], 0.4, isRoot}.
  EXPECT_FLOAT_EQ(earring->params.stiffness, 0.5f);
  EXPECT_FLOAT_EQ(earring->params.gravity_power, 1.0f);
  EXPECT_FLOAT_EQ(earring->params.drag, 0.6f);
  EXPECT_TRUE(earring->is_root);
  EXPECT_TRUE(earring->has_center);
  EXPECT_EQ(earring->center, "Avatar_Hips");
  EXPECT_FLOAT_EQ(hair->params.stiffness, 2.0f);
  EXPECT_FLOAT_EQ(hair->params.gravity_power, 0.8f);
  EXPECT_FLOAT_EQ(hair->params.drag, 0.4f);
  EXPECT_TRUE(vecNear(hair->params.gravity_dir, {0, -1, 0}, 0));
  EXPECT_TRUE(hair->is_root);
  EXPECT_FALSE(hair->has_center);
}

TEST(Metadata, KeepsEveryEntryOfTheChosenModelOnly) {
  json sb = springBonesWith(fullEntry());
  sb["models"][kHash]["SpringBone_b"] = fullEntry();
  sb["models"]["bafkreiotherhash"] = {{"SpringBone_other", fullEntry()}};
  const Parsed p = parse(sb);
  ASSERT_FALSE(p.error);
  ASSERT_EQ(p.model.bones.size(), 2u);
  for (const BoneEntry& b : p.model.bones) EXPECT_NE(b.name, "SpringBone_other");
}

TEST(Metadata, AcceptsAnEmptyModelEntry) {
  const Parsed p = parse({{"version", 1}, {"models", {{kHash, json::object()}}}});
  EXPECT_FALSE(p.error);
  EXPECT_TRUE(p.model.enabled);
  EXPECT_TRUE(p.model.bones.empty());
  EXPECT_TRUE(p.warnings.empty());
}

TEST(Metadata, IgnoresUnknownKeysInABoneEntry) {
  // The schema allows unknown keys in a bone entry (hitRadius is reserved in Unity's DTO).
  const Parsed p = parseEntry(with(fullEntry(), "hitRadius", 0.02));
  EXPECT_TRUE(p.warnings.empty()) << test::describeWarnings(p.warnings);
}

// ---------------------------------------------------------------------------------------------
// Defaults for missing fields

TEST(Metadata, DefaultsMissingStiffnessTo2WithAWarning) {
  const Parsed p = parseEntry(without(fullEntry(), "stiffness"));
  EXPECT_FLOAT_EQ(paramsOf(p).stiffness, 2.0f);
  EXPECT_EQ(p.warnings.size(), 1u);
  findWarning(p.warnings, "param-missing", kBonePath + "/stiffness");
}

TEST(Metadata, DefaultsMissingGravityPowerTo0WithAWarning) {
  const Parsed p = parseEntry(without(fullEntry(), "gravityPower"));
  EXPECT_FLOAT_EQ(paramsOf(p).gravity_power, 0.0f);
  EXPECT_EQ(p.warnings.size(), 1u);
  findWarning(p.warnings, "param-missing", kBonePath + "/gravityPower");
}

TEST(Metadata, DefaultsMissingGravityDirToDownWithAWarning) {
  json entry = without(fullEntry(), "gravityDir");
  const Parsed p = parseEntry(entry);
  EXPECT_TRUE(vecNear(paramsOf(p).gravity_dir, {0, -1, 0}, 0));
  EXPECT_EQ(p.warnings.size(), 1u);
  findWarning(p.warnings, "param-missing", kBonePath + "/gravityDir");
}

TEST(Metadata, DefaultsMissingDragToHalfWithAWarning) {
  const Parsed p = parseEntry(without(fullEntry(), "drag"));
  EXPECT_FLOAT_EQ(paramsOf(p).drag, 0.5f);
  EXPECT_EQ(p.warnings.size(), 1u);
  findWarning(p.warnings, "param-missing", kBonePath + "/drag");
}

TEST(Metadata, DefaultsEveryFieldOfAnEmptyEntryWithOneWarningEach) {
  const Parsed p = parseEntry(json::object());
  const BoneEntry& b = p.model.bones[0];
  EXPECT_FLOAT_EQ(b.params.stiffness, 2.0f);
  EXPECT_FLOAT_EQ(b.params.gravity_power, 0.0f);
  EXPECT_TRUE(vecNear(b.params.gravity_dir, {0, -1, 0}, 0));
  EXPECT_FLOAT_EQ(b.params.drag, 0.5f);
  EXPECT_FALSE(b.is_root);  // isRoot is optional: absent means a member, no warning
  EXPECT_FALSE(b.has_center);
  EXPECT_EQ(p.warnings.size(), 4u) << test::describeWarnings(p.warnings);
  EXPECT_EQ(test::countWarnings(p.warnings, "param-missing"), 4);
}

// ---------------------------------------------------------------------------------------------
// Out of range: clamped into the schema's inclusive ranges, with a warning

struct RangeCase {
  const char* key;
  double value;
  float expected;
};

float scalarOf(const BoneParams& p, const std::string& key) {
  if (key == "stiffness") return p.stiffness;
  if (key == "gravityPower") return p.gravity_power;
  return p.drag;
}

TEST(Metadata, ClampsOutOfRangeScalarsAtBothEndsWithAWarning) {
  const RangeCase cases[] = {
      {"stiffness", -1.0, 0.0f},   {"stiffness", 4.01, 4.0f}, {"stiffness", 1e9, 4.0f}, {"gravityPower", -0.5, 0.0f},
      {"gravityPower", 2.5, 2.0f}, {"drag", -0.1, 0.0f},      {"drag", 1.5, 1.0f},
  };
  for (const RangeCase& c : cases) {
    SCOPED_TRACE(std::string(c.key) + " = " + std::to_string(c.value));
    const Parsed p = parseEntry(with(fullEntry(), c.key, c.value));
    EXPECT_FLOAT_EQ(scalarOf(paramsOf(p), c.key), c.expected);
    EXPECT_EQ(p.warnings.size(), 1u);
    const Warning* w = findWarning(p.warnings, "param-out-of-range", kBonePath + "/" + c.key);
    if (w) { EXPECT_NE(w->message.find(c.key), std::string::npos) << w->message; }
  }
}

TEST(Metadata, AcceptsRangeEndpointsWithoutWarnings) {
  // The schema's ranges are inclusive (validator test vectors V5 and V6).
  const RangeCase cases[] = {
      {"stiffness", 0, 0.0f},    {"stiffness", 4, 4.0f}, {"gravityPower", 0, 0.0f},
      {"gravityPower", 2, 2.0f}, {"drag", 0, 0.0f},      {"drag", 1, 1.0f},
  };
  for (const RangeCase& c : cases) {
    SCOPED_TRACE(std::string(c.key) + " = " + std::to_string(c.value));
    const Parsed p = parseEntry(with(fullEntry(), c.key, c.value));
    EXPECT_FLOAT_EQ(scalarOf(paramsOf(p), c.key), c.expected);
    EXPECT_TRUE(p.warnings.empty()) << test::describeWarnings(p.warnings);
  }
}

TEST(Metadata, AcceptsIntegerValuedParameters) {
  // JSON integers (what JSON.stringify writes for 2.0) are numbers like any other.
  json entry = {{"stiffness", 3}, {"gravityPower", 1}, {"gravityDir", {1, 0, 0}}, {"drag", 1u}};
  const Parsed p = parseEntry(entry);
  EXPECT_FLOAT_EQ(paramsOf(p).stiffness, 3.0f);
  EXPECT_FLOAT_EQ(paramsOf(p).gravity_power, 1.0f);
  EXPECT_FLOAT_EQ(paramsOf(p).drag, 1.0f);
  EXPECT_TRUE(vecNear(paramsOf(p).gravity_dir, {1, 0, 0}, 0));
}

// ---------------------------------------------------------------------------------------------
// Wrong types and non-finite values: the default, with a warning

TEST(Metadata, ReplacesNonNumberScalarsByTheDefaultWithAWarning) {
  const json bad_values[] = {"2", true, nullptr, json::array({1}), json::object()};
  for (const char* key : {"stiffness", "gravityPower", "drag"}) {
    const float fallback = std::string(key) == "stiffness" ? 2.0f : key[0] == 'g' ? 0.0f : 0.5f;
    for (const json& value : bad_values) {
      SCOPED_TRACE(std::string(key) + " = " + value.dump());
      const Parsed p = parseEntry(with(fullEntry(), key, value));
      EXPECT_FLOAT_EQ(scalarOf(paramsOf(p), key), fallback);
      EXPECT_EQ(p.warnings.size(), 1u);
      findWarning(p.warnings, "param-not-number", kBonePath + "/" + key);
    }
  }
}

TEST(Metadata, ReplacesNonFiniteScalarsByTheDefaultWithAWarning) {
  // JSON text cannot hold NaN or Infinity, but a json value built in C++ (or handed over from
  // JavaScript by a binding) can.
  for (double value : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                       -std::numeric_limits<double>::infinity()}) {
    SCOPED_TRACE(value);
    const Parsed p = parseEntry(with(fullEntry(), "stiffness", value));
    EXPECT_FLOAT_EQ(paramsOf(p).stiffness, 2.0f);  // not clamped to 4 for +Infinity
    EXPECT_EQ(p.warnings.size(), 1u);
    findWarning(p.warnings, "param-not-finite", kBonePath + "/stiffness");
  }
}

TEST(Metadata, RejectsNumbersTooLargeForADoubleAsBadJson) {
  // 1e400 overflows a double; the JSON parser refuses it rather than produce Infinity.
  std::string text = springBonesWith(fullEntry()).dump();
  text.replace(text.find("1.25"), 4, "1e400");
  const Parsed p = parseText(text);
  EXPECT_EQ(p.error.code, ErrorCode::kMetadataBadJson);
}

// ---------------------------------------------------------------------------------------------
// gravityDir

TEST(Metadata, ReplacesGravityDirOfTheWrongLengthByTheDefault) {
  for (const json& value : {json{0, -1}, json{0, -1, 0, 0}, json::array()}) {
    SCOPED_TRACE(value.dump());
    const Parsed p = parseEntry(with(fullEntry(), "gravityDir", value));
    EXPECT_TRUE(vecNear(paramsOf(p).gravity_dir, {0, -1, 0}, 0));
    EXPECT_EQ(p.warnings.size(), 1u);
    findWarning(p.warnings, "param-not-vector", kBonePath + "/gravityDir");
  }
}

TEST(Metadata, ReplacesGravityDirWithNonNumbersByTheDefault) {
  const json bad_values[] = {json{0, "down", 0},
                             json{0, nullptr, 0},
                             json{true, 0, 0},
                             json("down"),
                             json{{"x", 0}, {"y", -1}, {"z", 0}},
                             json{0, std::numeric_limits<double>::quiet_NaN(), 0}};
  for (const json& value : bad_values) {
    SCOPED_TRACE(value.dump());
    // A gravityDir pointing up would be kept; every bad value must come back as the default down.
    const Parsed p = parseEntry(with(fullEntry(), "gravityDir", value));
    EXPECT_TRUE(vecNear(paramsOf(p).gravity_dir, {0, -1, 0}, 0));
    EXPECT_EQ(p.warnings.size(), 1u);
    findWarning(p.warnings, "param-not-vector", kBonePath + "/gravityDir");
  }
}

TEST(Metadata, ReplacesZeroGravityDirByTheDefaultWithAWarning) {
  // The schema accepts [0,0,0] (test vector V6) but it has no direction to normalize.
  const Parsed p = parseEntry(with(fullEntry(), "gravityDir", {0, 0, 0}));
  EXPECT_TRUE(vecNear(paramsOf(p).gravity_dir, {0, -1, 0}, 0));
  EXPECT_EQ(p.warnings.size(), 1u);
  findWarning(p.warnings, "gravity-dir-zero", kBonePath + "/gravityDir");
}

TEST(Metadata, NormalizesGravityDirWithoutWarning) {
  // [0,-2,0] / 2 = [0,-1,0]; [3,4,0] / 5 = [0.6,0.8,0]; [1,-1,0] / sqrt(2) = [0.7071,-0.7071,0];
  // [1,1,1] / sqrt(3) = 0.57735 each. The ADR: "MUST normalize the vector if it is not already
  // a unit vector", and all of these are valid under the schema, so no warning.
  struct Case {
    json value;
    glm::vec3 expected;
  };
  const float d = 1.0f / std::sqrt(2.0f);
  const float t = 1.0f / std::sqrt(3.0f);
  const Case cases[] = {{{0, -2, 0}, {0, -1, 0}},
                        {{3, 4, 0}, {0.6f, 0.8f, 0}},
                        {{1, -1, 0}, {d, -d, 0}},
                        {{1, 1, 1}, {t, t, t}},
                        {{0, 0, 0.001}, {0, 0, 1}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.value.dump());
    const Parsed p = parseEntry(with(fullEntry(), "gravityDir", c.value));
    EXPECT_TRUE(vecNear(paramsOf(p).gravity_dir, c.expected, 1e-6f));
    EXPECT_TRUE(p.warnings.empty()) << test::describeWarnings(p.warnings);
  }
}

TEST(Metadata, KeepsTheDirectionOfGravityDirBeyondTheSchemaBoundsWithAWarning) {
  // Components outside [-10, 10] fail the schema (vector I11); the runtime warns and keeps the
  // direction: [0,-11,0] -> [0,-1,0], [20,0,-20] -> [0.7071,0,-0.7071].
  const float d = 1.0f / std::sqrt(2.0f);
  const std::pair<json, glm::vec3> cases[] = {{{0, -11, 0}, {0, -1, 0}}, {{20, 0, -20}, {d, 0, -d}}};
  for (const auto& [value, expected] : cases) {
    SCOPED_TRACE(value.dump());
    const Parsed p = parseEntry(with(fullEntry(), "gravityDir", value));
    EXPECT_TRUE(vecNear(paramsOf(p).gravity_dir, expected, 1e-6f));
    EXPECT_EQ(p.warnings.size(), 1u);
    findWarning(p.warnings, "param-out-of-range", kBonePath + "/gravityDir");
  }
}

TEST(Metadata, KeepsTheDirectionOfHugeGravityDir) {
  // [1e200, 0, 0] points along +X; squaring its components overflows a double, which must not
  // turn a clear direction into "no direction".
  const Parsed p = parseEntry(with(fullEntry(), "gravityDir", {1e200, 0, 0}));
  EXPECT_TRUE(vecNear(paramsOf(p).gravity_dir, {1, 0, 0}, 1e-6f));
  EXPECT_EQ(test::countWarnings(p.warnings, "gravity-dir-zero"), 0) << test::describeWarnings(p.warnings);
}

// ---------------------------------------------------------------------------------------------
// version

TEST(Metadata, DisablesSpringBonesForVersion2WithAWarning) {
  json sb = springBonesWith(fullEntry());
  sb["version"] = 2;
  const Parsed p = parse(sb);
  EXPECT_FALSE(p.error);
  EXPECT_FALSE(p.model.enabled);
  EXPECT_TRUE(p.model.bones.empty());
  ASSERT_EQ(p.warnings.size(), 1u);
  findWarning(p.warnings, "unsupported-version", "/version");
}

TEST(Metadata, DisablesSpringBonesForMissingVersionWithAWarning) {
  json sb = springBonesWith(fullEntry());
  sb.erase("version");
  const Parsed p = parse(sb);
  EXPECT_FALSE(p.error);
  EXPECT_FALSE(p.model.enabled);
  findWarning(p.warnings, "unsupported-version", "/version");
}

TEST(Metadata, DisablesSpringBonesForNonNumberVersionWithAWarning) {
  // "1" is a string (validator vector I7); true and null are not numbers either.
  for (const json& version : {json("1"), json(true), json(nullptr), json{1}}) {
    SCOPED_TRACE(version.dump());
    json sb = springBonesWith(fullEntry());
    sb["version"] = version;
    const Parsed p = parse(sb);
    EXPECT_FALSE(p.error);
    EXPECT_FALSE(p.model.enabled);
    findWarning(p.warnings, "unsupported-version", "/version");
  }
}

TEST(Metadata, DisablesSpringBonesForVersionCloseToButNot1) {
  for (double version : {0.0, 0.999, 1.001, -1.0}) {
    json sb = springBonesWith(fullEntry());
    sb["version"] = version;
    const Parsed p = parse(sb);
    EXPECT_FALSE(p.model.enabled) << version;
  }
}

TEST(Metadata, AcceptsVersionWrittenAs1Point0) {
  // Validator vector V7: version 1.0 is valid; in JSON text it is a float literal.
  std::string text = springBonesWith(fullEntry()).dump();
  text.replace(text.find("\"version\":1"), 11, "\"version\":1.0");
  ASSERT_NE(text.find("1.0"), std::string::npos);
  const Parsed p = parseText(text);
  ASSERT_FALSE(p.error) << p.error.message;
  EXPECT_TRUE(p.model.enabled);
  EXPECT_TRUE(p.warnings.empty()) << test::describeWarnings(p.warnings);
}

// ---------------------------------------------------------------------------------------------
// Shapes: null, not an object, models

TEST(Metadata, NullSpringBonesDisablesWithoutErrorOrWarning) {
  const Parsed p = parse(nullptr);
  EXPECT_FALSE(p.error);
  EXPECT_FALSE(p.model.enabled);
  EXPECT_TRUE(p.warnings.empty());
  const Parsed t = parseText("null");
  EXPECT_FALSE(t.error);
  EXPECT_FALSE(t.model.enabled);
  EXPECT_TRUE(t.warnings.empty());
}

TEST(Metadata, RejectsSpringBonesThatIsNotAnObject) {
  for (const json& value : {json::array({1}), json("springBones"), json(1), json(false)}) {
    const Parsed p = parse(value);
    EXPECT_EQ(p.error.code, ErrorCode::kMetadataInvalid) << value.dump();
    EXPECT_FALSE(p.model.enabled);
  }
}

TEST(Metadata, RejectsModelsThatIsNotAnObject) {
  for (const json& models : {json::array(), json(nullptr), json("x"), json(3)}) {
    const Parsed p = parse({{"version", 1}, {"models", models}});
    EXPECT_EQ(p.error.code, ErrorCode::kMetadataInvalid) << models.dump();
    EXPECT_EQ(p.error.path, "/models");
  }
}

TEST(Metadata, RejectsModelEntryThatIsNotAnObject) {
  // Validator vector I22: models: {H: []}.
  const Parsed p = parse({{"version", 1}, {"models", {{kHash, json::array()}}}});
  EXPECT_EQ(p.error.code, ErrorCode::kMetadataInvalid);
  EXPECT_EQ(p.error.path, "/models/" + kHash);
  EXPECT_FALSE(p.model.enabled);
}

TEST(Metadata, MissingModelsDisablesWithAWarning) {
  const Parsed p = parse({{"version", 1}});
  EXPECT_FALSE(p.error);
  EXPECT_FALSE(p.model.enabled);
  findWarning(p.warnings, "models-missing", "/models");
}

TEST(Metadata, MissingHashDisablesWithModelNotFoundWarning) {
  const Parsed p = parse(springBonesWith(fullEntry()), "bafkreisomeotherglb");
  EXPECT_FALSE(p.error);
  EXPECT_FALSE(p.model.enabled);
  EXPECT_TRUE(p.model.bones.empty());
  const Warning* w = findWarning(p.warnings, "model-not-found", "/models/bafkreisomeotherglb");
  // The message lists the keys that are there, to spot a hash mix-up.
  if (w) { EXPECT_NE(w->message.find(kHash), std::string::npos) << w->message; }
}

TEST(Metadata, EmptyModelsDisablesWithModelNotFoundWarning) {
  const Parsed p = parse({{"version", 1}, {"models", json::object()}});
  EXPECT_FALSE(p.error);
  EXPECT_FALSE(p.model.enabled);
  findWarning(p.warnings, "model-not-found", "/models/" + kHash);
}

TEST(Metadata, HashLookupIsExact) {
  // Keys are content hashes: no case folding, no trimming.
  std::string upper = kHash;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  EXPECT_FALSE(parse(springBonesWith(fullEntry()), upper).model.enabled);
  EXPECT_FALSE(parse(springBonesWith(fullEntry()), kHash + " ").model.enabled);
}

TEST(Metadata, SkipsBoneEntryThatIsNotAnObjectWithAWarning) {
  // Validator vector I21: a null bone value; the other entries still apply.
  json sb = springBonesWith(fullEntry());
  sb["models"][kHash]["SpringBone_null"] = nullptr;
  sb["models"][kHash]["SpringBone_list"] = {1, 2};
  const Parsed p = parse(sb);
  ASSERT_FALSE(p.error);
  ASSERT_EQ(p.model.bones.size(), 1u);
  EXPECT_EQ(p.model.bones[0].name, kBone);
  findWarning(p.warnings, "bone-entry-invalid", "/models/" + kHash + "/SpringBone_null");
  findWarning(p.warnings, "bone-entry-invalid", "/models/" + kHash + "/SpringBone_list");
}

// ---------------------------------------------------------------------------------------------
// center and isRoot

TEST(Metadata, ReadsCenterNameAndExplicitNullCenter) {
  const Parsed named = parseEntry(with(fullEntry(), "center", "Avatar_Hips"));
  EXPECT_TRUE(named.model.bones[0].has_center);
  EXPECT_EQ(named.model.bones[0].center, "Avatar_Hips");
  // null (validator vector V8): explicitly world space, no warning.
  const Parsed null_center = parseEntry(with(fullEntry(), "center", nullptr));
  EXPECT_TRUE(null_center.model.bones[0].has_center);
  EXPECT_TRUE(null_center.model.bones[0].center.empty());
  EXPECT_TRUE(null_center.warnings.empty());
  // absent: no center of its own.
  const Parsed absent = parseEntry(fullEntry());
  EXPECT_FALSE(absent.model.bones[0].has_center);
}

TEST(Metadata, IgnoresCenterThatIsNotAStringWithAWarning) {
  // Validator vector I19: center 5.
  for (const json& center : {json(5), json(true), json::array({"Avatar_Hips"}), json::object()}) {
    SCOPED_TRACE(center.dump());
    const Parsed p = parseEntry(with(fullEntry(), "center", center));
    EXPECT_FALSE(p.model.bones[0].has_center);
    EXPECT_TRUE(p.model.bones[0].center.empty());
    EXPECT_EQ(p.warnings.size(), 1u);
    findWarning(p.warnings, "center-not-string", kBonePath + "/center");
  }
}

TEST(Metadata, ReadsIsRoot) {
  EXPECT_TRUE(parseEntry(with(fullEntry(), "isRoot", true)).model.bones[0].is_root);
  const Parsed f = parseEntry(with(fullEntry(), "isRoot", false));
  EXPECT_FALSE(f.model.bones[0].is_root);
  EXPECT_TRUE(f.warnings.empty());
  // null (validator vector V8) and absent: a member, no warning.
  const Parsed n = parseEntry(with(fullEntry(), "isRoot", nullptr));
  EXPECT_FALSE(n.model.bones[0].is_root);
  EXPECT_TRUE(n.warnings.empty());
  const Parsed a = parseEntry(without(fullEntry(), "isRoot"));
  EXPECT_FALSE(a.model.bones[0].is_root);
  EXPECT_TRUE(a.warnings.empty());
}

TEST(Metadata, TreatsIsRootThatIsNotABooleanAsFalseWithAWarning) {
  // Validator vector I20: isRoot "yes". 1 and "true" are not booleans either.
  for (const json& value : {json("yes"), json("true"), json(1), json::object()}) {
    SCOPED_TRACE(value.dump());
    const Parsed p = parseEntry(with(fullEntry(), "isRoot", value));
    EXPECT_FALSE(p.model.bones[0].is_root);
    EXPECT_EQ(p.warnings.size(), 1u);
    findWarning(p.warnings, "is-root-not-boolean", kBonePath + "/isRoot");
  }
}

// ---------------------------------------------------------------------------------------------
// Paths and text input

TEST(Metadata, WarningPathsAreJsonPointersWithEscapedKeys) {
  // RFC 6901: '~' is written "~0" and '/' is written "~1" inside a reference token.
  const std::string hash = "weird/hash~1";
  const std::string bone = "SpringBone/a~b";
  const json sb = {{"version", 1}, {"models", {{hash, {{bone, json::object()}}}}}};
  const Parsed p = parse(sb, hash);
  ASSERT_FALSE(p.error);
  ASSERT_EQ(p.model.bones.size(), 1u);
  EXPECT_EQ(p.model.path, "/models/weird~1hash~01");
  EXPECT_EQ(p.model.entryPath(p.model.bones[0]), "/models/weird~1hash~01/SpringBone~1a~0b");
  findWarning(p.warnings, "param-missing", "/models/weird~1hash~01/SpringBone~1a~0b/stiffness");
  // Every path must resolve in the document it describes.
  for (const Warning& w : p.warnings) {
    EXPECT_NO_THROW((void)sb.at(json::json_pointer(w.path.substr(0, w.path.rfind('/'))))) << w.path;
  }
}

TEST(Metadata, ErrorPathForABadModelsKeyIsAJsonPointer) {
  const Parsed p = parse({{"version", 1}, {"models", {{"a/b", 7}}}}, "a/b");
  EXPECT_EQ(p.error.code, ErrorCode::kMetadataInvalid);
  EXPECT_EQ(p.error.path, "/models/a~1b");
}

TEST(Metadata, RejectsTextThatIsNotJson) {
  for (const std::string text : {"", "{", "{\"version\": 1,}", "version: 1", "{'version': 1}", "NaN"}) {
    const Parsed p = parseText(text);
    EXPECT_EQ(p.error.code, ErrorCode::kMetadataBadJson) << text;
    EXPECT_FALSE(p.model.enabled);
  }
}

TEST(Metadata, ReadsTextLikeTheJsonValue) {
  const Parsed p = parseText(springBonesWith(fullEntry()).dump(2));
  ASSERT_FALSE(p.error);
  ASSERT_EQ(p.model.bones.size(), 1u);
  EXPECT_FLOAT_EQ(paramsOf(p).stiffness, 1.25f);
}

TEST(Metadata, RejectsTextLargerThanTheLimit) {
  // "null" padded with spaces: the size alone decides, at kMaxMetadataBytes + 1.
  std::string text = "null";
  text.resize(kMaxMetadataBytes + 1, ' ');
  EXPECT_EQ(parseText(text).error.code, ErrorCode::kLimitExceeded);
  text.resize(kMaxMetadataBytes);  // exactly at the limit: read
  const Parsed p = parseText(text);
  EXPECT_FALSE(p.error) << p.error.message;
}

TEST(Metadata, SurvivesDeeplyNestedValuesInText) {
  // A parameter holding 100,000 nested arrays: reading it and describing it in the warning must
  // not recurse once per level (the WebAssembly stack is far smaller than a native one).
  constexpr int kDepth = 100000;
  const std::string deep = std::string(kDepth, '[') + std::string(kDepth, ']');
  const std::string text = R"({"version":1,"models":{")" + kHash + R"(":{")" + kBone + R"(":{"stiffness":)" + deep +
                           R"(,"gravityDir":)" + deep + R"(,"center":)" + deep + R"(,"isRoot":)" + deep + "}}}}";
  const Parsed p = parseText(text);
  ASSERT_FALSE(p.error) << p.error.message;
  ASSERT_EQ(p.model.bones.size(), 1u);
  EXPECT_FLOAT_EQ(paramsOf(p).stiffness, 2.0f);
  findWarning(p.warnings, "param-not-number", kBonePath + "/stiffness");
  findWarning(p.warnings, "param-not-vector", kBonePath + "/gravityDir");
  findWarning(p.warnings, "center-not-string", kBonePath + "/center");
  findWarning(p.warnings, "is-root-not-boolean", kBonePath + "/isRoot");
  // The whole springBones value nested deeply is an error, also without recursion.
  EXPECT_EQ(parseText(deep).error.code, ErrorCode::kMetadataInvalid);
}

TEST(Metadata, ShortensLongValuesInWarningMessages) {
  const Parsed p = parseEntry(with(fullEntry(), "stiffness", std::string(10000, 'x')));
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_LT(p.warnings[0].message.size(), 200u) << p.warnings[0].message;
}

}  // namespace
}  // namespace springbones
