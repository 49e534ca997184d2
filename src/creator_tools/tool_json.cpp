#include "creator_tools/tool_json.h"

#include <cmath>
#include <utility>

namespace springbones {

using nlohmann::json;

ApiFailure parseArgument(std::string_view text, const char* what, json& out) {
  try {
    out = json::parse(text);
    return {};
  } catch (const json::exception& ex) {
    return ApiFailure{std::string(what) + "-bad-json", std::string(what) + " JSON does not parse: " + ex.what(), ""};
  }
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
  return dumpReplacingInvalidUtf8(FloatJson{
      {"contentHash", content_hash}, {"candidates", std::move(list)}, {"warnings", std::move(warnings_json)}});
}

}  // namespace springbones
