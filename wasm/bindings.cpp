// embind bindings of the runtime module: declarations over integers, pointers and strings, and
// nothing else. The creator tools (validation, Builder edits) are a second module with its own
// bindings, wasm/creator_tools_bindings.cpp.
//
// Contract with web/springbones.js (the only caller; nothing here is public API):
//  - Rigs, instances and scenes live in handle tables. A handle is a positive integer, never reused, so
//    a stale handle finds nothing instead of someone else's object. 0 means failure; the error is
//    then read once with takeError() as JSON {code, message, path} (binding_errors.h).
//  - Bulk data crosses as pointers into WASM memory: typed input in (the glTF's nodes,
//    springBones, the entity, the rig options: springbones/typed_input.h), driver matrices in,
//    rotations out; what comes back structured is one JSON string written by the core
//    (springbones/boundary.h). The runtime reads no JSON text.
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
#include <unordered_map>
#include <utility>

#include <emscripten/bind.h>

#include "binding_errors.h"
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
std::unordered_map<int, LoadedRig> g_rigs;
std::unordered_map<int, std::unique_ptr<Instance>> g_instances;
// Scenes hold raw Instance pointers (they own nothing): disposeInstance removes the instance from
// every scene first, so a scene never steps freed memory.
std::unordered_map<int, std::unique_ptr<Scene>> g_scenes;
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
            const std::string& hash, std::uintptr_t options_data, std::size_t options_size) {
  return guarded([&] {
    RigOptions options;
    if (ApiFailure f = readRigOptions(typedAt(options_data, options_size), options)) return fail(std::move(f));
    Skeleton skeleton;
    if (Error e = loadSkeleton(typedAt(gltf, gltf_size), skeleton)) return fail(e);
    LoadedRig loaded;
    loaded.hash = hash;
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
std::string mainFileHashFor(std::uintptr_t entity, std::size_t size, const std::string& body_shape) {
  std::string hash;
  const int ok = guarded([&] {
    if (Error e = springbones::mainFileHashFor(typedAt(entity, size), body_shape, hash)) return fail(e);
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

/// The rig description as JSON text (springbones/boundary.h), or "" with the error pending.
std::string describeRig(int rig) {
  std::string text;
  guarded([&] {
    auto it = g_rigs.find(rig);
    if (it == g_rigs.end()) return badHandle("rig", rig);
    text = springbones::describeRig(*it->second.rig, it->second.hash, it->second.format);
    return 1;
  });
  return text;
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
/// step; returns {frames, warnings} as JSON (describeColliderChange), or "" with the error pending.
std::string setColliders(int instance, std::uintptr_t data, std::size_t size) {
  std::string described;
  guarded([&] {
    Instance* i = findInstance(instance);
    if (i == nullptr) return badHandle("instance", instance);
    ColliderOptions options;
    if (ApiFailure f = readColliderOptions(typedAt(data, size), options)) return fail(std::move(f));
    const std::vector<Warning> warnings = i->setColliders(options);
    described = describeColliderChange(i->frameNames(), warnings);
    return 1;
  });
  return described;
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

/// Diagnostics for leak tests: live handles and the bytes requested from malloc and not freed.
std::string stats() { return statsJson(g_rigs.size(), g_instances.size(), g_scenes.size(), heapInUse()); }

}  // namespace
}  // namespace springbones::bindings

EMSCRIPTEN_BINDINGS(springbones) {
  using namespace springbones::bindings;
  emscripten::function("takeError", &takeError);
  emscripten::function("limitsJson", &springbones::limitsJson);
  emscripten::function("loadRig", &loadRig);
  emscripten::function("loadVrm", &loadVrm);
  emscripten::function("mainFileHashFor", &mainFileHashFor);
  emscripten::function("contentHash", &contentHash);
  emscripten::function("describeRig", &describeRig);
  emscripten::function("createInstance", &createInstance);
  emscripten::function("driverMatricesPtr", &driverMatricesPtr);
  emscripten::function("driverCount", &driverCount);
  emscripten::function("rotationsPtr", &rotationsPtr);
  emscripten::function("worldMatricesPtr", &worldMatricesPtr);
  emscripten::function("jointCount", &jointCount);
  emscripten::function("step", &step);
  emscripten::function("reset", &reset);
  emscripten::function("lastSteps", &lastSteps);
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
  emscripten::function("setWind", &setWind);
  emscripten::function("sceneSetWind", &sceneSetWind);
  emscripten::function("sceneActivePtr", &sceneActivePtr);
  emscripten::function("disposeScene", &disposeScene);
  emscripten::function("stats", &stats);
  // Motion
  emscripten::function("setJumpThresholds", &setJumpThresholds);
  emscripten::function("jump", &jump);
  emscripten::function("jumps", &jumps);
  emscripten::function("carryFrom", &carryFrom);
  emscripten::function("settle", &settle);
  emscripten::function("grab", &grab);
  emscripten::function("release", &release);
  emscripten::function("grabbedJoint", &grabbedJoint);
  emscripten::function("setInertia", &setInertia);
  emscripten::function("setColliders", &setColliders);
  emscripten::function("frameMatricesPtr", &frameMatricesPtr);
}
