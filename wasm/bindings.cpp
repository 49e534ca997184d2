// embind bindings of the core: a handful of functions over integers, pointers and strings.
//
// Contract with web/springbones.js (the only caller; nothing here is public API):
//  - Rigs, instances and scenes live in handle tables. A handle is a positive integer, never reused, so
//    a stale handle finds nothing instead of someone else's object. 0 means failure; the error is
//    then read once with takeError() as JSON {code, message, path}.
//  - Bulk data crosses as pointers into WASM memory (GLB bytes in, driver matrices in, rotations
//    out, the rig description as one block of 32-bit words, see rigInfo); structured data that is
//    read once (rig options, entities, validation errors, Builder edits, errors) crosses as one
//    JSON string.
//  - Nothing throws across the boundary: every entry point catches every C++ exception and turns
//    it into an error, so bad input never aborts the module and the next call works.
// The logic lives in src/; this file only moves data and catches.
#include <malloc.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <exception>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include <emscripten/bind.h>
#include <nlohmann/json.hpp>

#include "builder_edits.h"
#include "content_hash.h"
#include "entity.h"
#include "float_text.h"
#include "json_scan.h"
#include "springbones.h"
#include "validation.h"
#include "vrm_loader.h"

namespace springbones {
namespace {

using nlohmann::json;

struct LoadedRig {
  std::shared_ptr<const Rig> rig;
  std::string hash;  ///< the models key the rig was built from ("" for a VRM)
  std::string format = "dcl";  ///< where the springs came from: dcl, vrmc-springbone, vrm0, none
};

// Instances hold their rig through a shared_ptr, so disposing of a rig handle while instances of
// it are alive only drops the handle; the memory goes with the last instance.
std::unordered_map<int, LoadedRig> g_rigs;
std::unordered_map<int, std::unique_ptr<Instance>> g_instances;
// Scenes hold raw Instance pointers (they own nothing): disposeInstance removes the instance from
// every scene first, so a scene never steps freed memory.
std::unordered_map<int, std::unique_ptr<Scene>> g_scenes;
int g_next_handle = 1;

// The pending error. Its code is the core's errorCodeName(), or one of the codes that only exist
// at this boundary: "out-of-memory", "internal-error", "bad-handle".
struct PendingError {
  std::string code, message, path;
};
PendingError g_error;

int fail(std::string code, std::string message, std::string path = {}) {
  g_error = PendingError{std::move(code), std::move(message), std::move(path)};
  return 0;
}
int fail(const Error& error) { return fail(errorCodeName(error.code), error.message, error.path); }

int newHandle() {
  // 2^31 - 1 handles per module lifetime; past that, refuse rather than wrap onto live ones.
  if (g_next_handle == INT32_MAX) throw std::length_error("out of handles");
  return g_next_handle++;
}

// Runs body, turning any C++ exception into the pending error. Returns body's result or 0.
template <typename Body>
int guarded(Body&& body) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return fail("out-of-memory", "out of memory");
  } catch (const std::exception& ex) {
    return fail("internal-error", std::string("internal error: ") + ex.what());
  } catch (...) {
    return fail("internal-error", "internal error");
  }
}

// The shortest decimal that reads back as the same float, so 0.4f shows as 0.4 in JS, not as
// 0.4000000059604645: the value the simulation uses, written the way the metadata wrote it
// (src/float_text.h).
double shortestDouble(float value) { return shortestFloatDouble(value); }

json paramsJson(const BoneParams& p) {
  return json{{"stiffness", shortestDouble(p.stiffness)},
              {"gravityPower", shortestDouble(p.gravity_power)},
              {"gravityDir",
               {shortestDouble(p.gravity_dir.x), shortestDouble(p.gravity_dir.y),
                shortestDouble(p.gravity_dir.z)}},
              {"drag", shortestDouble(p.drag)}};
}

// ---------------------------------------------------------------------------------------------
// The rig description: numbers and names in a binary block, and the few strings that may need
// escaping as JSON text, written straight (no nlohmann DOM, no printf per float). The JSON is what
// nlohmann would dump, keys in its (sorted) order and the same numbers; the writers below hold no
// objects with destructors, so in WebAssembly their calls stay direct instead of going through the
// JavaScript exception trampolines.

#if defined(__GNUC__) || defined(__clang__)
#define SPRINGBONES_NOINLINE __attribute__((noinline))
#else
#define SPRINGBONES_NOINLINE
#endif

// A string that needs escaping or holds non-ASCII bytes: nlohmann's own escaping (replace: a
// message may quote a node name cut inside a UTF-8 sequence).
SPRINGBONES_NOINLINE void escapeString(const std::string& s, std::string& out) {
  out = json(s).dump(-1, ' ', false, json::error_handler_t::replace);
}

// Appends into a std::string sized ahead, through a plain pointer: at -Oz every std::string
// append is an out-of-line call, which at 1.5 MB of text was most of the time.
class TextWriter {
 public:
  TextWriter(std::string& out, std::string& scratch) : out_(out), scratch_(scratch) { grow(1 << 10); }

  void raw(const char* s, std::size_t n) {
    if (static_cast<std::size_t>(end_ - p_) < n) grow(n);
    std::memcpy(p_, s, n);
    p_ += n;
  }
  template <std::size_t N>
  void lit(const char (&s)[N]) {
    raw(s, N - 1);
  }
  void integer(long long v) {
    if (end_ - p_ < 24) grow(24);
    p_ += writeInteger(p_, v);
  }
  void number(float v) {
    // The same floats recur (parameters shared by a chain, equal bone lengths): a small cache of
    // their texts, keyed by the bits.
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    CachedFloat& c = cache_[(bits ^ (bits >> 13) ^ (bits >> 23)) & (kCacheSize - 1)];
    if (!c.valid || c.bits != bits) {
      c.length = static_cast<unsigned char>(writeShortestFloat(c.text, v));
      c.bits = bits;
      c.valid = true;
    }
    raw(c.text, c.length);
  }
  void string(const std::string& s) {
    for (char c : s) {
      if (c < 0x20 || c > 0x7E || c == '"' || c == '\\') {
        escapeString(s, scratch_);
        raw(scratch_.data(), scratch_.size());
        return;
      }
    }
    if (static_cast<std::size_t>(end_ - p_) < s.size() + 2) grow(s.size() + 2);
    *p_++ = '"';
    std::memcpy(p_, s.data(), s.size());
    p_ += s.size();
    *p_++ = '"';
  }
  void vec3(const glm::vec3& v) {
    lit("[");
    number(v.x);
    lit(",");
    number(v.y);
    lit(",");
    number(v.z);
    lit("]");
  }
  std::size_t size() const { return static_cast<std::size_t>(p_ - out_.data()); }
  void finish() { out_.resize(size()); }

 private:
  static constexpr std::size_t kCacheSize = 256;
  struct CachedFloat {
    std::uint32_t bits = 0;
    bool valid = false;
    unsigned char length = 0;
    char text[kMaxFloatTextLength];
  };

  SPRINGBONES_NOINLINE void grow(std::size_t n) {
    const std::size_t used = p_ ? static_cast<std::size_t>(p_ - out_.data()) : 0;
    out_.resize(std::max(out_.size() * 2, used + n + 1024));
    p_ = &out_[0] + used;
    end_ = &out_[0] + out_.size();
  }

  std::string& out_;
  std::string& scratch_;
  char* p_ = nullptr;
  char* end_ = nullptr;
  CachedFloat cache_[kCacheSize];
};

// The parts of the description that are JSON: strings the core may have to escape (a warning
// can quote a node name cut inside a UTF-8 sequence, a content hash is whatever the caller gave),
// in nlohmann's key order.
SPRINGBONES_NOINLINE void writeHeadJson(const LoadedRig& loaded, TextWriter& w) {
  w.lit("{\"contentHash\":");
  w.string(loaded.hash);
  w.lit(",\"format\":");
  w.string(loaded.format);
  w.lit("}");
}

SPRINGBONES_NOINLINE void writeListsJson(const Rig& rig, TextWriter& w) {
  w.lit("{\"colliders\":[");
  for (std::size_t i = 0; i < rig.colliders.size(); ++i) {
    const Collider& c = rig.colliders[i];
    const bool capsule = c.shape == Collider::Shape::kCapsule;
    if (i) w.lit(",");
    w.lit("{\"driver\":");
    w.integer(c.driver);
    w.lit(",\"node\":");
    if (c.driver >= 0) {
      w.string(rig.drivers[c.driver].name);
    } else {
      w.lit("null");
    }
    w.lit(",\"offset\":");
    w.vec3(c.offset);
    w.lit(",\"radius\":");
    w.number(c.radius);
    if (capsule) {
      w.lit(",\"shape\":\"capsule\",\"tail\":");
      w.vec3(c.tail);
    } else {
      w.lit(",\"shape\":\"sphere\"");
    }
    w.lit("}");
  }
  w.lit("],\"warnings\":[");
  for (std::size_t i = 0; i < rig.warnings.size(); ++i) {
    const Warning& x = rig.warnings[i];
    if (i) w.lit(",");
    w.lit("{\"code\":");
    w.string(x.code);
    w.lit(",\"message\":");
    w.string(x.message);
    w.lit(",\"path\":");
    w.string(x.path);
    w.lit("}");
  }
  w.lit("]}");
}

// The rig description block (rigInfo), read by RigDescription in web/springbones.js. Every
// section starts on a 4-byte boundary; counts and offsets are in the header:
//   header      kRigBlockHeaderWords uint32: total bytes, joints J, chains C, drivers D, nodes N,
//               strings S (= N + D), string bytes, head JSON bytes, lists JSON bytes
//   joint ints  J x 6 int32: node, tailNode (-1: no node), parent, parentDriver, centerDriver, chain
//   joint floats J x 11 float32: hitRadius, restLength, drag, gravityDir x y z, gravityPower,
//               stiffness, tailOffset x y z (the floats themselves: the JS side turns them into
//               the shortest decimals, shortestFloatValues, when the joints are first read)
//   chains      C int32; driver nodes D int32
//   string ends S uint32 (end offset of each string in the string bytes; names of the N nodes,
//               then of the D drivers: valid UTF-8, the readers check it)
//   string bytes, head JSON {contentHash, format}, lists JSON {colliders, warnings}
// Binary rather than JSON: for a 5,000-joint rig the JSON text (1.5 MB), its parse and the
// objects built from it took twice as long as loading the rig.
constexpr std::size_t kRigBlockHeaderWords = 9;
constexpr std::size_t kJointInts = 6;
constexpr std::size_t kJointFloats = 11;

std::size_t padded(std::size_t n) { return (n + 3) & ~std::size_t(3); }

// Inlines every call in the function. This file is built at -Oz, where std::string's size() and
// data() stay calls: for the 7,000 names of a large rig they were half of describing it.
#if defined(__clang__)
#define SPRINGBONES_FLATTEN __attribute__((flatten))
#else
#define SPRINGBONES_FLATTEN
#endif

// Bytes of the node and driver names.
SPRINGBONES_NOINLINE SPRINGBONES_FLATTEN std::size_t nameBytes(const Rig& rig) {
  std::size_t bytes = 0;
  for (const SkeletonNode& n : rig.skeleton.nodes) bytes += n.name.size();
  for (const Driver& d : rig.drivers) bytes += d.name.size();
  return bytes;
}

// Fills the numeric sections and the strings; no locals with destructors (see TextWriter). The
// block is malloc'd and every section 4-byte aligned, so the numbers are stored straight (at -Oz
// a small memcpy per field stays a call).
SPRINGBONES_NOINLINE SPRINGBONES_FLATTEN void writeRigBlock(const Rig& rig, std::uint8_t* block) {
  const auto& nodes = rig.skeleton.nodes;
  auto* ints = reinterpret_cast<std::int32_t*>(block + 4 * kRigBlockHeaderWords);
  for (const Joint& j : rig.joints) {
    // tail_node is -1 for a VRM 0.x leaf's virtual tail: no node, tail_local is the truth.
    const bool tail_is_node = j.tail_node >= 0 && static_cast<std::size_t>(j.tail_node) < nodes.size();
    ints[0] = j.node;
    ints[1] = tail_is_node ? j.tail_node : -1;
    ints[2] = j.parent_joint;
    ints[3] = j.parent_driver;
    ints[4] = j.center_driver;
    ints[5] = j.chain;
    ints += kJointInts;
  }
  auto* floats = reinterpret_cast<float*>(ints);
  for (const Joint& j : rig.joints) {
    const BoneParams& q = j.params;
    floats[0] = j.hit_radius;
    floats[1] = j.rest_length;
    floats[2] = q.drag;
    floats[3] = q.gravity_dir.x;
    floats[4] = q.gravity_dir.y;
    floats[5] = q.gravity_dir.z;
    floats[6] = q.gravity_power;
    floats[7] = q.stiffness;
    floats[8] = j.tail_local.x;
    floats[9] = j.tail_local.y;
    floats[10] = j.tail_local.z;
    floats += kJointFloats;
  }
  ints = reinterpret_cast<std::int32_t*>(floats);
  for (int root : rig.chain_roots) *ints++ = root;
  for (const Driver& d : rig.drivers) *ints++ = d.node;
  auto* ends = reinterpret_cast<std::uint32_t*>(ints);
  char* text = reinterpret_cast<char*>(ends + nodes.size() + rig.drivers.size());
  std::uint32_t end = 0;
  const auto add = [&](const std::string& name) {
    std::memcpy(text + end, name.data(), name.size());
    end += static_cast<std::uint32_t>(name.size());
    *ends++ = end;
  };
  for (const SkeletonNode& n : nodes) add(n.name);
  for (const Driver& d : rig.drivers) add(d.name);
}

// The whole block, malloc'd; nullptr when it cannot be allocated.
std::uint8_t* rigBlock(const LoadedRig& loaded) {
  const Rig& rig = *loaded.rig;
  // Both JSON texts in one buffer: the head, then the lists.
  std::string json_text, scratch;
  std::size_t head_size = 0;
  {
    auto writer = std::make_unique<TextWriter>(json_text, scratch);  // 10 KB of float cache: not on the stack
    writeHeadJson(loaded, *writer);
    head_size = writer->size();
    writeListsJson(rig, *writer);
    writer->finish();
  }
  const std::string_view head(json_text.data(), head_size);
  const std::string_view lists(json_text.data() + head_size, json_text.size() - head_size);
  const std::size_t string_bytes = nameBytes(rig);
  const std::size_t strings = rig.skeleton.nodes.size() + rig.drivers.size();
  const std::size_t words = kRigBlockHeaderWords + (kJointInts + kJointFloats) * rig.joints.size() +
                            rig.chain_roots.size() + rig.drivers.size() + strings;
  const std::size_t total = 4 * words + padded(string_bytes) + padded(head.size()) + lists.size();
  if (total > UINT32_MAX) throw std::length_error("rig description too large");
  auto* block = static_cast<std::uint8_t*>(std::malloc(total));
  if (block == nullptr) return nullptr;
  const std::uint32_t header[kRigBlockHeaderWords] = {
      static_cast<std::uint32_t>(total),           static_cast<std::uint32_t>(rig.joints.size()),
      static_cast<std::uint32_t>(rig.chain_roots.size()), static_cast<std::uint32_t>(rig.drivers.size()),
      static_cast<std::uint32_t>(rig.skeleton.nodes.size()), static_cast<std::uint32_t>(strings),
      static_cast<std::uint32_t>(string_bytes),    static_cast<std::uint32_t>(head.size()),
      static_cast<std::uint32_t>(lists.size())};
  std::memcpy(block, header, sizeof header);
  writeRigBlock(rig, block);
  std::uint8_t* json_at = block + 4 * words + padded(string_bytes);
  std::memcpy(json_at, head.data(), head.size());
  std::memcpy(json_at + padded(head.size()), lists.data(), lists.size());
  return block;
}

Instance* findInstance(int handle) {
  auto it = g_instances.find(handle);
  return it == g_instances.end() ? nullptr : it->second.get();
}

int badHandle(const char* what, int handle) {
  return fail("bad-handle", std::string("no live ") + what + " with handle " + std::to_string(handle));
}

// ---------------------------------------------------------------------------------------------
// Entry points

/// The pending error as JSON {code, message, path}, then clears it.
std::string takeError() {
  try {
    const std::string text =
        json{{"code", g_error.code}, {"message", g_error.message}, {"path", g_error.path}}
            .dump(-1, ' ', false, json::error_handler_t::replace);
    g_error = PendingError{};
    return text;
  } catch (...) {
    return R"({"code":"out-of-memory","message":"out of memory","path":""})";
  }
}

/// Reads RigOptions from the JSON the JS API writes after checking every field:
/// {"colliders": [{"node", "offset": [x,y,z], "radius", "tail"?: [x,y,z]}], "hitRadius"}.
/// A collider with a tail is a capsule. Shapes it does not expect throw json::exception (caught).
RigOptions rigOptionsFrom(const std::string& text) {
  RigOptions options;
  if (text.empty()) return options;
  const json value = json::parse(text);
  const auto vec3 = [](const json& a) {
    return glm::vec3(a.at(0).get<float>(), a.at(1).get<float>(), a.at(2).get<float>());
  };
  if (value.contains("hitRadius")) options.hit_radius = value.at("hitRadius").get<float>();
  if (value.contains("colliders")) {
    for (const json& c : value.at("colliders")) {
      ColliderSpec spec;
      spec.node = c.at("node").get<std::string>();
      spec.offset = vec3(c.at("offset"));
      spec.radius = c.at("radius").get<float>();
      if (c.contains("tail")) {
        spec.shape = Collider::Shape::kCapsule;
        spec.tail = vec3(c.at("tail"));
      }
      options.colliders.push_back(std::move(spec));
    }
  }
  return options;
}

/// The steps of loading a rig after the arguments: the rig options, the skeleton, then the model
/// entry from `readModel(bytes, size, hash, model, warnings)`, the rig; in this order, which is
/// the order of their errors. `hash` is the models key (empty: the GLB's own content hash).
/// Returns the rig handle, or 0 with the error pending. The caller keeps ownership of `data`.
template <typename ReadModel>
int loadRigWith(std::uintptr_t data, std::size_t size, const std::string& hash, const std::string& options_text,
                ReadModel&& readModel) {
  return guarded([&] {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(data);
    RigOptions options;
    try {
      options = rigOptionsFrom(options_text);
    } catch (const json::exception& ex) {
      return fail("invalid-argument", std::string("rig options could not be read: ") + ex.what());
    }
    Skeleton skeleton;
    if (Error e = loadSkeleton(bytes, size, skeleton)) return fail(e);
    LoadedRig loaded;
    loaded.hash = hash.empty() ? contentHash(bytes, size) : hash;
    ModelEntry model;
    std::vector<Warning> warnings;
    if (Error e = readModel(loaded.hash, model, warnings)) return fail(e);
    loaded.rig = buildRig(std::move(skeleton), model, std::move(warnings), options);
    const int handle = newHandle();
    g_rigs.emplace(handle, std::move(loaded));
    return handle;
  });
}

/// Loads a rig from `size` GLB/glTF bytes at `data`, the springBones JSON text as `metadata_size`
/// UTF-8 bytes at `metadata_data` (the text "null" for none; bytes, not a JS string, because
/// embind converts strings with a per-character JavaScript loop), the models key (empty: the
/// GLB's own content hash) and the rig options as JSON (empty for none). Returns the rig handle,
/// or 0 with the error pending. The caller keeps ownership of `data`.
int loadRig(std::uintptr_t data, std::size_t size, std::uintptr_t metadata_data, std::size_t metadata_size,
            const std::string& hash, const std::string& options_text) {
  const std::string_view metadata(reinterpret_cast<const char*>(metadata_data), metadata_size);
  return loadRigWith(data, size, hash, options_text,
                     [&](const std::string& key, ModelEntry& model, std::vector<Warning>& warnings) {
                       return parseSpringBonesTextView(metadata, key, model, warnings);
                     });
}

/// loadRig with the entries of models[hash] handed over decoded (readSpringBonesEntries,
/// json_scan.h) instead of the springBones JSON text: what the JS API does for a springBones
/// object, sparing JSON.stringify and the parse. `hash` is not empty. Returns -1, with nothing
/// done and no error pending, when the entries are not ones the fast reader takes; the caller then
/// uses loadRig with the text, which gives the real warnings or error. Read before the skeleton
/// (unlike loadRig's text) so a refusal costs nothing; readSpringBonesEntries has no errors, so
/// the order of errors is loadRig's.
int loadRigEntries(std::uintptr_t data, std::size_t size, std::uintptr_t entries_data, std::size_t entries_size,
                   const std::string& hash, const std::string& options_text) {
  ModelEntry model;
  std::vector<Warning> warnings;
  const int read = guarded([&] {
    return readSpringBonesEntries(reinterpret_cast<const std::uint8_t*>(entries_data), entries_size, hash, model,
                                  warnings)
               ? 1
               : -1;
  });
  if (read != 1) return read;  // -1, or 0 when it ran out of memory
  return loadRigWith(data, size, hash, options_text,
                     [&](const std::string&, ModelEntry& out, std::vector<Warning>& out_warnings) {
                       out = std::move(model);
                       out_warnings = std::move(warnings);
                       return Error{};
                     });
}

/// Loads the spring bones of a .vrm (VRMC_springBone 1.0 or VRM 0.x secondaryAnimation) into a
/// rig. Returns the rig handle, or 0 with the error pending.
int loadVrm(std::uintptr_t data, std::size_t size) {
  return guarded([&] {
    LoadedRig loaded;
    VrmSpringFormat format = VrmSpringFormat::kNone;
    if (Error e = loadVrmRig(reinterpret_cast<const std::uint8_t*>(data), size, loaded.rig, &format)) {
      return fail(e);
    }
    loaded.format = format == VrmSpringFormat::kVrmcSpringBone1 ? "vrmc-springbone"
                    : format == VrmSpringFormat::kVrm0          ? "vrm0"
                                                                : "none";
    const int handle = newHandle();
    g_rigs.emplace(handle, std::move(loaded));
    return handle;
  });
}

/// The GLB hash of the representation `body_shape` wears in the entity (JSON text), or "" with
/// the error pending.
std::string mainFileHash(const std::string& entity_text, const std::string& body_shape) {
  std::string hash;
  const int ok = guarded([&] {
    json entity;
    try {
      entity = json::parse(entity_text);
    } catch (const json::exception& ex) {
      return fail("entity-bad-json", std::string("entity JSON does not parse: ") + ex.what());
    }
    if (Error e = mainFileHashFor(entity, body_shape, hash)) return fail(e);
    return 1;
  });
  return ok ? hash : std::string();
}

/// The content hash (CIDv1) of `size` bytes at `data`.
std::string hashBytes(std::uintptr_t data, std::size_t size) {
  std::string hash;
  guarded([&] {
    hash = contentHash(reinterpret_cast<const std::uint8_t*>(data), size);
    return 1;
  });
  return hash;
}

/// The rig description (see rigBlock) in a malloc'd block the caller copies out and frees; 0 with
/// the error pending.
std::uintptr_t rigInfo(int rig) {
  std::uintptr_t block = 0;
  guarded([&] {
    auto it = g_rigs.find(rig);
    if (it == g_rigs.end()) return badHandle("rig", rig);
    std::uint8_t* p = rigBlock(it->second);
    if (p == nullptr) throw std::bad_alloc();
    block = reinterpret_cast<std::uintptr_t>(p);
    return 1;
  });
  return block;
}

/// Replaces `count` floats at `data` (8-byte aligned, room for `count` doubles) by the doubles
/// JSON.parse reads from their shortest text (float_text.h), so 0.4f shows as 0.4 in JS and not as
/// 0.4000000059604645: the value the simulation uses, written the way the metadata wrote it. The
/// values must be finite. Backwards, so each float is read before its slot is overwritten.
void shortestFloatValues(std::uintptr_t data, int count) {
  auto* floats = reinterpret_cast<const float*>(data);
  auto* doubles = reinterpret_cast<double*>(data);
  for (int i = count - 1; i >= 0; --i) {
    const float f = floats[i];
    doubles[i] = shortestFloatValue(f);
  }
}

/// A new instance of the rig; options out of range are clamped by the core (the JS API rejects
/// them before). integrator: 0 VRM, 1 XPBD. Returns the instance handle or 0.
int createInstance(int rig, double step_hz, int max_substeps, int integrator, int xpbd_iterations) {
  return guarded([&] {
    auto it = g_rigs.find(rig);
    if (it == g_rigs.end()) return badHandle("rig", rig);
    InstanceOptions options;
    options.step_hz = step_hz;
    options.max_substeps = max_substeps;
    options.integrator = integrator == 1 ? Integrator::kXpbd : Integrator::kVrm;
    options.xpbd_iterations = xpbd_iterations;
    auto instance = std::make_unique<Instance>(it->second.rig, options);
    const int handle = newHandle();
    g_instances.emplace(handle, std::move(instance));
    return handle;
  });
}

// Pointers and counts of an instance's buffers. They stay put for the instance's lifetime (the
// core sizes them once), but the memory they are in may move: the JS side rebuilds its views.
std::uintptr_t driverMatricesPtr(int instance) {
  Instance* i = findInstance(instance);
  return i ? reinterpret_cast<std::uintptr_t>(i->driverMatrices()) : 0;
}
int driverCount(int instance) {
  Instance* i = findInstance(instance);
  return i ? static_cast<int>(i->driverCount()) : -1;
}
std::uintptr_t rotationsPtr(int instance) {
  Instance* i = findInstance(instance);
  return i ? reinterpret_cast<std::uintptr_t>(i->rotations()) : 0;
}
/// Also fills the buffer: the core computes the joint world matrices only when asked.
std::uintptr_t worldMatricesPtr(int instance) {
  Instance* i = findInstance(instance);
  return i ? reinterpret_cast<std::uintptr_t>(i->worldMatrices()) : 0;
}
int jointCount(int instance) {
  Instance* i = findInstance(instance);
  return i ? static_cast<int>(i->jointCount()) : -1;
}

/// The per-frame call; false for an unknown handle. No try block here on purpose: Instance::step
/// neither throws nor allocates, and with JS-based exceptions every call made inside a try block
/// goes through a JS trampoline (invoke_*), which would cost each frame ~30 ns for nothing.
bool step(int instance, double dt) {
  Instance* i = findInstance(instance);
  if (i == nullptr) return false;
  i->step(dt);
  return true;
}

bool reset(int instance) {
  Instance* i = findInstance(instance);
  if (i == nullptr) return false;
  i->reset();
  return true;
}

bool disposeRig(int rig) { return g_rigs.erase(rig) == 1; }
bool disposeInstance(int instance) {
  auto it = g_instances.find(instance);
  if (it == g_instances.end()) return false;
  for (auto& [handle, scene] : g_scenes) scene->remove(it->second.get());
  g_instances.erase(it);
  return true;
}

// ---------------------------------------------------------------------------------------------
// Scenes: many instances stepped in one call

Scene* findScene(int handle) {
  auto it = g_scenes.find(handle);
  return it == g_scenes.end() ? nullptr : it->second.get();
}

int createScene() {
  return guarded([&] {
    auto scene = std::make_unique<Scene>();
    const int handle = newHandle();
    g_scenes.emplace(handle, std::move(scene));
    return handle;
  });
}

/// Adds an instance; returns its slot + 1 (so that 0 stays "failed", error pending).
int sceneAdd(int scene, int instance) {
  return guarded([&] {
    Scene* s = findScene(scene);
    if (s == nullptr) return badHandle("scene", scene);
    Instance* i = findInstance(instance);
    if (i == nullptr) return badHandle("instance", instance);
    return static_cast<int>(s->add(i)) + 1;
  });
}

bool sceneRemove(int scene, int instance) {
  Scene* s = findScene(scene);
  Instance* i = findInstance(instance);
  if (s == nullptr || i == nullptr) return false;
  s->remove(i);
  return true;
}

int sceneSize(int scene) {
  Scene* s = findScene(scene);
  return s ? static_cast<int>(s->size()) : -1;
}

/// Moves when instances are added or removed (the vector reallocates); the JS side re-reads it then.
std::uintptr_t scenePositionsPtr(int scene) {
  Scene* s = findScene(scene);
  return s ? reinterpret_cast<std::uintptr_t>(s->positions()) : 0;
}

bool sceneSetBudget(int scene, int max_active, float x, float y, float z) {
  Scene* s = findScene(scene);
  if (s == nullptr) return false;
  s->setBudget(max_active, glm::vec3(x, y, z));
  return true;
}

/// The per-frame call for a whole page. No try block, for the reason given at step().
bool sceneStep(int scene, double dt) {
  Scene* s = findScene(scene);
  if (s == nullptr) return false;
  s->step(dt);
  return true;
}

/// Moves when instances are added or removed, as scenePositionsPtr.
std::uintptr_t sceneActivePtr(int scene) {
  Scene* s = findScene(scene);
  return s ? reinterpret_cast<std::uintptr_t>(s->activeFlags()) : 0;
}

bool sceneIsActive(int scene, int slot) {
  Scene* s = findScene(scene);
  return s != nullptr && slot >= 0 && s->isActive(static_cast<std::size_t>(slot));
}

bool disposeScene(int scene) { return g_scenes.erase(scene) == 1; }

// ---------------------------------------------------------------------------------------------
// Deploy-time validation and Builder edits

// JSON has no NaN or Infinity, but a JS object can hold them and the validator must reject them
// as Ajv does ("must be number") rather than see the null JSON.stringify writes. The JS side writes
// each non-finite number as a string "<marker>NaN" (or Infinity, -Infinity), with a marker drawn at
// random per call so no real string can be taken for one; this puts the doubles back. Iterative:
// the value may nest deeply.
void restoreNonFinite(json& value, const std::string& marker) {
  if (marker.empty()) return;
  std::vector<json*> stack{&value};
  while (!stack.empty()) {
    json* v = stack.back();
    stack.pop_back();
    if (v->is_structured()) {
      for (json& child : *v) stack.push_back(&child);
    } else if (v->is_string()) {
      const std::string& text = v->get_ref<const std::string&>();
      if (text.size() <= marker.size() || text.compare(0, marker.size(), marker) != 0) continue;
      const std::string_view rest = std::string_view(text).substr(marker.size());
      if (rest == "NaN") {
        *v = std::nan("");
      } else if (rest == "Infinity") {
        *v = INFINITY;
      } else if (rest == "-Infinity") {
        *v = -INFINITY;
      }
    }
  }
}

// Parses JSON text handed over by the JS side; on failure sets the pending error and returns false.
bool parseJson(const std::string& text, const char* what, json& out) {
  try {
    out = json::parse(text);
    return true;
  } catch (const json::exception& ex) {
    fail(std::string(what) + "-bad-json", std::string(what) + " JSON does not parse: " + ex.what());
    return false;
  }
}

/// The catalyst's errors for the entity as JSON [{path, message}], or "" with the error pending.
std::string validateEntity(const std::string& entity_text, const std::string& marker) {
  std::string text;
  guarded([&] {
    json entity;
    if (!parseJson(entity_text, "entity", entity)) return 0;
    restoreNonFinite(entity, marker);
    json errors = json::array();
    for (const ValidationError& e : validateSpringBones(entity)) {
      errors.push_back(json{{"path", e.path}, {"message", e.message}});
    }
    text = errors.dump(-1, ' ', false, json::error_handler_t::replace);
    return 1;
  });
  return text;
}

/// The spring-bone candidates of a GLB with their prefill values, as JSON {contentHash,
/// candidates: [...], warnings: [...]}, or "" with the error pending. Same inputs as loadRig.
std::string detectCandidates(std::uintptr_t data, std::size_t size, const std::string& metadata,
                             const std::string& hash) {
  std::string text;
  guarded([&] {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(data);
    Skeleton skeleton;
    if (Error e = loadSkeleton(bytes, size, skeleton)) return fail(e);
    const std::string key = hash.empty() ? contentHash(bytes, size) : hash;
    ModelEntry model;
    std::vector<Warning> warnings;
    if (Error e = parseSpringBonesText(metadata, key, model, warnings)) return fail(e);
    json candidates = json::array();
    for (const SpringBoneCandidate& c : detectSpringBones(skeleton, model)) {
      json entry{{"name", c.name},
                 {"node", c.node},
                 {"parent", c.parent_candidate},
                 {"hasEntry", c.has_entry},
                 {"isRoot", c.is_root},
                 {"params", paramsJson(c.params)}};
      // No center key: the runtime default; null: explicitly world space; else a node name.
      if (c.has_center) entry["center"] = c.center.empty() ? json(nullptr) : json(c.center);
      candidates.push_back(std::move(entry));
    }
    json warnings_json = json::array();
    for (const Warning& w : warnings) {
      warnings_json.push_back(json{{"code", w.code}, {"message", w.message}, {"path", w.path}});
    }
    text = json{{"contentHash", key}, {"candidates", std::move(candidates)}, {"warnings", std::move(warnings_json)}}
               .dump(-1, ' ', false, json::error_handler_t::replace);
    return 1;
  });
  return text;
}

/// springBones with node_name's entry under the body shape's GLB hash set to params (JSON text;
/// "null" removes it), as JSON text, or "" with the error pending.
std::string setParams(const std::string& springbones_text, const std::string& entity_text,
                      const std::string& body_shape, const std::string& node_name,
                      const std::string& params_text) {
  std::string text;
  guarded([&] {
    json springBones, entity, params, out;
    if (!parseJson(springbones_text, "metadata", springBones)) return 0;
    if (!parseJson(entity_text, "entity", entity)) return 0;
    if (!parseJson(params_text, "params", params)) return 0;
    if (Error e = setSpringBoneParams(springBones, entity, body_shape, node_name, params, out)) return fail(e);
    text = out.dump(-1, ' ', false, json::error_handler_t::replace);  // at most 64 levels deep
    return 1;
  });
  return text;
}

/// Diagnostics for leak tests: live handles and bytes malloc has handed out.
std::string stats() {
  const struct mallinfo info = mallinfo();
  char text[128];
  std::snprintf(text, sizeof text, R"({"rigs":%zu,"instances":%zu,"scenes":%zu,"heapInUse":%zu})",
                g_rigs.size(), g_instances.size(), g_scenes.size(), static_cast<std::size_t>(info.uordblks));
  return text;
}

}  // namespace
}  // namespace springbones

EMSCRIPTEN_BINDINGS(springbones) {
  using namespace springbones;
  emscripten::function("takeError", &takeError);
  emscripten::function("loadRig", &loadRig);
  emscripten::function("loadRigEntries", &loadRigEntries);
  emscripten::function("loadVrm", &loadVrm);
  emscripten::function("mainFileHash", &mainFileHash);
  emscripten::function("hashBytes", &hashBytes);
  emscripten::function("rigInfo", &rigInfo);
  emscripten::function("shortestFloatValues", &shortestFloatValues);
  emscripten::function("createInstance", &createInstance);
  emscripten::function("driverMatricesPtr", &driverMatricesPtr);
  emscripten::function("driverCount", &driverCount);
  emscripten::function("rotationsPtr", &rotationsPtr);
  emscripten::function("worldMatricesPtr", &worldMatricesPtr);
  emscripten::function("jointCount", &jointCount);
  emscripten::function("step", &step);
  emscripten::function("reset", &reset);
  emscripten::function("disposeRig", &disposeRig);
  emscripten::function("disposeInstance", &disposeInstance);
  emscripten::function("createScene", &createScene);
  emscripten::function("sceneAdd", &sceneAdd);
  emscripten::function("sceneRemove", &sceneRemove);
  emscripten::function("sceneSize", &sceneSize);
  emscripten::function("scenePositionsPtr", &scenePositionsPtr);
  emscripten::function("sceneSetBudget", &sceneSetBudget);
  emscripten::function("sceneStep", &sceneStep);
  emscripten::function("sceneIsActive", &sceneIsActive);
  emscripten::function("sceneActivePtr", &sceneActivePtr);
  emscripten::function("disposeScene", &disposeScene);
  emscripten::function("validateEntity", &validateEntity);
  emscripten::function("detectCandidates", &detectCandidates);
  emscripten::function("setParams", &setParams);
  emscripten::function("stats", &stats);
}
