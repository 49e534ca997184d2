// Builder edits (ADR-316 "Builder"): list the spring-bone candidates of a GLB with the values to
// prefill, and write one node's parameters into data.springBones under the right GLB hash. The
// GLB itself is never touched: parameters live only in the item metadata.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "springbones/springbones.h"

namespace springbones {

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

/// Returns a copy of `springBones` (null or an object) with models[hash][node_name] = params, where
/// hash is the content hash of the main file of `body_shape`'s representation in `entity`. A GLB
/// shared by both body shapes therefore gets one entry. `params` null removes the node's entry.
/// Entries under hashes that no current representation uses are dropped, and version is set to 1.
/// Errors: unknown body shape, main file missing from the content list, a node name without the
/// "springbone" token, params that are neither an object nor null, springBones or params nested
/// more than 64 levels deep (they are copied, and copying recurses once per level).
Error setSpringBoneParams(const nlohmann::json& springBones, const nlohmann::json& entity,
                          const std::string& body_shape, const std::string& node_name,
                          const nlohmann::json& params, nlohmann::json& out);

}  // namespace springbones
