// The data.springBones reader: the runtime's forgiving rules (defaults, clamps, fallbacks, each
// with a warning) on a typed value, whichever front end produced it.
#pragma once

#include <string>
#include <vector>

#include "common/typed_value.h"
#include "springbones/springbones.h"

namespace springbones {

/// Picks data.springBones.models[hash] from the value of data.springBones (null: no spring bones)
/// and reads it. Errors only for shapes that cannot be read at all (not an object, models not an
/// object).
Error parseSpringBones(const TypedValue& springBones, const std::string& hash, ModelEntry& out,
                       std::vector<Warning>& warnings);

}  // namespace springbones
