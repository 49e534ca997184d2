#include "loading/instance_colliders.h"

#include <algorithm>
#include <string>

#include "common/shown_name.h"
#include "loading/body_colliders.h"
#include "loading/collider_from_spec.h"

namespace springbones {
namespace {

// What a collider's node name stands for on this rig: a driver, a frame, or a spring bone (no
// collider may sit on what it pushes).
class NodeResolver {
 public:
  NodeResolver(const Rig& rig, const ColliderOptions& options, ColliderSet& set)
      : rig_(rig), options_(options), set_(set) {}

  /// The collider's `driver` value for `name`, or -1 for a spring bone.
  int resolve(const std::string& name) {
    const auto& nodes = rig_.skeleton.nodes;
    const auto node = std::find_if(nodes.begin(), nodes.end(), [&](const SkeletonNode& n) { return n.name == name; });
    const int n = node == nodes.end() ? -1 : static_cast<int>(node - nodes.begin());
    if (n >= 0 && isSpringBone(n)) return -1;
    // The first node of the name, as the rig builder finds it; else an avatar bone the rig's
    // caller supplies by that name (a driver of node -1).
    for (std::size_t d = 0; d < rig_.drivers.size(); ++d) {
      const Driver& driver = rig_.drivers[d];
      if (n >= 0 ? driver.node == n : driver.node < 0 && driver.name == name) return static_cast<int>(d);
    }
    return static_cast<int>(rig_.drivers.size() + frame(name, n));
  }

 private:
  bool isSpringBone(int n) const {
    if (isSpringBoneName(rig_.skeleton.nodes[static_cast<std::size_t>(n)].name)) return true;
    return std::any_of(rig_.joints.begin(), rig_.joints.end(),
                       [&](const Joint& j) { return j.node == n || j.tail_node == n; });
  }

  // The frame of `name`, made on first use: it starts at the avatar bone's rest matrix, else the
  // GLB node's (`n`), else the identity.
  std::size_t frame(const std::string& name, int n) {
    auto& names = set_.frame_names;
    const auto found = std::find(names.begin(), names.end(), name);
    if (found != names.end()) return static_cast<std::size_t>(found - names.begin());
    Mat4 rest = n >= 0 ? rig_.skeleton.nodes[static_cast<std::size_t>(n)].rest_world : Mat4{};
    const auto& bones = options_.avatar_bones;
    const auto bone = std::find_if(bones.begin(), bones.end(), [&](const AvatarBone& b) { return b.name == name; });
    if (bone != bones.end()) rest = bone->rest_world;
    names.push_back(name);
    set_.frame_rest.push_back(rest);
    return names.size() - 1;
  }

  const Rig& rig_;
  const ColliderOptions& options_;
  ColliderSet& set_;
};

}  // namespace

ColliderSet resolveColliders(const Rig& rig, const ColliderOptions& options, std::vector<Warning>& warnings) {
  ColliderSet set;
  set.every_joint = true;
  // The preset's shapes first, then the caller's (RigOptions' order).
  std::vector<ColliderSpec> specs;
  if (options.preset == ColliderPreset::kDclBody) {
    specs = dclBodyColliders(rig.skeleton, options.avatar_bones, warnings, options.body);
    set.passes = kBodyColliderPasses;
  }
  specs.insert(specs.end(), options.colliders.begin(), options.colliders.end());
  NodeResolver nodes(rig, options, set);
  for (const ColliderSpec& spec : specs) {
    Collider collider;
    if (!colliderFromSpec(spec, collider, warnings)) continue;
    collider.driver = nodes.resolve(spec.node);
    if (collider.driver < 0) {
      warnings.push_back(Warning{"collider-on-spring-bone",
                                 "collider node '" + shownName(spec.node) + "' is a spring bone; ignored", ""});
      continue;
    }
    set.colliders.push_back(collider);
  }
  for (std::size_t c = 0; c < set.colliders.size(); ++c) set.every.push_back(static_cast<int>(c));
  return set;
}

}  // namespace springbones
