// The values of the runtime's boundary (springbones/boundary.h): the rig options read from typed
// input; failures, limits and stats written with TypedWriter.
#include "springbones/boundary.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <utility>

#include "boundary/page_text.h"
#include "common/json_pointer.h"
#include "common/typed_value.h"
#include "loading/vrm_limits.h"

namespace springbones {
namespace {

// Where a value sits in the options, spelled both ways: as the JavaScript would write it
// (`colliders[0].radius`, for the message) and as a JSON pointer (`/colliders/0/radius`, the
// failure's path, which tests compare with the JavaScript's message).
// `owner` says whose options they are, first in the message ("rig options", "setColliders").
struct OptionPath {
  std::string dotted;
  std::string pointer;
  const char* owner = "rig options";

  OptionPath key(const std::string& name) const {
    return {dotted.empty() ? name : dotted + "." + name, pointer + pointerToken(name), owner};
  }
  OptionPath index(std::size_t i) const {
    return {dotted + "[" + std::to_string(i) + "]", pointer + "/" + std::to_string(i), owner};
  }
};

ApiFailure badOption(const OptionPath& at, const std::string& why) {
  return ApiFailure{"invalid-argument", std::string(at.owner) + ": " + (at.dotted.empty() ? "" : at.dotted + " ") + why,
                    at.pointer};
}

ApiFailure checkKeys(const TypedValue& object, const OptionPath& at, std::initializer_list<const char*> known) {
  for (auto it = object.begin(); it != object.end(); ++it) {
    if (std::find_if(known.begin(), known.end(), [&](const char* k) { return it.key() == k; }) == known.end()) {
      return badOption(at.key(it.key()), "is not an option here");
    }
  }
  return {};
}

// A finite number (in double, as the page wrote it): what arrives out of float's range becomes
// infinite there, and the rig builder ignores that collider with a warning.
ApiFailure readFinite(const TypedValue& value, const OptionPath& at, double& out) {
  if (!value.is_number()) return badOption(at, "must be a number");
  out = value.get<double>();
  if (!std::isfinite(out)) return badOption(at, "must be finite");
  return {};
}

ApiFailure readVec3(const TypedValue& value, const OptionPath& at, double out[3]) {
  if (!value.is_array() || value.size() != 3) return badOption(at, "must be an array of 3 numbers");
  for (std::size_t i = 0; i < 3; ++i) {
    if (!value[i].is_number()) return badOption(at, "must be an array of 3 numbers");
    if (ApiFailure f = readFinite(value[i], at, out[i])) return f;
  }
  return {};
}

Vec3 toVec3(const double v[3]) {
  return Vec3{static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// A plane's normal as float, unit or not: one whose largest component is beyond float's normal
// range is divided by that component's size first, in double, as the JavaScript does before it
// sends it (web/rig_options.js), so that [1e39, 0, 0] stays a direction.
Vec3 scaledDirection(const double v[3]) {
  const double largest = std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
  if (largest >= 0x1p-126 && largest < 0x1p127) return toVec3(v);
  const double scaled[3] = {v[0] / largest, v[1] / largest, v[2] / largest};
  return toVec3(scaled);
}

// One collider, by the rules of loadRig's option (web/rig_options.js, colliderJson): a sphere, a
// capsule (a tail) or a plane (a normal), as `shape` says or, without it, as a tail makes it a
// capsule; each key only on the shapes that have it; offset, tail and normal default to
// [0, 0, 0], [0, 0, 0] and [0, 0, 1].
ApiFailure readCollider(const TypedValue& c, const OptionPath& at, ColliderSpec& spec) {
  if (!c.is_object()) return badOption(at, "must be an object");
  if (ApiFailure f = checkKeys(c, at, {"node", "shape", "offset", "radius", "tail", "normal", "inside"})) return f;
  // A key is there or not: null is a value, refused where a number or an array is wanted.
  const auto has = [&](const char* key) { return c.find(key) != c.end(); };
  const auto member = [&](const char* key) { return has(key) ? *c.find(key) : TypedValue(); };
  const TypedValue node = member("node");
  if (!node.is_string()) return badOption(at.key("node"), "must be a string (a node name)");
  spec.node = node.get<std::string>();
  if (spec.node.empty()) return badOption(at.key("node"), "must not be empty");
  std::string shape = has("tail") ? "capsule" : "sphere";
  if (has("shape")) {
    const TypedValue given = member("shape");
    if (!given.is_string()) return badOption(at.key("shape"), "must be a string");
    shape = given.get<std::string>();
    if (shape != "sphere" && shape != "capsule" && shape != "plane") {
      return badOption(at.key("shape"), "must be one of sphere, capsule, plane");
    }
  }
  const bool plane = shape == "plane";
  const auto only = [&](const char* key, bool allowed) {
    return !has(key) || allowed ? ApiFailure{}
                                : badOption(at.key(key), "is not a property of a " + shape + " collider");
  };
  if (ApiFailure f = only("tail", shape == "capsule")) return f;
  if (ApiFailure f = only("normal", plane)) return f;
  if (ApiFailure f = only("radius", !plane)) return f;
  if (ApiFailure f = only("inside", !plane)) return f;
  double v[3] = {0.0, 0.0, 0.0};
  if (has("offset")) {
    if (ApiFailure f = readVec3(member("offset"), at.key("offset"), v)) return f;
  }
  spec.offset = toVec3(v);
  if (plane) {
    spec.shape = Collider::Shape::kPlane;
    double n[3] = {0.0, 0.0, 1.0};
    if (has("normal")) {
      if (ApiFailure f = readVec3(member("normal"), at.key("normal"), n)) return f;
    }
    if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) return badOption(at.key("normal"), "must not be [0, 0, 0]");
    spec.normal = scaledDirection(n);
    return {};
  }
  double radius = 0.0;
  if (ApiFailure f = readFinite(member("radius"), at.key("radius"), radius)) return f;
  if (radius < 0.0) return badOption(at.key("radius"), "must be >= 0");
  spec.radius = static_cast<float>(radius);
  if (shape == "capsule") {
    spec.shape = Collider::Shape::kCapsule;
    double t[3] = {0.0, 0.0, 0.0};
    if (has("tail")) {
      if (ApiFailure f = readVec3(member("tail"), at.key("tail"), t)) return f;
    }
    spec.tail = toVec3(t);
  }
  if (has("inside")) {
    const TypedValue inside = member("inside");
    if (!inside.is_boolean()) return badOption(at.key("inside"), "must be a boolean");
    spec.inside = inside.get<bool>();
  }
  return {};
}

// The limits option by the rules of web/rig_options.js (checkedLimits): joint names to one limit
// each, {cone|hinge: {angle, rotation?}} or {spherical: {pitch, yaw, rotation?}}, every angle a
// finite number, a rotation 4 finite numbers not all 0. What passes is then read as the VRM
// extension's limits are (readLimitOptions), which clamps angles out of the draft's ranges with a
// warning.
ApiFailure checkLimits(const TypedValue& limits, const OptionPath& at) {
  if (!limits.is_object()) return badOption(at, "must be an object of joint names");
  for (auto it = limits.begin(); it != limits.end(); ++it) {
    const OptionPath joint = at.key(it.key());
    const TypedValue limit = *it;
    if (!limit.is_object()) return badOption(joint, "must be an object");
    const bool one_kind =
        limit.size() == 1 && (limit.find("cone") != limit.end() || limit.find("hinge") != limit.end() ||
                              limit.find("spherical") != limit.end());
    if (!one_kind) return badOption(joint, "must have exactly one of cone, hinge, spherical");
    const std::string kind = limit.begin().key();
    const OptionPath shape_at = joint.key(kind);
    const TypedValue shape = *limit.begin();  // a copy: the iterator is a temporary
    if (!shape.is_object()) return badOption(shape_at, "must be an object");
    const bool spherical = kind == "spherical";
    ApiFailure keys = spherical ? checkKeys(shape, shape_at, {"pitch", "yaw", "rotation"})
                                : checkKeys(shape, shape_at, {"angle", "rotation"});
    if (keys) return keys;
    for (const char* angle :
         spherical ? std::initializer_list<const char*>{"pitch", "yaw"} : std::initializer_list<const char*>{"angle"}) {
      double value = 0.0;
      const auto found = shape.find(angle);
      if (ApiFailure f = readFinite(found == shape.end() ? TypedValue() : *found, shape_at.key(angle), value)) return f;
    }
    if (auto rotation = shape.find("rotation"); rotation != shape.end()) {
      const OptionPath r = shape_at.key("rotation");
      if (!rotation->is_array() || rotation->size() != 4) return badOption(r, "must be 4 numbers (x, y, z, w)");
      bool all_zero = true;
      for (std::size_t i = 0; i < 4; ++i) {
        double value = 0.0;
        if (ApiFailure f = readFinite((*rotation)[i], r.index(i), value)) return f;
        all_zero = all_zero && value == 0.0;
      }
      if (all_zero) return badOption(r, "must not be [0, 0, 0, 0]");
    }
  }
  return {};
}

// avatarBones: an object from the avatar's bone names to their rest world matrices (16 numbers,
// column-major), each entry within the drivers' bound kMaxDriverEntry (the pose it describes is
// one a driver could take).
ApiFailure readAvatarBones(const TypedValue& bones, const OptionPath& at, std::vector<AvatarBone>& out) {
  if (!bones.is_object()) return badOption(at, "must be an object of bone names");
  out.reserve(bones.size());
  for (auto it = bones.begin(); it != bones.end(); ++it) {
    const OptionPath bone_at = at.key(it.key());
    const TypedValue& m = *it;
    if (!m.is_array() || m.size() != 16) return badOption(bone_at, "must be 16 numbers");
    AvatarBone bone;
    bone.name = it.key();
    for (std::size_t i = 0; i < 16; ++i) {
      double v = 0.0;
      if (ApiFailure f = readFinite(m[i], bone_at.index(i), v)) return f;
      if (!(std::fabs(v) <= kMaxDriverEntry)) return badOption(bone_at.index(i), "must be within +-1e12");
      bone.rest_world.m[i] = static_cast<float>(v);
    }
    out.push_back(std::move(bone));
  }
  return {};
}

// A list of colliders (readCollider each).
ApiFailure readColliders(const TypedValue& colliders, const OptionPath& at, std::vector<ColliderSpec>& out) {
  if (!colliders.is_array()) return badOption(at, "must be an array");
  out.reserve(colliders.size());
  for (std::size_t i = 0; i < colliders.size(); ++i) {
    ColliderSpec spec;
    if (ApiFailure f = readCollider(colliders[i], at.index(i), spec)) return f;
    out.push_back(std::move(spec));
  }
  return {};
}

// The rig options as they cross from loadRig (web/rig_options.js writes them): {colliders?,
// preset?, avatarBones?, hitRadius?, limits?}, with the rules the JavaScript checks them by, so
// that a value the JavaScript refuses is refused here too, at the same path
// (tests/wasm/rig_options.test.mjs).
ApiFailure readOptions(const TypedValue& value, RigOptions& out) {
  const OptionPath root;
  if (value.is_null()) return {};
  if (!value.is_object()) return badOption(root, "must be an object");
  if (ApiFailure f = checkKeys(value, root, {"colliders", "preset", "avatarBones", "hitRadius", "limits"})) return f;
  if (auto hit = value.find("hitRadius"); hit != value.end()) {
    double radius = 0.0;
    if (ApiFailure f = readFinite(*hit, root.key("hitRadius"), radius)) return f;
    if (radius < 0.0) return badOption(root.key("hitRadius"), "must be >= 0");
    out.hit_radius = static_cast<float>(radius);
  }
  if (auto preset = value.find("preset"); preset != value.end()) {
    if (!preset->is_string() || *preset != "dcl-body") return badOption(root.key("preset"), "must be 'dcl-body'");
    out.preset = ColliderPreset::kDclBody;
  }
  if (auto bones = value.find("avatarBones"); bones != value.end()) {
    if (ApiFailure f = readAvatarBones(*bones, root.key("avatarBones"), out.avatar_bones)) return f;
  }
  if (auto limits = value.find("limits"); limits != value.end()) {
    if (ApiFailure f = checkLimits(*limits, root.key("limits"))) return f;
    std::string why;
    if (!readLimitOptions(*limits, out.limits, why))
      return ApiFailure{"invalid-argument", "rig options: " + why, "/limits"};
  }
  if (auto colliders = value.find("colliders"); colliders != value.end()) {
    if (ApiFailure f = readColliders(*colliders, root.key("colliders"), out.colliders)) return f;
  }
  return {};
}

// setColliders' colliders as they cross from web/rig_options.js (colliderChange): {colliders?,
// preset?: "dcl-body", avatarBones?, scale?, omit?}, scale and omit only with the preset; by
// the rules loadRig's options are read by, and the same failures (tests/wasm/set_colliders.test.mjs).
ApiFailure readColliderChange(const TypedValue& value, ColliderOptions& out) {
  OptionPath root;
  root.owner = "setColliders";
  if (value.is_null()) return {};
  if (!value.is_object()) return badOption(root, "must be an object");
  if (ApiFailure f = checkKeys(value, root, {"colliders", "preset", "avatarBones", "scale", "omit"})) return f;
  if (auto preset = value.find("preset"); preset != value.end()) {
    if (!preset->is_string() || *preset != "dcl-body") return badOption(root.key("preset"), "must be 'dcl-body'");
    out.preset = ColliderPreset::kDclBody;
  }
  const bool body = out.preset == ColliderPreset::kDclBody;
  if (auto bones = value.find("avatarBones"); bones != value.end()) {
    if (ApiFailure f = readAvatarBones(*bones, root.key("avatarBones"), out.avatar_bones)) return f;
  }
  if (auto scale = value.find("scale"); scale != value.end()) {
    if (!body) return badOption(root.key("scale"), "only applies to 'dcl-body'");
    double v = 0.0;
    if (ApiFailure f = readFinite(*scale, root.key("scale"), v)) return f;
    if (v < 0.0) return badOption(root.key("scale"), "must be >= 0");
    out.body.scale = static_cast<float>(v);
  }
  if (auto omit = value.find("omit"); omit != value.end()) {
    const OptionPath at = root.key("omit");
    if (!body) return badOption(at, "only applies to 'dcl-body'");
    if (!omit->is_array()) return badOption(at, "must be an array of shape names");
    const std::vector<std::string>& names = dclBodyShapeNames();
    for (std::size_t i = 0; i < omit->size(); ++i) {
      const TypedValue name = (*omit)[i];
      const bool known =
          name.is_string() && std::find(names.begin(), names.end(), name.get<std::string>()) != names.end();
      if (!known) {
        std::string listed;
        for (const std::string& n : names) listed += (listed.empty() ? "" : ", ") + n;
        return badOption(at.index(i), "must be one of " + listed);
      }
      out.body.omit.push_back(name.get<std::string>());
    }
  }
  if (auto colliders = value.find("colliders"); colliders != value.end()) {
    if (ApiFailure f = readColliders(*colliders, root.key("colliders"), out.colliders)) return f;
  }
  return {};
}

}  // namespace

ApiFailure toFailure(const Error& error) {
  if (!error) return {};
  return ApiFailure{errorCodeName(error.code), error.message, error.path};
}

std::vector<std::uint8_t> describeFailure(const ApiFailure& failure) {
  TypedWriter out;
  pageCodeMessagePath(out, failure.code, failure.message, failure.path);
  return std::move(out.bytes());
}

namespace {

// Typed options read into `out` by `read`: the defaults for no bytes, and again after a refusal.
template <typename Options>
ApiFailure readTypedOptions(TypedBytes options, Options& out, ApiFailure (*read)(const TypedValue&, Options&)) {
  out = Options{};
  if (options.size == 0) return {};
  TypedDocument doc;
  if (Error e = doc.decode(options.data, options.size, kMaxMetadataBytes)) return toFailure(e);
  ApiFailure failure = read(doc.root(), out);
  if (failure) out = Options{};
  return failure;
}

}  // namespace

ApiFailure readRigOptions(TypedBytes options, RigOptions& out) { return readTypedOptions(options, out, readOptions); }

ApiFailure readColliderOptions(TypedBytes options, ColliderOptions& out) {
  return readTypedOptions(options, out, readColliderChange);
}

std::vector<std::uint8_t> describeLimits() {
  const IntegratorDefaults vrm = integratorDefaults(Integrator::kVrm);
  const IntegratorDefaults xpbd = integratorDefaults(Integrator::kXpbd);
  TypedWriter out;
  out.object(10);
  out.key("bodyColliderShapes");
  const std::vector<std::string>& shapes = dclBodyShapeNames();
  out.array(static_cast<std::uint32_t>(shapes.size()));
  for (const std::string& name : shapes) pageText(out, name);
  out.key("integrators");
  out.object(2);
  out.key("vrm");
  out.object(2);
  out.key("maxSubsteps");
  out.number(vrm.max_substeps);
  out.key("stepHz");
  out.number(vrm.step_hz);
  out.key("xpbd");
  out.object(3);
  out.key("maxSubsteps");
  out.number(xpbd.max_substeps);
  out.key("stepHz");
  out.number(xpbd.step_hz);
  out.key("xpbdIterations");
  out.number(kDefaultXpbdIterations);
  out.key("maxGustFrequency");
  out.float32(kMaxGustFrequency);
  out.key("maxMetadataBytes");
  out.number(static_cast<double>(kMaxMetadataBytes));
  out.key("maxStepHz");
  out.number(kMaxStepHz);
  out.key("maxSubsteps");
  out.number(kMaxSubsteps);
  out.key("maxWindStrength");
  out.float32(kMaxWindStrength);
  out.key("maxSettleSeconds");
  out.number(kMaxSettleSeconds);
  out.key("maxXpbdIterations");
  out.number(kMaxXpbdIterations);
  out.key("settleSeconds");
  out.number(kDefaultSettleSeconds);
  return std::move(out.bytes());
}

std::vector<std::uint8_t> describeStats(std::size_t rigs, std::size_t instances, std::size_t scenes,
                                        std::size_t heap_in_use) {
  TypedWriter out;
  out.object(4);
  out.key("heapInUse");
  out.number(static_cast<double>(heap_in_use));
  out.key("instances");
  out.number(static_cast<double>(instances));
  out.key("rigs");
  out.number(static_cast<double>(rigs));
  out.key("scenes");
  out.number(static_cast<double>(scenes));
  return std::move(out.bytes());
}

}  // namespace springbones
