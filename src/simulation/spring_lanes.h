// The fast path of the solver: joints laid out in lanes so one loop steps many chains at once,
// for every avatar wearing the same rig.
//
// A lane is a straight run of joints: a chain root followed by its tail joint, that joint's tail
// joint, and so on; every other child joint starts a lane of its own (a branch). A rig has R
// lanes and D depths. Every instance of the rig is a copy in one shared pool, and the copies of
// one rig lane sit side by side: joint (copy k, rig lane l, depth d) is lane l * copy_capacity + k
// of row d (rows are stored in blocks of lanes, see slotIndex). So one branch-free loop over a run
// of copies computes a rig slot for all of them (SIMD lanes in WebAssembly with -msimd128, plain
// scalar code elsewhere; every lane gets the same bits either way, wherever it sits in the run),
// the slot's constants (rest pose, parameters) are the same for the whole loop and stored once per
// rig, and lanes a depth does not have are not computed at all. Depth-major order is also
// parents-first.
// Transforms are similarities (rotation, translation, uniform scale); the solver only takes this
// path when every driver and every rest scale is one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "simulation/collider_kind.h"
#include "simulation/rig_constants.h"
#include "springbones/springbones.h"

namespace springbones {

/// Drivers' transforms for one step, as the kernel reads them: driver count + 1 rows of one entry
/// per copy (SpringLanes::driverIndex), the first row the identity (no parent driver, no center).
struct DriverTable {
  std::vector<float> px, py, pz, qx, qy, qz, qw, s;
};

/// Collider shapes in world space for one step: a segment (x0..x1; a point for a sphere) and a
/// radius, or for a plane a point of it (x0) and its unit normal (x1), radius 0. At most
/// kMaxLaneColliders per rig take part on the lane path (a bit mask per joint); there, one row per
/// rig collider of one entry per copy (SpringLanes::colliderIndex).
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
  /// The pool of a rig's lanes, shared by the rig's instances: the rig's constants hold it for
  /// them (RigConstants::lane_pool), the first instance makes it and the last one frees it.
  static std::shared_ptr<SpringLanes> acquire(const std::shared_ptr<const RigConstants>& constants);

  explicit SpringLanes(std::shared_ptr<const RigConstants> constants);

  /// A new copy; `rotations` (4 floats per rig joint, rig order) receives its local rotations
  /// after every run that includes it, until releaseCopy(). Seed it (run with seed) first.
  std::size_t addCopy(float* rotations);
  void releaseCopy(std::size_t copy);

  /// Where rig driver d of a copy goes in the driver table; driver d + 1 is driverStride() further.
  std::size_t driverIndex(std::size_t copy, int driver) const {
    return (static_cast<std::size_t>(driver) + 1) * copy_capacity_ + copy;
  }
  std::size_t driverStride() const { return copy_capacity_; }
  DriverTable& drivers() { return drivers_; }
  /// Where rig collider c of a copy goes in the collider table.
  std::size_t colliderIndex(std::size_t copy, std::size_t collider) const { return collider * copy_capacity_ + copy; }
  ColliderTable& colliders() { return colliders_; }
  /// A copy's wind for its next run: the displacement it adds to every tail in one step (world
  /// space, the wind's pull times h), as gravity adds its own.
  void setWind(std::size_t copy, const glm::vec3& step_pull) {
    wind_x_[copy] = step_pull.x;
    wind_y_[copy] = step_pull.y;
    wind_z_[copy] = step_pull.z;
  }

  /// Seeds (tails at rest, no velocity) or advances every joint of the copies in `ranges`
  /// (ascending, not overlapping) by one step of h seconds, then writes their rotations.
  void run(const CopyRange* ranges, std::size_t range_count, float h, bool seed);

  /// Queues one step of h seconds for a copy; runQueued() then steps every queued copy, those at
  /// the same rate together, and empties the queue (Instance::stepAll: all copies of a rig in as
  /// few runs as they allow, consecutive copies at one rate forming one run).
  void queueStep(std::size_t copy, float h) { queued_.push_back({h, copy}); }
  void runQueued();

  /// World transform of a joint of a copy after its last run (rig joint index).
  void jointWorld(std::size_t copy, std::size_t joint, glm::vec3& position, glm::quat& rotation, float& scale) const;

  /// A joint's tail state in a copy: the current and previous tail, in the joint's center space.
  /// Read and rewritten when an instance carries its chains across a jump of its drivers.
  void tailState(std::size_t copy, std::size_t joint, glm::vec3& current, glm::vec3& previous) const;
  void setTailState(std::size_t copy, std::size_t joint, const glm::vec3& current, const glm::vec3& previous);

 private:
  // What a rig slot (depth, rig lane) needs besides its state, the same for every copy.
  struct SlotConstants {
    float tx, ty, tz;                      // rest translation
    float rx, ry, rz, rw;                  // rest rotation
    float rs;                              // rest uniform scale
    float bx, by, bz;                      // unit tail axis at rest, in the parent's frame
    float nx, ny, nz;                      // a unit axis perpendicular to it (180-degree turns)
    float tail_distance;                   // |tail_local|, 0 keeps the joint at rest
    float stiffness, gravity_power, keep;  // keep = 1 - drag
    float gx, gy, gz;                      // unit gravity direction
    float hit_radius;
    std::size_t center;           // driver table row of the joint's center (0: world space)
    std::uint32_t collider_mask;  // bit c: collides with the rig's collider c
    bool continues;               // the joint is its parent's tail, so its head is the parent's new tail
  };
  struct LaneStart {
    int lane;           // rig lane that begins at this depth
    int parent_lane;    // rig lane of the joint it branches off (one depth up), -1 for a root
    int parent_driver;  // rig driver of a root's parent, -1: the identity
  };

  // Seed, Center, Continues: bool, or std::integral_constant<bool, ...> for a kernel of its own.
  template <typename Seed, typename Center, typename Continues>
  void runSlot(Seed seed, Center center, Continues continues, std::size_t depth, std::size_t lane,
               std::size_t first_copy, std::size_t end_copy, float h);
  void runSlotFor(bool seed, bool center, bool continues, std::size_t depth, std::size_t lane, std::size_t first_copy,
                  std::size_t end_copy, float h);
  void collideSlot(std::uint32_t mask, float hit_radius, std::size_t base_lane, std::size_t begin, std::size_t end);
  void beginLanes(std::size_t depth, std::size_t first_copy, std::size_t end_copy);
  void writeRotations(std::size_t first_copy, std::size_t end_copy);
  void growTo(std::size_t copies);

  // Where a value lives. Slots and world transforms are stored in blocks of eight lanes, field by
  // field (every field of eight neighbouring lanes in 32 consecutive bytes), so the kernel reaches
  // all of a block from one address: separate arrays per field cost it more in reloaded pointers
  // and spilled registers than the arithmetic itself.
  std::size_t slotIndex(std::size_t field, std::size_t row, std::size_t lane) const;
  std::size_t worldIndex(std::size_t field, std::size_t row, std::size_t lane) const;

  std::shared_ptr<const RigConstants> rig_constants_;  // and through them the rig
  std::size_t lanes_per_copy_ = 0;                     // R
  std::size_t depth_count_ = 0;                        // D
  std::size_t copy_capacity_ = 0;                      // a whole number of blocks
  std::size_t lane_capacity_ = 0;                      // R * copy_capacity_
  std::size_t blocks_per_row_ = 0;
  std::size_t collider_count_ = 0;            // rig colliders on the lane path
  int collider_passes_ = 1;                   // Rig::collider_passes
  std::vector<ColliderKind> collider_kinds_;  // per rig collider on the lane path
  bool any_center_ = false;

  // The rig's layout and constants.
  std::vector<std::vector<LaneStart>> starts_;  // per depth
  std::vector<std::vector<int>> lanes_at_;      // per depth: the rig lanes with a joint there
  std::vector<SlotConstants> constants_;        // per rig slot, depth * R + lane
  std::vector<int> joint_lane_, joint_depth_;   // per rig joint

  // Copies.
  std::vector<float*> copy_rotations_;  // nullptr: a free copy
  std::vector<std::size_t> free_copies_;
  // The steps queued for runQueued() and its runs, sized with the copies so a frame allocates nothing.
  struct QueuedStep {
    float h;
    std::size_t copy;
    bool operator<(const QueuedStep& o) const { return h != o.h ? h < o.h : copy < o.copy; }
  };
  std::vector<QueuedStep> queued_;
  std::vector<CopyRange> queued_runs_;
  DriverTable drivers_;
  ColliderTable colliders_;
  std::vector<float> wind_x_, wind_y_, wind_z_;  // per copy, see setWind

  // Per slot, depth_count_ rows in blocks: the tail state and the local rotation.
  std::vector<float> slots_;
  // World transforms, depth_count_ + 1 rows, in blocks: row d + 1 holds the joints of depth d,
  // row d the parents the lanes beginning at depth d hang from (a lane has no joint above its
  // start).
  std::vector<float> world_;
  // Per lane, in blocks: between the kernel's two passes (and the colliders'), the head, length,
  // scale and new tail.
  std::vector<float> between_;
};

}  // namespace springbones
