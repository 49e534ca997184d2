// VRM spring bones into a Rig (see springbones/vrm.h for the two formats). What a file's model
// becomes, and where we differ from three-vrm and UniVRM, is docs/semantics.md, "VRM avatars";
// here, how the code holds to it:
//  - The Rig holds every joint once, parents first; a joint's parent_joint is the joint of its
//    glTF parent, and a joint whose glTF parent is no joint is a chain root hanging from a driver,
//    as in rig_builder.cpp. The solver carries transforms only down joint links, so nodes skipped
//    between a VRMC_springBone joint and its next one, or between a spring root and a joint above
//    it, become fixed joints (zero tail: held at their rest rotation).
//  - A VRMC_springBone tail several nodes down is composed from the local transforms along the
//    path, so the bone points at the listed node.
//  - A VRM 0.x leaf's virtual tail (kVrm0LeafTailLength along its normalized translation, in its
//    own frame, unscaled) is three-vrm 3.5.5's rule and what UniVRM's 0.x -> 1.0 migration bakes
//    into an `_end` node; UniVRM 0.x's own component agrees on normalized rigs.
//  - gravityDir is stored normalized (the BoneParams contract) with its length folded into
//    gravity_power, so dir * power is exactly the file's impulse.
//  - A joint's collider list is its spring's groups' colliders in the order the spring lists the
//    groups, a collider in two of them twice: three-vrm and UniVRM test every group a joint uses,
//    collider by collider, so such a collider pushes twice (once per group), and so does ours. A
//    group listed twice by one spring, or a collider twice by one group, counts once. A rig whose
//    lists are not in index order once each steps on the general path (the lane path's collider
//    mask holds neither order nor repeats).
#include "loading/vrm_reader.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <optional>

#include "common/transform_math.h"
#include "common/typed_value.h"
#include "loading/gltf_nodes.h"
#include "loading/vrm_limits.h"

namespace springbones {
namespace {

using json = TypedValue;

constexpr float kMinBoneLength = 1e-6f;
constexpr std::size_t kMaxNamesInWarning = 8;
// Bytes of a node name shown in a message: a file can name one node in a warning per spring or
// per collider, and its whole name in each would grow the warnings as springs x name length.
constexpr std::size_t kMaxNameBytesInWarning = 64;

constexpr float kDefaultStiffness = 1.0f;
constexpr float kDefaultGravityPower = 0.0f;
constexpr float kDefaultDrag = 0.5f;
constexpr float kDefaultHitRadius = 0.0f;
constexpr float kUnbounded = std::numeric_limits<float>::max();

enum class Role : unsigned char { kNone, kSimulated, kFixed };

Error fail(ErrorCode code, std::string message, std::string path = {}) {
  return Error{code, std::move(message), std::move(path)};
}

// A double that fits a float and is finite.
bool readFloat(const json& value, float& out) {
  if (!value.is_number()) return false;
  const double v = value.get<double>();
  if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max())) return false;
  out = static_cast<float>(v);
  return true;
}

bool exceedsColliderSize(const ColliderShape& c) {
  const auto beyond = [](const Vec3& v) {
    return std::fabs(v.x) > kMaxColliderSize || std::fabs(v.y) > kMaxColliderSize || std::fabs(v.z) > kMaxColliderSize;
  };
  return c.radius > kMaxColliderSize || beyond(c.offset) || beyond(c.tail);
}

bool readIndex(const json& value, std::size_t count, int& out) {
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    if (v >= count) return false;
    out = static_cast<int>(v);
    return true;
  }
  if (value.is_number_integer()) {
    const auto v = value.get<std::int64_t>();
    if (v < 0 || std::uint64_t(v) >= count) return false;
    out = static_cast<int>(v);
    return true;
  }
  return false;
}

bool readVec3Array(const json& value, Vec3& out) {
  if (!value.is_array() || value.size() != 3) return false;
  float v[3];
  for (int i = 0; i < 3; ++i) {
    if (!readFloat(value[i], v[i])) return false;
  }
  out = Vec3{v[0], v[1], v[2]};
  return true;
}

// VRM 0.x vectors are objects {x, y, z}; a missing component is 0 (as three-vrm reads them).
bool readVec3Object(const json& value, Vec3& out) {
  if (!value.is_object()) return false;
  float v[3] = {0.0f, 0.0f, 0.0f};
  static const char* const kKeys[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    auto it = value.find(kKeys[i]);
    if (it != value.end() && !readFloat(*it, v[i])) return false;
  }
  out = Vec3{v[0], v[1], v[2]};
  return true;
}

// A spring / bone group as the file describes it, resolved at emission.
struct SpringInfo {
  std::string path;
  int center_node = -1;  // -1: world space
  std::vector<int> groups;     // collider group ids, first appearance order, no repeats
  std::vector<int> colliders;  // file collider ids of those groups, no repeats (emitColliders)
  int center_driver = -2;      // -2: not resolved yet
};

struct SimJoint {
  int spring = -1;
  int tail_node = -1;  // -1: a VRM 0.x virtual tail
  Vec3 tail_local;
  BoneParams params;
  float hit_radius = 0.0f;
  JointLimit limit;
};

// A collider as the file describes it: its shape, the node carrying it and where it was read.
struct FileCollider : ColliderShape {
  bool valid = false;
  int node = -1;
  std::string path;
};

class VrmRigBuilder {
 public:
  explicit VrmRigBuilder(Skeleton skeleton) : rig_(std::make_shared<Rig>()) {
    rig_->skeleton = std::move(skeleton);
    const std::size_t count = nodes().size();
    role_.assign(count, Role::kNone);
    sim_of_node_.assign(count, -1);
    fixed_tail_.assign(count, -1);
    walk_budget_ = 2 * count + 64;
    // Pre-order numbers and subtree sizes, for O(1) "is a descendant of" tests.
    pre_.assign(count, 0);
    subtree_.assign(count, 1);
    const auto& order = rig_->skeleton.parents_first;
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
      const int parent = nodes()[*it].parent;
      if (parent >= 0) subtree_[parent] += subtree_[*it];
    }
    std::vector<int> stack;
    int next = 0;
    for (int n : order) {
      if (nodes()[n].parent >= 0) continue;
      stack.push_back(n);
      while (!stack.empty()) {
        const int top = stack.back();
        stack.pop_back();
        pre_[top] = next++;
        const auto& children = nodes()[top].children;
        for (auto c = children.rbegin(); c != children.rend(); ++c) stack.push_back(*c);
      }
    }
  }

  Error build(const json& extensions, VrmSpringFormat& format, std::shared_ptr<const Rig>& out) {
    format = VrmSpringFormat::kNone;
    if (!extensions.is_null() && !extensions.is_object()) {
      return fail(ErrorCode::kGltfInvalid, "the glTF 'extensions' value is not an object", "/extensions");
    }
    std::optional<TypedValue> vrmc;
    std::optional<TypedValue> vrm0;
    if (extensions.is_object()) {
      if (auto it = extensions.find("VRMC_springBone"); it != extensions.end()) vrmc = *it;
      if (auto it = extensions.find("VRM"); it != extensions.end()) vrm0 = *it;
    }
    if (vrmc.has_value()) {
      format = VrmSpringFormat::kVrmcSpringBone1;
      if (Error e = readVrmc(*vrmc)) return e;
      if (vrm0.has_value()) {
        warn("vrm-both-formats", "the file has VRMC_springBone and VRM 0.x data; the VRM 0.x secondaryAnimation is ignored",
             "/extensions/VRM");
      }
    } else if (vrm0.has_value()) {
      if (!vrm0->is_object()) return fail(ErrorCode::kMetadataInvalid, "extensions.VRM is not an object", "/extensions/VRM");
      auto it = vrm0->find("secondaryAnimation");
      if (it != vrm0->end() && !it->is_null()) {
        format = VrmSpringFormat::kVrm0;
        if (Error e = readVrm0(*it)) return e;
      }
    }
    if (format == VrmSpringFormat::kNone) {
      warn("vrm-no-springs", "the file has neither VRMC_springBone nor VRM 0.x secondaryAnimation: nothing to simulate");
    }
    insertFixedAboveRoots();
    emitJoints();
    if (Error e = emitColliders()) return e;
    out = rig_;
    return {};
  }

 private:
  const std::vector<SkeletonNode>& nodes() const { return rig_->skeleton.nodes; }

  static std::string shownName(const std::string& name) {
    if (name.size() <= kMaxNameBytesInWarning) return name;
    std::size_t cut = kMaxNameBytesInWarning;
    while (cut > 0 && (static_cast<unsigned char>(name[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 sequence
    return name.substr(0, cut) + "...";
  }

  std::string nodeLabel(int n) const { return "node " + std::to_string(n) + " ('" + shownName(nodes()[n].name) + "')"; }

  void warn(const char* code, std::string message, std::string path = {}) {
    rig_->warnings.push_back(Warning{code, std::move(message), std::move(path)});
  }

  bool isDescendant(int node, int ancestor) const {
    return pre_[node] > pre_[ancestor] && pre_[node] < pre_[ancestor] + subtree_[ancestor];
  }

  // ------------------------------------------------------------------------------------------
  // Parameters

  float readParam(const json& object, const char* key, float fallback, float min, float max, const std::string& path) {
    auto it = object.find(key);
    if (it == object.end() || it->is_null()) return fallback;
    float v = 0.0f;
    if (!readFloat(*it, v)) {
      warn("vrm-param-invalid", std::string(key) + " is not a finite number; using " + std::to_string(fallback),
           path + "/" + key);
      return fallback;
    }
    if (v < min || v > max) {
      const float clamped = std::clamp(v, min, max);
      warn("vrm-param-clamped", std::string(key) + " " + std::to_string(v) + " is out of range; using " +
                                    std::to_string(clamped),
           path + "/" + key);
      return clamped;
    }
    return v;
  }

  // gravityDir * gravityPower as the file means it, with a unit direction (see the header).
  void setGravity(BoneParams& params, Vec3 dir, float power, const std::string& path) {
    const double length = std::sqrt(double(dir.x) * dir.x + double(dir.y) * dir.y + double(dir.z) * dir.z);
    if (!(length > 1e-6)) {
      if (power > 0.0f) {
        warn("vrm-gravity-dir-zero", "gravityDir is the zero vector: no gravity", path + "/gravityDir");
      }
      params.gravity_dir = Vec3{0.0f, -1.0f, 0.0f};
      params.gravity_power = 0.0f;
      return;
    }
    params.gravity_dir = Vec3{static_cast<float>(dir.x / length), static_cast<float>(dir.y / length),
                              static_cast<float>(dir.z / length)};
    params.gravity_power = static_cast<float>(std::min(double(power) * length, double(kUnbounded)));
    if (std::fabs(length - 1.0) > 1e-4) {
      warn("vrm-gravity-dir-scaled", "gravityDir has length " + std::to_string(length) +
                                         "; it is normalized and its length multiplies gravityPower",
           path + "/gravityDir");
    }
  }

  // ------------------------------------------------------------------------------------------
  // VRMC_springBone 1.0

  // Optional array member: null when absent, an Error when present but not an array.
  Error optionalArray(const json& object, const char* key, const std::string& path, std::optional<TypedValue>& out) {
    out.reset();
    auto it = object.find(key);
    if (it == object.end() || it->is_null()) return {};
    if (!it->is_array()) return fail(ErrorCode::kMetadataInvalid, std::string(key) + " is not an array", path + "/" + key);
    out = *it;
    return {};
  }

  Error readVrmc(const json& ext) {
    const std::string base = "/extensions/VRMC_springBone";
    if (!ext.is_object()) return fail(ErrorCode::kMetadataInvalid, "VRMC_springBone is not an object", base);
    auto version = ext.find("specVersion");
    if (version == ext.end() || !version->is_string()) {
      warn("vrm-spec-version", "VRMC_springBone has no specVersion; read as 1.0", base + "/specVersion");
    } else if (*version != "1.0" && *version != "1.0-beta") {
      warn("vrm-spec-version", "VRMC_springBone specVersion '" + version->get<std::string>() + "' is unknown; read as 1.0",
           base + "/specVersion");
    }
    std::optional<TypedValue> colliders;
    std::optional<TypedValue> groups;
    std::optional<TypedValue> springs;
    if (Error e = optionalArray(ext, "colliders", base, colliders)) return e;
    if (Error e = optionalArray(ext, "colliderGroups", base, groups)) return e;
    if (Error e = optionalArray(ext, "springs", base, springs)) return e;

    if (colliders.has_value()) {
      for (std::size_t i = 0; i < colliders->size(); ++i) {
        file_colliders_.push_back(readVrmcCollider((*colliders)[i], base + "/colliders/" + std::to_string(i)));
      }
    }
    if (groups.has_value()) {
      std::vector<std::size_t> listed(file_colliders_.size(), 0);  // group index + 1 that last listed it
      for (std::size_t g = 0; g < groups->size(); ++g) {
        const std::string path = base + "/colliderGroups/" + std::to_string(g);
        const json& group = (*groups)[g];
        std::vector<int> ids;
        auto list = group.is_object() ? group.find("colliders") : group.end();
        if (!group.is_object() || list == group.end() || !list->is_array()) {
          warn("vrm-collider-group-invalid", "collider group " + std::to_string(g) + " has no colliders array; ignored", path);
        } else {
          for (std::size_t k = 0; k < list->size(); ++k) {
            int id = -1;
            if (!readIndex((*list)[k], file_colliders_.size(), id)) {
              warn("vrm-collider-group-invalid", "collider group " + std::to_string(g) +
                                                     " names a collider that does not exist; ignored",
                   path + "/colliders/" + std::to_string(k));
              continue;
            }
            if (listed[id] == g + 1) continue;  // a repeat within the group counts once
            listed[id] = g + 1;
            ids.push_back(id);
          }
        }
        group_colliders_.push_back(std::move(ids));
      }
    }
    if (springs.has_value()) {
      for (std::size_t s = 0; s < springs->size(); ++s) readVrmcSpring((*springs)[s], base + "/springs/" + std::to_string(s));
    }
    return {};
  }

  FileCollider readVrmcCollider(const json& c, const std::string& path) {
    FileCollider out;
    out.path = path;
    auto invalid = [&](const std::string& why) {
      warn("vrm-collider-invalid", "collider " + path.substr(path.rfind('/') + 1) + " " + why + "; ignored", path);
      return out;
    };
    if (!c.is_object()) return invalid("is not an object");
    auto node = c.find("node");
    if (node == c.end() || !readIndex(*node, nodes().size(), out.node)) return invalid("names no node of the file");
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
      warn("vrm-collider-shape", "collider has both a sphere and a capsule; the sphere is used", path + "/shape");
    }
    std::string why;
    if (!readRoundShape(is_sphere ? *sphere : *capsule, !is_sphere, false, out, why)) return invalid(why);
    out.valid = true;
    return out;
  }

  // A sphere or capsule body ({offset, radius, tail (capsules), inside (extended shapes)}) into
  // `out`; false with the reason for a value that cannot be read.
  static bool readRoundShape(const json& body, bool capsule, bool extended, FileCollider& out, std::string& why) {
    static_cast<ColliderShape&>(out) = ColliderShape{};
    out.shape = capsule ? Collider::Shape::kCapsule : Collider::Shape::kSphere;
    if (auto it = body.find("offset"); it != body.end() && !readVec3Array(*it, out.offset)) {
      why = "has an offset that is not 3 finite numbers";
      return false;
    }
    if (auto it = body.find("radius"); it != body.end() && (!readFloat(*it, out.radius) || out.radius < 0.0f)) {
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
  bool readExtendedCollider(const json& ext, const std::string& path, FileCollider& out) {
    auto fallback = [&](const std::string& why) {
      warn("vrm-extended-collider", "extended collider " + why + "; the base shape is used", path);
      return false;
    };
    if (!ext.is_object()) return fallback("is not an object");
    auto version = ext.find("specVersion");
    if (version == ext.end() || !version->is_string()) return fallback("has no specVersion");
    const std::string v = version->get<std::string>();
    if (v != "1.0" && v != "1.0-draft") return fallback("has specVersion \"" + v + "\", which is not known");
    auto shape = ext.find("shape");
    if (shape == ext.end() || !shape->is_object()) return fallback("has no shape");
    const FileCollider base = out;
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
  static bool readPlaneShape(const json& body, FileCollider& out, std::string& why) {
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

  // Adds a collider group to the spring being read (springs_.size() is its index), once however
  // often the file lists it. Its colliders are gathered when the joints are known (emitColliders).
  void addSpringGroup(SpringInfo& spring, int group) {
    const int stamp = static_cast<int>(springs_.size()) + 1;
    group_stamp_.resize(group_colliders_.size(), 0);
    if (group_stamp_[group] == stamp) return;
    group_stamp_[group] = stamp;
    spring.groups.push_back(group);
  }

  // The colliderGroups of a spring (1.0) or a bone group (0.x): indices of the collider groups read
  // before it. One that names none is left out with a warning; `name` and `the` are what the
  // warnings call the owner ("bone group", "the group").
  void readSpringColliderGroups(const json& owner, const std::string& path, const char* name, const char* the,
                                SpringInfo& spring) {
    auto groups = owner.find("colliderGroups");
    if (groups == owner.end() || groups->is_null()) return;
    if (!groups->is_array()) {
      warn("vrm-collider-group-invalid", std::string("colliderGroups is not an array; ") + the + " has no colliders",
           path + "/colliderGroups");
      return;
    }
    for (std::size_t k = 0; k < groups->size(); ++k) {
      int g = -1;
      if (!readIndex((*groups)[k], group_colliders_.size(), g)) {
        warn("vrm-collider-group-invalid", std::string(name) + " names a collider group that does not exist; ignored",
             path + "/colliderGroups/" + std::to_string(k));
        continue;
      }
      addSpringGroup(spring, g);
    }
  }

  void readVrmcSpring(const json& s, const std::string& path) {
    if (!s.is_object()) {
      warn("vrm-spring-invalid", "spring is not an object; ignored", path);
      return;
    }
    auto joints = s.find("joints");
    if (joints == s.end() || !joints->is_array() || joints->size() < 2) {
      warn("vrm-spring-invalid", "spring has fewer than two joints (the last joint is only a tail): nothing to simulate",
           path + "/joints");
      return;
    }
    SpringInfo spring;
    spring.path = path;
    readSpringColliderGroups(s, path, "spring", "the spring", spring);
    if (auto center = s.find("center"); center != s.end() && !center->is_null()) {
      if (!readIndex(*center, nodes().size(), spring.center_node)) {
        spring.center_node = -1;
        warn("center-not-found", "spring center is not a node of the file; using world space", path + "/center");
      }
    }
    const int spring_index = static_cast<int>(springs_.size());
    springs_.push_back(std::move(spring));

    // Node of every joint, up to the first unreadable one.
    std::vector<int> joint_nodes;
    for (std::size_t k = 0; k < joints->size(); ++k) {
      const json& joint = (*joints)[k];
      auto node = joint.is_object() ? joint.find("node") : joint.end();
      int n = -1;
      if (!joint.is_object() || node == joint.end() || !readIndex(*node, nodes().size(), n)) {
        warn("vrm-joint-invalid", "joint " + std::to_string(k) +
                                      " is not an object with a node of the file; the spring ends before it",
             path + "/joints/" + std::to_string(k));
        break;
      }
      joint_nodes.push_back(n);
    }
    for (std::size_t k = 0; k + 1 < joint_nodes.size(); ++k) {
      const int head = joint_nodes[k];
      const int tail = joint_nodes[k + 1];
      const std::string joint_path = path + "/joints/" + std::to_string(k);
      if (role_[head] != Role::kNone) {
        warn("vrm-joint-conflict", nodeLabel(head) + " is already simulated by an earlier spring or held by one; the spring ends before it",
             joint_path);
        break;
      }
      if (!isDescendant(tail, head)) {
        warn("vrm-joint-not-descendant", "joint " + std::to_string(k + 1) + ", " + nodeLabel(tail) + ", is not a descendant of " +
                                             nodeLabel(head) + "; the spring ends at " + nodeLabel(head),
             path + "/joints/" + std::to_string(k + 1));
        break;
      }
      // The nodes strictly between head and tail, bottom-up.
      std::vector<int> between;
      bool conflict = false, exhausted = false;
      for (int n = nodes()[tail].parent; n != head; n = nodes()[n].parent) {
        if (walk_budget_ == 0) {
          exhausted = true;
          break;
        }
        --walk_budget_;
        if (role_[n] == Role::kSimulated) {
          conflict = true;
          break;
        }
        between.push_back(n);
      }
      if (exhausted) {
        warn("vrm-limit", "too many skipped nodes between listed joints in this file; the spring ends at " + nodeLabel(head),
             joint_path);
        break;
      }
      if (conflict) {
        warn("vrm-joint-conflict", "a node between " + nodeLabel(head) + " and " + nodeLabel(tail) +
                                       " is simulated by an earlier spring; the spring ends before " + nodeLabel(head),
             joint_path);
        break;
      }
      SimJoint sim;
      sim.spring = spring_index;
      sim.tail_node = tail;
      glm::mat4 path_matrix = composeTransform(nodes()[tail].rest_local);
      int below = tail;
      for (int n : between) {  // bottom-up: prepend each ancestor's local transform
        path_matrix = composeTransform(nodes()[n].rest_local) * path_matrix;
        role_[n] = Role::kFixed;
        if (fixed_tail_[n] < 0) fixed_tail_[n] = below;
        below = n;
      }
      sim.tail_local = fromGlm(glm::vec3(path_matrix[3]));
      if (!between.empty()) {
        std::string names;
        for (std::size_t i = between.size(); i-- > 0;) {
          if (between.size() - 1 - i == kMaxNamesInWarning) {
            names += ", ...";
            break;
          }
          names += (names.empty() ? "'" : ", '") + shownName(nodes()[between[i]].name) + "'";
        }
        warn("vrm-fixed-nodes", "joints " + std::to_string(k) + " and " + std::to_string(k + 1) + " are not parent and child: " +
                                    std::to_string(between.size()) + " node(s) between them (" + names +
                                    ") are held at their rest pose",
             joint_path);
      }
      const json& joint = (*joints)[k];
      sim.params.stiffness = readParam(joint, "stiffness", kDefaultStiffness, 0.0f, kUnbounded, joint_path);
      const float power = readParam(joint, "gravityPower", kDefaultGravityPower, 0.0f, kUnbounded, joint_path);
      Vec3 dir{0.0f, -1.0f, 0.0f};
      if (auto it = joint.find("gravityDir"); it != joint.end() && !it->is_null() && !readVec3Array(*it, dir)) {
        warn("vrm-param-invalid", "gravityDir is not 3 finite numbers; using (0, -1, 0)", joint_path + "/gravityDir");
        dir = Vec3{0.0f, -1.0f, 0.0f};
      }
      setGravity(sim.params, dir, power, joint_path);
      sim.params.drag = readParam(joint, "dragForce", kDefaultDrag, 0.0f, 1.0f, joint_path);
      sim.hit_radius = readParam(joint, "hitRadius", kDefaultHitRadius, 0.0f, kMaxHitRadius, joint_path);
      readVrmJointLimit(joint, joint_path, nodeLabel(head), sim.limit, rig_->warnings);
      claim(head, std::move(sim));
    }
    if (hasVrmJointLimit((*joints)[joints->size() - 1])) {  // the draft: ignored on the last joint, a tail
      warn("limit-on-end-joint", "the last joint of a spring is only a tail; its VRMC_springBone_limit is ignored",
           path + "/joints/" + std::to_string(joints->size() - 1) + "/extensions/VRMC_springBone_limit");
    }
  }

  void claim(int node, SimJoint sim) {
    role_[node] = Role::kSimulated;
    sim_of_node_[node] = static_cast<int>(sims_.size());
    sims_.push_back(std::move(sim));
  }

  // ------------------------------------------------------------------------------------------
  // VRM 0.x secondaryAnimation

  Error readVrm0(const json& sa) {
    const std::string base = "/extensions/VRM/secondaryAnimation";
    if (!sa.is_object()) return fail(ErrorCode::kMetadataInvalid, "secondaryAnimation is not an object", base);
    std::optional<TypedValue> groups;
    std::optional<TypedValue> bone_groups;
    if (Error e = optionalArray(sa, "colliderGroups", base, groups)) return e;
    if (Error e = optionalArray(sa, "boneGroups", base, bone_groups)) return e;

    if (groups.has_value()) {
      for (std::size_t g = 0; g < groups->size(); ++g) {
        const std::string path = base + "/colliderGroups/" + std::to_string(g);
        const json& group = (*groups)[g];
        std::vector<int> ids;
        int node = -1;
        auto node_it = group.is_object() ? group.find("node") : group.end();
        if (!group.is_object() || node_it == group.end() || !readIndex(*node_it, nodes().size(), node)) {
          warn("vrm-collider-group-invalid", "collider group " + std::to_string(g) + " names no node of the file; ignored", path);
        } else if (auto list = group.find("colliders"); list != group.end() && list->is_array()) {
          for (std::size_t k = 0; k < list->size(); ++k) {
            const json& c = (*list)[k];
            const std::string cpath = path + "/colliders/" + std::to_string(k);
            FileCollider collider;
            collider.path = cpath;
            collider.node = node;
            bool ok = c.is_object();
            if (ok) {
              if (auto it = c.find("offset"); it != c.end() && !readVec3Object(*it, collider.offset)) ok = false;
              if (auto it = c.find("radius"); it != c.end() && (!readFloat(*it, collider.radius) || collider.radius < 0.0f)) {
                ok = false;
              }
            }
            if (!ok) {
              warn("vrm-collider-invalid", "collider is not an object with a finite offset {x, y, z} and a radius >= 0; ignored", cpath);
              continue;
            }
            collider.offset.z = -collider.offset.z;  // Unity axes -> glTF (see the header)
            collider.tail = collider.offset;
            collider.valid = true;
            ids.push_back(static_cast<int>(file_colliders_.size()));
            file_colliders_.push_back(std::move(collider));
          }
        } else if (list != group.end()) {
          warn("vrm-collider-group-invalid", "collider group " + std::to_string(g) + ": colliders is not an array; ignored",
               path + "/colliders");
        }
        group_colliders_.push_back(std::move(ids));
      }
    }
    if (bone_groups.has_value()) {
      for (std::size_t g = 0; g < bone_groups->size(); ++g) readVrm0Group((*bone_groups)[g], base + "/boneGroups/" + std::to_string(g));
    }
    return {};
  }

  void readVrm0Group(const json& group, const std::string& path) {
    if (!group.is_object()) {
      warn("vrm-spring-invalid", "bone group is not an object; ignored", path);
      return;
    }
    auto bones = group.find("bones");
    if (bones == group.end() || !bones->is_array() || bones->empty()) {
      warn("vrm-spring-invalid", "bone group has no bones: nothing to simulate", path + "/bones");
      return;
    }
    SpringInfo spring;
    spring.path = path;
    readSpringColliderGroups(group, path, "bone group", "the group", spring);
    if (auto center = group.find("center"); center != group.end() && !center->is_null()) {
      // UniVRM writes -1 for "no center".
      const bool none = center->is_number_integer() && center->get<std::int64_t>() == -1;
      if (!none && !readIndex(*center, nodes().size(), spring.center_node)) {
        spring.center_node = -1;
        warn("center-not-found", "bone group center is not a node of the file; using world space", path + "/center");
      }
    }
    BoneParams params;
    params.stiffness = readParam(group, "stiffiness", kDefaultStiffness, 0.0f, kUnbounded, path);  // sic, the 0.x key
    const float power = readParam(group, "gravityPower", kDefaultGravityPower, 0.0f, kUnbounded, path);
    Vec3 dir{0.0f, -1.0f, 0.0f};
    if (auto it = group.find("gravityDir"); it != group.end() && !it->is_null()) {
      if (readVec3Object(*it, dir)) {
        dir.z = -dir.z;  // Unity axes -> glTF
      } else {
        warn("vrm-param-invalid", "gravityDir is not an object {x, y, z} of finite numbers; using (0, -1, 0)", path + "/gravityDir");
        dir = Vec3{0.0f, -1.0f, 0.0f};
      }
    }
    setGravity(params, dir, power, path);
    params.drag = readParam(group, "dragForce", kDefaultDrag, 0.0f, 1.0f, path);
    const float hit_radius = readParam(group, "hitRadius", kDefaultHitRadius, 0.0f, kMaxHitRadius, path);
    const int spring_index = static_cast<int>(springs_.size());
    springs_.push_back(std::move(spring));

    std::vector<int> queue;
    for (std::size_t b = 0; b < bones->size(); ++b) {
      const std::string bone_path = path + "/bones/" + std::to_string(b);
      int root = -1;
      if (!readIndex((*bones)[b], nodes().size(), root)) {
        warn("vrm-joint-invalid", "bone " + std::to_string(b) + " is not a node of the file; ignored", bone_path);
        continue;
      }
      if (role_[root] != Role::kNone) {
        warn("vrm-joint-conflict", nodeLabel(root) + " is already simulated (by an earlier root or bone group); this root is ignored", bone_path);
        continue;
      }
      std::size_t skipped = 0;
      queue.assign(1, root);
      for (std::size_t head = 0; head < queue.size(); ++head) {
        const int n = queue[head];
        if (role_[n] != Role::kNone) {
          ++skipped;  // a subtree an earlier group owns: it keeps that group's parameters
          continue;
        }
        const SkeletonNode& node = nodes()[n];
        SimJoint sim;
        sim.spring = spring_index;
        sim.params = params;
        sim.hit_radius = hit_radius;
        if (node.children.empty()) {
          const glm::vec3 t = toGlm(node.rest_local.translation);
          const float length = glm::length(t);
          if (length > kMinBoneLength && std::isfinite(length)) sim.tail_local = fromGlm(t / length * kVrm0LeafTailLength);
        } else {
          sim.tail_node = node.children.front();
          sim.tail_local = nodes()[sim.tail_node].rest_local.translation;
          for (int c : node.children) queue.push_back(c);
        }
        claim(n, std::move(sim));
      }
      if (skipped > 0) {
        warn("vrm-joint-conflict", std::to_string(skipped) + " subtree(s) under root " + nodeLabel(root) +
                                       " are already simulated (by an earlier root or bone group) and keep those parameters",
             bone_path);
      }
    }
  }

  // ------------------------------------------------------------------------------------------
  // Rig assembly

  // A simulated node below another joint through non-joint nodes: those nodes become fixed
  // joints, so the chain's transforms compose down to it (see the header).
  void insertFixedAboveRoots() {
    const auto& all = nodes();
    std::vector<bool> joint_above(all.size(), false);
    for (int n : rig_->skeleton.parents_first) {
      const int p = all[n].parent;
      joint_above[n] = p >= 0 && (role_[p] != Role::kNone || joint_above[p]);
    }
    for (int n : rig_->skeleton.parents_first) {
      const int p = all[n].parent;
      if (role_[n] != Role::kSimulated || p < 0 || role_[p] != Role::kNone || !joint_above[n]) continue;
      std::vector<int> held;
      int below = n;
      for (int x = p; x >= 0 && role_[x] == Role::kNone; x = all[x].parent) {
        role_[x] = Role::kFixed;
        fixed_tail_[x] = below;
        held.push_back(x);
        below = x;
      }
      std::string names;
      for (std::size_t i = 0; i < held.size() && i < kMaxNamesInWarning; ++i) {
        names += (i == 0 ? "'" : ", '") + shownName(all[held[i]].name) + "'";
      }
      if (held.size() > kMaxNamesInWarning) names += ", ...";
      warn("vrm-fixed-nodes", nodeLabel(n) + " starts a spring below another spring's joint; the " + std::to_string(held.size()) +
                                  " node(s) in between (" + names + ") are held at their rest pose",
           springs_[sims_[sim_of_node_[n]].spring].path);
    }
  }

  int driverFor(int node) {
    auto [it, added] = driver_of_node_.emplace(node, static_cast<int>(rig_->drivers.size()));
    if (added) rig_->drivers.push_back(Driver{node, nodes()[node].name});
    return it->second;
  }

  int centerDriver(int spring_index) {
    SpringInfo& spring = springs_[spring_index];
    if (spring.center_driver != -2) return spring.center_driver;
    spring.center_driver = -1;
    if (spring.center_node >= 0) {
      if (under_joint_[spring.center_node]) {
        warn("center-is-spring-bone", "center " + nodeLabel(spring.center_node) +
                                          " is a spring joint or moves with one; using world space",
             spring.path + "/center");
      } else {
        spring.center_driver = driverFor(spring.center_node);
      }
    }
    return spring.center_driver;
  }

  void emitJoints() {
    const auto& all = nodes();
    under_joint_.assign(all.size(), false);
    for (int n : rig_->skeleton.parents_first) {
      const int p = all[n].parent;
      under_joint_[n] = role_[n] != Role::kNone || (p >= 0 && under_joint_[p]);
    }
    joint_of_node_.assign(all.size(), -1);
    for (int n : rig_->skeleton.parents_first) {
      if (role_[n] == Role::kNone) continue;
      const SkeletonNode& node = all[n];
      Joint joint;
      joint.node = n;
      joint.rest_local = node.rest_local;
      const int index = static_cast<int>(rig_->joints.size());
      joint.parent_joint = node.parent >= 0 ? joint_of_node_[node.parent] : -1;
      if (joint.parent_joint >= 0) {
        joint.chain = rig_->joints[joint.parent_joint].chain;
      } else {
        joint.chain = index;
        if (node.parent >= 0) joint.parent_driver = driverFor(node.parent);
        rig_->chain_roots.push_back(index);
      }
      if (role_[n] == Role::kSimulated) {
        const SimJoint& sim = sims_[sim_of_node_[n]];
        joint.tail_node = sim.tail_node;
        joint.tail_local = sim.tail_local;
        joint.params = sim.params;
        joint.hit_radius = sim.hit_radius;
        joint.limit = sim.limit;
        joint.center_driver = centerDriver(sim.spring);
        joint.rest_length = glm::length(glm::mat3(toGlm(node.rest_world)) * toGlm(joint.tail_local));
        if (!(joint.rest_length > kMinBoneLength) || !std::isfinite(joint.rest_length)) {
          warn("zero-length-bone", nodeLabel(n) + (sim.tail_node >= 0 ? " and its tail " + nodeLabel(sim.tail_node) +
                                                                           " are at the same place"
                                                                     : " is a leaf at its parent's origin (no direction for its virtual tail)") +
                                       "; the bone keeps its rest rotation",
               springs_[sim.spring].path);
        }
      } else {
        joint.tail_node = fixed_tail_[n];  // tail_local stays zero: held at rest
      }
      joint_of_node_[n] = index;
      rig_->joints.push_back(std::move(joint));
    }
  }

  // The springs' collider lists, counted against kMaxVrmColliderReferences before they are built:
  // a spring's joints x the colliders of its groups (a collider in two of its groups counts
  // twice), so one pass over the springs' group lists bounds all the work after it.
  Error gatherSpringColliders() {
    std::vector<std::uint64_t> joints_of(springs_.size(), 0);
    for (const Joint& joint : rig_->joints) {
      if (role_[joint.node] == Role::kSimulated) ++joints_of[sims_[sim_of_node_[joint.node]].spring];
    }
    std::uint64_t references = 0;  // at most kMaxNodes joints x the file's group entries: no overflow
    for (std::size_t s = 0; s < springs_.size(); ++s) {
      std::uint64_t width = 0;
      for (int g : springs_[s].groups) width += group_colliders_[g].size();
      references += joints_of[s] * width;
    }
    if (references > kMaxVrmColliderReferences) {
      return fail(ErrorCode::kLimitExceeded, "the springs' joints reference colliders " + std::to_string(references) +
                                                 " times, more than the limit of " +
                                                 std::to_string(kMaxVrmColliderReferences));
    }
    std::vector<std::size_t> taken(file_colliders_.size(), 0);  // spring index + 1 that last took it
    for (std::size_t s = 0; s < springs_.size(); ++s) {
      if (joints_of[s] == 0) continue;
      std::size_t repeated = 0;
      for (int g : springs_[s].groups) {
        for (int id : group_colliders_[g]) {
          if (taken[id] == s + 1) ++repeated;
          taken[id] = s + 1;
          springs_[s].colliders.push_back(id);
        }
      }
      if (repeated > 0) {
        warn("vrm-collider-repeated", std::to_string(repeated) + " collider(s) are in more than one of the spring's collider "
                                      "groups; each pushes once per group, as in three-vrm and UniVRM",
             springs_[s].path + "/colliderGroups");
      }
    }
    return {};
  }

  Error emitColliders() {
    if (Error e = gatherSpringColliders()) return e;
    std::vector<bool> used(file_colliders_.size(), false);
    for (const Joint& joint : rig_->joints) {
      if (role_[joint.node] != Role::kSimulated) continue;
      for (int id : springs_[sims_[sim_of_node_[joint.node]].spring].colliders) used[id] = true;
    }
    std::vector<int> rig_index(file_colliders_.size(), -1);
    for (std::size_t id = 0; id < file_colliders_.size(); ++id) {
      const FileCollider& c = file_colliders_[id];
      if (!used[id] || !c.valid) continue;
      if (under_joint_[c.node]) {
        warn("collider-on-spring-bone", "collider on " + nodeLabel(c.node) + " moves with a spring joint; ignored", c.path);
        continue;
      }
      // Beyond it the squared distances overflow in float and the collider would move nothing
      // (the bound of loadRig's colliders, kMaxColliderSize).
      if (exceedsColliderSize(c)) {
        warn("vrm-collider-invalid", "collider on " + nodeLabel(c.node) +
                                         " has a radius, offset or tail beyond 1e6 (the node's units); ignored", c.path);
        continue;
      }
      Collider collider;
      static_cast<ColliderShape&>(collider) = c;
      collider.driver = driverFor(c.node);
      rig_index[id] = static_cast<int>(rig_->colliders.size());
      rig_->colliders.push_back(collider);
    }
    for (Joint& joint : rig_->joints) {
      if (role_[joint.node] != Role::kSimulated) continue;
      // In the spring's order, repeats kept (see the header).
      for (int id : springs_[sims_[sim_of_node_[joint.node]].spring].colliders) {
        if (rig_index[id] >= 0) joint.colliders.push_back(rig_index[id]);
      }
    }
    return {};
  }

  std::shared_ptr<Rig> rig_;
  std::vector<Role> role_;
  std::vector<int> sim_of_node_;
  std::vector<int> fixed_tail_;
  std::vector<int> pre_, subtree_;
  std::vector<bool> under_joint_;
  std::vector<int> joint_of_node_;
  std::size_t walk_budget_ = 0;
  std::vector<SimJoint> sims_;
  std::vector<SpringInfo> springs_;
  std::vector<FileCollider> file_colliders_;
  std::unordered_map<int, int> driver_of_node_;
  std::vector<std::vector<int>> group_colliders_;  // file collider ids per collider group, no repeats
  std::vector<int> group_stamp_;
};

}  // namespace

Error loadVrm(const TypedValue& gltf, std::shared_ptr<const Rig>& out, VrmSpringFormat* format) {
  out.reset();
  if (format != nullptr) *format = VrmSpringFormat::kNone;
  Skeleton skeleton;
  if (Error e = readGltfDocument(gltf, skeleton)) return e;
  const auto extensions = gltf.find("extensions");
  VrmSpringFormat read = VrmSpringFormat::kNone;
  std::shared_ptr<const Rig> rig;
  try {
    if (Error e = VrmRigBuilder(std::move(skeleton)).build(extensions == gltf.end() ? TypedValue() : *extensions,
                                                           read, rig)) {
      return e;
    }
  } catch (const std::exception& ex) {  // allocation failure on an absurd file; nothing else throws
    return fail(ErrorCode::kMetadataInvalid, std::string("VRM spring bones could not be read: ") + ex.what());
  }
  if (format != nullptr) *format = read;
  out = std::move(rig);
  return {};
}

}  // namespace springbones
