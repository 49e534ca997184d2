// The node hierarchy of a glTF document, read from a typed value (gltf_nodes.cpp has the rules).
#pragma once

#include "common/typed_value.h"
#include "springbones/springbones.h"

namespace springbones {

/// Reads `asset` (a string `version` must be there) and `nodes` of a glTF document: names,
/// parents, rest transforms. Errors: kGltfInvalid (a field of the wrong type, a child that does
/// not exist, a rest transform beyond float range), kHierarchyMultipleParents, kHierarchyCycle,
/// kLimitExceeded (more than kMaxNodes). On failure `out` is empty.
Error readGltfDocument(const TypedValue& doc, Skeleton& out);

}  // namespace springbones
