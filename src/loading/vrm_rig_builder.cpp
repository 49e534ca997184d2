// The rig both VRM formats become (see vrm_rig_builder.h).
#include "loading/vrm_rig_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "common/glm_interop.h"
#include "common/shown_name.h"
#include "loading/collider_size.h"

namespace springbones {
namespace {

Error fail(ErrorCode code, std::string message, std::string path = {}) {
  return Error{code, std::move(message), std::move(path)};
}

}  // namespace

bool readVrmFloat(const TypedValue& value, float& out) {
  if (!value.is_number()) return false;
  const double v = value.get<double>();
  if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max())) return false;
  out = static_cast<float>(v);
  return true;
}

bool readVrmIndex(const TypedValue& value, std::size_t count, int& out) {
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

Error optionalVrmArray(const TypedValue& object, const char* key, const std::string& path,
                       std::optional<TypedValue>& out) {
  out.reset();
  auto it = object.find(key);
  if (it == object.end() || it->is_null()) return {};
  if (!it->is_array()) {
    return fail(ErrorCode::kMetadataInvalid, std::string(key) + " is not an array", path + "/" + key);
  }
  out = *it;
  return {};
}

VrmRigBuilder::VrmRigBuilder(Skeleton skeleton) : rig_(std::make_shared<Rig>()) {
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

void VrmRigBuilder::warn(const char* code, std::string message, std::string path) {
  rig_->warnings.push_back(Warning{code, std::move(message), std::move(path)});
}

std::string VrmRigBuilder::shownName(const std::string& name) { return springbones::shownName(name); }

std::string VrmRigBuilder::nodeLabel(int n) const {
  return "node " + std::to_string(n) + " ('" + shownName(nodes()[n].name) + "')";
}

bool VrmRigBuilder::isDescendant(int node, int ancestor) const {
  return pre_[node] > pre_[ancestor] && pre_[node] < pre_[ancestor] + subtree_[ancestor];
}

bool VrmRigBuilder::isSimulated(int node) const { return role_[node] == Role::kSimulated; }

bool VrmRigBuilder::isClaimed(int node) const { return role_[node] != Role::kNone; }

bool VrmRigBuilder::spendWalk() {
  if (walk_budget_ == 0) return false;
  --walk_budget_;
  return true;
}

// ------------------------------------------------------------------------------------------
// Parameters

float VrmRigBuilder::readParam(const TypedValue& object, const char* key, float fallback, float min, float max,
                               const std::string& path) {
  auto it = object.find(key);
  if (it == object.end() || it->is_null()) return fallback;
  float v = 0.0f;
  if (!readVrmFloat(*it, v)) {
    warn("vrm-param-invalid", std::string(key) + " is not a finite number; using " + std::to_string(fallback),
         path + "/" + key);
    return fallback;
  }
  if (v < min || v > max) {
    const float clamped = std::clamp(v, min, max);
    warn("vrm-param-clamped",
         std::string(key) + " " + std::to_string(v) + " is out of range; using " + std::to_string(clamped),
         path + "/" + key);
    return clamped;
  }
  return v;
}

void VrmRigBuilder::setGravity(BoneParams& params, Vec3 dir, float power, const std::string& path) {
  const double length = std::sqrt(double(dir.x) * dir.x + double(dir.y) * dir.y + double(dir.z) * dir.z);
  if (!(length > 1e-6)) {
    if (power > 0.0f) {
      warn("vrm-gravity-dir-zero", "gravityDir is the zero vector: no gravity", path + "/gravityDir");
    }
    params.gravity_dir = Vec3{0.0f, -1.0f, 0.0f};
    params.gravity_power = 0.0f;
    return;
  }
  params.gravity_dir =
      Vec3{static_cast<float>(dir.x / length), static_cast<float>(dir.y / length), static_cast<float>(dir.z / length)};
  params.gravity_power = static_cast<float>(std::min(double(power) * length, double(kVrmUnbounded)));
  if (std::fabs(length - 1.0) > 1e-4) {
    warn(
        "vrm-gravity-dir-scaled",
        "gravityDir has length " + std::to_string(length) + "; it is normalized and its length multiplies gravityPower",
        path + "/gravityDir");
  }
}

// ------------------------------------------------------------------------------------------
// Springs, joints and collider groups as the readers find them

void VrmRigBuilder::readSpringColliderGroups(const TypedValue& owner, const std::string& path, const char* name,
                                             const char* the, VrmSpring& spring) {
  auto groups = owner.find("colliderGroups");
  if (groups == owner.end() || groups->is_null()) return;
  if (!groups->is_array()) {
    warn("vrm-collider-group-invalid", std::string("colliderGroups is not an array; ") + the + " has no colliders",
         path + "/colliderGroups");
    return;
  }
  // The spring being read is springs_.size(): its stamp marks the groups it has listed already.
  const int stamp = static_cast<int>(springs_.size()) + 1;
  group_stamp_.resize(group_colliders_.size(), 0);
  for (std::size_t k = 0; k < groups->size(); ++k) {
    int g = -1;
    if (!readVrmIndex((*groups)[k], group_colliders_.size(), g)) {
      warn("vrm-collider-group-invalid", std::string(name) + " names a collider group that does not exist; ignored",
           path + "/colliderGroups/" + std::to_string(k));
      continue;
    }
    if (group_stamp_[g] == stamp) continue;
    group_stamp_[g] = stamp;
    spring.groups.push_back(g);
  }
}

int VrmRigBuilder::addSpring(VrmSpring&& spring) {
  springs_.push_back(std::move(spring));
  return static_cast<int>(springs_.size()) - 1;
}

void VrmRigBuilder::claim(int node, VrmSimJoint&& sim) {
  role_[node] = Role::kSimulated;
  sim_of_node_[node] = static_cast<int>(sims_.size());
  sims_.push_back(std::move(sim));
}

void VrmRigBuilder::hold(int node, int below) {
  role_[node] = Role::kFixed;
  if (fixed_tail_[node] < 0) fixed_tail_[node] = below;
}

// ------------------------------------------------------------------------------------------
// Rig assembly

Error VrmRigBuilder::emit(std::shared_ptr<const Rig>& out) {
  insertFixedAboveRoots();
  emitJoints();
  if (Error e = emitColliders()) return e;
  out = rig_;
  return {};
}

// A simulated node below another joint through non-joint nodes: those nodes become fixed joints,
// so the chain's transforms compose down to it (see the header).
void VrmRigBuilder::insertFixedAboveRoots() {
  const auto& all = nodes();
  std::vector<unsigned char> joint_above(all.size(), 0);
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
      hold(x, below);
      held.push_back(x);
      below = x;
    }
    std::string names;
    for (std::size_t i = 0; i < held.size() && i < kVrmMaxNamesInWarning; ++i) {
      names += (i == 0 ? "'" : ", '") + shownName(all[held[i]].name) + "'";
    }
    if (held.size() > kVrmMaxNamesInWarning) names += ", ...";
    warn("vrm-fixed-nodes",
         nodeLabel(n) + " starts a spring below another spring's joint; the " + std::to_string(held.size()) +
             " node(s) in between (" + names + ") are held at their rest pose",
         springs_[sims_[sim_of_node_[n]].spring].path);
  }
}

int VrmRigBuilder::driverFor(int node) {
  auto [it, added] = driver_of_node_.emplace(node, static_cast<int>(rig_->drivers.size()));
  if (added) rig_->drivers.push_back(Driver{node, nodes()[node].name});
  return it->second;
}

int VrmRigBuilder::centerDriver(int spring_index) {
  VrmSpring& spring = springs_[spring_index];
  if (spring.center_driver != -2) return spring.center_driver;
  spring.center_driver = -1;
  if (spring.center_node >= 0) {
    if (under_joint_[spring.center_node]) {
      warn("center-is-spring-bone",
           "center " + nodeLabel(spring.center_node) + " is a spring joint or moves with one; using world space",
           spring.path + "/center");
    } else {
      spring.center_driver = driverFor(spring.center_node);
    }
  }
  return spring.center_driver;
}

void VrmRigBuilder::emitJoints() {
  const auto& all = nodes();
  under_joint_.assign(all.size(), 0);
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
      const VrmSimJoint& sim = sims_[sim_of_node_[n]];
      joint.tail_node = sim.tail_node;
      joint.tail_local = sim.tail_local;
      joint.params = sim.params;
      joint.hit_radius = sim.hit_radius;
      joint.limit = sim.limit;
      joint.center_driver = centerDriver(sim.spring);
      joint.rest_length = glm::length(glm::mat3(toGlm(node.rest_world)) * toGlm(joint.tail_local));
      if (!(joint.rest_length > kVrmMinBoneLength) || !std::isfinite(joint.rest_length)) {
        warn("zero-length-bone",
             nodeLabel(n) +
                 (sim.tail_node >= 0 ? " and its tail " + nodeLabel(sim.tail_node) + " are at the same place"
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

// The springs' collider lists, counted against kMaxVrmColliderReferences before they are built: a
// spring's joints x the colliders of its groups (a collider in two of its groups counts twice), so
// one pass over the springs' group lists bounds all the work after it.
Error VrmRigBuilder::gatherSpringColliders() {
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
      warn("vrm-collider-repeated",
           std::to_string(repeated) +
               " collider(s) are in more than one of the spring's collider "
               "groups; each pushes once per group, as in three-vrm and UniVRM",
           springs_[s].path + "/colliderGroups");
    }
  }
  return {};
}

Error VrmRigBuilder::emitColliders() {
  if (Error e = gatherSpringColliders()) return e;
  std::vector<unsigned char> used(file_colliders_.size(), 0);
  for (const Joint& joint : rig_->joints) {
    if (role_[joint.node] != Role::kSimulated) continue;
    for (int id : springs_[sims_[sim_of_node_[joint.node]].spring].colliders) used[id] = true;
  }
  std::vector<int> rig_index(file_colliders_.size(), -1);
  for (std::size_t id = 0; id < file_colliders_.size(); ++id) {
    const VrmFileCollider& c = file_colliders_[id];
    if (!used[id] || !c.valid) continue;
    if (under_joint_[c.node]) {
      warn("collider-on-spring-bone", "collider on " + nodeLabel(c.node) + " moves with a spring joint; ignored",
           c.path);
      continue;
    }
    // A sphere's tail is its offset and a plane's is zero, so only a capsule's tail adds to what
    // the bound checks.
    if (exceedsMaxColliderSize(c)) {
      warn("vrm-collider-invalid",
           "collider on " + nodeLabel(c.node) + " has a radius, offset or tail beyond 1e6 (the node's units); ignored",
           c.path);
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

}  // namespace springbones
