// The readers (springbones/readers.h): the GLB container, one nlohmann-json parse, and what the
// runtime reads of the document written as typed input.
#include "springbones/readers.h"

#include <exception>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "readers/glb_container.h"
#include "readers/json_values.h"

namespace springbones {
namespace {

using nlohmann::json;

constexpr const char* kNodeFields[] = {"children", "matrix", "name", "rotation", "scale", "translation"};

// {asset: {version}, nodes: [{the node fields}], extensions}: what the runtime reads of a glTF
// document. A member of a shape the runtime refuses (a node that is not an object, an asset that
// is not one) is written as null, which it refuses in the same words.
void writeGltfPart(const json& doc, GltfPart part, std::vector<std::uint8_t>& out) {
  TypedWriter w;
  if (!doc.is_object()) {
    w.null();
    out = std::move(w.bytes());
    return;
  }
  const auto asset = doc.find("asset");
  const auto nodes = doc.find("nodes");
  const auto extensions = part == GltfPart::kNodesAndExtensions ? doc.find("extensions") : doc.end();
  w.object(std::uint32_t(asset != doc.end()) + std::uint32_t(nodes != doc.end()) +
           std::uint32_t(extensions != doc.end()));
  if (asset != doc.end()) {
    w.key("asset");
    const auto version = asset->is_object() ? asset->find("version") : asset->end();
    if (!asset->is_object()) {
      w.null();
    } else if (version == asset->end()) {
      w.object(0);
    } else {
      w.object(1);
      w.key("version");
      writeTyped(*version, w.bytes());
    }
  }
  if (nodes != doc.end()) {
    w.key("nodes");
    if (!nodes->is_array()) {
      w.null();
    } else {
      w.array(static_cast<std::uint32_t>(nodes->size()));
      for (const json& node : *nodes) {
        if (!node.is_object()) {
          w.null();
          continue;
        }
        std::uint32_t present = 0;
        for (const char* field : kNodeFields) present += node.contains(field) ? 1 : 0;
        w.object(present);
        for (const char* field : kNodeFields) {
          if (auto it = node.find(field); it != node.end()) {
            w.key(field);
            writeTyped(*it, w.bytes());
          }
        }
      }
    }
  }
  if (extensions != doc.end()) {
    w.key("extensions");
    writeTyped(*extensions, w.bytes());
  }
  out = std::move(w.bytes());
}

}  // namespace

Error readGltf(const std::uint8_t* data, std::size_t size, GltfPart part, std::vector<std::uint8_t>& typed) {
  typed.clear();
  const char* json_begin = nullptr;
  std::size_t json_size = 0;
  if (Error e = findGltfJson(data, size, json_begin, json_size)) return e;
  try {
    // No parser callback: nlohmann's callback parser scans a container's elements each time one of
    // them ends, which is quadratic in the length of an array or object.
    const json doc = json::parse(json_begin, json_begin + json_size);
    writeGltfPart(doc, part, typed);
  } catch (const json::exception& ex) {
    typed.clear();
    return Error{ErrorCode::kGltfBadJson, std::string("glTF JSON does not parse: ") + ex.what(), ""};
  } catch (const std::exception& ex) {  // allocation failure on an absurd document
    typed.clear();
    return Error{ErrorCode::kGltfBadJson, std::string("glTF JSON could not be read: ") + ex.what(), ""};
  }
  return {};
}

Error readJsonText(std::string_view text, ErrorCode bad_json, const char* what, std::vector<std::uint8_t>& typed) {
  typed.clear();
  try {
    writeTyped(json::parse(text), typed);
  } catch (const json::exception& ex) {
    typed.clear();
    return Error{bad_json, std::string(what) + " JSON does not parse: " + ex.what(), ""};
  }
  return {};
}

Error loadSkeleton(const std::uint8_t* data, std::size_t size, Skeleton& out) {
  out = Skeleton{};
  std::vector<std::uint8_t> typed;
  if (Error e = readGltf(data, size, GltfPart::kNodes, typed)) return e;
  return loadSkeleton(TypedBytes{typed.data(), typed.size()}, out);
}

Error parseSpringBonesText(std::string_view text, const std::string& hash, ModelEntry& out,
                           std::vector<Warning>& warnings) {
  out = ModelEntry{};
  if (text.size() > kMaxMetadataBytes) {
    return Error{ErrorCode::kLimitExceeded,
                 "springBones JSON is " + std::to_string(text.size()) + " bytes, more than the limit of " +
                     std::to_string(kMaxMetadataBytes),
                 ""};
  }
  std::vector<std::uint8_t> typed;
  if (Error e = readJsonText(text, ErrorCode::kMetadataBadJson, "springBones", typed)) return e;
  return parseSpringBones(TypedBytes{typed.data(), typed.size()}, hash, out, warnings);
}

Error loadVrm(const std::uint8_t* data, std::size_t size, std::shared_ptr<const Rig>& out, VrmSpringFormat* format) {
  out.reset();
  if (format != nullptr) *format = VrmSpringFormat::kNone;
  std::vector<std::uint8_t> typed;
  if (Error e = readGltf(data, size, GltfPart::kNodesAndExtensions, typed)) return e;
  return loadVrm(TypedBytes{typed.data(), typed.size()}, out, format);
}

}  // namespace springbones
