// The JSON texts of the runtime's boundary (springbones/boundary.h), written with JsonText, and the
// rig options read from typed input.
#include "springbones/boundary.h"

#include <utility>

#include "common/json_text.h"
#include "common/typed_value.h"
#include "loading/vrm_limits.h"

namespace springbones {
namespace {

ApiFailure badOptions(const std::string& why) {
  return ApiFailure{"invalid-argument", "rig options could not be read: " + why, ""};
}

bool readVec3(const TypedValue& value, Vec3& out) {
  if (!value.is_array() || value.size() != 3) return false;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!value[i].is_number()) return false;
  }
  out = Vec3{value[0].get<float>(), value[1].get<float>(), value[2].get<float>()};
  return true;
}

ApiFailure readCollider(const TypedValue& c, std::size_t index, ColliderSpec& spec) {
  const std::string where = "collider " + std::to_string(index);
  const auto node = c.find("node");
  const auto offset = c.find("offset");
  if (node == c.end() || !node->is_string()) return badOptions(where + " has no node name");
  spec.node = node->get<std::string>();
  if (offset == c.end() || !readVec3(*offset, spec.offset)) return badOptions(where + " has no offset [x, y, z]");
  if (auto radius = c.find("radius"); radius != c.end()) {
    if (!radius->is_number()) return badOptions(where + ": radius is not a number");
    spec.radius = radius->get<float>();
  }
  if (auto inside = c.find("inside"); inside != c.end()) {
    if (!inside->is_boolean()) return badOptions(where + ": inside is not a boolean");
    spec.inside = inside->get<bool>();
  }
  if (auto normal = c.find("normal"); normal != c.end()) {
    spec.shape = Collider::Shape::kPlane;
    if (!readVec3(*normal, spec.normal)) return badOptions(where + ": normal is not [x, y, z]");
  } else if (auto tail = c.find("tail"); tail != c.end()) {
    spec.shape = Collider::Shape::kCapsule;
    if (!readVec3(*tail, spec.tail)) return badOptions(where + ": tail is not [x, y, z]");
  }
  return {};
}

ApiFailure readOptions(const TypedValue& value, RigOptions& out) {
  if (value.is_null()) return {};
  if (!value.is_object()) return badOptions("not an object");
  if (auto hit = value.find("hitRadius"); hit != value.end()) {
    if (!hit->is_number()) return badOptions("hitRadius is not a number");
    out.hit_radius = hit->get<float>();
  }
  if (auto preset = value.find("preset"); preset != value.end()) {
    if (*preset != "dcl-body") {
      return ApiFailure{"invalid-argument", "rig options: unknown collider preset '" + preset->get<std::string>() + "'",
                        ""};
    }
    out.preset = ColliderPreset::kDclBody;
  }
  if (auto limits = value.find("limits"); limits != value.end()) {
    std::string why;
    if (!readLimitOptions(*limits, out.limits, why)) return ApiFailure{"invalid-argument", "rig options: " + why, ""};
  }
  if (auto colliders = value.find("colliders"); colliders != value.end()) {
    if (!colliders->is_array()) return badOptions("colliders is not an array");
    out.colliders.reserve(colliders->size());
    for (std::size_t i = 0; i < colliders->size(); ++i) {
      ColliderSpec spec;
      if (ApiFailure f = readCollider((*colliders)[i], i, spec)) return f;
      out.colliders.push_back(std::move(spec));
    }
  }
  return {};
}

}  // namespace

ApiFailure toFailure(const Error& error) {
  if (!error) return {};
  return ApiFailure{errorCodeName(error.code), error.message, error.path};
}

std::string failureJson(const ApiFailure& failure) {
  JsonText out;
  out.beginObject().key("code").value(failure.code).key("message").value(failure.message);
  out.key("path").value(failure.path).endObject();
  return out.take();
}

ApiFailure readRigOptions(TypedBytes options, RigOptions& out) {
  out = RigOptions{};
  if (options.size == 0) return {};
  TypedDocument doc;
  if (Error e = doc.decode(options.data, options.size, kMaxMetadataBytes)) return toFailure(e);
  ApiFailure failure = readOptions(doc.root(), out);
  if (failure) out = RigOptions{};
  return failure;
}

std::string limitsJson() {
  const IntegratorDefaults vrm = integratorDefaults(Integrator::kVrm);
  const IntegratorDefaults xpbd = integratorDefaults(Integrator::kXpbd);
  JsonText out;
  out.beginObject();
  out.key("integrators").beginObject();
  out.key("vrm").beginObject().key("maxSubsteps").value(vrm.max_substeps).key("stepHz").value(vrm.step_hz).endObject();
  out.key("xpbd").beginObject().key("maxSubsteps").value(xpbd.max_substeps).key("stepHz").value(xpbd.step_hz);
  out.key("xpbdIterations").value(kDefaultXpbdIterations).endObject();
  out.endObject();
  out.key("maxGustFrequency").value(kMaxGustFrequency);
  out.key("maxMetadataBytes").value(kMaxMetadataBytes);
  out.key("maxStepHz").value(kMaxStepHz);
  out.key("maxSubsteps").value(kMaxSubsteps);
  out.key("maxWindStrength").value(kMaxWindStrength);
  out.key("maxSettleSeconds").value(kMaxSettleSeconds);
  out.key("maxXpbdIterations").value(kMaxXpbdIterations);
  out.key("settleSeconds").value(kDefaultSettleSeconds);
  out.endObject();
  return out.take();
}

std::string statsJson(std::size_t rigs, std::size_t instances, std::size_t scenes, std::size_t heap_in_use) {
  JsonText out;
  out.beginObject().key("heapInUse").value(heap_in_use).key("instances").value(instances);
  out.key("rigs").value(rigs).key("scenes").value(scenes).endObject();
  return out.take();
}

}  // namespace springbones
