// The runtime's typed entry points (springbones/typed_input.h): decode, then the one reader of
// each input.
#include "springbones/typed_input.h"

#include "common/typed_value.h"
#include "loading/entity.h"
#include "loading/gltf_nodes.h"
#include "loading/metadata.h"
#include "loading/vrm_reader.h"

namespace springbones {

Error loadSkeleton(TypedBytes gltf, Skeleton& out) {
  out = Skeleton{};
  TypedDocument doc;
  if (Error e = doc.decode(gltf.data, gltf.size)) return e;
  return readGltfDocument(doc.root(), out);
}

Error parseSpringBones(TypedBytes springBones, const std::string& hash, ModelEntry& out,
                       std::vector<Warning>& warnings) {
  out = ModelEntry{};
  TypedDocument doc;
  if (Error e = doc.decode(springBones.data, springBones.size)) return e;
  return parseSpringBones(doc.root(), hash, out, warnings);
}

Error mainFileHashFor(TypedBytes entity, const std::string& body_shape, std::string& hash) {
  hash.clear();
  TypedDocument doc;
  if (Error e = doc.decode(entity.data, entity.size)) return e;
  return mainFileHashFor(doc.root(), body_shape, hash);
}

Error loadVrm(TypedBytes gltf, std::shared_ptr<const Rig>& out, VrmSpringFormat* format) {
  out.reset();
  if (format != nullptr) *format = VrmSpringFormat::kNone;
  TypedDocument doc;
  if (Error e = doc.decode(gltf.data, gltf.size)) return e;
  return loadVrm(doc.root(), out, format);
}

}  // namespace springbones
