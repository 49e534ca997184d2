// Deploy-time validation of a wearable's data.springBones: the accept/reject decisions of
// Decentraland's catalyst, i.e. the SpringBonesData JSON schema of @dcl/schemas (checked as Ajv 8
// checks it, with allErrors) followed by the content validator's cross-checks against the entity.
// Strict where the runtime reader (metadata.cpp) is forgiving: what this rejects, a catalyst
// rejects too.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "springbones/creator_tools.h"

namespace springbones {

/// Checks springBones against the SpringBonesData schema as Ajv 8 does with allErrors: every error,
/// in Ajv's order, with Ajv's text ("must be <= 4"); empty means valid. NaN and infinities held by
/// the json are "must be number". Never throws.
std::vector<ValidationError> validateSpringBonesSchema(const nlohmann::json& springBones);

/// Checks the springBones of a catalyst entity {content: [{file, hash}], metadata: {data}} or of a
/// Builder item {contents: {file: hash}, data} alike, as the catalyst does: absent or null is
/// valid; else the schema errors alone ("springBones<path> <message>"), else every models key that
/// is no mainFile's content hash and every bone name without "springbone" (ASCII
/// case-insensitive). Any other value (not an object, `{}`, metadata without data, data without
/// contents) is an invalid-argument Error naming both shapes, never an empty list. Never throws.
Error validateSpringBones(const nlohmann::json& subject, std::vector<ValidationError>& errors);

}  // namespace springbones
