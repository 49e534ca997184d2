// Chain reconstruction (ADR-316 "Chain reconstruction"; our reading of it: docs/semantics.md,
// "Discovery and roots" to "Center").
//
// Candidates are nodes whose name contains "springbone" (ASCII case-insensitive); a candidate is a
// root only when its metadata entry says isRoot: true. A chain is the root and every glTF
// descendant. Each chain node with children is a simulated joint whose tail is its first child;
// further children start branches under it; leaves only mark where their parent bone ends.
// Nothing here fails: every questionable input becomes a warning and a documented fallback.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>

#include "common/name_index.h"
#include "common/shown_name.h"
#include "common/transform_math.h"
#include "loading/body_colliders.h"
#include "loading/collider_from_spec.h"
#include "loading/vrm_limits.h"
#include "springbones/springbones.h"

namespace springbones {
namespace {

constexpr float kMinBoneLength = 1e-6f;  // shorter bones have no direction to simulate

// A number for a warning: 7 significant digits, 1e+30 rather than 31 digits.
std::string formatNumber(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", static_cast<double>(v));
  return text;
}

class RigBuilder {
 public:
  RigBuilder(Skeleton skeleton, const ModelEntry& model, std::vector<Warning> warnings, const RigOptions& options)
      : model_(model), options_(options) {
    rig_ = std::make_shared<Rig>();
    rig_->skeleton = std::move(skeleton);
    rig_->warnings = std::move(warnings);
  }

  std::shared_ptr<const Rig> build() {
    if (!model_.enabled) return rig_;
    indexNodes();
    matchEntries();
    assignChains();
    buildJoints();
    addColliders();
    applyLimitOptions(options_.limits, *rig_);
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
    for (std::size_t i = 0; i < all.size(); ++i) is_candidate_[i] = isSpringBoneName(all[i].name);
  }

  // The first node named `name`, or -1. Only centers and colliders look nodes up by name, and most
  // wearables have neither: the index is built on the first lookup (for 7,000 nodes it was a
  // tenth of the build).
  int nodeNamed(std::string_view name) {
    if (!nodes_indexed_) {
      const auto& all = nodes();
      first_node_by_name_.reserve(all.size());
      for (std::size_t i = 0; i < all.size(); ++i) first_node_by_name_.insertFirst(all[i].name, static_cast<int>(i));
      nodes_indexed_ = true;
    }
    return first_node_by_name_.find(name);
  }

  // Entry per node, by exact (case-sensitive) name. Entries that cannot apply are reported.
  void matchEntries() {
    matchNodes();
    for (std::size_t e = 0; e < model_.bones.size(); ++e) {
      if (matches_[e] != 1 || !entry_is_spring_[e]) warnEntry(e);
    }
  }

  void matchNodes() {
    const auto& all = nodes();
    entry_of_node_.assign(all.size(), -1);
    entry_by_name_.reserve(model_.bones.size());
    entry_is_spring_.resize(model_.bones.size());
    bool every_entry_spring = true;
    for (std::size_t e = 0; e < model_.bones.size(); ++e) {
      entry_by_name_.insertFirst(model_.bones[e].name, static_cast<int>(e));
      entry_is_spring_[e] = isSpringBoneName(model_.bones[e].name);
      every_entry_spring = every_entry_spring && entry_is_spring_[e];
    }
    matches_.assign(model_.bones.size(), 0);
    for (std::size_t i = 0; i < all.size(); ++i) {
      // A node named without the token can only match an entry named without it.
      if (every_entry_spring && !is_candidate_[i]) continue;
      const int entry = entry_by_name_.find(all[i].name);
      if (entry < 0) continue;
      ++matches_[entry];
      if (is_candidate_[i]) entry_of_node_[i] = entry;
    }
  }

  void warnEntry(std::size_t e) {
    const BoneEntry& entry = model_.bones[e];
    const int matches = matches_[e];
    if (matches == 0) {
      warn("bone-not-found", "metadata names '" + shownName(entry.name) + "', but the GLB has no such node",
           model_.entryPath(entry));
    } else if (!entry_is_spring_[e]) {
      warn("bone-not-spring",
           "metadata names '" + shownName(entry.name) +
               "', whose name lacks the 'springbone' token; the entry is ignored",
           model_.entryPath(entry));
    } else if (matches > 1) {
      warn("duplicate-node-name",
           "the GLB has " + std::to_string(matches) + " nodes named '" + shownName(entry.name) +
               "'; the entry applies to each",
           model_.entryPath(entry));
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
        if (is_root) warnNestedRoot(n, parent_chain, entry);
      } else if (is_root) {
        chain_of_node_[n] = n;
        root_nodes_.push_back(n);
      }
    }
  }

  void warnNestedRoot(int n, int parent_chain, int entry) {
    const auto& all = nodes();
    warn("nested-root",
         "'" + shownName(all[n].name) + "' is marked isRoot but lies inside the chain of '" +
             shownName(all[parent_chain].name) + "'; it is simulated as a member of that chain with its own parameters",
         model_.entryPath(model_.bones[entry]));
  }

  int driverFor(int node) {
    if (driver_of_node_.empty()) driver_of_node_.assign(nodes().size(), -1);
    int& driver = driver_of_node_[node];
    if (driver < 0) {
      driver = static_cast<int>(rig_->drivers.size());
      rig_->drivers.emplace_back();
      rig_->drivers.back().node = node;
      rig_->drivers.back().name = nodes()[node].name;
    }
    return driver;
  }

  // The driver of an entry's center, or -1 (world space) with a warning when it cannot be used.
  // Resolved once per entry so a chain sharing an entry warns once.
  int resolveCenter(int entry_index) {
    if (center_of_entry_.empty()) center_of_entry_.assign(model_.bones.size(), kCenterUnresolved);
    if (center_of_entry_[entry_index] != kCenterUnresolved) return center_of_entry_[entry_index];
    const BoneEntry& entry = model_.bones[entry_index];
    int driver = -1;
    if (!entry.center.empty()) {
      const int node = nodeNamed(entry.center);
      if (node < 0) {
        warn("center-not-found",
             "center '" + shownName(entry.center) + "' of '" + shownName(entry.name) +
                 "' is not a node of the GLB; using world space",
             model_.entryPath(entry) + "/center");
      } else if (is_candidate_[node] || chain_of_node_[node] >= 0) {
        warn("center-is-spring-bone",
             "center '" + shownName(entry.center) + "' of '" + shownName(entry.name) +
                 "' is a spring bone itself; using world space",
             model_.entryPath(entry) + "/center");
      } else {
        driver = driverFor(node);
      }
    }
    center_of_entry_[entry_index] = driver;
    return driver;
  }

  void buildJoints() {
    const auto& all = nodes();
    auto& joint_of_node = joint_of_node_;
    joint_of_node.assign(all.size(), -1);
    // Every chain node with children becomes a joint: reserved exactly, as a Joint is large and
    // growing the vector would move each one several times.
    std::size_t joints = 0;
    for (std::size_t n = 0; n < all.size(); ++n) joints += chain_of_node_[n] >= 0 && !all[n].children.empty();
    rig_->joints.reserve(joints);
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
          if (entry >= 0 && n != root) warnTipEntry(n, entry);
          continue;
        }
        const int joint_index = static_cast<int>(rig_->joints.size());
        const int parent_joint = node.parent >= 0 ? joint_of_node[node.parent] : -1;
        rig_->joints.emplace_back();
        Joint& joint = rig_->joints.back();
        joint.node = n;
        joint.tail_node = node.children.front();
        joint.chain = chain_joint;
        joint.rest_local = node.rest_local;
        joint.tail_local = all[joint.tail_node].rest_local.translation;
        joint.rest_length =
            glm::length(glm::vec3(toGlm(all[joint.tail_node].rest_world)[3]) - glm::vec3(toGlm(node.rest_world)[3]));
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
        if (!(joint.rest_length > kMinBoneLength)) warnZeroLength(n, joint.tail_node);
        joint_of_node[n] = joint_index;
        chain_has_joint = true;
      }
      if (chain_has_joint) {
        rig_->chain_roots.push_back(chain_joint);
      } else {
        warnRootWithoutTail(root);
      }
    }
  }

  void warnTipEntry(int n, int entry) {
    warn("tip-entry-ignored",
         "'" + shownName(nodes()[n].name) +
             "' is a chain tip (no children): it only marks where its parent bone ends, so "
             "its parameters are ignored",
         model_.entryPath(model_.bones[entry]));
  }

  void warnZeroLength(int n, int tail) {
    warn("zero-length-bone", "'" + shownName(nodes()[n].name) + "' and its tail '" + shownName(nodes()[tail].name) +
                                 "' are at the same place; the bone keeps its rest rotation");
  }

  void warnRootWithoutTail(int root) {
    warn("root-without-tail",
         "spring root '" + shownName(nodes()[root].name) + "' has no child bone, so there is nothing to simulate");
  }

  // Colliders are attached to drivers by node name; a name the GLB lacks becomes an external
  // driver (the avatar's bone, supplied by the caller). Every joint collides with all of them.
  void addColliders() {
    const float hit_radius = hitRadius();
    if ((options_.colliders.empty() && options_.preset == ColliderPreset::kNone) || rig_->joints.empty()) return;
    // A preset's shapes first, then the caller's.
    const std::vector<ColliderSpec>* specs = &options_.colliders;
    std::vector<ColliderSpec> with_preset;
    if (options_.preset == ColliderPreset::kDclBody) {
      with_preset = dclBodyColliders(rig_->skeleton, options_.avatar_bones, rig_->warnings);
      rig_->collider_passes = kBodyColliderPasses;
      for (const ColliderSpec& spec : options_.colliders) with_preset.push_back(spec);
      specs = &with_preset;
    }
    NameIndex external;  // a collider node the GLB lacks -> its external driver
    external.reserve(specs->size());
    for (const ColliderSpec& spec : *specs) {
      Collider collider;
      if (!colliderFromSpec(spec, collider, rig_->warnings)) continue;
      int driver = -1;
      const int node = nodeNamed(spec.node);
      if (node >= 0) {
        if (is_candidate_[node] || chain_of_node_[node] >= 0) {
          warn("collider-on-spring-bone", "collider node '" + shownName(spec.node) + "' is a spring bone; ignored");
          continue;
        }
        driver = driverFor(node);
      } else {
        driver = external.find(spec.node);
        const bool added = driver < 0;
        if (added) {
          driver = static_cast<int>(rig_->drivers.size());
          external.insertFirst(spec.node, driver);
          rig_->drivers.push_back(Driver{-1, spec.node});
        }
        // The caller's (after the preset's): a name that is no node here and no Decentraland avatar
        // bone (Avatar_*, which a wearable's GLB may lack) is more often a typo ('Head' for
        // 'Avatar_Head') than a bone the page will supply.
        const bool from_caller =
            static_cast<std::size_t>(&spec - specs->data()) >= specs->size() - options_.colliders.size();
        if (added && from_caller && spec.node.rfind("Avatar_", 0) != 0) warnColliderNodeNotFound(spec.node);
      }
      collider.driver = driver;
      rig_->colliders.push_back(collider);
    }
    for (Joint& joint : rig_->joints) {
      joint.hit_radius = hit_radius;
      for (std::size_t c = 0; c < rig_->colliders.size(); ++c) joint.colliders.push_back(static_cast<int>(c));
    }
  }

  // A collider on a name the GLB has no node of, and no avatar bone's: it follows a driver the
  // page supplies by that name, so the warning lists the nodes a collider can be on here (not
  // spring bones), at most kListed of them.
  void warnColliderNodeNotFound(const std::string& name) {
    constexpr std::size_t kListed = 10;
    constexpr std::size_t kQuoted = 64;
    const auto quoted = [&](const std::string& s) {
      return "'" + (s.size() > kQuoted ? s.substr(0, kQuoted) + "..." : s) + "'";
    };
    std::string listed;
    std::size_t count = 0;
    for (std::size_t i = 0; i < nodes().size(); ++i) {
      if (is_candidate_[i] || chain_of_node_[i] >= 0) continue;
      if (count < kListed) listed += (count > 0 ? ", " : "") + quoted(nodes()[i].name);
      ++count;
    }
    if (count > kListed) listed += " and " + std::to_string(count - kListed) + " more";
    const std::string where = count == 0 ? std::string("the GLB has no node a collider can be on")
                                         : "the GLB's nodes a collider can be on are " + listed;
    warn("collider-node-not-found", "collider node " + quoted(name) +
                                        " is neither a node of this GLB nor a Decentraland avatar bone (Avatar_...), "
                                        "so it follows a driver the page must supply by that name; " +
                                        where);
  }

  // The hitRadius option as used: in [0, kMaxHitRadius], with a warning when it was not (a
  // non-finite or huge one made the core skip every collider, silently, before).
  float hitRadius() {
    const float given = options_.hit_radius;
    if (given >= 0.0f && given <= kMaxHitRadius) return given;
    const float used = given > kMaxHitRadius ? kMaxHitRadius : 0.0f;  // NaN and negatives: 0
    warn("hit-radius-out-of-range", "hitRadius " + formatNumber(given) + " is outside [0, " +
                                        formatNumber(kMaxHitRadius) + "] world units; using " + formatNumber(used));
    return used;
  }

  const ModelEntry& model_;
  const RigOptions& options_;
  std::shared_ptr<Rig> rig_;
  std::vector<unsigned char> is_candidate_;
  std::vector<int> entry_of_node_;
  std::vector<int> chain_of_node_;
  std::vector<int> root_nodes_;
  // Views of the skeleton's names (the rig owns the skeleton and never changes it), so indexing
  // 7,000 nodes copies no strings.
  NameIndex first_node_by_name_;  ///< filled by nodeNamed
  bool nodes_indexed_ = false;
  // Per models entry: the driver of its center (-1: world space), kCenterUnresolved until asked.
  static constexpr int kCenterUnresolved = -2;
  std::vector<int> center_of_entry_;
  // Scratch of the phases, members rather than locals for the same reason as the in-place Joint.
  NameIndex entry_by_name_;
  std::vector<int> matches_;
  std::vector<unsigned char> entry_is_spring_;  ///< the entry's name has the token
  std::vector<int> joint_of_node_;
  std::vector<int> queue_;
  std::vector<int> driver_of_node_;  ///< node -> driver, -1 (sized on first use)
};

}  // namespace

bool isSpringBoneName(const std::string& name) {
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

std::shared_ptr<const Rig> buildRig(Skeleton skeleton, const ModelEntry& model, std::vector<Warning> warnings,
                                    const RigOptions& options) {
  return RigBuilder(std::move(skeleton), model, std::move(warnings), options).build();
}

}  // namespace springbones
