// Reading a Decentraland wearable entity (or a Builder item): which GLB hash each representation
// uses. The runtime's models key at load time (mainFileHashFor); the Builder edits read the
// representations through the readers (readers/json_values.h).
#pragma once

#include <string>
#include <vector>

#include "common/typed_value.h"
#include "springbones/springbones.h"

namespace springbones {

struct Representation {
  std::vector<std::string> body_shapes;
  std::string main_file;
  std::string main_file_hash;  ///< empty when the content list has no entry for main_file
};

/// The representations of an entity `{content: [{file, hash}], metadata: {data: {representations}}}`
/// or of a Builder item `{contents: {file: hash}, data: {representations}}`. Error (with a JSON
/// path) when the structure cannot be read.
Error readRepresentations(const TypedValue& entity, std::vector<Representation>& out);

/// The GLB hash of the representation worn by `body_shape` (a full URN such as
/// "urn:decentraland:off-chain:base-avatars:BaseMale", or its last segment "BaseMale").
Error mainFileHashFor(const TypedValue& entity, const std::string& body_shape, std::string& hash);

}  // namespace springbones
