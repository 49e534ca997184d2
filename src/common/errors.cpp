// Stable names of the core's error codes; the JS API exposes them as SpringBonesError.code.
#include "springbones/springbones.h"

namespace springbones {

const char* errorCodeName(ErrorCode code) {
  switch (code) {
    case ErrorCode::kOk: return "ok";
    case ErrorCode::kInvalidArgument: return "invalid-argument";
    case ErrorCode::kGlbTruncated: return "glb-truncated";
    case ErrorCode::kGlbBadMagic: return "glb-bad-magic";
    case ErrorCode::kGlbBadChunk: return "glb-bad-chunk";
    case ErrorCode::kGltfBadJson: return "gltf-bad-json";
    case ErrorCode::kGltfInvalid: return "gltf-invalid";
    case ErrorCode::kHierarchyMultipleParents: return "hierarchy-multiple-parents";
    case ErrorCode::kHierarchyCycle: return "hierarchy-cycle";
    case ErrorCode::kMetadataBadJson: return "metadata-bad-json";
    case ErrorCode::kMetadataInvalid: return "metadata-invalid";
    case ErrorCode::kLimitExceeded: return "limit-exceeded";
  }
  return "unknown";
}

}  // namespace springbones
