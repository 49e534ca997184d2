#include "creator_tools/builder_edits.h"

#include <algorithm>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "creator_tools/json_depth.h"
#include "creator_tools/tool_json.h"
#include "readers/json_values.h"
#include "springbones/content_hash.h"
#include "springbones/readers.h"

namespace springbones {

using nlohmann::json;

namespace {

// Metadata is at most five levels deep (springBones/models/hash/bone/gravityDir); unknown keys in
// a bone entry may add some. nlohmann's copy (and dump) recurse once per level, so a document
// nested millions deep would overflow the stack (the WebAssembly one first) when copied below.
constexpr std::size_t kMaxCopyDepth = 64;

}  // namespace

std::vector<SpringBoneCandidate> detectSpringBones(const Skeleton& skeleton, const ModelEntry& existing) {
  std::unordered_map<std::string, const BoneEntry*> entries;
  for (const BoneEntry& e : existing.bones) entries.emplace(e.name, &e);

  std::vector<SpringBoneCandidate> candidates;
  std::vector<int> candidate_of_node(skeleton.nodes.size(), -1);
  for (int n : skeleton.parents_first) {
    const SkeletonNode& node = skeleton.nodes[n];
    // Nearest candidate ancestor: the parent's, or the parent itself when it is a candidate.
    const int inherited = node.parent >= 0 ? candidate_of_node[node.parent] : -1;
    if (!isSpringBoneName(node.name)) {
      candidate_of_node[n] = inherited;
      continue;
    }
    SpringBoneCandidate c;
    c.name = node.name;
    c.node = n;
    c.parent_candidate = inherited;
    if (auto it = entries.find(node.name); it != entries.end()) {
      c.has_entry = true;
      c.is_root = it->second->is_root;
      c.params = it->second->params;
      c.has_center = it->second->has_center;
      c.center = it->second->center;
    } else {
      c.is_root = inherited < 0;  // a top-most candidate is where a creator starts a chain
    }
    candidate_of_node[n] = static_cast<int>(candidates.size());
    candidates.push_back(std::move(c));
  }
  return candidates;
}

Error setSpringBoneParams(const json& springBones, const json& entity, const std::string& body_shape,
                          const std::string& node_name, const json& params, json& out) {
  out = json();
  if (!isSpringBoneName(node_name)) {
    return Error{ErrorCode::kInvalidArgument,
                 "node '" + node_name + "' does not contain the 'springbone' token, so it cannot carry parameters", ""};
  }
  if (!params.is_object() && !params.is_null()) {
    return Error{ErrorCode::kInvalidArgument, "params must be an object (or null to remove the entry)", ""};
  }
  if (!springBones.is_null() && !springBones.is_object()) {
    return Error{ErrorCode::kMetadataInvalid, "springBones is not an object", ""};
  }
  if (nestsDeeperThan(params, kMaxCopyDepth)) {
    return Error{ErrorCode::kInvalidArgument, "params nest more than " + std::to_string(kMaxCopyDepth) + " levels deep",
                 ""};
  }
  if (nestsDeeperThan(springBones, kMaxCopyDepth)) {
    return Error{ErrorCode::kMetadataInvalid,
                 "springBones nests more than " + std::to_string(kMaxCopyDepth) + " levels deep", ""};
  }
  std::vector<Representation> representations;
  if (Error e = readRepresentations(entity, representations)) return e;
  std::string hash;
  if (Error e = mainFileHashFor(entity, body_shape, hash)) return e;

  json result = springBones.is_object() ? springBones : json::object();
  result["version"] = 1;
  json models = result.contains("models") && result["models"].is_object() ? result["models"] : json::object();
  // The hashes some representation's main file has; an entry under any other is dropped.
  std::unordered_set<std::string> active;
  for (const Representation& r : representations) {
    if (!r.main_file_hash.empty()) active.insert(r.main_file_hash);
  }
  for (auto it = models.begin(); it != models.end();) {
    if (active.count(it.key()) == 0) {
      it = models.erase(it);  // a stale hash from an earlier upload
    } else {
      ++it;
    }
  }
  json& model = models[hash];
  if (!model.is_object()) model = json::object();
  if (params.is_null()) {
    model.erase(node_name);
  } else {
    model[node_name] = params;
  }
  result["models"] = std::move(models);
  out = std::move(result);
  return {};
}

ApiFailure detectSpringBones(const std::uint8_t* data, std::size_t size, std::string_view springbones_text,
                             const std::string& hash, std::string& candidates_json) {
  candidates_json.clear();
  Skeleton skeleton;
  if (Error e = loadSkeleton(data, size, skeleton)) return toFailure(e);
  const std::string key = hash.empty() ? contentHash(data, size) : hash;
  ModelEntry model;
  std::vector<Warning> warnings;
  if (Error e = parseSpringBonesText(springbones_text, key, model, warnings)) return toFailure(e);
  candidates_json = candidatesJson(key, detectSpringBones(skeleton, model), warnings);
  return {};
}

ApiFailure setSpringBoneParams(std::string_view springbones_text, std::string_view entity_text,
                               const std::string& body_shape, const std::string& node_name,
                               std::string_view params_text, std::string& out_text) {
  out_text.clear();
  json springBones, entity, params, out;
  if (ApiFailure f = parseArgument(springbones_text, "metadata", springBones)) return f;
  if (ApiFailure f = parseArgument(entity_text, "entity", entity)) return f;
  if (ApiFailure f = parseArgument(params_text, "params", params)) return f;
  if (Error e = setSpringBoneParams(springBones, entity, body_shape, node_name, params, out)) return toFailure(e);
  out_text = dumpReplacingInvalidUtf8(out);  // at most 64 levels deep
  return {};
}

}  // namespace springbones
