// The readers (springbones/readers.h): the GLB container, one reading of its JSON as a page's
// JSON.parse reads it (page_json.h), and what the runtime reads of the document written as typed
// input.
#include "springbones/readers.h"

#include <exception>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/typed_encoding.h"
#include "readers/glb_container.h"
#include "readers/json_values.h"
#include "readers/page_json.h"

namespace springbones {
namespace {

using nlohmann::json;

// A member the runtime reads only for its type: a scalar as it is, a container by its kind alone.
void writeShapeOnly(const json& value, TypedWriter& w) {
  if (value.is_array()) {
    w.array(0);
  } else if (value.is_object()) {
    w.object(0);
  } else if (value.is_string()) {
    w.string("");
  } else {
    writeTyped(value, w.bytes());
  }
}

// The root extensions the runtime reads (kGltfRootExtensionMembers), and of each only its members
// the runtime reads, as web/typed_value.js keeps them of a parsed document.
void writeRootExtensions(const json& extensions, TypedWriter& w) {
  if (!extensions.is_object()) return writeShapeOnly(extensions, w);
  std::vector<const char*> present;
  for (const auto& [extension, member] : kGltfRootExtensionMembers) {
    if (extensions.contains(extension) && (present.empty() || std::string_view(present.back()) != extension)) {
      present.push_back(extension);
    }
  }
  w.object(static_cast<std::uint32_t>(present.size()));
  for (const char* name : present) {
    w.key(name);
    const json& extension = extensions.at(name);
    std::vector<const char*> members;
    bool all = false;
    for (const auto& [e, member] : kGltfRootExtensionMembers) {
      if (std::string_view(e) != name) continue;
      if (member == nullptr) all = true;
      if (member != nullptr && extension.is_object() && extension.contains(member)) members.push_back(member);
    }
    if (all) {
      writeTyped(extension, w.bytes());
    } else if (!extension.is_object()) {
      writeShapeOnly(extension, w);
    } else {
      w.object(static_cast<std::uint32_t>(members.size()));
      for (const char* member : members) {
        w.key(member);
        writeTyped(extension.at(member), w.bytes());
      }
    }
  }
}

// {asset: {version}, nodes: [{the node fields}], extensions}: what the runtime reads of a glTF
// document (src/common/typed_encoding.json, "gltf"). A member of a shape the runtime refuses (a
// node that is not an object, an asset that is not one) is written as null, which it refuses in
// the same words. More nodes than kMaxNodes is refused before any is written.
Error writeGltfPart(const json& doc, GltfPart part, std::vector<std::uint8_t>& out) {
  TypedWriter w;
  if (!doc.is_object()) {
    w.null();
    out = std::move(w.bytes());
    return {};
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
    } else if (nodes->size() > kMaxNodes) {
      return Error{
          ErrorCode::kLimitExceeded,
          "glTF has " + std::to_string(nodes->size()) + " nodes, more than the limit of " + std::to_string(kMaxNodes),
          "/nodes"};
    } else {
      w.array(static_cast<std::uint32_t>(nodes->size()));
      for (const json& node : *nodes) {
        if (!node.is_object()) {
          w.null();
          continue;
        }
        std::uint32_t present = 0;
        for (const char* field : kGltfNodeFields) present += node.contains(field) ? 1 : 0;
        w.object(present);
        for (const char* field : kGltfNodeFields) {
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
    writeRootExtensions(*extensions, w);
  }
  out = std::move(w.bytes());
  return {};
}

}  // namespace

Error readGltf(const std::uint8_t* data, std::size_t size, GltfPart part, std::vector<std::uint8_t>& typed) {
  typed.clear();
  const char* json_begin = nullptr;
  std::size_t json_size = 0;
  if (Error e = findGltfJson(data, size, json_begin, json_size)) return e;
  try {
    json doc;
    if (Error e = readGltfJsonAsPage(json_begin, json_size, part == GltfPart::kNodesAndExtensions, doc)) return e;
    if (Error e = writeGltfPart(doc, part, typed)) {
      typed.clear();
      return e;
    }
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
