// The bodies of the fuzz targets, shared by the libFuzzer entry points (tests/fuzz/*_fuzzer.cpp)
// and by the GoogleTest that replays the checked-in corpus and every past finding
// (tests/native/fuzz_regressions_test.cpp), so a crash found by the fuzzer stays a test in the
// ordinary native suite (and under the sanitizers) without clang or libFuzzer.
//
// Each run* function takes arbitrary bytes, drives the public API with them and returns an empty
// string when every invariant held, else a description of the broken one. Crashes, leaks and
// undefined behaviour are the sanitizers' to report; the invariants here are the ones no
// sanitizer sees: output rotations are finite unit quaternions, errors carry a code and a
// message, rig indices stay in range.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/typed_encoding.h"
#include "creator_tools/builder_edits.h"
#include "creator_tools/tool_json.h"
#include "loading/entity.h"
#include "readers/json_values.h"
#include "springbones/boundary.h"
#include "springbones/content_hash.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "springbones/typed_input.h"
#if __has_include("simulation/xpbd_solver.h")
#include "simulation/xpbd_solver.h"
#define SPRINGBONES_FUZZ_HAS_XPBD 1
#endif
#if __has_include("springbones/vrm.h")
#include "springbones/vrm.h"
#define SPRINGBONES_FUZZ_HAS_VRM 1
#endif
#if __has_include("creator_tools/validation.h")
#include "creator_tools/validation.h"
#define SPRINGBONES_FUZZ_HAS_VALIDATION 1
#endif

namespace springbones {
namespace fuzz {

/// The libFuzzer entry points' ending: a broken invariant is printed and aborts, so libFuzzer
/// keeps and reports the input.
inline int abortIfBroken(const std::string& failure) {
  if (failure.empty()) return 0;
  std::fprintf(stderr, "springbones invariant broken: %s\n", failure.c_str());
  std::abort();
}

using nlohmann::json;

// Splits input (a) into a GLB part and springBones text: the text follows the last separator;
// without one the whole input is the GLB and there is no metadata.
inline constexpr char kMetadataSeparator[] = "\n@@springBones@@\n";

// ---------------------------------------------------------------------------------------------
// Invariants

inline std::string checkError(const Error& e, const char* what) {
  if (!e) return {};
  if (e.message.empty()) return std::string(what) + ": error without a message";
  if (std::string(errorCodeName(e.code)) == "unknown") return std::string(what) + ": unknown error code";
  return {};
}

inline std::string checkRotations(const Instance& instance, const char* when) {
  const float* r = instance.rotations();
  for (std::size_t j = 0; j < instance.jointCount(); ++j) {
    const float x = r[4 * j], y = r[4 * j + 1], z = r[4 * j + 2], w = r[4 * j + 3];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(w)) {
      return std::string("non-finite rotation of joint ") + std::to_string(j) + " " + when;
    }
    const double len = std::sqrt(double(x) * x + double(y) * y + double(z) * z + double(w) * w);
    if (std::fabs(len - 1.0) > 1e-3) {
      return std::string("rotation of joint ") + std::to_string(j) + " has length " + std::to_string(len) + " " + when;
    }
  }
  return {};
}

inline std::string checkRig(const Rig& rig) {
  const int nodes = static_cast<int>(rig.skeleton.nodes.size());
  const int drivers = static_cast<int>(rig.drivers.size());
  for (std::size_t j = 0; j < rig.joints.size(); ++j) {
    const Joint& joint = rig.joints[j];
    // tail_node -1: a VRM 0.x leaf's virtual tail.
    if (joint.node < 0 || joint.node >= nodes || joint.tail_node < -1 || joint.tail_node >= nodes) {
      return "joint node index out of range";
    }
    if (joint.parent_joint >= static_cast<int>(j)) return "joint listed before its parent joint";
    if (joint.parent_driver >= drivers || joint.center_driver >= drivers) return "driver index out of range";
    if (joint.chain < 0 || joint.chain > static_cast<int>(j)) return "chain index out of range";
    for (int c : joint.colliders) {
      if (c < 0 || c >= static_cast<int>(rig.colliders.size())) return "collider index out of range";
    }
    if (!(joint.hit_radius >= 0.0f) || !std::isfinite(joint.hit_radius)) return "bad hit radius";
  }
  for (const Driver& d : rig.drivers) {
    if (d.node < -1 || d.node >= nodes) return "driver node out of range";  // -1: external
  }
  for (const Collider& c : rig.colliders) {
    if (c.driver < 0 || c.driver >= drivers) return "collider driver out of range";
    if (!(c.radius >= 0.0f) || !std::isfinite(c.radius)) return "bad collider radius";
    if (c.shape == Collider::Shape::kPlane) {
      if (c.inside || c.radius != 0.0f) return "a plane collider with inside or a radius";
      if (!(std::fabs(glm::length(toGlm(c.normal)) - 1.0f) < 1e-5f)) return "a plane normal that is not unit";
    }
  }
  for (const Warning& w : rig.warnings) {
    if (w.code.empty() || w.message.empty()) return "warning without code or message";
  }
  return {};
}

// True when every number in the value is finite (JSON.parse turns 1e999 into Infinity).
inline bool allNumbersFinite(const json& value) {
  std::vector<const json*> stack = {&value};
  while (!stack.empty()) {
    const json* v = stack.back();
    stack.pop_back();
    if (v->is_number_float() && !std::isfinite(v->get<double>())) return false;
    if (v->is_structured()) {
      for (const json& child : *v) stack.push_back(&child);
    }
  }
  return true;
}

// What the runtime writes for the page (springbones/boundary.h, typed values) as JSON, as
// web/typed_output.js reads it: a float tag is a number. Discarded when the bytes are not exactly
// one value.
inline json typedOutputJson(const std::vector<std::uint8_t>& bytes) {
  std::size_t at = 0;
  const auto u32 = [&]() -> std::uint32_t {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t(bytes.at(at++)) << (8 * i);
    return v;
  };
  const auto text = [&]() {
    const std::uint32_t length = u32();
    if (bytes.size() - at < length) throw std::out_of_range("a string runs past the end");
    std::string s(reinterpret_cast<const char*>(bytes.data() + at), length);
    at += length;
    return s;
  };
  const auto value = [&](const auto& self) -> json {
    const std::uint8_t tag = bytes.at(at++);
    switch (tag) {
      case kTypedTagNull: return nullptr;
      case kTypedTagFalse: return false;
      case kTypedTagTrue: return true;
      case kTypedTagNumber: {
        std::uint64_t bits = 0;
        for (int i = 0; i < 8; ++i) bits |= std::uint64_t(bytes.at(at++)) << (8 * i);
        double v = 0;
        std::memcpy(&v, &bits, sizeof v);
        return v;
      }
      case kTypedTagFloat: {
        const std::uint32_t bits = u32();
        float v = 0;
        std::memcpy(&v, &bits, sizeof v);
        return v;
      }
      case kTypedTagString: return text();
      case kTypedTagArray: {
        json out = json::array();
        for (std::uint32_t n = u32(); n > 0; --n) out.push_back(self(self));
        return out;
      }
      case kTypedTagObject: {
        json out = json::object();
        for (std::uint32_t n = u32(); n > 0; --n) {
          const std::string key = text();
          out[key] = self(self);
        }
        return out;
      }
      default: throw std::out_of_range("unknown tag");
    }
  };
  try {
    json out = value(value);
    return at == bytes.size() ? out : json(json::value_t::discarded);
  } catch (const std::out_of_range&) { return json(json::value_t::discarded); }
}

// The rig description as the JS API reads it (rig.joints, rig.drivers, ...: one decoding of these
// typed values): it must be one value, an object with the documented members, and carry only
// finite numbers.
inline std::string checkDescription(const Rig& rig, const std::string& hash, const std::string& format) {
  const json value = typedOutputJson(describeRig(rig, hash, format));
  if (value.is_discarded()) return "rig description is not one typed value";
  for (const char* key :
       {"contentHash", "format", "nodeCount", "joints", "chains", "drivers", "colliders", "warnings"}) {
    if (!value.contains(key)) return std::string("rig description lacks ") + key;
  }
  if (!value["joints"].is_array() || value["joints"].size() != rig.joints.size())
    return "rig description joints differ";
  if (!allNumbersFinite(value)) return "rig description holds a non-finite number";
  return {};
}

// Steps an instance through a few ordinary frames with the drivers at rest.
inline std::string stepAtRest(Instance& instance) {
  if (std::string f = checkRotations(instance, "after construction"); !f.empty()) return f;
  const double frames[] = {1.0 / 60, 1.0 / 60, 0.1, 1.0 / 144, 1e9, -1.0};
  for (double dt : frames) {
    instance.step(dt);
    if (std::string f = checkRotations(instance, "after a step at rest"); !f.empty()) return f;
  }
  return {};
}

// The first key of springBones.models in the text, or "" when there is none to read.
inline std::string firstModelKey(const json& value) {
  if (!value.is_object()) return {};
  auto models = value.find("models");
  if (models == value.end() || !models->is_object() || models->empty()) return {};
  return models->begin().key();
}

inline json parseOrDiscard(const std::string& text) { return json::parse(text, nullptr, /*allow_exceptions=*/false); }

// ---------------------------------------------------------------------------------------------
// (a) GLB + metadata: load, parse, build, a few steps at rest.

inline std::string runGlbAndMetadata(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::size_t glb_size = size;
  std::string text;
  const std::size_t at = input.rfind(kMetadataSeparator);
  if (at != std::string::npos) {
    glb_size = at;
    text = input.substr(at + sizeof(kMetadataSeparator) - 1);
  }

  Skeleton skeleton;
  const Error load = loadSkeleton(data, glb_size, skeleton);
  if (std::string f = checkError(load, "loadSkeleton"); !f.empty()) return f;
  if (load && !skeleton.nodes.empty()) return "failed load left nodes behind";
  if (!load && skeleton.parents_first.size() != skeleton.nodes.size()) return "parents_first incomplete";
  // The content hash accepts anything.
  if (contentHash(data, glb_size).empty()) return "empty content hash";

  const json value = parseOrDiscard(text);
  std::string hash = firstModelKey(value);
  if (hash.empty()) hash = "h";
  ModelEntry model;
  std::vector<Warning> warnings;
  const Error meta = parseSpringBonesText(text, hash, model, warnings);
  if (std::string f = checkError(meta, "parseSpringBonesText"); !f.empty()) return f;
  if (load || meta) return {};

  (void)detectSpringBones(skeleton, model);
  const std::shared_ptr<const Rig> rig = buildRig(std::move(skeleton), model, std::move(warnings));
  if (std::string f = checkRig(*rig); !f.empty()) return f;
  if (std::string f = checkDescription(*rig, hash, "dcl"); !f.empty()) return f;
  Instance instance(rig);
  return stepAtRest(instance);
}

// ---------------------------------------------------------------------------------------------
// (a') a .vrm avatar: VRMC_springBone 1.0 or VRM 0.x secondaryAnimation, then steps at rest.

#ifdef SPRINGBONES_FUZZ_HAS_VRM
inline std::string runVrm(const std::uint8_t* data, std::size_t size) {
  std::shared_ptr<const Rig> rig;
  VrmSpringFormat format = VrmSpringFormat::kNone;
  const Error e = loadVrm(data, size, rig, &format);
  if (std::string f = checkError(e, "loadVrm"); !f.empty()) return f;
  if (e) return {};
  if (!rig) return "loadVrm succeeded without a rig";
  if (std::string f = checkRig(*rig); !f.empty()) return f;
  if (std::string f = checkDescription(*rig, "", "vrm0"); !f.empty()) return f;
  Instance instance(rig);
  return stepAtRest(instance);
}
#endif

// ---------------------------------------------------------------------------------------------
// (a'') typed input: the bytes a page's parse becomes (web/typed_value.js), as every typed entry
// point of the runtime reads them: a glTF document (then a rig of its nodes, stepped), a VRM
// document, data.springBones, an entity, the rig options.

inline std::string runTyped(const std::uint8_t* data, std::size_t size) {
  const TypedBytes typed{data, size};
  Skeleton skeleton;
  const Error nodes = loadSkeleton(typed, skeleton);
  if (std::string f = checkError(nodes, "loadSkeleton(typed)"); !f.empty()) return f;
  ModelEntry model;
  std::vector<Warning> warnings;
  const Error meta = parseSpringBones(typed, "h", model, warnings);
  if (std::string f = checkError(meta, "parseSpringBones(typed)"); !f.empty()) return f;
  std::string hash;
  const Error entity = mainFileHashFor(typed, "BaseMale", hash);
  if (std::string f = checkError(entity, "mainFileHashFor(typed)"); !f.empty()) return f;
  if (!entity && hash.empty()) return "mainFileHashFor(typed) succeeded without a hash";
  RigOptions options;
  if (const ApiFailure f = readRigOptions(typed, options); f && f.message.empty()) {
    return "readRigOptions(typed): a failure without a message";
  }
  if (!nodes) {
    const std::shared_ptr<const Rig> rig = buildRig(std::move(skeleton), model, std::move(warnings));
    if (std::string f = checkRig(*rig); !f.empty()) return f;
    Instance instance(rig);
    if (std::string f = stepAtRest(instance); !f.empty()) return f;
  }
#ifdef SPRINGBONES_FUZZ_HAS_VRM
  std::shared_ptr<const Rig> vrm;
  const Error e = loadVrm(typed, vrm);
  if (std::string f = checkError(e, "loadVrm(typed)"); !f.empty()) return f;
  if (!e) {
    if (!vrm) return "loadVrm(typed) succeeded without a rig";
    if (std::string f = checkRig(*vrm); !f.empty()) return f;
    Instance instance(vrm);
    return stepAtRest(instance);
  }
#endif
  return {};
}

// ---------------------------------------------------------------------------------------------
// (b) metadata alone: the runtime reader (fixed hash and first key), the validator, Builder edits.

inline std::string runMetadata(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ModelEntry model;
  std::vector<Warning> warnings;
  const Error fixed = parseSpringBonesText(text, "bafkreifixedhash", model, warnings);
  if (std::string f = checkError(fixed, "parseSpringBonesText(fixed hash)"); !f.empty()) return f;

  const json value = parseOrDiscard(text);
  if (value.is_discarded()) return {};
  const std::string key = firstModelKey(value);
  warnings.clear();
  const Error first = parseSpringBonesText(text, key, model, warnings);
  if (std::string f = checkError(first, "parseSpringBonesText(first key)"); !f.empty()) return f;
  for (const Warning& w : warnings) {
    if (w.code.empty() || w.message.empty()) return "warning without code or message";
  }

  const json entity = {
      {"content", {{{"file", "a.glb"}, {"hash", key}}}},
      {"metadata",
       {{"data",
         {{"representations",
           {{{"bodyShapes", {"urn:decentraland:off-chain:base-avatars:BaseMale"}}, {"mainFile", "a.glb"}}}},
          {"springBones", value}}}}}};
#ifdef SPRINGBONES_FUZZ_HAS_VALIDATION
  const std::vector<ValidationError> schema = validateSpringBonesSchema(value);
  for (const ValidationError& e : schema) {
    if (e.message.empty()) return "validation error without a message";
    if (!e.path.empty() && e.path[0] != '/') return "validation path is not a JSON pointer";
  }
  // The same springBones in a catalyst entity and in a Builder item: the same answer. springBones
  // alone is neither shape (it has no data), so it must be refused, never answered "valid".
  const json item = {{"contents", {{"a.glb", key}}},
                     {"data", {{"representations", {{{"mainFile", "a.glb"}}}}, {"springBones", value}}}};
  std::vector<ValidationError> entity_errors;
  std::vector<ValidationError> item_errors;
  std::vector<ValidationError> bare_errors;
  if (validateSpringBones(entity, entity_errors)) return "validateSpringBones refused an entity";
  if (validateSpringBones(item, item_errors)) return "validateSpringBones refused a Builder item";
  if (entity_errors.size() != item_errors.size()) return "entity and Builder item validate differently";
  for (std::size_t i = 0; i < entity_errors.size(); ++i) {
    if (entity_errors[i].path != item_errors[i].path || entity_errors[i].message != item_errors[i].message) {
      return "entity and Builder item validate differently";
    }
  }
  const bool has_data = value.is_object() && (value.contains("metadata") || value.contains("data"));
  if (!has_data && !validateSpringBones(value, bare_errors)) return "validateSpringBones read springBones as an entity";
  // What the deploy-time validator accepts, the runtime reads without complaint (a zero
  // gravityDir is valid in the schema and only has no direction).
  if (schema.empty() && !first && !value["models"].empty()) {
    for (const Warning& w : warnings) {
      if (w.code != "gravity-dir-zero") return "validator accepts what the reader warns about: " + w.code;
    }
  }
#endif

  // Builder edits on the same document: as existing springBones and as the params written.
  json out;
  json params = json::object();
  if (model.enabled && !model.bones.empty() && value.is_object()) {
    params = value["models"][key][model.bones.front().name];
  }
  for (const json* p : {static_cast<const json*>(&params), &value}) {
    const Error e = setSpringBoneParams(value, entity, "BaseMale", "springbone_fuzz", *p, out);
    if (std::string f = checkError(e, "setSpringBoneParams"); !f.empty()) return f;
  }
  return {};
}

// ---------------------------------------------------------------------------------------------
// (c) simulation: a fuzzed skeleton, parameters, options, driver matrices and frame times.

class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint16_t u16() { return static_cast<std::uint16_t>(byte() | (byte() << 8)); }
  float rawFloat() {
    std::uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits |= std::uint32_t(byte()) << (8 * i);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }
  // Mostly ordinary values in [-range, range], sometimes an edge case: kFloat edges stay in the
  // float range (transforms beyond it are rejected by the loader), kDouble adds finite doubles
  // beyond it, kAny adds NaN and the infinities.
  enum Edges { kFloat, kDouble, kAny };
  double number(double range, Edges edges) {
    static const double kEdges[] = {0.0,
                                    -0.0,
                                    1.0,
                                    -1.0,
                                    0.5,
                                    1e-7,
                                    -1e-7,
                                    1e-30,
                                    1e30,
                                    -1e30,
                                    3.4e38,
                                    -3.4e38,
                                    1.2e-38,
                                    1e-45,
                                    4.0,
                                    10.0,
                                    1e39,
                                    1e300,
                                    -1e300,
                                    std::numeric_limits<double>::infinity(),
                                    -std::numeric_limits<double>::infinity(),
                                    std::numeric_limits<double>::quiet_NaN()};
    constexpr std::size_t kAll = sizeof(kEdges) / sizeof(kEdges[0]);
    const std::uint8_t mode = byte();
    if (mode < 200) return (u16() / 65535.0 * 2.0 - 1.0) * range;
    const std::size_t count = edges == kFloat ? kAll - 6 : edges == kDouble ? kAll - 3 : kAll;
    return kEdges[(mode - 200) % count];
  }
  bool empty() const { return pos_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// A double as the float it would be stored in; beyond the float range, an infinity.
inline float toFloat(double value) {
  if (value > std::numeric_limits<float>::max()) return std::numeric_limits<float>::infinity();
  if (value < -std::numeric_limits<float>::max()) return -std::numeric_limits<float>::infinity();
  return static_cast<float>(value);
}

// A parameter value as metadata might hold it: usually a number, sometimes not.
inline json fuzzParam(ByteReader& in, double range) {
  switch (in.byte() % 16) {
    case 0: return nullptr;
    case 1: return "1";
    case 2: return json::array({1});
    case 3: return in.number(range, ByteReader::kAny);  // NaN/inf only a C++ json can hold
    case 4: return in.byte() % 2 == 0;
    case 5: return json::object();
    default: return in.number(range, ByteReader::kDouble);
  }
}

inline std::string runSimulation(const std::uint8_t* data, std::size_t size) {
  ByteReader in(data, size);
  const int node_count = 1 + in.byte() % 48;
  json nodes = json::array();
  std::vector<std::vector<int>> children(node_count);
  std::vector<std::string> names(node_count);
  for (int i = 0; i < node_count; ++i) {
    const int parent = i == 0 ? -1 : static_cast<int>(in.byte() % (i + 1)) - 1;
    if (parent >= 0) children[parent].push_back(i);
    switch (in.byte() % 8) {
      case 0: {  // the armature bones the 'dcl-body' preset measures, or a bone it does not know
        static const char* const kBodyBones[] = {
            "Avatar_Spine1",  "Avatar_Spine2",      "Avatar_Neck",          "Avatar_Head",     "Avatar_LeftShoulder",
            "Avatar_LeftArm", "Avatar_LeftForeArm", "Avatar_RightShoulder", "Avatar_RightArm", "Avatar_RightForeArm"};
        names[i] = i % 2 == 0 ? std::string(kBodyBones[(i / 2) % 10]) : "Avatar_Hips_" + std::to_string(i);
        break;
      }
      case 1: names[i] = i > 0 ? names[in.byte() % i] : "dup"; break;  // duplicate names
      case 2: names[i] = "SpringBone_" + std::to_string(i); break;
      default: names[i] = "springbone_" + std::to_string(i); break;
    }
    json node = {{"name", names[i]}};
    const std::uint8_t transform = in.byte();
    auto numbers = [&in](int count, double range) {
      json values = json::array();
      for (int k = 0; k < count; ++k) values.push_back(in.number(range, ByteReader::kFloat));
      return values;
    };
    if (transform & 1) node["translation"] = numbers(3, 1);
    if (transform & 2) node["rotation"] = numbers(4, 1);
    if (transform & 4) node["scale"] = numbers(3, 2);
    if ((transform & 8) && !(transform & 7)) {
      json m = numbers(16, 1);
      for (int k = 0; k < 16; k += 5) m[k] = 1.0 + m[k].get<double>();  // near the identity
      node["matrix"] = m;
    }
    nodes.push_back(std::move(node));
  }
  for (int i = 0; i < node_count; ++i) {
    if (!children[i].empty()) nodes[i]["children"] = children[i];
  }

  json bones = json::object();
  for (int i = 0; i < node_count; ++i) {
    if (in.byte() % 4 == 0) continue;
    json entry = json::object();
    if (in.byte() % 8 != 0) entry["stiffness"] = fuzzParam(in, 4);
    if (in.byte() % 8 != 0) entry["gravityPower"] = fuzzParam(in, 2);
    if (in.byte() % 8 != 0) entry["drag"] = fuzzParam(in, 1);
    const std::uint8_t dir = in.byte();
    if (dir % 8 == 0) {
      entry["gravityDir"] = fuzzParam(in, 10);
    } else if (dir % 8 != 1) {
      json d = json::array();
      const int length = dir % 8 == 2 ? 2 : dir % 8 == 3 ? 4 : 3;
      for (int k = 0; k < length; ++k) d.push_back(fuzzParam(in, 10));
      entry["gravityDir"] = d;
    }
    const std::uint8_t root = in.byte();
    if (root % 4 != 0) entry["isRoot"] = root % 4 != 3;
    const std::uint8_t center = in.byte();
    if (center % 4 == 1) entry["center"] = nullptr;
    if (center % 4 == 2) entry["center"] = names[in.byte() % node_count];
    if (center % 4 == 3) entry["center"] = "no such node";
    bones[names[i]] = std::move(entry);
  }

  const std::string gltf = json{{"asset", {{"version", "2.0"}}}, {"nodes", nodes}}.dump();
  if (std::getenv("SPRINGBONES_FUZZ_VERBOSE") != nullptr) {  // to read a finding
    std::fprintf(stderr, "glTF: %s\nbones: %s\n", gltf.c_str(),
                 bones.dump(-1, ' ', false, json::error_handler_t::replace).c_str());
  }
  Skeleton skeleton;
  const Error load = loadSkeleton(reinterpret_cast<const std::uint8_t*>(gltf.data()), gltf.size(), skeleton);
  if (std::string f = checkError(load, "loadSkeleton"); !f.empty()) return f;
  if (load) return {};  // cannot happen for generated trees; a sanitizer would still see a crash
  ModelEntry model;
  std::vector<Warning> warnings;
  const Error meta = parseSpringBones(json{{"version", 1}, {"models", {{"h", bones}}}}, "h", model, warnings);
  if (std::string f = checkError(meta, "parseSpringBones"); !f.empty()) return f;
  if (meta) return {};
  const auto vec3 = [&](double range) {  // three numbers from the bytes, x first
    float v[3];
    for (float& c : v) c = toFloat(in.number(range, ByteReader::kAny));
    return Vec3{v[0], v[1], v[2]};
  };
  // Colliders by node name (or on an avatar bone the GLB lacks), with any numbers at all.
  const auto fuzzCollider = [&](const char* external) {
    ColliderSpec spec;
    spec.node = in.byte() % 4 == 0 ? std::string(external) : names[in.byte() % node_count];
    // Sphere, capsule, plane, inside sphere, inside capsule; a plane with any inside and radius.
    const int shape = in.byte() % 5;
    spec.shape = shape == 2       ? Collider::Shape::kPlane
                 : shape % 2 == 1 ? Collider::Shape::kCapsule
                                  : Collider::Shape::kSphere;
    spec.inside = shape >= 3 || (shape == 2 && in.byte() % 2 == 0);
    spec.offset = vec3(0.2);
    spec.tail = vec3(0.2);
    spec.radius = toFloat(in.number(0.2, ByteReader::kAny));
    if (shape == 2) spec.normal = vec3(1.0);
    return spec;
  };
  RigOptions rig_options;
  const int collider_count = in.byte() % 4;
  for (int c = 0; c < collider_count; ++c) rig_options.colliders.push_back(fuzzCollider("Avatar_External"));
  rig_options.hit_radius = toFloat(in.number(0.05, ByteReader::kAny));
  if (in.byte() % 4 == 0) rig_options.preset = ColliderPreset::kDclBody;
  const std::shared_ptr<const Rig> rig = buildRig(std::move(skeleton), model, std::move(warnings), rig_options);
  if (std::string f = checkRig(*rig); !f.empty()) return f;

  InstanceOptions options;
  static const double kStepHz[] = {60,
                                   30,
                                   144,
                                   1,
                                   1000,
                                   0,
                                   -1,
                                   1e9,
                                   1e-9,
                                   std::numeric_limits<double>::quiet_NaN(),
                                   std::numeric_limits<double>::infinity()};
  options.step_hz = kStepHz[in.byte() % (sizeof(kStepHz) / sizeof(kStepHz[0]))];
  options.max_substeps = static_cast<int>(static_cast<std::int8_t>(in.byte()));
  Instance instance(rig, options);
  if (std::string f = checkRotations(instance, "after construction"); !f.empty()) return f;
  // Wind with any numbers at all, on the instance or through the scene below.
  const std::uint8_t wind_mode = in.byte() % 4;
  Wind wind;
  if (wind_mode != 0) {
    wind.direction = vec3(1);
    wind.strength = toFloat(in.number(20, ByteReader::kAny));
    wind.gust_frequency = toFloat(in.number(20, ByteReader::kAny));
    wind.seed = in.u16() | (std::uint32_t(in.u16()) << 16);
  }
  if (wind_mode == 1) instance.setWind(wind);

  Scene scene;
  if (wind_mode == 2) scene.setWind(wind);
  scene.add(&instance);
  if (wind_mode == 3) scene.setWind(wind);
  float* drivers = instance.driverMatrices();
  const std::size_t driver_count = instance.driverCount();
  std::vector<float> rest(drivers, drivers + 16 * driver_count);
  static const double kFrames[] = {1.0 / 60,
                                   1.0 / 30,
                                   1.0 / 144,
                                   0.1,
                                   0.25,
                                   1e9,
                                   -1,
                                   0,
                                   1e-300,
                                   std::numeric_limits<double>::quiet_NaN(),
                                   std::numeric_limits<double>::infinity()};
  for (int frame = 0; frame < 100; ++frame) {
    for (std::size_t d = 0; d < driver_count; ++d) {
      float* m = drivers + 16 * d;
      const std::uint8_t mode = in.byte();
      switch (mode % 8) {
        case 0: break;  // unchanged
        case 1: {       // rest pose moved and turned: the ordinary animated case
          std::memcpy(m, rest.data() + 16 * d, sizeof(float) * 16);
          const float angle = toFloat(in.number(3.2, ByteReader::kFloat));
          const float c = std::cos(angle), s = std::sin(angle);
          const float x0 = m[0], x1 = m[1], x2 = m[2], z0 = m[8], z1 = m[9], z2 = m[10];
          m[0] = c * x0 + s * z0;
          m[1] = c * x1 + s * z1;
          m[2] = c * x2 + s * z2;
          m[8] = c * z0 - s * x0;
          m[9] = c * z1 - s * x1;
          m[10] = c * z2 - s * x2;
          m[12] += toFloat(in.number(1, ByteReader::kFloat));
          m[13] += toFloat(in.number(1, ByteReader::kFloat));
          break;
        }
        case 2:  // every element from the bytes: shear, projection, huge, denormal, NaN
          for (int k = 0; k < 16; ++k) m[k] = in.rawFloat();
          break;
        case 3:  // singular
          std::memset(m, 0, sizeof(float) * 16);
          m[15] = 1.0f;
          break;
        case 4:  // one element replaced by an edge value
          m[in.byte() % 16] = toFloat(in.number(1, ByteReader::kAny));
          break;
        case 5:  // uniform scale
          for (int k = 0; k < 12; ++k) m[k] *= toFloat(in.number(4, ByteReader::kFloat));
          break;
        default: std::memcpy(m, rest.data() + 16 * d, sizeof(float) * 16); break;
      }
    }
    const std::uint8_t time = in.byte();
    if (time == 255) instance.reset();
    const double dt = time < 128 ? 1.0 / 60 : kFrames[time % (sizeof(kFrames) / sizeof(kFrames[0]))];
    if (time % 8 == 7) {  // through a Scene, with a budget and a viewer from the bytes
      scene.positions()[0] = toFloat(in.number(10, ByteReader::kAny));
      scene.setBudget(static_cast<int>(in.byte() % 4) - 1, Vec3{toFloat(in.number(10, ByteReader::kAny)), 0.0f, 0.0f});
      scene.step(dt);
    } else {
      instance.step(dt);
    }
    if (std::string f = checkRotations(instance, "after a fuzzed step"); !f.empty()) return f;
    (void)instance.worldMatrices();
  }
  // Colliders changed at run time (Instance::setColliders): any numbers, on drivers, spring bones
  // or frames, the body preset at any scale; then frames of any matrices.
  ColliderOptions change;
  const int changed = in.byte() % 4;
  for (int c = 0; c < changed; ++c) change.colliders.push_back(fuzzCollider("a frame"));
  if (in.byte() % 4 == 0) {
    change.preset = ColliderPreset::kDclBody;
    change.body.scale = toFloat(in.number(4, ByteReader::kAny));
  }
  (void)instance.setColliders(change);
  for (int frame = 0; frame < 20; ++frame) {
    float* frames = instance.frameMatrices();
    for (std::size_t k = 0; k < 16 * instance.frameNames().size(); ++k)
      frames[k] = in.byte() % 2 ? in.rawFloat() : (k % 5 == 0 ? 1.0f : 0.0f);
    instance.step(1.0 / 60);
    if (std::string f = checkRotations(instance, "after setColliders"); !f.empty()) return f;
  }
#ifdef SPRINGBONES_FUZZ_HAS_XPBD
  // The XPBD integrator on the same rig, fed as an owner feeds it: finite driver matrices (the
  // Instance keeps the last good pose of a non-finite one), world colliders, a positive h.
  XpbdOptions xpbd_options;
  xpbd_options.reference_hz = kStepHz[in.byte() % (sizeof(kStepHz) / sizeof(kStepHz[0]))];
  xpbd_options.iterations = static_cast<int>(static_cast<std::int8_t>(in.byte()));
  XpbdSolver xpbd(*rig, xpbd_options);
  std::vector<glm::mat4> driver_world(driver_count, glm::mat4(1.0f));
  std::vector<glm::mat4> joint_world(rig->joints.size());
  std::vector<float> xpbd_rotations(4 * rig->joints.size());
  std::vector<XpbdCollider> colliders(rig->colliders.size());
  auto readDriverWorld = [&] {
    for (std::size_t d = 0; d < driver_count; ++d) {
      const float* m = drivers + 16 * d;
      bool finite = true;
      for (int k = 0; k < 16; ++k) finite = finite && std::isfinite(m[k]);
      if (finite) std::memcpy(&driver_world[d][0][0], m, sizeof(float) * 16);
    }
    for (std::size_t c = 0; c < colliders.size(); ++c) {
      const Collider& collider = rig->colliders[c];
      const glm::mat4& m = driver_world[collider.driver];
      colliders[c].kind = colliderKind(collider);
      colliders[c].start = glm::vec3(m * glm::vec4(toGlm(collider.offset), 1.0f));
      colliders[c].end = collider.shape == Collider::Shape::kPlane
                             ? glm::normalize(glm::transpose(glm::inverse(glm::mat3(m))) * toGlm(collider.normal))
                         : collider.shape == Collider::Shape::kCapsule
                             ? glm::vec3(m * glm::vec4(toGlm(collider.tail), 1.0f))
                             : colliders[c].start;
      colliders[c].radius =
          collider.shape == Collider::Shape::kPlane ? 0.0f : collider.radius * glm::length(glm::vec3(m[0]));
    }
  };
  auto checkXpbd = [&](const char* when) -> std::string {
    for (std::size_t j = 0; j < rig->joints.size(); ++j) {
      const float* q = xpbd_rotations.data() + 4 * j;
      const double len =
          std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
      if (!std::isfinite(len) || std::fabs(len - 1.0) > 1e-3) {
        return "XPBD rotation of joint " + std::to_string(j) + " is not a finite unit quaternion " + when;
      }
    }
    return {};
  };
  readDriverWorld();
  xpbd.seed(driver_world.data(), xpbd_rotations.data(), joint_world.data());
  if (std::string f = checkXpbd("after seeding"); !f.empty()) return f;
  static const float kSubsteps[] = {1.0f / 120, 1.0f / 60, 1.0f / 1000, 1e-30f, 0.25f, 1.0f};
  for (int substep = 0; substep < 100 && !in.empty(); ++substep) {
    float* m = drivers + 16 * (driver_count > 0 ? in.byte() % driver_count : 0);
    if (driver_count > 0 && in.byte() % 2 == 0) m[12 + in.byte() % 3] += toFloat(in.number(0.2, ByteReader::kFloat));
    readDriverWorld();
    const float h = kSubsteps[in.byte() % (sizeof(kSubsteps) / sizeof(kSubsteps[0]))];
    xpbd.step(driver_world.data(), colliders.data(), colliders.size(), h, xpbd_rotations.data(), joint_world.data());
    if (std::string f = checkXpbd("after an XPBD substep"); !f.empty()) return f;
  }
#endif
  return {};
}

// ---------------------------------------------------------------------------------------------
// (d) an entity or Builder item as JSON text: which GLB hash loadRig and the Builder edits take
// from it, the validator, and a Builder edit through it.

inline std::string runEntity(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const json entity = parseOrDiscard(text);
  if (entity.is_discarded()) return {};

  std::vector<Representation> representations;
  const Error read = readRepresentations(entity, representations);
  if (std::string f = checkError(read, "readRepresentations"); !f.empty()) return f;
  for (const char* shape : {"BaseMale", "urn:decentraland:off-chain:base-avatars:BaseFemale"}) {
    std::string hash;
    const Error e = mainFileHashFor(entity, shape, hash);
    if (std::string f = checkError(e, "mainFileHashFor"); !f.empty()) return f;
    if (!e && hash.empty()) return "mainFileHashFor succeeded without a hash";
    if (e && !hash.empty()) return "mainFileHashFor failed but left a hash";
    // What loadRig would then read: the entity's springBones under that hash.
    if (!e) {
      ModelEntry model;
      std::vector<Warning> warnings;
      const Error parsed = parseSpringBones(springBonesOf(entity), hash, model, warnings);
      if (std::string f = checkError(parsed, "parseSpringBones(entity)"); !f.empty()) return f;
    }
  }

#ifdef SPRINGBONES_FUZZ_HAS_VALIDATION
  std::vector<ValidationError> errors;
  const Error refused = validateSpringBones(entity, errors);
  if (std::string f = checkError(refused, "validateSpringBones"); !f.empty()) return f;
  if (refused && !errors.empty()) return "validateSpringBones refused the value and listed errors";
  if (refused && refused.code != ErrorCode::kInvalidArgument) return "validateSpringBones refused with another code";
  for (const ValidationError& v : errors) {
    if (v.message.empty()) return "validation error without a message";
    if (!v.path.empty() && v.path[0] != '/') return "validation path is not a JSON pointer";
  }
#endif

  json out;
  const json params = {{"stiffness", 1}, {"gravityPower", 0}, {"gravityDir", {0, -1, 0}}, {"drag", 0.5}};
  const Error edit = setSpringBoneParams(springBonesOf(entity), entity, "BaseMale", "springbone_fuzz", params, out);
  if (std::string f = checkError(edit, "setSpringBoneParams(entity)"); !f.empty()) return f;
  if (!edit && (!out.is_object() || out.value("version", 0) != 1)) return "setSpringBoneParams wrote no version 1";
  return {};
}

}  // namespace fuzz
}  // namespace springbones
