// VRMC_springBone 1.0 (VRM 1.0) into the shared VRM rig (vrm_rig_builder.h): its colliders,
// including VRMC_springBone_extended_collider's shapes, its collider groups and its springs.
// docs/semantics.md, "VRM avatars", has the rules; here, how the code holds to them:
//  - A tail several nodes down is composed from the local transforms along the path, so the bone
//    points at the listed node; the nodes between become fixed joints, held at their rest
//    rotation (the solver carries transforms only down joint links).
//  - A joint's VRMC_springBone_limit is read by vrm_limits.cpp.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/transform_math.h"
#include "loading/vrm_formats.h"
#include "loading/vrm_limits.h"

namespace springbones {
namespace {

using json = TypedValue;

bool readVec3Array(const json& value, Vec3& out) {
  if (!value.is_array() || value.size() != 3) return false;
  float v[3];
  for (int i = 0; i < 3; ++i) {
    if (!readVrmFloat(value[i], v[i])) return false;
  }
  out = Vec3{v[0], v[1], v[2]};
  return true;
}

class VrmcReader {
 public:
  explicit VrmcReader(VrmRigBuilder& rig) : rig_(rig), nodes_(rig.nodes()) {}

  Error readVrmc(const json& ext) {
    const std::string base = "/extensions/VRMC_springBone";
    if (!ext.is_object()) return Error{ErrorCode::kMetadataInvalid, "VRMC_springBone is not an object", base};
    auto version = ext.find("specVersion");
    if (version == ext.end() || !version->is_string()) {
      rig_.warn("vrm-spec-version", "VRMC_springBone has no specVersion; read as 1.0", base + "/specVersion");
    } else if (*version != "1.0" && *version != "1.0-beta") {
      rig_.warn("vrm-spec-version",
                "VRMC_springBone specVersion '" + version->get<std::string>() + "' is unknown; read as 1.0",
                base + "/specVersion");
    }
    std::optional<TypedValue> colliders;
    std::optional<TypedValue> groups;
    std::optional<TypedValue> springs;
    if (Error e = optionalVrmArray(ext, "colliders", base, colliders)) return e;
    if (Error e = optionalVrmArray(ext, "colliderGroups", base, groups)) return e;
    if (Error e = optionalVrmArray(ext, "springs", base, springs)) return e;

    if (colliders.has_value()) {
      for (std::size_t i = 0; i < colliders->size(); ++i) {
        rig_.addCollider(readVrmcCollider((*colliders)[i], base + "/colliders/" + std::to_string(i)));
      }
    }
    if (groups.has_value()) {
      std::vector<std::size_t> listed(rig_.colliderCount(), 0);  // group index + 1 that last listed it
      for (std::size_t g = 0; g < groups->size(); ++g) {
        const std::string path = base + "/colliderGroups/" + std::to_string(g);
        const json& group = (*groups)[g];
        std::vector<int> ids;
        auto list = group.is_object() ? group.find("colliders") : group.end();
        if (!group.is_object() || list == group.end() || !list->is_array()) {
          rig_.warn("vrm-collider-group-invalid",
                    "collider group " + std::to_string(g) + " has no colliders array; ignored", path);
        } else {
          for (std::size_t k = 0; k < list->size(); ++k) {
            int id = -1;
            if (!readVrmIndex((*list)[k], rig_.colliderCount(), id)) {
              rig_.warn("vrm-collider-group-invalid",
                        "collider group " + std::to_string(g) + " names a collider that does not exist; ignored",
                        path + "/colliders/" + std::to_string(k));
              continue;
            }
            if (listed[id] == g + 1) continue;  // a repeat within the group counts once
            listed[id] = g + 1;
            ids.push_back(id);
          }
        }
        rig_.addColliderGroup(std::move(ids));
      }
    }
    if (springs.has_value()) {
      for (std::size_t s = 0; s < springs->size(); ++s) {
        readVrmcSpring((*springs)[s], base + "/springs/" + std::to_string(s));
      }
    }
    return {};
  }

 private:
  VrmFileCollider readVrmcCollider(const json& c, const std::string& path) {
    VrmFileCollider out;
    out.path = path;
    auto invalid = [&](const std::string& why) {
      rig_.warn("vrm-collider-invalid", "collider " + path.substr(path.rfind('/') + 1) + " " + why + "; ignored", path);
      return out;
    };
    if (!c.is_object()) return invalid("is not an object");
    auto node = c.find("node");
    if (node == c.end() || !readVrmIndex(*node, nodes_.size(), out.node)) {
      return invalid("names no node of the file");
    }
    if (auto ext = c.find("extensions"); ext != c.end() && ext->is_object()) {
      if (auto extended = ext->find("VRMC_springBone_extended_collider"); extended != ext->end()) {
        if (readExtendedCollider(*extended, path + "/extensions/VRMC_springBone_extended_collider", out)) return out;
      }
    }
    auto shape = c.find("shape");
    if (shape == c.end() || !shape->is_object()) return invalid("has no shape");
    auto sphere = shape->find("sphere");
    auto capsule = shape->find("capsule");
    const bool is_sphere = sphere != shape->end() && sphere->is_object();
    const bool is_capsule = capsule != shape->end() && capsule->is_object();
    if (!is_sphere && !is_capsule) return invalid("has neither a sphere nor a capsule shape");
    if (is_sphere && is_capsule) {
      rig_.warn("vrm-collider-shape", "collider has both a sphere and a capsule; the sphere is used", path + "/shape");
    }
    std::string why;
    if (!readRoundShape(is_sphere ? *sphere : *capsule, !is_sphere, false, out, why)) return invalid(why);
    out.valid = true;
    return out;
  }

  // A sphere or capsule body ({offset, radius, tail (capsules), inside (extended shapes)}) into
  // `out`; false with the reason for a value that cannot be read.
  static bool readRoundShape(const json& body, bool capsule, bool extended, VrmFileCollider& out, std::string& why) {
    static_cast<ColliderShape&>(out) = ColliderShape{};
    out.shape = capsule ? Collider::Shape::kCapsule : Collider::Shape::kSphere;
    if (auto it = body.find("offset"); it != body.end() && !readVec3Array(*it, out.offset)) {
      why = "has an offset that is not 3 finite numbers";
      return false;
    }
    if (auto it = body.find("radius"); it != body.end() && (!readVrmFloat(*it, out.radius) || out.radius < 0.0f)) {
      why = "has a radius that is not a finite number >= 0";
      return false;
    }
    if (!capsule) {
      out.tail = out.offset;
    } else if (auto it = body.find("tail"); it != body.end() && !readVec3Array(*it, out.tail)) {
      why = "has a tail that is not 3 finite numbers";
      return false;
    }
    if (auto it = body.find("inside"); extended && it != body.end()) {
      if (!it->is_boolean()) {
        why = "has an inside that is not a boolean";
        return false;
      }
      out.inside = it->get<bool>();
    }
    return true;
  }

  // VRMC_springBone_extended_collider: its shape replaces the base shape when the extension's
  // specVersion is one we know ("1.0", or the draft's "1.0-draft") and its shape is one of the
  // three and readable. Otherwise the base shape is the fallback the extension requires writers
  // to provide, with a warning (three-vrm 3.5.5 falls back the same way for an unknown version;
  // it reads "1.0" only).
  bool readExtendedCollider(const json& ext, const std::string& path, VrmFileCollider& out) {
    auto fallback = [&](const std::string& why) {
      rig_.warn("vrm-extended-collider", "extended collider " + why + "; the base shape is used", path);
      return false;
    };
    if (!ext.is_object()) return fallback("is not an object");
    auto version = ext.find("specVersion");
    if (version == ext.end() || !version->is_string()) return fallback("has no specVersion");
    const std::string v = version->get<std::string>();
    if (v != "1.0" && v != "1.0-draft") return fallback("has specVersion \"" + v + "\", which is not known");
    auto shape = ext.find("shape");
    if (shape == ext.end() || !shape->is_object()) return fallback("has no shape");
    const VrmFileCollider base = out;
    std::string why;
    bool read = false;
    if (auto sphere = shape->find("sphere"); sphere != shape->end() && sphere->is_object()) {
      read = readRoundShape(*sphere, false, true, out, why);
    } else if (auto capsule = shape->find("capsule"); capsule != shape->end() && capsule->is_object()) {
      read = readRoundShape(*capsule, true, true, out, why);
    } else if (auto plane = shape->find("plane"); plane != shape->end() && plane->is_object()) {
      read = readPlaneShape(*plane, out, why);
    } else {
      return fallback("has no sphere, capsule or plane shape");
    }
    if (!read) {
      out = base;
      return fallback(why);
    }
    out.valid = true;
    return true;
  }

  // A plane body ({offset, normal}, normal (0, 0, 1) by default) into `out`.
  static bool readPlaneShape(const json& body, VrmFileCollider& out, std::string& why) {
    static_cast<ColliderShape&>(out) = ColliderShape{};
    out.shape = Collider::Shape::kPlane;
    if (auto it = body.find("offset"); it != body.end() && !readVec3Array(*it, out.offset)) {
      why = "has an offset that is not 3 finite numbers";
      return false;
    }
    if (auto it = body.find("normal"); it != body.end() && !readVec3Array(*it, out.normal)) {
      why = "has a normal that is not 3 finite numbers";
      return false;
    }
    glm::vec3 normal = toGlm(out.normal);
    if (!toUnitLength(normal)) {
      why = "has a zero normal";
      return false;
    }
    out.normal = fromGlm(normal);
    return true;
  }

  void readVrmcSpring(const json& s, const std::string& path) {
    if (!s.is_object()) {
      rig_.warn("vrm-spring-invalid", "spring is not an object; ignored", path);
      return;
    }
    auto joints = s.find("joints");
    if (joints == s.end() || !joints->is_array() || joints->size() < 2) {
      rig_.warn("vrm-spring-invalid",
                "spring has fewer than two joints (the last joint is only a tail): nothing to simulate",
                path + "/joints");
      return;
    }
    VrmSpring spring;
    spring.path = path;
    rig_.readSpringColliderGroups(s, path, "spring", "the spring", spring);
    if (auto center = s.find("center"); center != s.end() && !center->is_null()) {
      if (!readVrmIndex(*center, nodes_.size(), spring.center_node)) {
        spring.center_node = -1;
        rig_.warn("center-not-found", "spring center is not a node of the file; using world space", path + "/center");
      }
    }
    const int spring_index = rig_.addSpring(std::move(spring));

    // Node of every joint, up to the first unreadable one.
    std::vector<int> joint_nodes;
    for (std::size_t k = 0; k < joints->size(); ++k) {
      const json& joint = (*joints)[k];
      auto node = joint.is_object() ? joint.find("node") : joint.end();
      int n = -1;
      if (!joint.is_object() || node == joint.end() || !readVrmIndex(*node, nodes_.size(), n)) {
        rig_.warn("vrm-joint-invalid",
                  "joint " + std::to_string(k) + " is not an object with a node of the file; the spring ends before it",
                  path + "/joints/" + std::to_string(k));
        break;
      }
      joint_nodes.push_back(n);
    }
    for (std::size_t k = 0; k + 1 < joint_nodes.size(); ++k) {
      const int head = joint_nodes[k];
      const int tail = joint_nodes[k + 1];
      const std::string joint_path = path + "/joints/" + std::to_string(k);
      if (rig_.isClaimed(head)) {
        rig_.warn("vrm-joint-conflict",
                  rig_.nodeLabel(head) +
                      " is already simulated by an earlier spring or held by one; the spring ends before it",
                  joint_path);
        break;
      }
      if (!rig_.isDescendant(tail, head)) {
        rig_.warn("vrm-joint-not-descendant",
                  "joint " + std::to_string(k + 1) + ", " + rig_.nodeLabel(tail) + ", is not a descendant of " +
                      rig_.nodeLabel(head) + "; the spring ends at " + rig_.nodeLabel(head),
                  path + "/joints/" + std::to_string(k + 1));
        break;
      }
      // The nodes strictly between head and tail, bottom-up.
      std::vector<int> between;
      bool conflict = false, exhausted = false;
      for (int n = nodes_[tail].parent; n != head; n = nodes_[n].parent) {
        if (!rig_.spendWalk()) {
          exhausted = true;
          break;
        }
        if (rig_.isSimulated(n)) {
          conflict = true;
          break;
        }
        between.push_back(n);
      }
      if (exhausted) {
        rig_.warn(
            "vrm-limit",
            "too many skipped nodes between listed joints in this file; the spring ends at " + rig_.nodeLabel(head),
            joint_path);
        break;
      }
      if (conflict) {
        rig_.warn("vrm-joint-conflict",
                  "a node between " + rig_.nodeLabel(head) + " and " + rig_.nodeLabel(tail) +
                      " is simulated by an earlier spring; the spring ends before " + rig_.nodeLabel(head),
                  joint_path);
        break;
      }
      VrmSimJoint sim;
      sim.spring = spring_index;
      sim.tail_node = tail;
      glm::mat4 path_matrix = composeTransform(nodes_[tail].rest_local);
      int below = tail;
      for (int n : between) {  // bottom-up: prepend each ancestor's local transform
        path_matrix = composeTransform(nodes_[n].rest_local) * path_matrix;
        rig_.hold(n, below);
        below = n;
      }
      sim.tail_local = fromGlm(glm::vec3(path_matrix[3]));
      if (!between.empty()) {
        std::string names;
        for (std::size_t i = between.size(); i-- > 0;) {
          if (between.size() - 1 - i == kVrmMaxNamesInWarning) {
            names += ", ...";
            break;
          }
          names += (names.empty() ? "'" : ", '") + VrmRigBuilder::shownName(nodes_[between[i]].name) + "'";
        }
        rig_.warn("vrm-fixed-nodes",
                  "joints " + std::to_string(k) + " and " + std::to_string(k + 1) +
                      " are not parent and child: " + std::to_string(between.size()) + " node(s) between them (" +
                      names + ") are held at their rest pose",
                  joint_path);
      }
      const json& joint = (*joints)[k];
      sim.params.stiffness = rig_.readParam(joint, "stiffness", kVrmDefaultStiffness, 0.0f, kVrmUnbounded, joint_path);
      const float power =
          rig_.readParam(joint, "gravityPower", kVrmDefaultGravityPower, 0.0f, kVrmUnbounded, joint_path);
      Vec3 dir{0.0f, -1.0f, 0.0f};
      if (auto it = joint.find("gravityDir"); it != joint.end() && !it->is_null() && !readVec3Array(*it, dir)) {
        rig_.warn("vrm-param-invalid", "gravityDir is not 3 finite numbers; using (0, -1, 0)",
                  joint_path + "/gravityDir");
        dir = Vec3{0.0f, -1.0f, 0.0f};
      }
      rig_.setGravity(sim.params, dir, power, joint_path);
      sim.params.drag = rig_.readParam(joint, "dragForce", kVrmDefaultDrag, 0.0f, 1.0f, joint_path);
      sim.hit_radius = rig_.readParam(joint, "hitRadius", kVrmDefaultHitRadius, 0.0f, kMaxHitRadius, joint_path);
      readVrmJointLimit(joint, joint_path, rig_.nodeLabel(head), sim.limit, rig_.warnings());
      rig_.claim(head, std::move(sim));
    }
    if (hasVrmJointLimit((*joints)[joints->size() - 1])) {  // the draft: ignored on the last joint, a tail
      rig_.warn("limit-on-end-joint", "the last joint of a spring is only a tail; its VRMC_springBone_limit is ignored",
                path + "/joints/" + std::to_string(joints->size() - 1) + "/extensions/VRMC_springBone_limit");
    }
  }

  VrmRigBuilder& rig_;
  const std::vector<SkeletonNode>& nodes_;
};

}  // namespace

Error readVrmcSpringBone(const TypedValue& extension, VrmRigBuilder& rig) {
  return VrmcReader(rig).readVrmc(extension);
}

}  // namespace springbones
