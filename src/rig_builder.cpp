// Chain reconstruction (ADR-316 "Chain reconstruction", made precise in DESIGN.md section 4).
//
// Candidates are nodes whose name contains "springbone" (ASCII case-insensitive); a candidate is a
// root only when its metadata entry says isRoot: true. A chain is the root and every glTF
// descendant. Each chain node with children is a simulated joint whose tail is its first child;
// further children start branches under it; leaves only mark where their parent bone ends.
// Nothing here fails: every questionable input becomes a warning and a documented fallback.
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "springbones.h"
#include "transform_math.h"

namespace springbones {
namespace {

constexpr float kMinBoneLength = 1e-6f;  // shorter bones have no direction to simulate

bool containsSpringBoneToken(const std::string& name) {
  static constexpr char kToken[] = "springbone";
  constexpr std::size_t kTokenLength = sizeof(kToken) - 1;
  if (name.size() < kTokenLength) return false;
  for (std::size_t i = 0; i + kTokenLength <= name.size(); ++i) {
    std::size_t k = 0;
    while (k < kTokenLength) {
      char c = name[i + k];
      if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
      if (c != kToken[k]) break;
      ++k;
    }
    if (k == kTokenLength) return true;
  }
  return false;
}

class RigBuilder {
 public:
  RigBuilder(Skeleton skeleton, const ModelEntry& model, std::vector<Warning> warnings, const RigOptions& options)
      : model_(model), options_(options) {
    rig_ = std::make_shared<Rig>();
    rig_->skeleton = std::move(skeleton);
    rig_->warnings = std::move(warnings);
  }

  // Kept out of buildRig, whose frame owns this builder: inlined there, every call of the phases
  // would sit behind an exception landing pad (a JavaScript trampoline in WebAssembly).
#if defined(__GNUC__) || defined(__clang__)
  __attribute__((noinline))
#endif
  std::shared_ptr<const Rig> build() {
    if (!model_.enabled) return rig_;
    indexNodes();
    matchEntries();
    assignChains();
    buildJoints();
    addColliders();
    return rig_;
  }

 private:
  const std::vector<SkeletonNode>& nodes() const { return rig_->skeleton.nodes; }

  void warn(const char* code, std::string message, std::string path = {}) {
    rig_->warnings.push_back(Warning{code, std::move(message), std::move(path)});
  }

  void indexNodes() {
    const auto& all = nodes();
    is_candidate_.resize(all.size());
    first_node_by_name_.reserve(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
      is_candidate_[i] = containsSpringBoneToken(all[i].name);
      first_node_by_name_.emplace(all[i].name, static_cast<int>(i));  // keeps the first
    }
  }

  // Entry per node, by exact (case-sensitive) name. Entries that cannot apply are reported.
  void matchEntries() {
    const auto& all = nodes();
    entry_of_node_.assign(all.size(), -1);
    auto& entry_by_name = entry_by_name_;
    entry_by_name.reserve(model_.bones.size());
    for (std::size_t e = 0; e < model_.bones.size(); ++e) {
      entry_by_name.emplace(model_.bones[e].name, static_cast<int>(e));
    }
    auto& matches = matches_;
    matches.assign(model_.bones.size(), 0);
    for (std::size_t i = 0; i < all.size(); ++i) {
      auto it = entry_by_name.find(all[i].name);
      if (it == entry_by_name.end()) continue;
      ++matches[it->second];
      if (is_candidate_[i]) entry_of_node_[i] = it->second;
    }
    for (std::size_t e = 0; e < model_.bones.size(); ++e) {
      const BoneEntry& entry = model_.bones[e];
      if (matches[e] == 0) {
        warn("bone-not-found", "metadata names '" + entry.name + "', but the GLB has no such node",
             entry.path);
      } else if (!containsSpringBoneToken(entry.name)) {
        warn("bone-not-spring",
             "metadata names '" + entry.name +
                 "', whose name lacks the 'springbone' token; the entry is ignored",
             entry.path);
      } else if (matches[e] > 1) {
        warn("duplicate-node-name", "the GLB has " + std::to_string(matches[e]) + " nodes named '" +
                                        entry.name + "'; the entry applies to each",
             entry.path);
      }
    }
  }

  // chain_of_node_[n] = index of the root joint's node for nodes inside a chain, else -1.
  void assignChains() {
    const auto& all = nodes();
    chain_of_node_.assign(all.size(), -1);
    for (int n : rig_->skeleton.parents_first) {
      const int parent = all[n].parent;
      const int parent_chain = parent >= 0 ? chain_of_node_[parent] : -1;
      const int entry = entry_of_node_[n];
      const bool is_root = entry >= 0 && model_.bones[entry].is_root;
      if (parent_chain >= 0) {
        chain_of_node_[n] = parent_chain;
        if (is_root) {
          warn("nested-root", "'" + all[n].name + "' is marked isRoot but lies inside the chain of '" +
                                  all[parent_chain].name +
                                  "'; it is simulated as a member of that chain with its own parameters",
               model_.bones[entry].path);
        }
      } else if (is_root) {
        chain_of_node_[n] = n;
        root_nodes_.push_back(n);
      }
    }
  }

  int driverFor(int node) {
    auto [it, added] = driver_of_node_.emplace(node, static_cast<int>(rig_->drivers.size()));
    if (added) rig_->drivers.push_back(Driver{node, nodes()[node].name});
    return it->second;
  }

  // The driver of an entry's center, or -1 (world space) with a warning when it cannot be used.
  // Resolved once per entry so a chain sharing an entry warns once.
  int resolveCenter(int entry_index) {
    auto cached = center_of_entry_.find(entry_index);
    if (cached != center_of_entry_.end()) return cached->second;
    const BoneEntry& entry = model_.bones[entry_index];
    int driver = -1;
    if (!entry.center.empty()) {
      auto it = first_node_by_name_.find(entry.center);
      if (it == first_node_by_name_.end()) {
        warn("center-not-found", "center '" + entry.center + "' of '" + entry.name +
                                     "' is not a node of the GLB; using world space",
             entry.path + "/center");
      } else if (is_candidate_[it->second] || chain_of_node_[it->second] >= 0) {
        warn("center-is-spring-bone", "center '" + entry.center + "' of '" + entry.name +
                                          "' is a spring bone itself; using world space",
             entry.path + "/center");
      } else {
        driver = driverFor(it->second);
      }
    }
    center_of_entry_.emplace(entry_index, driver);
    return driver;
  }

  void buildJoints() {
    const auto& all = nodes();
    auto& joint_of_node = joint_of_node_;
    joint_of_node.assign(all.size(), -1);
    auto& queue = queue_;
    for (int root : root_nodes_) {
      const int chain_joint = static_cast<int>(rig_->joints.size());
      bool chain_has_joint = false;
      queue.assign(1, root);
      // Breadth-first inside the chain: parents before children, no recursion.
      for (std::size_t head = 0; head < queue.size(); ++head) {
        const int n = queue[head];
        const SkeletonNode& node = all[n];
        for (int c : node.children) queue.push_back(c);
        const int entry = entry_of_node_[n];
        if (node.children.empty()) {
          if (entry >= 0 && n != root) {
            warn("tip-entry-ignored", "'" + node.name +
                                          "' is a chain tip (no children): it only marks where its "
                                          "parent bone ends, so its parameters are ignored",
                 model_.bones[entry].path);
          }
          continue;
        }
        // Built in place: a local Joint (it owns a vector) would put every call of this loop
        // behind an exception landing pad, which in WebAssembly is a JavaScript trampoline.
        const int joint_index = static_cast<int>(rig_->joints.size());
        const int parent_joint = node.parent >= 0 ? joint_of_node[node.parent] : -1;
        rig_->joints.emplace_back();
        Joint& joint = rig_->joints.back();
        joint.node = n;
        joint.tail_node = node.children.front();
        joint.chain = chain_joint;
        joint.rest_local = node.rest_local;
        joint.tail_local = all[joint.tail_node].rest_local.translation;
        joint.rest_length = glm::length(glm::vec3(all[joint.tail_node].rest_world[3]) -
                                        glm::vec3(node.rest_world[3]));
        joint.parent_joint = parent_joint;
        if (parent_joint >= 0) {
          const Joint& parent = rig_->joints[parent_joint];
          joint.params = parent.params;
          joint.center_driver = parent.center_driver;
        } else if (node.parent >= 0) {
          joint.parent_driver = driverFor(node.parent);
        }
        if (entry >= 0) {
          joint.params = model_.bones[entry].params;
          if (model_.bones[entry].has_center) joint.center_driver = resolveCenter(entry);
        }
        if (!(joint.rest_length > kMinBoneLength)) {
          warn("zero-length-bone", "'" + node.name + "' and its tail '" + all[joint.tail_node].name +
                                       "' are at the same place; the bone keeps its rest rotation");
        }
        joint_of_node[n] = joint_index;
        chain_has_joint = true;
      }
      if (chain_has_joint) {
        rig_->chain_roots.push_back(chain_joint);
      } else {
        warn("root-without-tail", "spring root '" + all[root].name +
                                      "' has no child bone, so there is nothing to simulate");
      }
    }
  }

  // Colliders are attached to drivers by node name; a name the GLB lacks becomes an external
  // driver (the avatar's bone, supplied by the caller). Every joint collides with all of them.
  void addColliders() {
    if (options_.colliders.empty() || rig_->joints.empty()) return;
    const float hit_radius = std::isfinite(options_.hit_radius) ? std::max(0.0f, options_.hit_radius) : 0.0f;
    std::unordered_map<std::string, int> external;
    for (const ColliderSpec& spec : options_.colliders) {
      const bool finite = isFinite(spec.offset) && isFinite(spec.tail) && std::isfinite(spec.radius);
      if (!finite || spec.radius < 0.0f) {
        warn("collider-invalid", "collider on '" + spec.node + "' has a non-finite or negative size; ignored");
        continue;
      }
      int driver = -1;
      auto it = first_node_by_name_.find(spec.node);
      if (it != first_node_by_name_.end()) {
        if (is_candidate_[it->second] || chain_of_node_[it->second] >= 0) {
          warn("collider-on-spring-bone", "collider node '" + spec.node + "' is a spring bone; ignored");
          continue;
        }
        driver = driverFor(it->second);
      } else {
        auto [e, added] = external.emplace(spec.node, static_cast<int>(rig_->drivers.size()));
        if (added) rig_->drivers.push_back(Driver{-1, spec.node});
        driver = e->second;
      }
      Collider collider;
      collider.shape = spec.shape;
      collider.driver = driver;
      collider.offset = spec.offset;
      collider.tail = spec.shape == Collider::Shape::kCapsule ? spec.tail : spec.offset;
      collider.radius = spec.radius;
      rig_->colliders.push_back(collider);
    }
    for (Joint& joint : rig_->joints) {
      joint.hit_radius = hit_radius;
      for (std::size_t c = 0; c < rig_->colliders.size(); ++c) joint.colliders.push_back(static_cast<int>(c));
    }
  }

  const ModelEntry& model_;
  const RigOptions& options_;
  std::shared_ptr<Rig> rig_;
  std::vector<bool> is_candidate_;
  std::vector<int> entry_of_node_;
  std::vector<int> chain_of_node_;
  std::vector<int> root_nodes_;
  // Views of the skeleton's names (the rig owns the skeleton and never changes it), so indexing
  // 7,000 nodes copies no strings.
  std::unordered_map<std::string_view, int> first_node_by_name_;
  std::unordered_map<int, int> center_of_entry_;
  // Scratch of the phases, members rather than locals for the same reason as the in-place Joint.
  std::unordered_map<std::string_view, int> entry_by_name_;
  std::vector<int> matches_;
  std::vector<int> joint_of_node_;
  std::vector<int> queue_;
  std::unordered_map<int, int> driver_of_node_;
};

}  // namespace

bool isSpringBoneName(const std::string& name) { return containsSpringBoneToken(name); }

std::shared_ptr<const Rig> buildRig(Skeleton skeleton, const ModelEntry& model,
                                    std::vector<Warning> warnings, const RigOptions& options) {
  return RigBuilder(std::move(skeleton), model, std::move(warnings), options).build();
}

}  // namespace springbones
