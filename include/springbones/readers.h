// The readers: GLB / glTF bytes, VRM files and JSON text into the runtime's typed input
// (springbones/typed_input.h), with nlohmann-json. In WebAssembly they are a module of their own,
// which a page that hands over what it already parsed never downloads; natively they are how the
// tools and the tests load files. Each function here is the reader followed by the runtime's
// typed entry point of the same name, so both paths run one set of rules.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "springbones/springbones.h"
#include "springbones/typed_input.h"
#include "springbones/vrm.h"

namespace springbones {

/// What readGltf keeps of a document.
enum class GltfPart { kNodes, kNodesAndExtensions };

/// Reads the GLB container or glTF JSON text (embedded data allowed; buffers, images, meshes and
/// accessors are never decoded) and writes, as typed input, the document's `asset`, its `nodes`
/// with the fields the hierarchy needs (name, children, translation, rotation, scale, matrix) and,
/// for kNodesAndExtensions, its root `extensions`. Errors: kInvalidArgument, kGlbTruncated,
/// kGlbBadMagic, kGlbBadChunk, kLimitExceeded, kGltfBadJson.
Error readGltf(const std::uint8_t* data, std::size_t size, GltfPart part, std::vector<std::uint8_t>& typed);

/// Parses JSON text into typed input; `bad_json` is the code of the Error when it does not parse
/// (its message starts with `what`).
Error readJsonText(std::string_view text, ErrorCode bad_json, const char* what, std::vector<std::uint8_t>& typed);

/// Reads the node hierarchy of a GLB or of glTF JSON text held in memory. On failure returns an
/// Error and leaves `out` empty.
Error loadSkeleton(const std::uint8_t* data, std::size_t size, Skeleton& out);

/// Picks data.springBones.models[hash] from the JSON text of data.springBones (at most
/// kMaxMetadataBytes; "null": no spring bones) and reads it with the runtime's forgiving rules:
/// defaults for missing fields, clamping of out-of-range values and replacement of non-finite
/// ones, each with a warning. Errors only for text that does not parse (kMetadataBadJson) and
/// shapes that cannot be read at all (not an object, models not an object).
Error parseSpringBonesText(std::string_view text, const std::string& hash, ModelEntry& out,
                           std::vector<Warning>& warnings);

/// Loads the hierarchy and the spring bones of a .vrm / glTF held in memory. Errors: everything
/// loadSkeleton reports, kMetadataInvalid (with `path`) when a spring-bone extension has a shape
/// that cannot be read at all (not an object, `springs` not an array...), kLimitExceeded beyond
/// kMaxVrmColliderReferences. Everything else that is skipped or replaced becomes a Warning in
/// Rig::warnings. On failure `out` is reset. `format`, when given, receives which extension was
/// read.
Error loadVrm(const std::uint8_t* data, std::size_t size, std::shared_ptr<const Rig>& out,
              VrmSpringFormat* format = nullptr);

}  // namespace springbones
