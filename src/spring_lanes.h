// The fast path of the solver: joints laid out in lanes so one loop steps many chains at once.
//
// A lane is a straight run of joints: a chain root followed by its tail joint, that joint's tail
// joint, and so on; every other child joint starts a lane of its own (a branch). Joint (lane l,
// depth d) lives at slot d * lane_count + l, so the joints of one depth sit side by side and one
// branch-free loop over the lanes computes them together (SIMD lanes in WebAssembly with
// -msimd128, plain scalar code elsewhere, same results). Depth-major order is also parents-first.
// Transforms are similarities (rotation, translation, uniform scale); the solver only takes this
// path when every driver and every rest scale is one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "springbones.h"

namespace springbones {

/// A driver's transform for one step, as the kernel reads it. Slot 0 of the table is the identity
/// (no parent driver, no center).
struct DriverTable {
  std::vector<float> px, py, pz, qx, qy, qz, qw, s;
  void resize(std::size_t slots);
  void set(std::size_t slot, const glm::vec3& p, const glm::quat& q, float scale);
};

/// Collider shapes in world space for one step: a segment (x0..x1; a point for a sphere) and a
/// radius. At most kMaxLaneColliders take part on this path (a bit mask per joint).
struct ColliderTable {
  std::size_t count = 0;
  std::vector<float> x0, y0, z0, x1, y1, z1, radius;
  void resize(std::size_t colliders);
  void set(std::size_t collider, const glm::vec3& start, const glm::vec3& end, float radius);
};

inline constexpr std::size_t kMaxLaneColliders = 32;

class SpringLanes {
 public:
  explicit SpringLanes(const Rig& rig);

  /// Seeds (tails at rest, no velocity) or advances every joint by one step of h seconds, and
  /// writes the local rotations (x, y, z, w per joint, rig order) to `rotations`.
  void run(const DriverTable& drivers, const ColliderTable& colliders, float h, bool seed, float* rotations);

  /// World transform of a joint after the last run (rig joint index).
  void jointWorld(std::size_t joint, glm::vec3& position, glm::quat& rotation, float& scale) const;

  std::size_t laneCount() const { return lane_count_; }
  std::size_t depthCount() const { return depth_count_; }

 private:
  template <bool kSeed, bool kCenter>
  void runDepth(std::size_t depth, const DriverTable& drivers, const ColliderTable& colliders, float h);

  std::size_t lane_count_ = 0;   // padded to a multiple of kLaneMultiple
  std::size_t depth_count_ = 0;
  bool any_center_ = false;

  // Per lane.
  std::vector<int> lane_start_depth_;
  std::vector<int> lane_parent_driver_;  // driver table slot of a root lane, else -1
  std::vector<int> lane_parent_slot_;    // joint slot of a branch lane's parent, else -1

  // Per slot: which joint (-1 for padding) and its constants.
  std::vector<int> slot_joint_;
  std::vector<int> joint_slot_;  // inverse map, per rig joint
  std::vector<int> center_;      // driver table slot, 0 for world space
  std::vector<float> tx_, ty_, tz_;            // rest translation
  std::vector<float> rx_, ry_, rz_, rw_;       // rest rotation
  std::vector<float> rs_;                      // rest uniform scale
  std::vector<float> ax_, ay_, az_;            // unit tail axis, local
  std::vector<float> px_, py_, pz_;            // a unit axis perpendicular to it (180-degree turns)
  std::vector<float> tail_distance_;           // |tail_local|, 0 keeps the joint at rest
  std::vector<float> stiffness_, gravity_power_, keep_;  // keep = 1 - drag
  std::vector<float> gx_, gy_, gz_;            // unit gravity direction
  std::vector<float> hit_radius_;
  std::vector<std::uint32_t> collider_mask_;   // bit c: collides with collider c

  // Per slot: simulation state and world transforms.
  std::vector<float> cx_, cy_, cz_, ox_, oy_, oz_;  // current and previous tail, center space
  std::vector<float> wpx_, wpy_, wpz_, wqx_, wqy_, wqz_, wqw_, ws_;
  std::vector<float> out_x_, out_y_, out_z_, out_w_;

  // Per lane scratch: the parent transform of the joint being computed, and its center.
  std::vector<float> ppx_, ppy_, ppz_, pqx_, pqy_, pqz_, pqw_, ps_;
  std::vector<float> cpx_, cpy_, cpz_, cqx_, cqy_, cqz_, cqw_, cs_;
  // Per lane scratch between the kernel's passes: head, rest world rotation, length, scale, tail.
  std::vector<float> hx_, hy_, hz_, qx_, qy_, qz_, qw_, len_, scale_, nx_w_, ny_w_, nz_w_;
};

}  // namespace springbones
