// GLB / glTF loading: the node hierarchy and rest pose, and for the VRM reader the document's root
// `extensions`, all from one parse.
//
// Wearables arrive from anyone and we only need node names, parents and rest transforms, so:
//  1. our own check of the GLB container (gltf_json.h), so a truncated or malformed file gets a
//     precise error code (tinygltf reports these as text only);
//  2. nlohmann-json parses the JSON text once, in linear time and without recursion (so deeply
//     nested values are harmless). Only the root's `asset`, `nodes` and, for the VRM reader,
//     `extensions` are read: buffers, images, meshes, accessors, materials... stay JSON values,
//     never decoded, fetched or validated, so a broken one cannot stop the load;
//  3. each node's fields are type-checked (wrong types are errors: a node we cannot place would
//     misplace every bone below it), its `extras` and `extensions` erased (tinygltf would convert
//     them into its Value type recursively, which a deeply nested one would turn into a stack
//     overflow), and tinygltf's own node reader fills a tinygltf::Node from it. tinygltf's public
//     entry points cannot be used: they fail the whole load on any broken buffer, accessor or mesh
//     and convert every extras/extensions recursively; the node reader is visible here because
//     this is the one file that compiles tinygltf's implementation;
//  4. we check the hierarchy ourselves: child indices in range, no node with two parents, no
//     cycles, then rest world matrices computed iteratively.
#include <fstream>  // tiny_gltf.h uses it even with TINYGLTF_NO_FS

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

#include "common/transform_math.h"
#include "loading/gltf_json.h"
#include "springbones/springbones.h"

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

// The types of the fields we use. tinygltf's node reader skips a field of the wrong type without
// a word, which would leave the node at the origin.
Error checkNode(const json& node, std::size_t index) {
  const std::string where = "node " + std::to_string(index);
  if (!node.is_object()) return fail(ErrorCode::kGltfInvalid, where + " is not an object");
  if (auto it = node.find("name"); it != node.end() && !it->is_string()) {
    return fail(ErrorCode::kGltfInvalid, where + ": name is not a string");
  }
  if (auto it = node.find("children"); it != node.end()) {
    if (!it->is_array()) return fail(ErrorCode::kGltfInvalid, where + ": children is not an array");
    for (const json& c : *it) {
      // Bounded here because tinygltf and the skeleton store indices as int.
      if (!c.is_number_integer() || c.get<std::int64_t>() < 0 ||
          c.get<std::int64_t>() > std::int64_t(kMaxNodes)) {
        return fail(ErrorCode::kGltfInvalid, where + ": a child index is not a node index");
      }
    }
  }
  static const std::pair<const char*, std::size_t> kTransformFields[] = {
      {"translation", 3}, {"rotation", 4}, {"scale", 3}, {"matrix", 16}};
  for (const auto& [field, length] : kTransformFields) {
    auto it = node.find(field);
    if (it != node.end() && !isNumberArray(*it, length)) {
      return fail(ErrorCode::kGltfInvalid, where + ": " + field + " is not an array of " +
                                               std::to_string(length) +
                                               " finite numbers within float range");
    }
  }
  return {};
}

// a * b, the same IEEE operations in the same order as glm's mat4 operator* (so the same bits),
// written out: at -Oz glm's vector operators are each an out-of-line call, 7,000 times a load.
void multiplyLikeGlm(const float* A, const float* B, float* out) {
  float R[16];
  for (int i = 0; i < 4; ++i) {
    for (int r = 0; r < 4; ++r) {
      R[4 * i + r] = A[r] * B[4 * i] + A[4 + r] * B[4 * i + 1] + A[8 + r] * B[4 * i + 2] + A[12 + r] * B[4 * i + 3];
    }
  }
  std::memcpy(out, R, sizeof R);
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
      n.rest_world = fromGlm(local);
    } else {
      multiplyLikeGlm(nodes[n.parent].rest_world.m, &local[0][0], n.rest_world.m);
    }
    // Float overflow (a decomposed matrix of huge entries, scales multiplying down a chain)
    // would hand infinities and NaNs to the solver.
    const Transform& t = n.rest_local;
    bool finite = std::isfinite(t.translation.x) && std::isfinite(t.translation.y) &&
                  std::isfinite(t.translation.z) && std::isfinite(t.scale.x) && std::isfinite(t.scale.y) &&
                  std::isfinite(t.scale.z) && std::isfinite(t.rotation.x) && std::isfinite(t.rotation.y) &&
                  std::isfinite(t.rotation.z) && std::isfinite(t.rotation.w);
    const float* w = n.rest_world.m;
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

// The rest transform from a node's fields (null when absent): `matrix` wins over TRS, as in glTF.
Transform restTransform(const double* matrix, const double* translation, const double* rotation,
                        const double* scale) {
  if (matrix != nullptr) return decomposeTransform(glm::mat4(glm::make_mat4(matrix)));
  const auto vec3 = [](const double* v) { return Vec3{float(v[0]), float(v[1]), float(v[2])}; };
  Transform t;
  if (translation != nullptr) t.translation = vec3(translation);
  if (rotation != nullptr) {
    const double* r = rotation;
    // In double: the squares of float-range components overflow a float.
    const double len = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
    // glTF demands unit quaternions; renormalize small errors, treat a zero one as identity.
    if (len > 1e-6) t.rotation = Quat{float(r[0] / len), float(r[1] / len), float(r[2] / len), float(r[3] / len)};
  }
  if (scale != nullptr) t.scale = vec3(scale);
  return t;
}

// The message tinygltf gives for a document without a string `asset.version`, kept word for word.
constexpr const char* kAssetMissing = "\"asset\" object not found in .gltf or not an object type\n";

SkeletonNode skeletonNode(tinygltf::Node& node) {
  SkeletonNode out;
  out.name = std::move(node.name);
  out.children = std::move(node.children);
  auto present = [](const std::vector<double>& v) { return v.empty() ? nullptr : v.data(); };
  out.rest_local = restTransform(present(node.matrix), present(node.translation), present(node.rotation),
                                 present(node.scale));
  return out;
}

// Stages 3 and 4 on the parsed document (see the top of the file).
Error readDocument(json& doc, Skeleton& skeleton) {
  if (!doc.is_object()) return fail(ErrorCode::kGltfInvalid, "glTF JSON is not an object");
  auto nodes = doc.find("nodes");
  if (nodes != doc.end()) {
    if (!nodes->is_array()) return fail(ErrorCode::kGltfInvalid, "glTF 'nodes' is not an array");
    if (nodes->size() > kMaxNodes) {
      return fail(ErrorCode::kLimitExceeded, "glTF has " + std::to_string(nodes->size()) +
                                                 " nodes, more than the limit of " + std::to_string(kMaxNodes));
    }
    for (std::size_t i = 0; i < nodes->size(); ++i) {
      if (Error e = checkNode((*nodes)[i], i)) return e;
    }
  }
  auto asset = doc.find("asset");
  auto version = asset != doc.end() && asset->is_object() ? asset->find("version") : doc.end();
  if (asset == doc.end() || !asset->is_object() || version == asset->end() || !version->is_string()) {
    return fail(ErrorCode::kGltfInvalid, std::string("not a valid glTF: ") + kAssetMissing);
  }
  if (nodes == doc.end()) return linkHierarchy(skeleton);
  skeleton.nodes.reserve(nodes->size());
  std::string ignored;  // the node reader reports only missing required fields, and a node has none
  for (json& node : *nodes) {
    node.erase("extras");
    node.erase("extensions");
    tinygltf::Node read;
    tinygltf::ParseNode(&read, &ignored, node, /*store_original_json_for_extras_and_extensions=*/false);
    skeleton.nodes.push_back(skeletonNode(read));
  }
  return linkHierarchy(skeleton);
}

}  // namespace

Error loadSkeletonAndExtensions(const std::uint8_t* data, std::size_t size, Skeleton& out,
                                json* extensions) {
  out = Skeleton{};
  if (extensions != nullptr) *extensions = nullptr;
  const char* json_begin = nullptr;
  std::size_t json_size = 0;
  if (Error e = findGltfJson(data, size, json_begin, json_size)) return e;
  try {
    // No parser callback: nlohmann's callback parser scans a container's elements each time one of
    // them ends, which is quadratic in the length of an array or object.
    json doc = json::parse(json_begin, json_begin + json_size);
    Skeleton skeleton;
    if (Error e = readDocument(doc, skeleton)) return e;
    if (extensions != nullptr) {
      if (auto it = doc.find("extensions"); it != doc.end()) *extensions = std::move(*it);
    }
    out = std::move(skeleton);
  } catch (const json::exception& ex) {
    return fail(ErrorCode::kGltfBadJson, std::string("glTF JSON does not parse: ") + ex.what());
  } catch (const std::exception& ex) {  // allocation failure on an absurd document
    return fail(ErrorCode::kGltfBadJson, std::string("glTF JSON could not be read: ") + ex.what());
  }
  return {};
}

Error loadSkeleton(const std::uint8_t* data, std::size_t size, Skeleton& out) {
  return loadSkeletonAndExtensions(data, size, out, nullptr);
}

}  // namespace springbones
