#include "boundary/api_json.h"

#include <cmath>
#include <cstddef>
#include <utility>

#include "boundary/rig_description.h"
#include "loading/entity.h"

namespace springbones {

using nlohmann::json;

ApiFailure toFailure(const Error& error) {
  if (!error) return {};
  return ApiFailure{errorCodeName(error.code), error.message, error.path};
}

std::string failureJson(const ApiFailure& failure) {
  return dumpReplacingInvalidUtf8(json{{"code", failure.code}, {"message", failure.message}, {"path", failure.path}});
}

ApiFailure parseArgument(std::string_view text, const char* what, json& out) {
  try {
    out = json::parse(text);
    return {};
  } catch (const json::exception& ex) {
    return ApiFailure{std::string(what) + "-bad-json", std::string(what) + " JSON does not parse: " + ex.what(), ""};
  }
}

ApiFailure readRigOptions(std::string_view text, RigOptions& out) {
  out = RigOptions{};
  if (text.empty()) return {};
  try {
    const json value = json::parse(text);
    const auto vec3 = [](const json& a) {
      return Vec3{a.at(0).get<float>(), a.at(1).get<float>(), a.at(2).get<float>()};
    };
    if (value.contains("hitRadius")) out.hit_radius = value.at("hitRadius").get<float>();
    if (value.contains("preset")) {
      const std::string preset = value.at("preset").get<std::string>();
      if (preset != "dcl-body") {
        out = RigOptions{};
        return ApiFailure{"invalid-argument", "rig options: unknown collider preset '" + preset + "'", ""};
      }
      out.preset = ColliderPreset::kDclBody;
    }
    if (value.contains("colliders")) {
      for (const json& c : value.at("colliders")) {
        ColliderSpec spec;
        spec.node = c.at("node").get<std::string>();
        spec.offset = vec3(c.at("offset"));
        spec.radius = c.value("radius", 0.0f);
        spec.inside = c.value("inside", false);
        if (c.contains("normal")) {
          spec.shape = Collider::Shape::kPlane;
          spec.normal = vec3(c.at("normal"));
        } else if (c.contains("tail")) {
          spec.shape = Collider::Shape::kCapsule;
          spec.tail = vec3(c.at("tail"));
        }
        out.colliders.push_back(std::move(spec));
      }
    }
  } catch (const json::exception& ex) {
    out = RigOptions{};
    return ApiFailure{"invalid-argument", std::string("rig options could not be read: ") + ex.what(), ""};
  }
  return {};
}

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

std::string validationErrorsJson(const std::vector<ValidationError>& errors) {
  json out = json::array();
  for (const ValidationError& e : errors) out.push_back(json{{"path", e.path}, {"message", e.message}});
  return dumpReplacingInvalidUtf8(out);
}

std::string candidatesJson(const std::string& content_hash, const std::vector<SpringBoneCandidate>& candidates,
                           const std::vector<Warning>& warnings) {
  FloatJson list = FloatJson::array();
  for (const SpringBoneCandidate& c : candidates) {
    const BoneParams& p = c.params;
    FloatJson entry{{"name", c.name},
                    {"node", c.node},
                    {"parent", c.parent_candidate},
                    {"hasEntry", c.has_entry},
                    {"isRoot", c.is_root},
                    {"params",
                     {{"stiffness", p.stiffness},
                      {"gravityPower", p.gravity_power},
                      {"gravityDir", {p.gravity_dir.x, p.gravity_dir.y, p.gravity_dir.z}},
                      {"drag", p.drag}}}};
    if (c.has_center) entry["center"] = c.center.empty() ? FloatJson(nullptr) : FloatJson(c.center);
    list.push_back(std::move(entry));
  }
  FloatJson warnings_json = FloatJson::array();
  for (const Warning& w : warnings) {
    warnings_json.push_back(FloatJson{{"code", w.code}, {"message", w.message}, {"path", w.path}});
  }
  return dumpReplacingInvalidUtf8(
      FloatJson{{"contentHash", content_hash}, {"candidates", std::move(list)}, {"warnings", std::move(warnings_json)}});
}

std::string limitsJson() {
  const IntegratorDefaults vrm = integratorDefaults(Integrator::kVrm);
  const IntegratorDefaults xpbd = integratorDefaults(Integrator::kXpbd);
  return json{{"maxStepHz", kMaxStepHz},
              {"maxSubsteps", kMaxSubsteps},
              {"maxXpbdIterations", kMaxXpbdIterations},
              {"maxMetadataBytes", kMaxMetadataBytes},
              {"maxWindStrength", kMaxWindStrength},
              {"maxGustFrequency", kMaxGustFrequency},
              {"settleSeconds", kDefaultSettleSeconds},
              {"maxSettleSeconds", kMaxSettleSeconds},
              {"integrators",
               {{"vrm", {{"stepHz", vrm.step_hz}, {"maxSubsteps", vrm.max_substeps}}},
                {"xpbd",
                 {{"stepHz", xpbd.step_hz},
                  {"maxSubsteps", xpbd.max_substeps},
                  {"xpbdIterations", kDefaultXpbdIterations}}}}}}
      .dump();
}

std::string statsJson(std::size_t rigs, std::size_t instances, std::size_t scenes, std::size_t heap_in_use) {
  return json{{"rigs", rigs}, {"instances", instances}, {"scenes", scenes}, {"heapInUse", heap_in_use}}.dump();
}

ApiFailure mainFileHashFor(std::string_view entity_text, const std::string& body_shape, std::string& hash) {
  hash.clear();
  json entity;
  if (ApiFailure f = parseArgument(entity_text, "entity", entity)) return f;
  return toFailure(mainFileHashFor(entity, body_shape, hash));
}

}  // namespace springbones
