// VRM 0.x's extensions.VRM.secondaryAnimation into the shared VRM rig (vrm_rig_builder.h): its
// collider groups of spheres and its bone groups. docs/semantics.md, "VRM avatars", has the rules;
// here, how the code holds to them:
//  - Every node of a bone group's roots' subtrees is a joint whose tail is its first child. A
//    leaf's virtual tail (kVrm0LeafTailLength along its normalized translation, in its own frame,
//    unscaled) is three-vrm 3.5.5's rule and what UniVRM's 0.x -> 1.0 migration bakes into an
//    `_end` node; UniVRM 0.x's own component agrees on normalized rigs.
//  - Vectors are Unity's: z is negated into glTF's axes.
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/glm_interop.h"
#include "loading/vrm_formats.h"

namespace springbones {
namespace {

using json = TypedValue;

// VRM 0.x vectors are objects {x, y, z}; a missing component is 0 (as three-vrm reads them).
bool readVec3Object(const json& value, Vec3& out) {
  if (!value.is_object()) return false;
  float v[3] = {0.0f, 0.0f, 0.0f};
  static const char* const kKeys[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    auto it = value.find(kKeys[i]);
    if (it != value.end() && !readVrmFloat(*it, v[i])) return false;
  }
  out = Vec3{v[0], v[1], v[2]};
  return true;
}

class Vrm0Reader {
 public:
  explicit Vrm0Reader(VrmRigBuilder& rig) : rig_(rig), nodes_(rig.nodes()) {}

  Error readVrm0(const json& sa) {
    const std::string base = "/extensions/VRM/secondaryAnimation";
    if (!sa.is_object()) return Error{ErrorCode::kMetadataInvalid, "secondaryAnimation is not an object", base};
    std::optional<TypedValue> groups;
    std::optional<TypedValue> bone_groups;
    if (Error e = optionalVrmArray(sa, "colliderGroups", base, groups)) return e;
    if (Error e = optionalVrmArray(sa, "boneGroups", base, bone_groups)) return e;

    if (groups.has_value()) {
      for (std::size_t g = 0; g < groups->size(); ++g) {
        const std::string path = base + "/colliderGroups/" + std::to_string(g);
        const json& group = (*groups)[g];
        std::vector<int> ids;
        int node = -1;
        auto node_it = group.is_object() ? group.find("node") : group.end();
        if (!group.is_object() || node_it == group.end() || !readVrmIndex(*node_it, nodes_.size(), node)) {
          rig_.warn("vrm-collider-group-invalid",
                    "collider group " + std::to_string(g) + " names no node of the file; ignored", path);
        } else if (auto list = group.find("colliders"); list != group.end() && list->is_array()) {
          for (std::size_t k = 0; k < list->size(); ++k) {
            const json& c = (*list)[k];
            const std::string cpath = path + "/colliders/" + std::to_string(k);
            VrmFileCollider collider;
            collider.path = cpath;
            collider.node = node;
            bool ok = c.is_object();
            if (ok) {
              if (auto it = c.find("offset"); it != c.end() && !readVec3Object(*it, collider.offset)) ok = false;
              if (auto it = c.find("radius");
                  it != c.end() && (!readVrmFloat(*it, collider.radius) || collider.radius < 0.0f)) {
                ok = false;
              }
            }
            if (!ok) {
              rig_.warn("vrm-collider-invalid",
                        "collider is not an object with a finite offset {x, y, z} and a radius >= 0; ignored", cpath);
              continue;
            }
            collider.offset.z = -collider.offset.z;  // Unity axes -> glTF (see the header)
            collider.tail = collider.offset;
            collider.valid = true;
            ids.push_back(static_cast<int>(rig_.colliderCount()));
            rig_.addCollider(std::move(collider));
          }
        } else if (list != group.end()) {
          rig_.warn("vrm-collider-group-invalid",
                    "collider group " + std::to_string(g) + ": colliders is not an array; ignored",
                    path + "/colliders");
        }
        rig_.addColliderGroup(std::move(ids));
      }
    }
    if (bone_groups.has_value()) {
      for (std::size_t g = 0; g < bone_groups->size(); ++g) {
        readVrm0Group((*bone_groups)[g], base + "/boneGroups/" + std::to_string(g));
      }
    }
    return {};
  }

 private:
  void readVrm0Group(const json& group, const std::string& path) {
    if (!group.is_object()) {
      rig_.warn("vrm-spring-invalid", "bone group is not an object; ignored", path);
      return;
    }
    auto bones = group.find("bones");
    if (bones == group.end() || !bones->is_array() || bones->empty()) {
      rig_.warn("vrm-spring-invalid", "bone group has no bones: nothing to simulate", path + "/bones");
      return;
    }
    VrmSpring spring;
    spring.path = path;
    rig_.readSpringColliderGroups(group, path, "bone group", "the group", spring);
    if (auto center = group.find("center"); center != group.end() && !center->is_null()) {
      // UniVRM writes -1 for "no center".
      const bool none = center->is_number_integer() && center->get<std::int64_t>() == -1;
      if (!none && !readVrmIndex(*center, nodes_.size(), spring.center_node)) {
        spring.center_node = -1;
        rig_.warn("center-not-found", "bone group center is not a node of the file; using world space",
                  path + "/center");
      }
    }
    BoneParams params;
    params.stiffness =
        rig_.readParam(group, "stiffiness", kVrmDefaultStiffness, 0.0f, kVrmUnbounded, path);  // sic, the 0.x key
    const float power = rig_.readParam(group, "gravityPower", kVrmDefaultGravityPower, 0.0f, kVrmUnbounded, path);
    Vec3 dir{0.0f, -1.0f, 0.0f};
    if (auto it = group.find("gravityDir"); it != group.end() && !it->is_null()) {
      if (readVec3Object(*it, dir)) {
        dir.z = -dir.z;  // Unity axes -> glTF
      } else {
        rig_.warn("vrm-param-invalid", "gravityDir is not an object {x, y, z} of finite numbers; using (0, -1, 0)",
                  path + "/gravityDir");
        dir = Vec3{0.0f, -1.0f, 0.0f};
      }
    }
    rig_.setGravity(params, dir, power, path);
    params.drag = rig_.readParam(group, "dragForce", kVrmDefaultDrag, 0.0f, 1.0f, path);
    const float hit_radius = rig_.readParam(group, "hitRadius", kVrmDefaultHitRadius, 0.0f, kMaxHitRadius, path);
    const int spring_index = rig_.addSpring(std::move(spring));

    std::vector<int> queue;
    for (std::size_t b = 0; b < bones->size(); ++b) {
      const std::string bone_path = path + "/bones/" + std::to_string(b);
      int root = -1;
      if (!readVrmIndex((*bones)[b], nodes_.size(), root)) {
        rig_.warn("vrm-joint-invalid", "bone " + std::to_string(b) + " is not a node of the file; ignored", bone_path);
        continue;
      }
      if (rig_.isClaimed(root)) {
        rig_.warn(
            "vrm-joint-conflict",
            rig_.nodeLabel(root) + " is already simulated (by an earlier root or bone group); this root is ignored",
            bone_path);
        continue;
      }
      std::size_t skipped = 0;
      queue.assign(1, root);
      for (std::size_t head = 0; head < queue.size(); ++head) {
        const int n = queue[head];
        if (rig_.isClaimed(n)) {
          ++skipped;  // a subtree an earlier group owns: it keeps that group's parameters
          continue;
        }
        const SkeletonNode& node = nodes_[n];
        VrmSimJoint sim;
        sim.spring = spring_index;
        sim.params = params;
        sim.hit_radius = hit_radius;
        if (node.children.empty()) {
          const glm::vec3 t = toGlm(node.rest_local.translation);
          const float length = glm::length(t);
          if (length > kVrmMinBoneLength && std::isfinite(length)) {
            sim.tail_local = fromGlm(t / length * kVrm0LeafTailLength);
          }
        } else {
          sim.tail_node = node.children.front();
          sim.tail_local = nodes_[sim.tail_node].rest_local.translation;
          for (int c : node.children) queue.push_back(c);
        }
        rig_.claim(n, std::move(sim));
      }
      if (skipped > 0) {
        rig_.warn("vrm-joint-conflict",
                  std::to_string(skipped) + " subtree(s) under root " + rig_.nodeLabel(root) +
                      " are already simulated (by an earlier root or bone group) and keep those parameters",
                  bone_path);
      }
    }
  }

  VrmRigBuilder& rig_;
  const std::vector<SkeletonNode>& nodes_;
};

}  // namespace

Error readVrm0SecondaryAnimation(const TypedValue& secondary_animation, VrmRigBuilder& rig) {
  return Vrm0Reader(rig).readVrm0(secondary_animation);
}

}  // namespace springbones
