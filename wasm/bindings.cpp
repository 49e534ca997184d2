// embind bindings of the core: a handful of functions over integers, pointers and strings.
//
// Contract with web/springbones.js (the only caller; nothing here is public API):
//  - Rigs and instances live in handle tables. A handle is a positive integer, never reused, so
//    a stale handle finds nothing instead of someone else's object. 0 means failure; the error is
//    then read once with takeError() as JSON {code, message, path}.
//  - Bulk data crosses as pointers into WASM memory (GLB bytes in, driver matrices in, rotations
//    out); structured data that is read once (rig description, errors) crosses as one JSON string.
//  - Nothing throws across the boundary: every entry point catches every C++ exception and turns
//    it into an error, so bad input never aborts the module and the next call works.
// The logic lives in src/; this file only moves data and catches.
#include <malloc.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

#include <emscripten/bind.h>
#include <nlohmann/json.hpp>

#include "content_hash.h"
#include "entity.h"
#include "springbones.h"

namespace springbones {
namespace {

using nlohmann::json;

struct LoadedRig {
  std::shared_ptr<const Rig> rig;
  std::string hash;  ///< the models key the rig was built from
};

// Instances hold their rig through a shared_ptr, so disposing of a rig handle while instances of
// it are alive only drops the handle; the memory goes with the last instance.
std::unordered_map<int, LoadedRig> g_rigs;
std::unordered_map<int, std::unique_ptr<Instance>> g_instances;
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
// 0.4000000059604645: the value the simulation uses, written the way the metadata wrote it.
// (The loop always ends by 9 digits, which round-trip every float.)
double shortestDouble(float value) {
  char text[32];
  for (int precision = 6; precision <= 9; ++precision) {
    std::snprintf(text, sizeof text, "%.*g", precision, static_cast<double>(value));
    if (std::strtof(text, nullptr) == value) break;
  }
  return std::strtod(text, nullptr);
}

json paramsJson(const BoneParams& p) {
  return json{{"stiffness", shortestDouble(p.stiffness)},
              {"gravityPower", shortestDouble(p.gravity_power)},
              {"gravityDir",
               {shortestDouble(p.gravity_dir.x), shortestDouble(p.gravity_dir.y),
                shortestDouble(p.gravity_dir.z)}},
              {"drag", shortestDouble(p.drag)}};
}

std::string rigJson(const LoadedRig& loaded) {
  const Rig& rig = *loaded.rig;
  const auto& nodes = rig.skeleton.nodes;
  json joints = json::array();
  for (const Joint& j : rig.joints) {
    joints.push_back(json{{"name", nodes[j.node].name},
                          {"node", j.node},
                          {"tail", nodes[j.tail_node].name},
                          {"tailNode", j.tail_node},
                          {"parent", j.parent_joint},
                          {"parentDriver", j.parent_driver},
                          {"centerDriver", j.center_driver},
                          {"chain", j.chain},
                          {"restLength", shortestDouble(j.rest_length)},
                          {"params", paramsJson(j.params)}});
  }
  json drivers = json::array();
  for (const Driver& d : rig.drivers) drivers.push_back(json{{"name", d.name}, {"node", d.node}});
  json warnings = json::array();
  for (const Warning& w : rig.warnings) {
    warnings.push_back(json{{"code", w.code}, {"message", w.message}, {"path", w.path}});
  }
  json out{{"contentHash", loaded.hash},
           {"nodeCount", nodes.size()},
           {"joints", std::move(joints)},
           {"chains", rig.chain_roots},
           {"drivers", std::move(drivers)},
           {"warnings", std::move(warnings)}};
  // replace: a message may quote a truncated node name cut inside a UTF-8 sequence.
  return out.dump(-1, ' ', false, json::error_handler_t::replace);
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

/// Loads a rig from `size` GLB/glTF bytes at `data`, the springBones JSON text (the text "null"
/// for none) and the models key; an empty hash means the GLB's own content hash. Returns the rig
/// handle, or 0 with the error pending. The caller keeps ownership of `data`.
int loadRig(std::uintptr_t data, std::size_t size, const std::string& metadata,
            const std::string& hash) {
  return guarded([&] {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(data);
    Skeleton skeleton;
    if (Error e = loadSkeleton(bytes, size, skeleton)) return fail(e);
    LoadedRig loaded;
    loaded.hash = hash.empty() ? contentHash(bytes, size) : hash;
    ModelEntry model;
    std::vector<Warning> warnings;
    if (Error e = parseSpringBonesText(metadata, loaded.hash, model, warnings)) {
      return fail(e);
    }
    loaded.rig = buildRig(std::move(skeleton), model, std::move(warnings));
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

/// The rig as JSON (contentHash, nodeCount, joints, chains, drivers, warnings), or "".
std::string rigInfo(int rig) {
  std::string text;
  guarded([&] {
    auto it = g_rigs.find(rig);
    if (it == g_rigs.end()) return badHandle("rig", rig);
    text = rigJson(it->second);
    return 1;
  });
  return text;
}

/// A new instance of the rig; options out of range are clamped by the core (the JS API rejects
/// them before). Returns the instance handle or 0.
int createInstance(int rig, double step_hz, int max_substeps) {
  return guarded([&] {
    auto it = g_rigs.find(rig);
    if (it == g_rigs.end()) return badHandle("rig", rig);
    InstanceOptions options;
    options.step_hz = step_hz;
    options.max_substeps = max_substeps;
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
bool disposeInstance(int instance) { return g_instances.erase(instance) == 1; }

/// Diagnostics for leak tests: live handles and bytes malloc has handed out.
std::string stats() {
  const struct mallinfo info = mallinfo();
  char text[96];
  std::snprintf(text, sizeof text, R"({"rigs":%zu,"instances":%zu,"heapInUse":%zu})", g_rigs.size(),
                g_instances.size(), static_cast<std::size_t>(info.uordblks));
  return text;
}

}  // namespace
}  // namespace springbones

EMSCRIPTEN_BINDINGS(springbones) {
  using namespace springbones;
  emscripten::function("takeError", &takeError);
  emscripten::function("loadRig", &loadRig);
  emscripten::function("mainFileHash", &mainFileHash);
  emscripten::function("hashBytes", &hashBytes);
  emscripten::function("rigInfo", &rigInfo);
  emscripten::function("createInstance", &createInstance);
  emscripten::function("driverMatricesPtr", &driverMatricesPtr);
  emscripten::function("driverCount", &driverCount);
  emscripten::function("rotationsPtr", &rotationsPtr);
  emscripten::function("jointCount", &jointCount);
  emscripten::function("step", &step);
  emscripten::function("reset", &reset);
  emscripten::function("disposeRig", &disposeRig);
  emscripten::function("disposeInstance", &disposeInstance);
  emscripten::function("stats", &stats);
}
