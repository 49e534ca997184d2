// The fast path of the solver: joints laid out in lanes so one loop steps many chains at once,
// for every avatar wearing the same rig.
//
// A lane is a straight run of joints: a chain root followed by its tail joint, that joint's tail
// joint, and so on; every other child joint starts a lane of its own (a branch). A rig has R
// lanes and D depths. Every instance of the rig is a copy of those R lanes in one shared pool, so
// a scene steps all avatars of a rig together: joint (copy k, lane l, depth d) is lane k * R + l
// of row d (rows are stored in blocks of lanes, see slotIndex). The joints of one depth sit side
// by side for all copies and one branch-free loop over a run of copies computes them together
// (SIMD lanes in WebAssembly with -msimd128, plain scalar code elsewhere; every lane gets the same
// bits either way, wherever it sits in the run). Depth-major order is also parents-first.
// Transforms are similarities (rotation, translation, uniform scale); the solver only takes this
// path when every driver and every rest scale is one.
//
// The pool is shared by every instance of a rig (see acquire()); like the instances it is not
// thread-safe: step the instances of one rig from one thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "springbones.h"

namespace springbones {

/// Drivers' transforms for one step, as the kernel reads them: per copy a block of
/// driver count + 1 slots, the first of which is the identity (no parent driver, no center).
struct DriverTable {
  std::vector<float> px, py, pz, qx, qy, qz, qw, s;
  void resize(std::size_t slots);
};

/// Collider shapes in world space for one step: a segment (x0..x1; a point for a sphere) and a
/// radius. At most kMaxLaneColliders per rig take part on the lane path (a bit mask per joint).
struct ColliderTable {
  std::size_t count = 0;
  std::vector<float> x0, y0, z0, x1, y1, z1, radius;
  void resize(std::size_t colliders);
  void set(std::size_t collider, const glm::vec3& start, const glm::vec3& end, float radius);
};

inline constexpr std::size_t kMaxLaneColliders = 32;

/// A run of consecutive copies [first, end) stepped by one SpringLanes::run.
struct CopyRange {
  std::size_t first = 0, end = 0;
};

class SpringLanes {
 public:
  /// The pool of `rig`'s lanes, shared by every instance of that rig alive in this process (one
  /// is made on first use and freed with its last instance).
  static std::shared_ptr<SpringLanes> acquire(const std::shared_ptr<const Rig>& rig);

  explicit SpringLanes(std::shared_ptr<const Rig> rig);

  /// A new copy at rest under identity drivers; `rotations` (4 floats per rig joint, rig order)
  /// receives its local rotations after every run that includes it, until releaseCopy().
  std::size_t addCopy(float* rotations);
  void releaseCopy(std::size_t copy);

  /// The copy's block of the driver table: slot 1 + d is rig driver d.
  std::size_t driverSlot(std::size_t copy, int driver) const { return copy * driver_block_ + 1 + driver; }
  DriverTable& drivers() { return drivers_; }
  /// The copy's colliders start at collider copy * rig colliders.
  std::size_t colliderBase(std::size_t copy) const { return copy * collider_block_; }
  ColliderTable& colliders() { return colliders_; }

  /// Seeds (tails at rest, no velocity) or advances every joint of the copies in `ranges`
  /// (ascending, not overlapping) by one step of h seconds, then writes their rotations.
  void run(const CopyRange* ranges, std::size_t range_count, float h, bool seed);

  /// World transform of a joint of a copy after its last run (rig joint index).
  void jointWorld(std::size_t copy, std::size_t joint, glm::vec3& position, glm::quat& rotation,
                  float& scale) const;

  std::size_t lanesPerCopy() const { return lanes_per_copy_; }
  std::size_t depthCount() const { return depth_count_; }

 private:
  struct LaneStart {
    int lane;          // rig lane that begins at this depth
    int parent_lane;   // rig lane of the joint it branches off (one depth up), -1 for a root
    int parent_driver; // rig driver of a root's parent, -1: the identity
  };

  template <bool kSeed, bool kCenter, bool kColliders>
  void runDepth(std::size_t depth, std::size_t first_copy, std::size_t end_copy, float h);
  void beginLanes(std::size_t depth, std::size_t first_copy, std::size_t end_copy);
  void copyDriver(std::size_t slot, float* to) const;
  void writeRotations(std::size_t first_copy, std::size_t end_copy);
  void growTo(std::size_t copies);

  // Where a value lives. Slots and world transforms are stored in blocks of eight lanes, field by
  // field (every field of eight neighbouring lanes in 32 consecutive bytes), so the kernel reaches
  // all of a block from one address: separate arrays per field cost it more in reloaded pointers
  // and spilled registers than the arithmetic itself.
  std::size_t slotIndex(std::size_t field, std::size_t row, std::size_t lane) const;
  std::size_t worldIndex(std::size_t field, std::size_t row, std::size_t lane) const;

  std::shared_ptr<const Rig> rig_;
  std::size_t lanes_per_copy_ = 0;  // R
  std::size_t depth_count_ = 0;     // D
  std::size_t copy_capacity_ = 0;
  std::size_t lane_capacity_ = 0;   // copy_capacity_ * R, rounded up to whole blocks
  std::size_t blocks_per_row_ = 0;
  std::size_t driver_block_ = 1;    // rig drivers + 1
  std::size_t collider_block_ = 0;  // rig colliders
  bool any_center_ = false;

  // The rig's layout.
  std::vector<std::vector<LaneStart>> starts_;  // per depth
  std::vector<int> joint_lane_, joint_depth_;   // per rig joint
  std::vector<int> template_joint_;             // per depth and rig lane (depth * R + lane): joint or -1

  // Copies.
  std::vector<float*> copy_rotations_;          // nullptr: a free copy
  std::vector<std::size_t> free_copies_;
  DriverTable drivers_;
  ColliderTable colliders_;

  // Per slot, depth_count_ rows: the joint's constants, its tail state and its local rotation
  // (fields in spring_lanes.cpp), in blocks.
  std::vector<float> slots_;
  // Per slot, plain rows of lane_capacity_: read one lane at a time.
  std::vector<int> center_;                    // driver table slot of the joint's center
  std::vector<std::uint32_t> collider_mask_;   // bit c: collides with the rig's collider c
  // World transforms, depth_count_ + 1 rows, in blocks: row d + 1 holds the joints of depth d,
  // row d the parents the lanes beginning at depth d hang from (a lane has no joint above its
  // start).
  std::vector<float> world_;
  // Per lane, in blocks: the center's transform of the current depth; between the kernel's two
  // passes (and the colliders'), the head, length, scale and new tail.
  std::vector<float> centers_, between_;
};

}  // namespace springbones
