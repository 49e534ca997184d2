// What both VRM formats share: the springs, joints and colliders a format reader
// (vrmc_spring_bone.cpp, vrm0_secondary_animation.cpp) finds in a file, and the rig they become.
// What a file's model becomes, and where we differ from three-vrm and UniVRM, is
// docs/semantics.md, "VRM avatars"; here, how the shared part holds to it:
//  - The Rig holds every joint once, parents first; a joint's parent_joint is the joint of its
//    glTF parent, and a joint whose glTF parent is no joint is a chain root hanging from a driver,
//    as in rig_builder.cpp. The solver carries transforms only down joint links, so nodes skipped
//    between a spring root and a joint above it become fixed joints (zero tail: held at their
//    rest rotation), as do the nodes a reader holds (hold()).
//  - gravityDir is stored normalized (the BoneParams contract) with its length folded into
//    gravity_power, so dir * power is exactly the file's impulse.
//  - A joint's collider list is its spring's groups' colliders in the order the spring lists the
//    groups, a collider in two of them twice: three-vrm and UniVRM test every group a joint uses,
//    collider by collider, so such a collider pushes twice (once per group), and so does ours. A
//    group listed twice by one spring, or a collider twice by one group, counts once. A rig whose
//    lists are not in index order once each steps on the general path (the lane path's collider
//    mask holds neither order nor repeats).
#pragma once

#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/typed_value.h"
#include "springbones/springbones.h"
#include "springbones/vrm.h"

namespace springbones {

// What a parameter a file leaves out is, in both formats; kVrmUnbounded is the upper bound of one
// the formats do not bound.
inline constexpr float kVrmDefaultStiffness = 1.0f;
inline constexpr float kVrmDefaultGravityPower = 0.0f;
inline constexpr float kVrmDefaultDrag = 0.5f;
inline constexpr float kVrmDefaultHitRadius = 0.0f;
inline constexpr float kVrmUnbounded = std::numeric_limits<float>::max();
/// Shorter bones have no direction to simulate.
inline constexpr float kVrmMinBoneLength = 1e-6f;
/// Node names one vrm-fixed-nodes warning lists before "...".
inline constexpr std::size_t kVrmMaxNamesInWarning = 8;

/// A double that fits a float and is finite.
bool readVrmFloat(const TypedValue& value, float& out);
/// An integer in [0, count).
bool readVrmIndex(const TypedValue& value, std::size_t count, int& out);

/// Optional array member: nullopt when absent or null, an Error (kMetadataInvalid) when present but
/// not an array.
Error optionalVrmArray(const TypedValue& object, const char* key, const std::string& path,
                       std::optional<TypedValue>& out);

/// A spring (1.0) or bone group (0.x) as the file describes it, resolved at emission.
struct VrmSpring {
  std::string path;
  int center_node = -1;        // -1: world space
  std::vector<int> groups;     // collider group ids, first appearance order, no repeats
  std::vector<int> colliders;  // file collider ids of those groups, no repeats (emitColliders)
  int center_driver = -2;      // -2: not resolved yet
};

/// A simulated joint as a reader found it.
struct VrmSimJoint {
  int spring = -1;
  int tail_node = -1;  // -1: a VRM 0.x virtual tail
  Vec3 tail_local;
  BoneParams params;
  float hit_radius = 0.0f;
  JointLimit limit;
};

/// A collider as the file describes it: its shape, the node carrying it and where it was read.
struct VrmFileCollider : ColliderShape {
  bool valid = false;
  int node = -1;
  std::string path;
};

class VrmRigBuilder {
 public:
  explicit VrmRigBuilder(Skeleton skeleton);

  // ------------------------------------------------------------------------------------------
  // For the format readers

  const std::vector<SkeletonNode>& nodes() const { return rig_->skeleton.nodes; }
  std::vector<Warning>& warnings() { return rig_->warnings; }
  void warn(const char* code, std::string message, std::string path = {});

  /// A node name cut to a bounded length for a message: a file can name one node in a warning per
  /// spring or per collider, and its whole name in each would grow the warnings as springs x name
  /// length.
  static std::string shownName(const std::string& name);
  /// "node 3 ('hair')".
  std::string nodeLabel(int n) const;

  bool isDescendant(int node, int ancestor) const;
  /// Whether a node is a simulated joint, or a simulated or held one.
  bool isSimulated(int node) const;
  bool isClaimed(int node) const;
  /// One step of walking the nodes between listed joints; false when the file has used them all
  /// (a bound linear in the node count).
  bool spendWalk();

  /// A parameter in [min, max]: the fallback when absent or null; a warning for one that is not a
  /// finite number (the fallback) or out of range (clamped).
  float readParam(const TypedValue& object, const char* key, float fallback, float min, float max,
                  const std::string& path);
  /// gravityDir * gravityPower as the file means it, with a unit direction (see the header).
  void setGravity(BoneParams& params, Vec3 dir, float power, const std::string& path);

  std::size_t colliderCount() const { return file_colliders_.size(); }
  std::size_t colliderGroupCount() const { return group_colliders_.size(); }
  void addCollider(VrmFileCollider&& collider) { file_colliders_.push_back(std::move(collider)); }
  /// File collider ids, no repeats.
  void addColliderGroup(std::vector<int>&& colliders) { group_colliders_.push_back(std::move(colliders)); }

  /// The colliderGroups of a spring (1.0) or a bone group (0.x) into `spring`: indices of the
  /// collider groups read before it, each once. One that names none is left out with a warning;
  /// `name` and `the` are what the warnings call the owner ("bone group", "the group").
  void readSpringColliderGroups(const TypedValue& owner, const std::string& path, const char* name, const char* the,
                                VrmSpring& spring);
  /// The spring's index.
  int addSpring(VrmSpring&& spring);

  /// `node` becomes a simulated joint.
  void claim(int node, VrmSimJoint&& sim);
  /// `node` becomes a fixed joint whose tail is `below` (unless it has one already).
  void hold(int node, int below);

  // ------------------------------------------------------------------------------------------
  // The rig

  /// The joints, chains, drivers and colliders of what the readers found. kLimitExceeded beyond
  /// kMaxVrmColliderReferences.
  Error emit(std::shared_ptr<const Rig>& out);

 private:
  enum class Role : unsigned char { kNone, kSimulated, kFixed };

  void insertFixedAboveRoots();
  int driverFor(int node);
  int centerDriver(int spring_index);
  void emitJoints();
  Error gatherSpringColliders();
  Error emitColliders();

  std::shared_ptr<Rig> rig_;
  std::vector<Role> role_;
  std::vector<int> sim_of_node_;
  std::vector<int> fixed_tail_;
  std::vector<int> pre_, subtree_;
  std::vector<unsigned char> under_joint_;
  std::vector<int> joint_of_node_;
  std::size_t walk_budget_ = 0;
  std::vector<VrmSimJoint> sims_;
  std::vector<VrmSpring> springs_;
  std::vector<VrmFileCollider> file_colliders_;
  std::unordered_map<int, int> driver_of_node_;
  std::vector<std::vector<int>> group_colliders_;  // file collider ids per collider group, no repeats
  std::vector<int> group_stamp_;
};

}  // namespace springbones
