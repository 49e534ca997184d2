// The node hierarchy and rest pose of a glTF document given as a typed value (its `asset` and
// `nodes`; nothing else of the document is read or needs to be given):
//  1. each node's fields are type-checked: a wrong type is an error, because a node we cannot
//     place would misplace every bone below it;
//  2. the rest transform comes from `matrix` (decomposed) or from TRS, rotations renormalized;
//  3. the hierarchy is checked: child indices in range, no node with two parents, no cycles; then
//     rest world matrices are computed iteratively, and must stay finite.
#include "loading/gltf_nodes.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "common/shown_name.h"
#include "common/transform_math.h"
#include "springbones/springbones.h"

namespace springbones {
namespace {

Error fail(ErrorCode code, std::string message) { return Error{code, std::move(message), {}}; }

bool isNumberArray(const TypedValue& value, std::size_t length) {
  if (!value.is_array() || value.size() != length) return false;
  for (const TypedValue& v : value) {
    // Stored as float: a double beyond float range would become infinity.
    if (!v.is_number() || !(std::fabs(v.get<double>()) <= std::numeric_limits<float>::max())) { return false; }
  }
  return true;
}

// The types of the fields we use: a field of the wrong type is an error, never skipped without
// a word, which would leave the node at the origin.
Error checkNode(const TypedValue& node, std::size_t index) {
  const std::string where = "node " + std::to_string(index);
  if (!node.is_object()) return fail(ErrorCode::kGltfInvalid, where + " is not an object");
  if (auto it = node.find("name"); it != node.end() && !it->is_string()) {
    return fail(ErrorCode::kGltfInvalid, where + ": name is not a string");
  }
  if (auto it = node.find("children"); it != node.end()) {
    if (!it->is_array()) return fail(ErrorCode::kGltfInvalid, where + ": children is not an array");
    for (const TypedValue& c : *it) {
      // Bounded here because the skeleton stores indices as int.
      if (!c.is_number_integer() || c.get<std::int64_t>() < 0 || c.get<std::int64_t>() > std::int64_t(kMaxNodes)) {
        return fail(ErrorCode::kGltfInvalid, where + ": a child index is not a node index");
      }
    }
  }
  static const std::pair<const char*, std::size_t> kTransformFields[] = {
      {"translation", 3}, {"rotation", 4}, {"scale", 3}, {"matrix", 16}};
  for (const auto& [field, length] : kTransformFields) {
    auto it = node.find(field);
    if (it != node.end() && !isNumberArray(*it, length)) {
      return fail(ErrorCode::kGltfInvalid, where + ": " + field + " is not an array of " + std::to_string(length) +
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
        return fail(ErrorCode::kGltfInvalid,
                    "node " + std::to_string(p) + " lists child " + std::to_string(c) + ", which does not exist");
      }
      if (c == p) {
        return fail(ErrorCode::kHierarchyCycle,
                    "node " + std::to_string(p) + " ('" + shownName(nodes[p].name) + "') is its own child");
      }
      if (nodes[c].parent != -1) {
        return fail(ErrorCode::kHierarchyMultipleParents,
                    "node " + std::to_string(c) + " ('" + shownName(nodes[c].name) + "') is a child of both node " +
                        std::to_string(nodes[c].parent) + " and node " + std::to_string(p));
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
    std::vector<unsigned char> reached(nodes.size(), 0);
    for (int i : order) reached[i] = true;
    int first = 0;
    while (reached[first]) ++first;
    return fail(ErrorCode::kHierarchyCycle, "node " + std::to_string(first) + " ('" + shownName(nodes[first].name) +
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
    bool finite = std::isfinite(t.translation.x) && std::isfinite(t.translation.y) && std::isfinite(t.translation.z) &&
                  std::isfinite(t.scale.x) && std::isfinite(t.scale.y) && std::isfinite(t.scale.z) &&
                  std::isfinite(t.rotation.x) && std::isfinite(t.rotation.y) && std::isfinite(t.rotation.z) &&
                  std::isfinite(t.rotation.w);
    const float* w = n.rest_world.m;
    for (int c = 0; c < 4; ++c) {
      finite = finite && std::isfinite(w[4 * c]) && std::isfinite(w[4 * c + 1]) && std::isfinite(w[4 * c + 2]);
    }
    if (!finite) {
      return fail(ErrorCode::kGltfInvalid, "node " + std::to_string(i) + " ('" + shownName(n.name) +
                                               "'): its rest transform overflows float range");
    }
  }
  return {};
}

// The rest transform from a node's fields (null when absent): `matrix` wins over TRS, as in glTF.
Transform restTransform(const double* matrix, const double* translation, const double* rotation, const double* scale) {
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

// The message a document without a string `asset.version` has always had (tinygltf's, word for
// word, when tinygltf read the nodes).
constexpr const char* kAssetMissing = "\"asset\" object not found in .gltf or not an object type\n";

// The numbers of a field checked by checkNode, or null when the node does not have it.
const double* numbers(const TypedValue& node, const char* field, double* storage) {
  auto it = node.find(field);
  if (it == node.end()) return nullptr;
  for (std::size_t i = 0; i < it->size(); ++i) storage[i] = (*it)[i].number();
  return storage;
}

SkeletonNode skeletonNode(const TypedValue& node) {
  SkeletonNode out;
  if (auto name = node.find("name"); name != node.end()) out.name = name->get<std::string>();
  if (auto children = node.find("children"); children != node.end()) {
    out.children.reserve(children->size());
    for (const TypedValue& c : *children) out.children.push_back(c.get<int>());
  }
  double matrix[16], translation[3], rotation[4], scale[3];
  out.rest_local = restTransform(numbers(node, "matrix", matrix), numbers(node, "translation", translation),
                                 numbers(node, "rotation", rotation), numbers(node, "scale", scale));
  return out;
}

}  // namespace

Error readGltfDocument(const TypedValue& doc, Skeleton& out) {
  out = Skeleton{};
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
  Skeleton skeleton;
  if (nodes != doc.end()) {
    skeleton.nodes.reserve(nodes->size());
    for (const TypedValue& node : *nodes) skeleton.nodes.push_back(skeletonNode(node));
  }
  if (Error e = linkHierarchy(skeleton)) return e;
  out = std::move(skeleton);
  return {};
}

}  // namespace springbones
