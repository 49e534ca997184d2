// The runtime's typed entry points (springbones/typed_input.h): decode, within the bound of the
// input's kind, then the one reader of each input. A string argument beside the typed input (a
// hash, a body shape) is held to the bound of a typed string before it is copied or read.
#include "springbones/typed_input.h"

#include "common/typed_value.h"
#include "loading/entity.h"
#include "loading/gltf_nodes.h"
#include "loading/metadata.h"
#include "loading/vrm_reader.h"

namespace springbones {
namespace {

Error checkStringArgument(const char* what, const std::string& value) {
  if (value.size() <= kTypedMaxStringBytes) return {};
  return Error{ErrorCode::kLimitExceeded,
               std::string(what) + " is " + std::to_string(value.size()) + " bytes, more than the limit of " +
                   std::to_string(kTypedMaxStringBytes),
               ""};
}

}  // namespace

Error loadSkeleton(TypedBytes gltf, Skeleton& out) {
  out = Skeleton{};
  TypedDocument doc;
  if (Error e = doc.decode(gltf.data, gltf.size, kMaxGltfJsonBytes)) return e;
  return readGltfDocument(doc.root(), out);
}

Error parseSpringBones(TypedBytes springBones, const std::string& hash, ModelEntry& out,
                       std::vector<Warning>& warnings) {
  out = ModelEntry{};
  if (Error e = checkStringArgument("the content hash", hash)) return e;
  TypedDocument doc;
  if (Error e = doc.decode(springBones.data, springBones.size, kMaxMetadataBytes)) return e;
  return parseSpringBones(doc.root(), hash, out, warnings);
}

Error mainFileHashFor(TypedBytes entity, const std::string& body_shape, std::string& hash) {
  hash.clear();
  if (Error e = checkStringArgument("the body shape", body_shape)) return e;
  TypedDocument doc;
  if (Error e = doc.decode(entity.data, entity.size, kMaxMetadataBytes)) return e;
  return mainFileHashFor(doc.root(), body_shape, hash);
}

Error loadVrm(TypedBytes gltf, std::shared_ptr<const Rig>& out, VrmSpringFormat* format) {
  out.reset();
  if (format != nullptr) *format = VrmSpringFormat::kNone;
  TypedDocument doc;
  if (Error e = doc.decode(gltf.data, gltf.size, kMaxGltfJsonBytes)) return e;
  return loadVrm(doc.root(), out, format);
}

}  // namespace springbones
