// The creator tools (the second WebAssembly module, sb.creatorTools()): deploy-time validation of a
// wearable's data.springBones as Decentraland's catalyst decides it, and the Builder edits
// (ADR-316 "Builder"): the spring-bone candidates of a GLB with the values to prefill, and one
// node's parameters written into data.springBones under the right GLB hash. The GLB itself is
// never touched: parameters live only in the item metadata. Arguments and results cross as JSON
// text, as in boundary.h. Implemented in src/creator_tools/, a library of its own over the runtime.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "springbones/boundary.h"
#include "springbones/springbones.h"

namespace springbones {

// ---------------------------------------------------------------------------------------------
// Validation

struct ValidationError {
  /// JSON pointer (RFC 6901 escaping, like Ajv's instancePath) of the offending value inside
  /// springBones, e.g. "/models/<hash>/<bone>/stiffness"; empty for springBones itself. Errors
  /// about the entity's own structure point into the entity instead ("/content/2",
  /// "/metadata/data/representations"); their message says so.
  std::string path;
  std::string message;
};


/// The catalyst's errors for the springBones of an entity or Builder item given as JSON text, as
/// JSON [{path, message}] in `errors_json` (empty array: valid), by the rules of
/// validateSpringBones in src/creator_tools/validation.h. `marker`: the JS side's stand-in for the
/// non-finite numbers JSON cannot hold, put back before validating ("" for none; restoreNonFinite
/// in src/creator_tools/tool_json.h). Failures: "entity-bad-json", or the Error of an entity of
/// neither shape.
ApiFailure validateSpringBones(std::string_view entity_text, const std::string& marker, std::string& errors_json);

// ---------------------------------------------------------------------------------------------
// Builder edits

struct SpringBoneCandidate {
  std::string name;
  int node = -1;
  int parent_candidate = -1;  ///< index in the returned list of the nearest candidate ancestor
  bool has_entry = false;     ///< the metadata already has an entry for this node
  bool is_root = false;       ///< the entry's isRoot, or (no entry) true for top-most candidates
  BoneParams params;          ///< the entry's values as the runtime reads them, or the defaults
  bool has_center = false;
  std::string center;
};


/// Every node whose name contains "springbone", parents first, with prefill values taken from
/// `existing` (the parsed entry for this GLB's hash; pass a default ModelEntry when there is none).
std::vector<SpringBoneCandidate> detectSpringBones(const Skeleton& skeleton, const ModelEntry& existing);


/// detectSpringBones over GLB bytes and the springBones JSON text, as JSON {contentHash,
/// candidates: [{name, node, parent, hasEntry, isRoot, params, center?}], warnings} in
/// `candidates_json`. `hash` is the models key (empty: the GLB's own content hash). Failures:
/// loadSkeleton's and parseSpringBonesText's errors.
ApiFailure detectSpringBones(const std::uint8_t* data, std::size_t size, std::string_view springbones_text,
                             const std::string& hash, std::string& candidates_json);

/// setSpringBoneParams (the rules: src/creator_tools/builder_edits.h) over JSON texts: springBones
/// (null or an object), the entity, and params (an object, or null to remove the node's entry);
/// the new springBones as JSON text in `out_text`. Failures: "metadata-bad-json",
/// "entity-bad-json", "params-bad-json", or the Error of the edit.
ApiFailure setSpringBoneParams(std::string_view springbones_text, std::string_view entity_text,
                               const std::string& body_shape, const std::string& node_name,
                               std::string_view params_text, std::string& out_text);

}  // namespace springbones
