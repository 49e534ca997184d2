// Shared helpers for the native tests: fixture files (tests/fixtures, written by
// scripts/generate/make_fixtures.mjs), GLB/glTF bytes built in memory, approximate comparisons, and
// warning look-ups.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/glm_interop.h"
#include "readers/json_values.h"
#include "springbones/readers.h"

namespace springbones {
namespace test {

// ---------------------------------------------------------------------------------------------
// Fixtures

/// tests/fixtures of this checkout (fixtures_dir.cpp).
const char* fixturesDir();

inline std::string fixturePath(const std::string& name) { return std::string(fixturesDir()) + "/" + name; }

/// The bytes of a fixture file; fails the current test (and returns nothing) when it is missing.
inline std::vector<std::uint8_t> readFixture(const std::string& name) {
  std::ifstream in(fixturePath(name), std::ios::binary);
  EXPECT_TRUE(in.good()) << "missing fixture " << fixturePath(name)
                         << " (run: node scripts/generate/make_fixtures.mjs)";
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

inline std::string readFixtureText(const std::string& name) {
  const std::vector<std::uint8_t> bytes = readFixture(name);
  return std::string(bytes.begin(), bytes.end());
}

/// tests/fixtures/manifest.json: per file its content hash and the metadata key to load it with.
inline const nlohmann::json& fixtureManifest() {
  static const nlohmann::json manifest = nlohmann::json::parse(readFixtureText("manifest.json"));
  return manifest;
}

inline std::string metadataKeyOf(const std::string& file) {
  return fixtureManifest().at("files").at(file).at("metadataKey").get<std::string>();
}

inline Error loadBytes(const std::vector<std::uint8_t>& bytes, Skeleton& out) {
  return loadSkeleton(bytes.data(), bytes.size(), out);
}

inline Error loadText(const std::string& text, Skeleton& out) {
  return loadSkeleton(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), out);
}

/// Loads a fixture GLB/glTF; fails the current test when it does not load.
inline Skeleton loadFixtureSkeleton(const std::string& name) {
  Skeleton skeleton;
  const Error e = loadBytes(readFixture(name), skeleton);
  EXPECT_FALSE(e) << name << ": " << e.message;
  return skeleton;
}

// ---------------------------------------------------------------------------------------------
// Building inputs in memory

inline void appendU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

inline std::uint32_t readU32(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  return std::uint32_t(bytes[at]) | (std::uint32_t(bytes[at + 1]) << 8) | (std::uint32_t(bytes[at + 2]) << 16) |
         (std::uint32_t(bytes[at + 3]) << 24);
}

inline void writeU32(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

constexpr std::uint32_t kMagicGltf = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"

/// A well-formed GLB around `json_text` (padded with spaces), with an optional BIN chunk.
inline std::vector<std::uint8_t> makeGlb(std::string json_text, const std::vector<std::uint8_t>& bin = {}) {
  while (json_text.size() % 4 != 0) json_text.push_back(' ');
  std::vector<std::uint8_t> body;
  appendU32(body, static_cast<std::uint32_t>(json_text.size()));
  appendU32(body, kChunkJson);
  body.insert(body.end(), json_text.begin(), json_text.end());
  if (!bin.empty()) {
    std::vector<std::uint8_t> padded = bin;
    while (padded.size() % 4 != 0) padded.push_back(0);
    appendU32(body, static_cast<std::uint32_t>(padded.size()));
    appendU32(body, kChunkBin);
    body.insert(body.end(), padded.begin(), padded.end());
  }
  std::vector<std::uint8_t> out;
  appendU32(out, kMagicGltf);
  appendU32(out, 2);
  appendU32(out, static_cast<std::uint32_t>(12 + body.size()));
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

/// glTF JSON text of a document with `asset.version` "2.0" and the given nodes. Pass a JSON array:
/// beware that `gltfWithNodes({n})` with a json `n` copies n instead of wrapping it (C++ list
/// initialization from one element of the same type), hence the check; write json::array({n}).
inline std::string gltfWithNodes(const nlohmann::json& nodes) {
  EXPECT_TRUE(nodes.is_array()) << "gltfWithNodes wants an array of nodes, got " << nodes.dump();
  return nlohmann::json{{"asset", {{"version", "2.0"}}}, {"nodes", nodes}}.dump();
}

/// A glTF node; TRS only when given.
inline nlohmann::json node(const std::string& name, std::vector<int> children = {},
                           std::vector<double> translation = {}) {
  nlohmann::json n = {{"name", name}};
  if (!children.empty()) n["children"] = children;
  if (!translation.empty()) n["translation"] = translation;
  return n;
}

/// The rig of a glTF made of `nodes` (a JSON array) with `bones` as the entries of its one models
/// key; fails the current test when the glTF or the metadata does not load.
inline std::shared_ptr<const Rig> rigFromJson(const nlohmann::json& nodes, const nlohmann::json& bones,
                                              const RigOptions& options = {}) {
  Skeleton skeleton;
  const Error e = loadText(gltfWithNodes(nodes), skeleton);
  EXPECT_FALSE(e) << e.message;
  ModelEntry model;
  std::vector<Warning> warnings;
  const Error m = parseSpringBones(nlohmann::json{{"version", 1}, {"models", {{"h", bones}}}}, "h", model, warnings);
  EXPECT_FALSE(m) << m.message;
  return buildRig(std::move(skeleton), model, warnings, options);
}

inline int nodeIndex(const Skeleton& skeleton, const std::string& name) {
  for (std::size_t i = 0; i < skeleton.nodes.size(); ++i) {
    if (skeleton.nodes[i].name == name) return static_cast<int>(i);
  }
  ADD_FAILURE() << "no node named " << name;
  return -1;
}

inline glm::vec3 worldPosition(const Skeleton& skeleton, const std::string& name) {
  const int i = nodeIndex(skeleton, name);
  return i < 0 ? glm::vec3(NAN) : glm::vec3(toGlm(skeleton.nodes[i].rest_world)[3]);
}

/// A sphere collider to attach by node name (RigOptions::colliders).
inline ColliderSpec sphereSpec(const std::string& node, Vec3 offset, float radius) {
  ColliderSpec c;
  c.node = node;
  c.offset = offset;
  c.radius = radius;
  return c;
}

/// A capsule collider from `offset` to `tail`, to attach by node name.
inline ColliderSpec capsuleSpec(const std::string& node, Vec3 offset, Vec3 tail, float radius) {
  ColliderSpec c = sphereSpec(node, offset, radius);
  c.shape = Collider::Shape::kCapsule;
  c.tail = tail;
  return c;
}

// ---------------------------------------------------------------------------------------------
// Approximate comparisons, of the public value types and of GLM's alike

struct AnyVec3 : glm::vec3 {
  AnyVec3(const glm::vec3& v) : glm::vec3(v) {}
  AnyVec3(const Vec3& v) : glm::vec3(toGlm(v)) {}
  AnyVec3(float x, float y, float z) : glm::vec3(x, y, z) {}
};
struct AnyQuat : glm::quat {
  AnyQuat(const glm::quat& q) : glm::quat(q) {}
  AnyQuat(const Quat& q) : glm::quat(toGlm(q)) {}
};

inline ::testing::AssertionResult vecNear(const AnyVec3& actual, const AnyVec3& expected, float eps = 1e-5f) {
  const float d = glm::length(actual - expected);
  if (d <= eps) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << actual.x << ", " << actual.y << ", " << actual.z << ") is " << d
                                       << " from expected (" << expected.x << ", " << expected.y << ", " << expected.z
                                       << ")";
}

/// q and -q are the same rotation.
inline ::testing::AssertionResult quatNear(const AnyQuat& actual, const AnyQuat& expected, float eps = 1e-5f) {
  const float d = std::fmin(glm::length(glm::vec4(actual.x - expected.x, actual.y - expected.y, actual.z - expected.z,
                                                  actual.w - expected.w)),
                            glm::length(glm::vec4(actual.x + expected.x, actual.y + expected.y, actual.z + expected.z,
                                                  actual.w + expected.w)));
  if (d <= eps) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(x " << actual.x << ", y " << actual.y << ", z " << actual.z << ", w "
                                       << actual.w << ") is " << d << " from expected (x " << expected.x << ", y "
                                       << expected.y << ", z " << expected.z << ", w " << expected.w << ")";
}

// ---------------------------------------------------------------------------------------------
// Warnings

inline int countWarnings(const std::vector<Warning>& warnings, const std::string& code) {
  int n = 0;
  for (const Warning& w : warnings) n += w.code == code ? 1 : 0;
  return n;
}

/// The single warning with this code and path; fails the test when there is not exactly one.
inline std::string describeWarnings(const std::vector<Warning>& warnings) {
  std::string all;
  for (const Warning& w : warnings) all += "\n  " + w.code + " " + w.path + ": " + w.message;
  return all;
}

inline const Warning* findWarning(const std::vector<Warning>& warnings, const std::string& code,
                                  const std::string& path) {
  const Warning* found = nullptr;
  int n = 0;
  for (const Warning& w : warnings) {
    if (w.code == code && w.path == path) {
      found = &w;
      ++n;
    }
  }
  if (n != 1) {
    ADD_FAILURE() << n << " warnings '" << code << "' at '" << path << "'; warnings:" << describeWarnings(warnings);
  }
  return n == 1 ? found : nullptr;
}

inline bool hasWarning(const std::vector<Warning>& warnings, const std::string& code,
                       const std::string& message_part = {}) {
  for (const Warning& w : warnings) {
    if (w.code == code && w.message.find(message_part) != std::string::npos) return true;
  }
  return false;
}

/// Lower-case hexadecimal of a sequence of bytes (a digest, a CID).
template <typename Bytes>
std::string toHex(const Bytes& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string hex;
  for (std::uint8_t byte : bytes) {
    hex.push_back(kDigits[byte >> 4]);
    hex.push_back(kDigits[byte & 15]);
  }
  return hex;
}

}  // namespace test
}  // namespace springbones
