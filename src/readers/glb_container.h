// Where the glTF JSON of an input is: the JSON chunk of a GLB, or the whole input when it is glTF
// JSON text.
#pragma once

#include <cstddef>
#include <cstdint>

#include "springbones/springbones.h"

namespace springbones {

/// Checks the GLB container (magic, version 2, declared length, first chunk is JSON and fits) or
/// recognises glTF JSON text (optional UTF-8 BOM and whitespace, then '{'), and points
/// `json_begin`/`json_size` at the JSON text inside `data` (no copy). Errors are the ones
/// loadSkeleton reports for the same input: kInvalidArgument, kGlbTruncated, kGlbBadMagic,
/// kGlbBadChunk, kLimitExceeded (JSON longer than kMaxGltfJsonBytes).
Error findGltfJson(const std::uint8_t* data, std::size_t size, const char*& json_begin, std::size_t& json_size);

}  // namespace springbones
