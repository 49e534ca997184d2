// The runtime module's bindings: entry points over integers, pointers and strings, exported as C
// functions (the list at the end), and nothing else. The readers and the creator tools are
// modules with bindings of their own (wasm/readers_bindings.cpp, wasm/creator_tools_bindings.cpp).
//
// Contract with web/springbones.js (the only caller, through web/runtime_calls.js; nothing here is
// public API):
//  - Rigs, instances and scenes live in handle tables. A handle is a positive integer, never reused, so
//    a stale handle finds nothing instead of someone else's object. 0 means failure; the error is
//    then read once with takeError(), typed {code, message, path} (binding_errors.h).
//  - Bulk data crosses as pointers into WASM memory: typed input in (the glTF's nodes,
//    springBones, the entity, the rig options: springbones/typed_input.h), driver matrices in,
//    rotations out; what comes back structured is typed values written by the core
//    (springbones/boundary.h), left in the typed result (binding_errors.h) for
//    web/typed_output.js. The runtime reads no JSON text and writes none.
//  - An entry point has the name of the core function it calls (contentHash, describeRig...) and
//    of the JS method that calls it; an instance's operations are the Instance methods' names
//    (step, jump...), a scene's are prefixed with "scene" (sceneStep), their handle first.
//  - Nothing throws across the boundary: every entry point that can fail catches every C++
//    exception and turns it into an error, so bad input never aborts the module and the next call
//    works.
#include <cstdint>
#include <exception>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include <emscripten/emscripten.h>

#include "binding_errors.h"
#include "handle_table.h"
#include "heap_in_use.h"
#include "springbones/boundary.h"
#include "springbones/content_hash.h"
#include "springbones/springbones.h"
#include "springbones/typed_input.h"
#include "springbones/vrm.h"

namespace springbones::bindings {
namespace {

struct LoadedRig {
  std::shared_ptr<const Rig> rig;
  std::string hash;            ///< the models key the rig was built from ("" for a VRM)
  std::string format = "dcl";  ///< where the springs came from: dcl, vrmc-springbone, vrm0, none
};

// Instances hold their rig through a shared_ptr, so disposing of a rig handle while instances of
// it are alive only drops the handle; the memory goes with the last instance.
HandleTable<LoadedRig> g_rigs;
HandleTable<std::unique_ptr<Instance>> g_instances;
// Scenes hold raw Instance pointers (they own nothing): disposeInstance removes the instance from
// every scene first, so a scene never steps freed memory.
HandleTable<std::unique_ptr<Scene>> g_scenes;
int g_next_handle = 1;

int newHandle() {
  // 2^31 - 1 handles per module lifetime; past that, refuse rather than wrap onto live ones.
  if (g_next_handle == INT32_MAX) throw std::length_error("out of handles");
  return g_next_handle++;
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

TypedBytes typedAt(std::uintptr_t data, std::size_t size) {
  return TypedBytes{reinterpret_cast<const std::uint8_t*>(data), size};
}

/// Loads a rig from typed input (springbones/typed_input.h, written by web/typed_value.js): the
/// glTF document's {asset, nodes} at `gltf`, data.springBones at `metadata` (null for none), the
/// models key, and the rig options at `options` (no bytes for none). The steps run in the order of
/// their errors: options, skeleton, metadata. Returns the rig handle, or 0 with the error
/// pending. The caller keeps ownership of the bytes.
int loadRig(std::uintptr_t gltf, std::size_t gltf_size, std::uintptr_t metadata, std::size_t metadata_size,
            std::string_view hash, std::uintptr_t options_data, std::size_t options_size) {
  return guarded([&] {
    RigOptions options;
    if (ApiFailure f = readRigOptions(typedAt(options_data, options_size), options)) return fail(std::move(f));
    Skeleton skeleton;
    if (Error e = loadSkeleton(typedAt(gltf, gltf_size), skeleton)) return fail(e);
    LoadedRig loaded;
    loaded.hash = std::string(hash);
    ModelEntry model;
    std::vector<Warning> warnings;
    if (Error e = parseSpringBones(typedAt(metadata, metadata_size), loaded.hash, model, warnings)) return fail(e);
    loaded.rig = buildRig(std::move(skeleton), model, std::move(warnings), options);
    const int handle = newHandle();
    g_rigs.emplace(handle, std::move(loaded));
    return handle;
  });
}

/// Takes a VRM avatar's rig, built by the readers module from the document (its loadVrm, with
/// every error and warning of the VRM rules) and handed over as rig data (springbones/boundary.h,
/// readRigData): the runtime carries no VRM reader. Returns the rig handle, or 0 with the error
/// pending.
int loadVrm(std::uintptr_t rig_data, std::size_t size) {
  return guarded([&] {
    LoadedRig loaded;
    VrmSpringFormat format = VrmSpringFormat::kNone;
    if (Error e = readRigData(typedAt(rig_data, size), loaded.rig, format)) return fail(e);
    loaded.format = format == VrmSpringFormat::kVrmcSpringBone1 ? "vrmc-springbone"
                    : format == VrmSpringFormat::kVrm0          ? "vrm0"
                                                                : "none";
    const int handle = newHandle();
    g_rigs.emplace(handle, std::move(loaded));
    return handle;
  });
}

/// The GLB hash of the representation `body_shape` wears in the entity (typed input), or "" with
/// the error pending.
std::string mainFileHashFor(std::uintptr_t entity, std::size_t size, std::string_view body_shape) {
  std::string hash;
  const int ok = guarded([&] {
    if (Error e = springbones::mainFileHashFor(typedAt(entity, size), std::string(body_shape), hash)) return fail(e);
    return 1;
  });
  return ok ? hash : std::string();
}

/// The content hash (CIDv1) of `size` bytes at `data`.
std::string contentHash(std::uintptr_t data, std::size_t size) {
  std::string hash;
  guarded([&] {
    hash = springbones::contentHash(reinterpret_cast<const std::uint8_t*>(data), size);
    return 1;
  });
  return hash;
}

/// The rig description (springbones/boundary.h) as the typed result: its length, or 0 with the
/// error pending.
int describeRig(int rig) {
  return guarded([&] {
    auto it = g_rigs.find(rig);
    if (it == g_rigs.end()) return badHandle("rig", rig);
    return result(springbones::describeRig(*it->second.rig, it->second.hash, it->second.format));
  });
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

/// The per-frame call; false for an unknown handle. Instance::step neither throws nor allocates.
bool step(int instance, double dt) {
  Instance* i = findInstance(instance);
  if (i == nullptr) return false;
  i->step(dt);
  return true;
}

int lastSteps(int instance) {
  Instance* i = findInstance(instance);
  return i ? i->lastSteps() : -1;
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
  s->setBudget(max_active, Vec3{x, y, z});
  return true;
}

/// The per-frame call for a whole page (Scene::step neither throws nor allocates).
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
// Motion: jumps (Instance::jump), kept in one block

/// NaN leaves a threshold as it is.
bool setJumpThresholds(int instance, float distance, float angle) {
  Instance* i = findInstance(instance);
  if (i != nullptr) i->setJumpThresholds(distance, angle);
  return i != nullptr;
}
bool jump(int instance) {
  Instance* i = findInstance(instance);
  if (i != nullptr) i->jump();
  return i != nullptr;
}
int jumps(int instance) {
  Instance* i = findInstance(instance);
  return i ? i->jumps() : -1;
}

// ---------------------------------------------------------------------------------------------
// Edits: an instance of a rebuilt rig takes over the previous instance's motion (Instance::carryFrom)

/// False when either handle is not a live instance.
bool carryFrom(int instance, int previous) {
  Instance* i = findInstance(instance);
  const Instance* p = findInstance(previous);
  if (i != nullptr && p != nullptr) i->carryFrom(*p);
  return i != nullptr && p != nullptr;
}

// Settle, grab and inertia (Instance::settle, grab, release, setInertia), checked by the JS side;
// the core clamps or ignores anyway.

/// The steps settle ran, -1 for an unknown handle.
int settle(int instance, double seconds) {
  Instance* i = findInstance(instance);
  return i ? i->settle(seconds) : -1;
}
bool grab(int instance, int joint, float x, float y, float z) {
  Instance* i = findInstance(instance);
  if (i != nullptr && joint >= 0) i->grab(static_cast<std::size_t>(joint), Vec3{x, y, z});
  return i != nullptr;
}
bool release(int instance) {
  Instance* i = findInstance(instance);
  if (i != nullptr) i->release();
  return i != nullptr;
}
int grabbedJoint(int instance) {
  Instance* i = findInstance(instance);
  return i ? i->grabbedJoint() : -1;
}
/// chain < 0: every chain.
bool setInertia(int instance, float value, int chain) {
  Instance* i = findInstance(instance);
  if (i != nullptr) i->setInertia(value, chain);
  return i != nullptr;
}

// Colliders changed at run time (Instance::setColliders, frameMatrices).

/// The colliders at `data` (typed input, readColliderOptions) as the instance's from its next
/// step; leaves {frames, warnings} (describeColliderChange) as the typed result and returns its
/// length, or 0 with the error pending.
int setColliders(int instance, std::uintptr_t data, std::size_t size) {
  return guarded([&] {
    Instance* i = findInstance(instance);
    if (i == nullptr) return badHandle("instance", instance);
    ColliderOptions options;
    if (ApiFailure f = readColliderOptions(typedAt(data, size), options)) return fail(std::move(f));
    const std::vector<Warning> warnings = i->setColliders(options);
    return result(describeColliderChange(i->frameNames(), warnings));
  });
}
/// Moves with every setColliders.
std::uintptr_t frameMatricesPtr(int instance) {
  Instance* i = findInstance(instance);
  return i ? reinterpret_cast<std::uintptr_t>(i->frameMatrices()) : 0;
}

// ---------------------------------------------------------------------------------------------
// Wind (Instance::setWind, Scene::setWind), checked by the JS side; the core clamps anyway.

Wind windOf(float dx, float dy, float dz, float strength, float gust_frequency, double seed) {
  Wind wind;
  wind.direction = Vec3{dx, dy, dz};
  wind.strength = strength;
  wind.gust_frequency = gust_frequency;
  wind.seed = seed >= 0.0 && seed <= 4294967295.0 ? static_cast<std::uint32_t>(seed) : 0u;
  return wind;
}
bool setWind(int instance, float dx, float dy, float dz, float strength, float gust_frequency, double seed) {
  Instance* i = findInstance(instance);
  if (i != nullptr) i->setWind(windOf(dx, dy, dz, strength, gust_frequency, seed));
  return i != nullptr;
}
bool sceneSetWind(int scene, float dx, float dy, float dz, float strength, float gust_frequency, double seed) {
  Scene* s = findScene(scene);
  if (s != nullptr) s->setWind(windOf(dx, dy, dz, strength, gust_frequency, seed));
  return s != nullptr;
}

/// Diagnostics for leak tests: live handles and the bytes requested from malloc and not freed, as
/// the typed result.
int stats() {
  // The previous typed result freed first, so that the bytes in use do not count it.
  g_result = std::vector<std::uint8_t>();
  return result(describeStats(g_rigs.size(), g_instances.size(), g_scenes.size(), heapInUse()));
}

/// The core's limits and defaults (describeLimits) as the typed result.
int limits() { return result(describeLimits()); }

}  // namespace
}  // namespace springbones::bindings

// The entry points as the module exports them: C functions over numbers named sb_<name>, which
// web/runtime_calls.js lists with the kinds of their arguments and results and installs on the
// Module object as <name> (tests/wasm/runtime_calls.test.mjs holds the two lists together). A
// text argument crosses as UTF-8 bytes and their size; what comes back is left in the typed result
// (binding_errors.h), typed values or a text's UTF-8 bytes, and the entry point returns its length.
// No embind: its JavaScript runtime was two thirds of the glue (docs/performance.md, "Every byte").
#define SPRINGBONES_EXPORT extern "C" EMSCRIPTEN_KEEPALIVE

namespace springbones::bindings {
namespace {

std::string_view textAt(std::uintptr_t data, std::size_t size) {
  return std::string_view(reinterpret_cast<const char*>(data), size);
}

// A text as the result: its UTF-8 bytes (not typed values: the caller reads them as text), and
// their length; "" is 0, which its callers return for a failure with the error pending.
int textResult(const std::string& text) {
  return guarded([&] { return result(std::vector<std::uint8_t>(text.begin(), text.end())); });
}

}  // namespace
}  // namespace springbones::bindings

using namespace springbones::bindings;

SPRINGBONES_EXPORT std::uintptr_t sb_typedResult() { return typedResult(); }
SPRINGBONES_EXPORT int sb_takeError() { return takeError(); }
SPRINGBONES_EXPORT int sb_limits() { return limits(); }
SPRINGBONES_EXPORT int sb_loadRig(std::uintptr_t gltf, std::size_t gltf_size, std::uintptr_t metadata,
                                  std::size_t metadata_size, std::uintptr_t hash, std::size_t hash_size,
                                  std::uintptr_t options_data, std::size_t options_size) {
  return loadRig(gltf, gltf_size, metadata, metadata_size, textAt(hash, hash_size), options_data, options_size);
}
SPRINGBONES_EXPORT int sb_loadVrm(std::uintptr_t rig_data, std::size_t size) { return loadVrm(rig_data, size); }
SPRINGBONES_EXPORT int sb_mainFileHashFor(std::uintptr_t entity, std::size_t size, std::uintptr_t body_shape,
                                          std::size_t body_shape_size) {
  return textResult(mainFileHashFor(entity, size, textAt(body_shape, body_shape_size)));
}
SPRINGBONES_EXPORT int sb_contentHash(std::uintptr_t data, std::size_t size) {
  return textResult(contentHash(data, size));
}
SPRINGBONES_EXPORT int sb_describeRig(int rig) { return describeRig(rig); }
SPRINGBONES_EXPORT int sb_createInstance(int rig, double step_hz, int max_substeps, int integrator,
                                         int xpbd_iterations) {
  return createInstance(rig, step_hz, max_substeps, integrator, xpbd_iterations);
}
SPRINGBONES_EXPORT std::uintptr_t sb_driverMatricesPtr(int instance) { return driverMatricesPtr(instance); }
SPRINGBONES_EXPORT int sb_driverCount(int instance) { return driverCount(instance); }
SPRINGBONES_EXPORT std::uintptr_t sb_rotationsPtr(int instance) { return rotationsPtr(instance); }
SPRINGBONES_EXPORT std::uintptr_t sb_worldMatricesPtr(int instance) { return worldMatricesPtr(instance); }
SPRINGBONES_EXPORT int sb_jointCount(int instance) { return jointCount(instance); }
SPRINGBONES_EXPORT int sb_step(int instance, double dt) { return step(instance, dt) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_reset(int instance) { return reset(instance) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_lastSteps(int instance) { return lastSteps(instance); }
SPRINGBONES_EXPORT int sb_disposeRig(int rig) { return disposeRig(rig) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_disposeInstance(int instance) { return disposeInstance(instance) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_createScene() { return createScene(); }
SPRINGBONES_EXPORT int sb_sceneAdd(int scene, int instance) { return sceneAdd(scene, instance); }
SPRINGBONES_EXPORT int sb_sceneRemove(int scene, int instance) { return sceneRemove(scene, instance) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_sceneSize(int scene) { return sceneSize(scene); }
SPRINGBONES_EXPORT std::uintptr_t sb_scenePositionsPtr(int scene) { return scenePositionsPtr(scene); }
SPRINGBONES_EXPORT int sb_sceneSetBudget(int scene, int max_active, float x, float y, float z) {
  return sceneSetBudget(scene, max_active, x, y, z) ? 1 : 0;
}
SPRINGBONES_EXPORT int sb_sceneStep(int scene, double dt) { return sceneStep(scene, dt) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_sceneIsActive(int scene, int slot) { return sceneIsActive(scene, slot) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_setWind(int instance, float dx, float dy, float dz, float strength, float gust_frequency,
                                  double seed) {
  return setWind(instance, dx, dy, dz, strength, gust_frequency, seed) ? 1 : 0;
}
SPRINGBONES_EXPORT int sb_sceneSetWind(int scene, float dx, float dy, float dz, float strength, float gust_frequency,
                                       double seed) {
  return sceneSetWind(scene, dx, dy, dz, strength, gust_frequency, seed) ? 1 : 0;
}
SPRINGBONES_EXPORT std::uintptr_t sb_sceneActivePtr(int scene) { return sceneActivePtr(scene); }
SPRINGBONES_EXPORT int sb_disposeScene(int scene) { return disposeScene(scene) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_stats() { return stats(); }
SPRINGBONES_EXPORT int sb_setJumpThresholds(int instance, float distance, float angle) {
  return setJumpThresholds(instance, distance, angle) ? 1 : 0;
}
SPRINGBONES_EXPORT int sb_jump(int instance) { return jump(instance) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_jumps(int instance) { return jumps(instance); }
SPRINGBONES_EXPORT int sb_carryFrom(int instance, int previous) { return carryFrom(instance, previous) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_settle(int instance, double seconds) { return settle(instance, seconds); }
SPRINGBONES_EXPORT int sb_grab(int instance, int joint, float x, float y, float z) {
  return grab(instance, joint, x, y, z) ? 1 : 0;
}
SPRINGBONES_EXPORT int sb_release(int instance) { return release(instance) ? 1 : 0; }
SPRINGBONES_EXPORT int sb_grabbedJoint(int instance) { return grabbedJoint(instance); }
SPRINGBONES_EXPORT int sb_setInertia(int instance, float value, int chain) {
  return setInertia(instance, value, chain) ? 1 : 0;
}
SPRINGBONES_EXPORT int sb_setColliders(int instance, std::uintptr_t data, std::size_t size) {
  return setColliders(instance, data, size);
}
SPRINGBONES_EXPORT std::uintptr_t sb_frameMatricesPtr(int instance) { return frameMatricesPtr(instance); }
