// GLB / glTF loading: the node hierarchy and rest pose, nothing else.
//
// We only need node names, parents and rest transforms, and wearables arrive from anyone, so the
// loader works in three stages:
//  1. our own check of the GLB container (magic, version, chunk lengths; gltf_json.h), so a
//     truncated or malformed file gets a precise error code instead of a generic parse failure;
//  2. the JSON chunk is read for `asset.version` and the TRS/matrix, name and children of each
//     node. Buffers, images, meshes, accessors, extras and extensions are skipped without being
//     decoded (base64 data URIs included), and nothing recurses, so hostile payloads (deeply
//     nested extras) cannot exhaust the stack: nlohmann-json parses the whole document, the
//     fields we use are type-checked node by node (reduceDocument) and `asset.version` required,
//     with the precise error for a bad document;
//  3. we check the hierarchy ourselves: child indices in range, no node with two parents, no
//     cycles, then rest world matrices computed iteratively.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "gltf_json.h"
#include "springbones.h"
#include "transform_math.h"

namespace springbones {
namespace {

using nlohmann::json;

Error fail(ErrorCode code, std::string message) { return Error{code, std::move(message), {}}; }

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
      // Bounded here because the skeleton stores indices as int.
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

// a * b, the same IEEE operations in the same order as glm's mat4 operator* (so the same bits),
// written out: at -Oz glm's vector operators are each an out-of-line call, 7,000 times a load.
void multiplyLikeGlm(const glm::mat4& a, const glm::mat4& b, glm::mat4& out) {
  const float* A = &a[0][0];
  const float* B = &b[0][0];
  float R[16];
  for (int i = 0; i < 4; ++i) {
    for (int r = 0; r < 4; ++r) {
      R[4 * i + r] = A[r] * B[4 * i] + A[4 + r] * B[4 * i + 1] + A[8 + r] * B[4 * i + 2] + A[12 + r] * B[4 * i + 3];
    }
  }
  std::memcpy(&out[0][0], R, sizeof R);
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
    if (n.parent < 0) {
      n.rest_world = local;
    } else {
      multiplyLikeGlm(nodes[n.parent].rest_world, local, n.rest_world);
    }
    // Float overflow (a decomposed matrix of huge entries, scales multiplying down a chain)
    // would hand infinities and NaNs to the solver.
    const Transform& t = n.rest_local;
    bool finite = std::isfinite(t.translation.x) && std::isfinite(t.translation.y) &&
                  std::isfinite(t.translation.z) && std::isfinite(t.scale.x) && std::isfinite(t.scale.y) &&
                  std::isfinite(t.scale.z) && std::isfinite(t.rotation.x) && std::isfinite(t.rotation.y) &&
                  std::isfinite(t.rotation.z) && std::isfinite(t.rotation.w);
    const float* w = &n.rest_world[0][0];
    for (int c = 0; c < 4; ++c) {
      finite = finite && std::isfinite(w[4 * c]) && std::isfinite(w[4 * c + 1]) && std::isfinite(w[4 * c + 2]);
    }
    if (!finite) {
      return fail(ErrorCode::kGltfInvalid, "node " + std::to_string(i) + " ('" + n.name +
                                               "'): its rest transform overflows float range");
    }
  }
  return {};
}

// The rest transform from a node's fields (null when absent): `matrix` wins over TRS, as in
// glTF. Both readers hand their doubles to this one function, so they agree to the bit.
Transform restTransform(const double* matrix, const double* translation, const double* rotation,
                        const double* scale) {
  Transform t;
  if (matrix != nullptr) {
    glm::mat4 m;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) m[c][r] = static_cast<float>(matrix[c * 4 + r]);
    }
    return decomposeTransform(m);
  }
  if (translation != nullptr) {
    t.translation = glm::vec3(translation[0], translation[1], translation[2]);
  }
  if (rotation != nullptr) {
    const double* r = rotation;
    // In double: the squares of float-range components overflow a float.
    const double len = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
    // glTF demands unit quaternions; renormalize small errors, treat a zero one as identity.
    t.rotation = len > 1e-6 ? glm::quat(static_cast<float>(r[3] / len), static_cast<float>(r[0] / len),
                                        static_cast<float>(r[1] / len), static_cast<float>(r[2] / len))
                            : glm::quat(1, 0, 0, 0);
  }
  if (scale != nullptr) t.scale = glm::vec3(scale[0], scale[1], scale[2]);
  return t;
}

// The message tinygltf gave for a document without a string `asset.version`, kept word for word.
constexpr const char* kAssetMissing = "\"asset\" object not found in .gltf or not an object type\n";

// ---------------------------------------------------------------------------------------------
// The checked reader: nlohmann DOM, reduced and type-checked.

Error readCheckedDocument(const char* json_begin, std::size_t json_size, Skeleton& skeleton) {
  json reduced;
  try {
    json doc = json::parse(json_begin, json_begin + json_size);
    if (Error e = reduceDocument(doc, reduced)) return e;
  } catch (const json::exception& ex) {
    return fail(ErrorCode::kGltfBadJson, std::string("glTF JSON does not parse: ") + ex.what());
  } catch (const std::exception& ex) {
    return fail(ErrorCode::kGltfBadJson, std::string("glTF JSON could not be read: ") + ex.what());
  }
  if (!reduced.contains("asset") || !reduced["asset"].contains("version")) {
    return fail(ErrorCode::kGltfInvalid, std::string("not a valid glTF: ") + kAssetMissing);
  }
  const json& nodes = reduced["nodes"];
  skeleton.nodes.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const json& src = nodes[i];
    SkeletonNode& dst = skeleton.nodes[i];
    if (auto it = src.find("name"); it != src.end()) dst.name = it->get<std::string>();
    if (auto it = src.find("children"); it != src.end()) {
      dst.children.reserve(it->size());
      for (const json& c : *it) dst.children.push_back(static_cast<int>(c.get<std::int64_t>()));
    }
    double fields[4][16];
    const double* present[4] = {nullptr, nullptr, nullptr, nullptr};
    static const char* const kFields[4] = {"matrix", "translation", "rotation", "scale"};
    for (int f = 0; f < 4; ++f) {
      auto it = src.find(kFields[f]);
      if (it == src.end()) continue;
      for (std::size_t k = 0; k < it->size(); ++k) fields[f][k] = (*it)[k].get<double>();
      present[f] = fields[f];
    }
    dst.rest_local = restTransform(present[0], present[1], present[2], present[3]);
  }
  return {};
}

Error loadSkeletonWith(const std::uint8_t* data, std::size_t size, Skeleton& out) {
  out = Skeleton{};
  const char* json_begin = nullptr;
  std::size_t json_size = 0;
  if (Error e = findGltfJson(data, size, json_begin, json_size)) return e;

  Skeleton skeleton;
  if (Error e = readCheckedDocument(json_begin, json_size, skeleton)) return e;
  if (skeleton.nodes.capacity() > skeleton.nodes.size() + skeleton.nodes.size() / 4 + 16) {
    skeleton.nodes.shrink_to_fit();  // the rig keeps the skeleton for its lifetime
  }
  if (Error e = linkHierarchy(skeleton)) return e;
  out = std::move(skeleton);
  return {};
}

}  // namespace

Error loadSkeleton(const std::uint8_t* data, std::size_t size, Skeleton& out) {
  return loadSkeletonWith(data, size, out);
}

}  // namespace springbones
