// nlohmann-json values into the runtime's typed input: the readers' side of the one set of rules.
// The creator tools and the tests hold parsed nlohmann values; these give them the runtime's
// readers without a second implementation.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "loading/entity.h"
#include "springbones/springbones.h"

namespace springbones {

/// Appends the typed encoding of `value` (iterative: any depth). Binary values are written as null.
void writeTyped(const nlohmann::json& value, std::vector<std::uint8_t>& out);

/// The runtime's readers, on a nlohmann value.
Error parseSpringBones(const nlohmann::json& springBones, const std::string& hash, ModelEntry& out,
                       std::vector<Warning>& warnings);
Error readRepresentations(const nlohmann::json& entity, std::vector<Representation>& out);
Error mainFileHashFor(const nlohmann::json& entity, const std::string& body_shape, std::string& hash);
/// The data.springBones value of an entity or item (null when absent), in the data the runtime
/// reads the representations from.
const nlohmann::json& springBonesOf(const nlohmann::json& entity);

}  // namespace springbones
