// Builder edits (ADR-316 "Builder"): list the spring-bone candidates of a GLB with the values to
// prefill, and write one node's parameters into data.springBones under the right GLB hash. The
// GLB itself is never touched: parameters live only in the item metadata.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "springbones/creator_tools.h"

namespace springbones {

/// Returns a copy of `springBones` (null or an object) with models[hash][node_name] = params, where
/// hash is the content hash of the main file of `body_shape`'s representation in `entity`. A GLB
/// shared by both body shapes therefore gets one entry. `params` null removes the node's entry.
/// Entries under hashes that no current representation uses are dropped, and version is set to 1.
/// Errors: unknown body shape, main file missing from the content list, a node name without the
/// "springbone" token, params that are neither an object nor null, springBones or params nested
/// more than 64 levels deep (they are copied, and copying recurses once per level).
Error setSpringBoneParams(const nlohmann::json& springBones, const nlohmann::json& entity,
                          const std::string& body_shape, const std::string& node_name, const nlohmann::json& params,
                          nlohmann::json& out);

}  // namespace springbones
