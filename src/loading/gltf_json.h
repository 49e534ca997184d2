// The glTF document of an input: where its JSON is (the JSON chunk of a GLB, or the whole input
// when it is glTF JSON text), and the one parse of it that both the node hierarchy and the VRM
// spring-bone reader take their data from.
#pragma once

#include <cstddef>
#include <cstdint>

#include <nlohmann/json_fwd.hpp>

#include "springbones/springbones.h"

namespace springbones {

/// Checks the GLB container (magic, version 2, declared length, first chunk is JSON and fits) or
/// recognises glTF JSON text (optional UTF-8 BOM and whitespace, then '{'), and points
/// `json_begin`/`json_size` at the JSON text inside `data` (no copy). Errors are the ones
/// loadSkeleton reports for the same input: kInvalidArgument, kGlbTruncated, kGlbBadMagic,
/// kGlbBadChunk, kLimitExceeded (JSON longer than kMaxGltfJsonBytes).
Error findGltfJson(const std::uint8_t* data, std::size_t size, const char*& json_begin, std::size_t& json_size);

/// loadSkeleton, and when `extensions` is not null the value of the document's root "extensions"
/// from the same parse (null when absent). glb_loader.cpp.
Error loadSkeletonAndExtensions(const std::uint8_t* data, std::size_t size, Skeleton& out,
                                nlohmann::json* extensions);

}  // namespace springbones
