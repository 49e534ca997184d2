// loadVrm on typed input (vrm_reader.h): the hierarchy, then the one spring-bone format a file is
// read with (springbones/vrm.h: VRMC_springBone wins over VRM 0.x, as in three-vrm), then the rig
// both formats share (vrm_rig_builder.h).
#include <exception>
#include <new>
#include <optional>
#include <string>
#include <utility>

#include "loading/gltf_nodes.h"
#include "loading/vrm_formats.h"
#include "loading/vrm_reader.h"
#include "loading/vrm_rig_builder.h"

namespace springbones {
namespace {

Error fail(ErrorCode code, std::string message, std::string path = {}) {
  return Error{code, std::move(message), std::move(path)};
}

// The springs of the format `extensions` holds into `rig`; `format` says which was read.
Error readSprings(const TypedValue& extensions, VrmRigBuilder& rig, VrmSpringFormat& format) {
  format = VrmSpringFormat::kNone;
  if (!extensions.is_null() && !extensions.is_object()) {
    return fail(ErrorCode::kGltfInvalid, "the glTF 'extensions' value is not an object", "/extensions");
  }
  std::optional<TypedValue> vrmc;
  std::optional<TypedValue> vrm0;
  if (extensions.is_object()) {
    if (auto it = extensions.find("VRMC_springBone"); it != extensions.end()) vrmc = *it;
    if (auto it = extensions.find("VRM"); it != extensions.end()) vrm0 = *it;
  }
  if (vrmc.has_value()) {
    format = VrmSpringFormat::kVrmcSpringBone1;
    if (Error e = readVrmcSpringBone(*vrmc, rig)) return e;
    if (vrm0.has_value()) {
      rig.warn("vrm-both-formats",
               "the file has VRMC_springBone and VRM 0.x data; the VRM 0.x secondaryAnimation is ignored",
               "/extensions/VRM");
    }
  } else if (vrm0.has_value()) {
    if (!vrm0->is_object()) {
      return fail(ErrorCode::kMetadataInvalid, "extensions.VRM is not an object", "/extensions/VRM");
    }
    auto it = vrm0->find("secondaryAnimation");
    if (it != vrm0->end() && !it->is_null()) {
      format = VrmSpringFormat::kVrm0;
      if (Error e = readVrm0SecondaryAnimation(*it, rig)) return e;
    }
  }
  if (format == VrmSpringFormat::kNone) {
    rig.warn("vrm-no-springs",
             "the file has neither VRMC_springBone nor VRM 0.x secondaryAnimation: nothing to simulate");
  }
  return {};
}

}  // namespace

Error loadVrm(const TypedValue& gltf, std::shared_ptr<const Rig>& out, VrmSpringFormat* format) {
  out.reset();
  if (format != nullptr) *format = VrmSpringFormat::kNone;
  Skeleton skeleton;
  if (Error e = readGltfDocument(gltf, skeleton)) return e;
  const auto extensions = gltf.find("extensions");
  VrmSpringFormat read = VrmSpringFormat::kNone;
  std::shared_ptr<const Rig> rig;
  try {
    VrmRigBuilder builder(std::move(skeleton));
    if (Error e = readSprings(extensions == gltf.end() ? TypedValue() : *extensions, builder, read)) return e;
    if (Error e = builder.emit(rig)) return e;
  } catch (const std::bad_alloc&) {
    throw;  // a full heap, not a bad file: the boundary says out-of-memory, as for every entry point
  } catch (const std::exception& ex) {  // a size beyond the containers' bounds on an absurd file
    return fail(ErrorCode::kMetadataInvalid, std::string("VRM spring bones could not be read: ") + ex.what());
  }
  if (format != nullptr) *format = read;
  out = std::move(rig);
  return {};
}

}  // namespace springbones
