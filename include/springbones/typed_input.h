// The runtime's inputs as typed data: JSON values that a page has already parsed (the glTF JSON a
// loader read, the entity holding data.springBones), encoded by web/typed_value.js, or produced
// from bytes and text by the readers (springbones/readers.h). The runtime reads no JSON text: the
// rules (discovery, chains, defaults, clamps, centers, warnings) run here on these values, so
// every front end gets the same errors and warnings. The encoding is docs/design.md's "Typed
// input"; malformed bytes are a kInvalidArgument Error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "springbones/springbones.h"
#include "springbones/vrm.h"

namespace springbones {

/// One value in the typed encoding, held by the caller for the duration of a call.
struct TypedBytes {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
};

/// The node hierarchy of a glTF document given as {asset, nodes} (other members are ignored):
/// names, parents, rest transforms. The same errors loadSkeleton reports for a document's JSON.
Error loadSkeleton(TypedBytes gltf, Skeleton& out);

/// The data.springBones value (null: no spring bones), read as parseSpringBonesText reads text.
Error parseSpringBones(TypedBytes springBones, const std::string& hash, ModelEntry& out,
                       std::vector<Warning>& warnings);

/// The GLB hash of the representation `body_shape` (a URN or its last segment) wears in a
/// catalyst entity or Builder item: kInvalidArgument with a path when the entity has no such
/// representation or its main file is not in the content list.
Error mainFileHashFor(TypedBytes entity, const std::string& body_shape, std::string& hash);

/// The spring bones of a VRM document given as {asset, nodes, extensions}: loadVrm's rules.
Error loadVrm(TypedBytes gltf, std::shared_ptr<const Rig>& out, VrmSpringFormat* format = nullptr);

}  // namespace springbones
