// Reading a Decentraland wearable entity (or a Builder item): which GLB hash each representation
// uses. Shared by the validator (active hashes), the Builder edits and hash lookup at load time.
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

/// The set of hashes some representation's main file has (each once, in representation order).
std::vector<std::string> activeModelHashes(const std::vector<Representation>& representations);

/// The data.springBones value of an entity or item (null when absent).
TypedValue springBonesOf(const TypedValue& entity);

}  // namespace springbones
