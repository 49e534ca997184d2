// The data.springBones reader over a value already parsed, for the callers that hold one (the
// fuzz and hostile-input tests build values no JSON text would give, such as NaN parameters).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "springbones/springbones.h"

namespace springbones {

/// parseSpringBonesText's rules, on the value of data.springBones (null: no spring bones).
Error parseSpringBones(const nlohmann::json& springBones, const std::string& hash, ModelEntry& out,
                       std::vector<Warning>& warnings);

}  // namespace springbones
