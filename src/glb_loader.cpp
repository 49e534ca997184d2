// GLB / glTF loading: the node hierarchy and rest pose, nothing else.
//
// We only need node names, parents and rest transforms, and wearables arrive from anyone, so the
// loader works in three stages:
//  1. our own check of the GLB container (magic, version, chunk lengths), so a truncated or
//     malformed file gets a precise error code instead of a generic parse failure;
//  2. nlohmann-json parses the JSON chunk; we keep only `asset.version` and the TRS/matrix,
//     name and children of each node. Buffers, images, meshes, accessors, extras and extensions
//     are dropped before anything decodes them (base64 data URIs included), which keeps loading
//     cheap and keeps hostile payloads (deeply nested extras) away from recursive code;
//  3. tinygltf reads that reduced document into its node model (the glTF semantics, defaults,
//     required `asset.version`), and we check the hierarchy ourselves: child indices in range, no
//     node with two parents, no cycles, then rest world matrices computed iteratively.
#include <fstream>  // tinygltf expects it even with TINYGLTF_NO_FS

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_FS
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include "springbones.h"
#include "transform_math.h"

namespace springbones {
namespace {

using nlohmann::json;

constexpr std::uint32_t kGlbMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;     // "JSON"
constexpr std::size_t kGlbHeaderBytes = 12;
constexpr std::size_t kChunkHeaderBytes = 8;

std::uint32_t readU32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) |
         (std::uint32_t(p[3]) << 24);
}

Error fail(ErrorCode code, std::string message) { return Error{code, std::move(message), {}}; }

bool looksLikeJsonText(const std::uint8_t* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
    // A UTF-8 byte order mark is tolerated in front of glTF JSON text.
    if (i == 0 && size >= 3 && data[0] == 0xEF && data[1] == 0xBB && data[2] == 0xBF) {
      i += 2;
      continue;
    }
    return c == '{';
  }
  return false;
}

// Finds the JSON text inside the input: the JSON chunk of a GLB, or the whole input.
Error extractJsonText(const std::uint8_t* data, std::size_t size, const char*& json_begin,
                      std::size_t& json_size) {
  if (size >= 4 && readU32(data) == kGlbMagic) {
    if (size < kGlbHeaderBytes + kChunkHeaderBytes) {
      return fail(ErrorCode::kGlbTruncated, "GLB is " + std::to_string(size) +
                                                " bytes, shorter than its 20-byte header");
    }
    const std::uint32_t version = readU32(data + 4);
    if (version != 2) {
      return fail(ErrorCode::kGlbBadChunk,
                  "GLB container version " + std::to_string(version) + " is not supported (2 is)");
    }
    const std::uint32_t declared = readU32(data + 8);
    if (declared > size) {
      return fail(ErrorCode::kGlbTruncated, "GLB header declares " + std::to_string(declared) +
                                                " bytes but only " + std::to_string(size) +
                                                " are present");
    }
    if (declared < kGlbHeaderBytes + kChunkHeaderBytes) {
      return fail(ErrorCode::kGlbBadChunk,
                  "GLB header declares a length of " + std::to_string(declared) + " bytes");
    }
    const std::uint32_t chunk_length = readU32(data + 12);
    const std::uint32_t chunk_type = readU32(data + 16);
    if (chunk_type != kChunkJson) {
      return fail(ErrorCode::kGlbBadChunk, "the first GLB chunk is not a JSON chunk");
    }
    if (std::size_t(chunk_length) > declared - kGlbHeaderBytes - kChunkHeaderBytes) {
      return fail(ErrorCode::kGlbTruncated, "GLB JSON chunk declares " +
                                                std::to_string(chunk_length) +
                                                " bytes, more than the file holds");
    }
    json_begin = reinterpret_cast<const char*>(data + kGlbHeaderBytes + kChunkHeaderBytes);
    json_size = chunk_length;
    return {};
  }
  if (looksLikeJsonText(data, size)) {
    json_begin = reinterpret_cast<const char*>(data);
    json_size = size;
    return {};
  }
  if (size < 4) {
    return fail(ErrorCode::kGlbTruncated,
                "input is " + std::to_string(size) + " bytes: too short to be a GLB or glTF");
  }
  return fail(ErrorCode::kGlbBadMagic, "input is neither a GLB (magic 'glTF') nor glTF JSON text");
}

bool isNumberArray(const json& value, std::size_t length) {
  if (!value.is_array() || value.size() != length) return false;
  for (const json& v : value) {
    // Stored as float: a double beyond float range would become infinity.
    if (!v.is_number() || !(std::fabs(v.get<double>()) <= std::numeric_limits<float>::max())) {
      return false;
    }
  }
  return true;
}

// Copies the fields we use from one node, checking their types. Wrong types are errors: a node
// whose transform we cannot read would put every bone below it in the wrong place.
Error reduceNode(const json& node, std::size_t index, json& out) {
  const std::string where = "node " + std::to_string(index);
  if (!node.is_object()) return fail(ErrorCode::kGltfInvalid, where + " is not an object");
  out = json::object();
  if (auto it = node.find("name"); it != node.end()) {
    if (!it->is_string()) return fail(ErrorCode::kGltfInvalid, where + ": name is not a string");
    out["name"] = *it;
  }
  if (auto it = node.find("children"); it != node.end()) {
    if (!it->is_array()) return fail(ErrorCode::kGltfInvalid, where + ": children is not an array");
    for (const json& c : *it) {
      // Bounded here because tinygltf stores indices as int.
      if (!c.is_number_integer() || c.get<std::int64_t>() < 0 ||
          c.get<std::int64_t>() > std::int64_t(kMaxNodes)) {
        return fail(ErrorCode::kGltfInvalid, where + ": a child index is not a node index");
      }
    }
    out["children"] = *it;
  }
  static const std::pair<const char*, std::size_t> kTransformFields[] = {
      {"translation", 3}, {"rotation", 4}, {"scale", 3}, {"matrix", 16}};
  for (const auto& [field, length] : kTransformFields) {
    auto it = node.find(field);
    if (it == node.end()) continue;
    if (!isNumberArray(*it, length)) {
      return fail(ErrorCode::kGltfInvalid, where + ": " + field + " is not an array of " +
                                               std::to_string(length) +
                                               " finite numbers within float range");
    }
    out[field] = *it;
  }
  return {};
}

Error reduceDocument(const json& doc, json& out) {
  if (!doc.is_object()) return fail(ErrorCode::kGltfInvalid, "glTF JSON is not an object");
  out = json::object();
  if (auto it = doc.find("asset"); it != doc.end() && it->is_object()) {
    out["asset"] = json::object();
    if (auto v = it->find("version"); v != it->end() && v->is_string()) {
      out["asset"]["version"] = *v;
    }
  }
  json nodes = json::array();
  if (auto it = doc.find("nodes"); it != doc.end()) {
    if (!it->is_array()) return fail(ErrorCode::kGltfInvalid, "glTF 'nodes' is not an array");
    if (it->size() > kMaxNodes) {
      return fail(ErrorCode::kLimitExceeded, "glTF has " + std::to_string(it->size()) +
                                                 " nodes, more than the limit of " +
                                                 std::to_string(kMaxNodes));
    }
    for (std::size_t i = 0; i < it->size(); ++i) {
      json reduced;
      if (Error e = reduceNode((*it)[i], i, reduced)) return e;
      nodes.push_back(std::move(reduced));
    }
  }
  out["nodes"] = std::move(nodes);
  return {};
}

// Parent links from children lists, rejecting out-of-range indices and second parents; then an
// iterative walk from the roots that must reach every node, or some nodes form a cycle.
Error linkHierarchy(Skeleton& skeleton) {
  auto& nodes = skeleton.nodes;
  const int count = static_cast<int>(nodes.size());
  for (int p = 0; p < count; ++p) {
    for (int c : nodes[p].children) {
      if (c < 0 || c >= count) {
        return fail(ErrorCode::kGltfInvalid, "node " + std::to_string(p) + " lists child " +
                                                 std::to_string(c) + ", which does not exist");
      }
      if (c == p) {
        return fail(ErrorCode::kHierarchyCycle,
                    "node " + std::to_string(p) + " ('" + nodes[p].name + "') is its own child");
      }
      if (nodes[c].parent != -1) {
        return fail(ErrorCode::kHierarchyMultipleParents,
                    "node " + std::to_string(c) + " ('" + nodes[c].name +
                        "') is a child of both node " + std::to_string(nodes[c].parent) +
                        " and node " + std::to_string(p));
      }
      nodes[c].parent = p;
    }
  }
  auto& order = skeleton.parents_first;
  order.clear();
  order.reserve(nodes.size());
  for (int i = 0; i < count; ++i) {
    if (nodes[i].parent == -1) order.push_back(i);
  }
  // Breadth-first over the forest: `order` doubles as the queue, so no recursion and no stack.
  for (std::size_t head = 0; head < order.size(); ++head) {
    for (int c : nodes[order[head]].children) order.push_back(c);
  }
  if (order.size() != nodes.size()) {
    std::vector<bool> reached(nodes.size(), false);
    for (int i : order) reached[i] = true;
    int first = 0;
    while (reached[first]) ++first;
    return fail(ErrorCode::kHierarchyCycle, "node " + std::to_string(first) + " ('" +
                                                nodes[first].name +
                                                "') is its own ancestor (the hierarchy has a cycle)");
  }
  for (int i : order) {
    SkeletonNode& n = nodes[i];
    const glm::mat4 local = composeTransform(n.rest_local);
    n.rest_world = n.parent < 0 ? local : nodes[n.parent].rest_world * local;
    // Float overflow (a decomposed matrix of huge entries, scales multiplying down a chain)
    // would hand infinities and NaNs to the solver.
    const glm::quat& q = n.rest_local.rotation;
    bool finite = isFinite(n.rest_local.translation) && isFinite(n.rest_local.scale) &&
                  isFinite(glm::vec3(q.x, q.y, q.z)) && std::isfinite(q.w);
    for (int c = 0; c < 4; ++c) finite = finite && isFinite(glm::vec3(n.rest_world[c]));
    if (!finite) {
      return fail(ErrorCode::kGltfInvalid, "node " + std::to_string(i) + " ('" + n.name +
                                               "'): its rest transform overflows float range");
    }
  }
  return {};
}

Transform nodeRestTransform(const tinygltf::Node& node) {
  Transform t;
  if (node.matrix.size() == 16) {
    glm::mat4 m;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) m[c][r] = static_cast<float>(node.matrix[c * 4 + r]);
    }
    return decomposeTransform(m);
  }
  if (node.translation.size() == 3) {
    t.translation = glm::vec3(node.translation[0], node.translation[1], node.translation[2]);
  }
  if (node.rotation.size() == 4) {
    const std::vector<double>& r = node.rotation;
    // In double: the squares of float-range components overflow a float.
    const double len = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
    // glTF demands unit quaternions; renormalize small errors, treat a zero one as identity.
    t.rotation = len > 1e-6 ? glm::quat(static_cast<float>(r[3] / len), static_cast<float>(r[0] / len),
                                        static_cast<float>(r[1] / len), static_cast<float>(r[2] / len))
                            : glm::quat(1, 0, 0, 0);
  }
  if (node.scale.size() == 3) t.scale = glm::vec3(node.scale[0], node.scale[1], node.scale[2]);
  return t;
}

}  // namespace

Error loadSkeleton(const std::uint8_t* data, std::size_t size, Skeleton& out) {
  out = Skeleton{};
  if (data == nullptr && size != 0) return fail(ErrorCode::kInvalidArgument, "null GLB buffer");
  if (size == 0) return fail(ErrorCode::kGlbTruncated, "input is empty");

  const char* json_begin = nullptr;
  std::size_t json_size = 0;
  if (Error e = extractJsonText(data, size, json_begin, json_size)) return e;
  if (json_size > kMaxGltfJsonBytes) {
    return fail(ErrorCode::kLimitExceeded, "glTF JSON is " + std::to_string(json_size) +
                                               " bytes, more than the limit of " +
                                               std::to_string(kMaxGltfJsonBytes));
  }

  json reduced;
  try {
    json doc = json::parse(json_begin, json_begin + json_size);
    if (Error e = reduceDocument(doc, reduced)) return e;
  } catch (const json::exception& ex) {
    return fail(ErrorCode::kGltfBadJson, std::string("glTF JSON does not parse: ") + ex.what());
  } catch (const std::exception& ex) {
    return fail(ErrorCode::kGltfBadJson, std::string("glTF JSON could not be read: ") + ex.what());
  }

  tinygltf::Model model;
  try {
    tinygltf::TinyGLTF gltf;
    std::string err, warn;
    const std::string text = reduced.dump();
    if (!gltf.LoadASCIIFromString(&model, &err, &warn, text.data(),
                                  static_cast<unsigned int>(text.size()), "",
                                  tinygltf::REQUIRE_VERSION)) {
      return fail(ErrorCode::kGltfInvalid, "not a valid glTF: " + (err.empty() ? warn : err));
    }
  } catch (const std::exception& ex) {
    return fail(ErrorCode::kGltfInvalid, std::string("not a valid glTF: ") + ex.what());
  }

  Skeleton skeleton;
  skeleton.nodes.resize(model.nodes.size());
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const tinygltf::Node& src = model.nodes[i];
    SkeletonNode& dst = skeleton.nodes[i];
    dst.name = src.name;
    dst.children = src.children;
    dst.rest_local = nodeRestTransform(src);
  }
  if (Error e = linkHierarchy(skeleton)) return e;
  out = std::move(skeleton);
  return {};
}

}  // namespace springbones
