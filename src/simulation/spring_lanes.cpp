// The lane kernel: the spring update of general_integrator.cpp written on plain floats in structure-of-arrays
// form, one loop over a run of copies per rig slot (depth, rig lane). The loop bodies have no branches
// (selects only) and no calls, so clang vectorises them for WebAssembly SIMD; every operation is
// a single IEEE operation with -ffp-contract=off, so vectorised and scalar code produce the same
// bits, whichever lanes of a vector a joint falls in.
#include "simulation/spring_lanes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <type_traits>
#include <utility>

#if defined(__GNUC__)
#define SPRINGBONES_ALWAYS_INLINE __attribute__((always_inline))
#define SPRINGBONES_NOINLINE __attribute__((noinline))
#else
#define SPRINGBONES_ALWAYS_INLINE
#define SPRINGBONES_NOINLINE
#endif

namespace springbones {
namespace {

constexpr float kMinLength = 1e-6f;
constexpr float kOppositeDot = -0.999999f;  // rest axis and target nearly opposite

// v' = v + w t + q x t with t = 2 (q x v): the rotation of v by the unit quaternion (x, y, z, w).
inline void rotate(float qx, float qy, float qz, float qw, float vx, float vy, float vz, float& ox, float& oy,
                   float& oz) {
  const float tx = 2.0f * (qy * vz - qz * vy);
  const float ty = 2.0f * (qz * vx - qx * vz);
  const float tz = 2.0f * (qx * vy - qy * vx);
  ox = vx + qw * tx + (qy * tz - qz * ty);
  oy = vy + qw * ty + (qz * tx - qx * tz);
  oz = vz + qw * tz + (qx * ty - qy * tx);
}

// (a * b), Hamilton product.
inline void multiply(float ax, float ay, float az, float aw, float bx, float by, float bz, float bw, float& ox,
                     float& oy, float& oz, float& ow) {
  ox = aw * bx + ax * bw + ay * bz - az * by;
  oy = aw * by - ax * bz + ay * bw + az * bx;
  oz = aw * bz + ax * by - ay * bx + az * bw;
  ow = aw * bw - ax * bx - ay * by - az * bz;
}

// The block layout (see slotIndex in spring_lanes.h): eight lanes per block, one field after
// the other. A block is two SIMD vectors of four, computed interleaved: the square roots and
// divisions of one then overlap the other's (one vector per block was ~5% slower in Node 20).
constexpr std::size_t kBlockLanes = 8;
enum SlotField : std::size_t {
  kCx,
  kCy,
  kCz,
  kOx,
  kOy,
  kOz,  // current and previous tail, center space
  kOutX,
  kOutY,
  kOutZ,
  kOutW,  // local rotation
  kSlotFields
};
enum TransformField : std::size_t { kPx, kPy, kPz, kQx, kQy, kQz, kQw, kS, kTransformFields };
enum BetweenField : std::size_t { kHeadX, kHeadY, kHeadZ, kLength, kScale, kTailX, kTailY, kTailZ, kBetweenFields };
constexpr std::size_t kSlotBlock = kSlotFields * kBlockLanes;
constexpr std::size_t kTransformBlock = kTransformFields * kBlockLanes;
constexpr std::size_t kBetweenBlock = kBetweenFields * kBlockLanes;

// What a lane holds before its copy is seeded: rest rotations and identity transforms, finite.
float restSlot(std::size_t field) { return field == kOutW ? 1.0f : 0.0f; }
float identityTransform(std::size_t field) { return field == kQw || field == kS ? 1.0f : 0.0f; }

// Calls body(block, lane in block) for the lanes [begin, end). Whole blocks go through a loop
// the vectoriser turns into straight SIMD code; the partial blocks at the ends of a run of copies
// (their other lanes belong to copies not stepping) go lane by lane, with the same arithmetic.
template <typename Body>
SPRINGBONES_ALWAYS_INLINE inline void forEachLane(std::size_t begin, std::size_t end, const Body& body) {
  for (std::size_t block = begin / kBlockLanes; block * kBlockLanes < end; ++block) {
    const std::size_t first = block * kBlockLanes;
    const std::size_t lo = begin > first ? begin - first : 0;
    const std::size_t hi = end < first + kBlockLanes ? end - first : kBlockLanes;
    if (lo == 0 && hi == kBlockLanes) {
#if defined(__clang__)
#pragma clang loop vectorize(assume_safety) vectorize_width(4) interleave_count(2)
#endif
      for (std::size_t i = 0; i < kBlockLanes; ++i) body(block, i);
    } else {
#if defined(__clang__)
#pragma clang loop vectorize(disable)
#endif
      for (std::size_t i = lo; i < hi; ++i) body(block, i);
    }
  }
}

glm::vec3 perpendicularTo(const glm::vec3& axis) {
  glm::vec3 p = glm::cross(glm::vec3(1, 0, 0), axis);
  if (glm::dot(p, p) < 1e-12f) p = glm::cross(glm::vec3(0, 1, 0), axis);
  return glm::normalize(p);
}

// One collider against the tails of the lanes [begin, end) (between row, lane l = copy + base),
// each then put back at the bone's length from its head. The collider's row in `table` starts
// at shape_at. The arithmetic of moveTailByCollider (collider_kind.h), branch-free.
template <ColliderKind kKind>
SPRINGBONES_ALWAYS_INLINE inline void collideLanes(const ColliderTable& table, std::size_t shape_at, float* between_row,
                                                   std::size_t base_lane, std::size_t begin, std::size_t end,
                                                   float hit_radius) {
  constexpr std::size_t B = kBlockLanes;
  const float* __restrict x0 = table.x0.data() + shape_at;
  const float* __restrict y0 = table.y0.data() + shape_at;
  const float* __restrict z0 = table.z0.data() + shape_at;
  const float* __restrict x1 = table.x1.data() + shape_at;
  const float* __restrict y1 = table.y1.data() + shape_at;
  const float* __restrict z1 = table.z1.data() + shape_at;
  const float* __restrict radius = table.radius.data() + shape_at;
  forEachLane(begin, end, [&](std::size_t block, std::size_t i) SPRINGBONES_ALWAYS_INLINE {
    float* __restrict t = between_row + block * kBetweenBlock + i;
    const std::size_t l = block * B + i - base_lane;  // the copy
    const float tx = t[kTailX * B], ty = t[kTailY * B], tz = t[kTailZ * B];
    const float vx = tx - x0[l], vy = ty - y0[l], vz = tz - z0[l];
    bool pushed;
    float px, py, pz;
    if (kKind == ColliderKind::kPlane) {
      const float nx = x1[l], ny = y1[l], nz = z1[l];
      const float penetration = hit_radius - (vx * nx + vy * ny + vz * nz);
      pushed = penetration > 0.0f;
      const float push = pushed ? penetration : 0.0f;
      px = tx + nx * push;
      py = ty + ny * push;
      pz = tz + nz * push;
    } else {
      const float sgx = x1[l] - x0[l], sgy = y1[l] - y0[l], sgz = z1[l] - z0[l];
      const float segment2 = sgx * sgx + sgy * sgy + sgz * sgz;
      float along = segment2 > 0.0f ? (vx * sgx + vy * sgy + vz * sgz) / segment2 : 0.0f;
      along = along < 0.0f ? 0.0f : (along > 1.0f ? 1.0f : along);
      const float dx = vx - sgx * along, dy = vy - sgy * along, dz = vz - sgz * along;
      const float distance = std::sqrt(dx * dx + dy * dy + dz * dz);
      const float penetration =
          kKind == ColliderKind::kInside ? distance + hit_radius - radius[l] : radius[l] + hit_radius - distance;
      pushed = penetration > 0.0f && distance > kMinLength;
      const float ratio = penetration / distance;
      const float push = pushed ? (kKind == ColliderKind::kInside ? -ratio : ratio) : 0.0f;
      px = tx + dx * push;
      py = ty + dy * push;
      pz = tz + dz * push;
    }
    const float hx = t[kHeadX * B], hy = t[kHeadY * B], hz = t[kHeadZ * B];
    const float fx = px - hx, fy = py - hy, fz = pz - hz;
    const float offset_length = std::sqrt(fx * fx + fy * fy + fz * fz);
    const bool usable = pushed && offset_length > kMinLength && offset_length < 1e30f;
    const float to_length = t[kLength * B] / offset_length;
    t[kTailX * B] = usable ? hx + fx * to_length : tx;
    t[kTailY * B] = usable ? hy + fy * to_length : ty;
    t[kTailZ * B] = usable ? hz + fz * to_length : tz;
  });
}

}  // namespace

void ColliderTable::resize(std::size_t colliders) {
  count = colliders;
  for (auto* v : {&x0, &y0, &z0, &x1, &y1, &z1, &radius}) v->assign(colliders, 0.0f);
}

void ColliderTable::set(std::size_t c, const glm::vec3& start, const glm::vec3& end, float r) {
  x0[c] = start.x;
  y0[c] = start.y;
  z0[c] = start.z;
  x1[c] = end.x;
  y1[c] = end.y;
  z1[c] = end.z;
  radius[c] = r;
}

// ---------------------------------------------------------------------------------------------
// The pool

std::shared_ptr<SpringLanes> SpringLanes::acquire(const std::shared_ptr<const RigConstants>& constants) {
  if (std::shared_ptr<SpringLanes> pool = constants->lane_pool.lock()) return pool;
  // Not make_shared: its single allocation would outlive the pool for as long as a weak_ptr does.
  // The constants forget the pool when it dies, so nothing of it stays allocated while they live on.
  std::shared_ptr<SpringLanes> pool(new SpringLanes(constants), [](SpringLanes* dying) {
    dying->rig_constants_->lane_pool.reset();
    delete dying;
  });
  constants->lane_pool = pool;
  return pool;
}

SpringLanes::SpringLanes(std::shared_ptr<const RigConstants> constants) : rig_constants_(std::move(constants)) {
  const Rig& rig = rig_constants_->rig;
  const auto& joints = rig.joints;
  // Lanes and depths: a joint continues its parent's lane when it is the parent's tail.
  joint_lane_.assign(joints.size(), -1);
  joint_depth_.assign(joints.size(), 0);
  int lanes = 0;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const int parent = joint.parent_joint;
    joint_lane_[j] = parent >= 0 && joints[parent].tail_node == joint.node ? joint_lane_[parent] : lanes++;
    joint_depth_[j] = parent >= 0 ? joint_depth_[parent] + 1 : 0;
    depth_count_ = std::max<std::size_t>(depth_count_, joint_depth_[j] + 1);
  }
  lanes_per_copy_ = static_cast<std::size_t>(lanes);
  collider_count_ = std::min(rig.colliders.size(), kMaxLaneColliders);
  collider_passes_ = std::max(rig.collider_passes, 1);
  for (std::size_t k = 0; k < collider_count_; ++k) collider_kinds_.push_back(colliderKind(rig.colliders[k]));
  starts_.resize(depth_count_);
  lanes_at_.resize(depth_count_);
  constants_.resize(depth_count_ * lanes_per_copy_);
  std::vector<unsigned char> started(lanes_per_copy_, 0);
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const int lane = joint_lane_[j];
    const int depth = joint_depth_[j];
    lanes_at_[depth].push_back(lane);
    any_center_ = any_center_ || joint.center_driver >= 0;

    SlotConstants& c = constants_[depth * lanes_per_copy_ + lane];
    const Transform& rest = joint.rest_local;
    c.tx = rest.translation.x;
    c.ty = rest.translation.y;
    c.tz = rest.translation.z;
    c.rx = rest.rotation.x;
    c.ry = rest.rotation.y;
    c.rz = rest.rotation.z;
    c.rw = rest.rotation.w;
    c.rs = rest.scale.x;
    const float distance = rig_constants_->tail_distance[j];
    const glm::vec3& axis = rig_constants_->tail_axis[j];
    // The tail axis and its perpendicular turned by the rest rotation: the kernel aims in the
    // parent's frame, where the rest rotation is already applied.
    const glm::vec3 axis_in_parent = glm::normalize(glm::normalize(toGlm(rest.rotation)) * axis);
    const glm::vec3 perpendicular = perpendicularTo(axis_in_parent);
    c.bx = axis_in_parent.x;
    c.by = axis_in_parent.y;
    c.bz = axis_in_parent.z;
    c.nx = perpendicular.x;
    c.ny = perpendicular.y;
    c.nz = perpendicular.z;
    c.tail_distance = distance > kMinLength ? distance : 0.0f;
    c.stiffness = joint.params.stiffness;
    c.gravity_power = joint.params.gravity_power;
    c.keep = 1.0f - joint.params.drag;
    c.gx = joint.params.gravity_dir.x;
    c.gy = joint.params.gravity_dir.y;
    c.gz = joint.params.gravity_dir.z;
    c.hit_radius = joint.hit_radius;
    c.center = static_cast<std::size_t>(joint.center_driver + 1);
    c.collider_mask = 0;
    for (int k : joint.colliders) {
      if (k >= 0 && k < static_cast<int>(kMaxLaneColliders)) c.collider_mask |= 1u << k;
    }

    // A joint continuing its parent's lane is the parent's tail node, but only where the parent's
    // tail is this joint's rest translation does it sit on the parent's simulated tail (a VRM
    // joint held at rest has a zero tail toward its next joint).
    c.continues = started[lane] && toGlm(joints[joint.parent_joint].tail_local) == toGlm(rest.translation) &&
                  glm::length(toGlm(rest.translation)) > kMinLength;
    if (started[lane]) continue;
    started[lane] = true;
    LaneStart start;
    start.lane = lane;
    start.parent_lane = joint.parent_joint >= 0 ? joint_lane_[joint.parent_joint] : -1;
    start.parent_driver = joint.parent_joint >= 0 ? -1 : joint.parent_driver;
    starts_[depth].push_back(start);
  }
}

std::size_t SpringLanes::slotIndex(std::size_t field, std::size_t row, std::size_t lane) const {
  return (row * blocks_per_row_ + lane / kBlockLanes) * kSlotBlock + field * kBlockLanes + lane % kBlockLanes;
}

std::size_t SpringLanes::worldIndex(std::size_t field, std::size_t row, std::size_t lane) const {
  return (row * blocks_per_row_ + lane / kBlockLanes) * kTransformBlock + field * kBlockLanes + lane % kBlockLanes;
}

void SpringLanes::growTo(std::size_t copies) {
  if (copies <= copy_capacity_) return;
  const std::size_t wanted = std::max<std::size_t>(copies, 2 * copy_capacity_);
  const std::size_t capacity = (wanted + kBlockLanes - 1) / kBlockLanes * kBlockLanes;
  const std::size_t old_capacity = copy_capacity_, old_blocks = blocks_per_row_;
  const std::size_t blocks = lanes_per_copy_ * capacity / kBlockLanes;
  // Every wider array is built aside and swapped in only once all of them exist, so an allocation
  // that fails (out of memory) leaves the pool as it was, every array in the old layout.
  std::vector<std::pair<std::vector<float>*, std::vector<float>>> staged;
  staged.reserve(32);
  // Every value keeps its (row, rig lane, copy); lane l * capacity + k moves with the capacity.
  const auto widen = [&](std::vector<float>& v, std::size_t rows, std::size_t fields, float (*fill)(std::size_t)) {
    const std::size_t block_floats = fields * kBlockLanes;
    std::vector<float> wider(rows * blocks * block_floats);
    for (std::size_t row = 0; row < rows; ++row) {
      for (std::size_t block = 0; block < blocks; ++block) {
        float* to = wider.data() + (row * blocks + block) * block_floats;
        for (std::size_t f = 0; f < fields; ++f) std::fill(to + f * kBlockLanes, to + (f + 1) * kBlockLanes, fill(f));
      }
      for (std::size_t lane = 0; lane < lanes_per_copy_; ++lane) {
        for (std::size_t k = 0; k < old_capacity; ++k) {
          const std::size_t from_lane = lane * old_capacity + k, to_lane = lane * capacity + k;
          const float* from =
              v.data() + (row * old_blocks + from_lane / kBlockLanes) * block_floats + from_lane % kBlockLanes;
          float* to = wider.data() + (row * blocks + to_lane / kBlockLanes) * block_floats + to_lane % kBlockLanes;
          for (std::size_t f = 0; f < fields; ++f) to[f * kBlockLanes] = from[f * kBlockLanes];
        }
      }
    }
    staged.emplace_back(&v, std::move(wider));
  };
  widen(slots_, depth_count_, kSlotFields, restSlot);
  widen(world_, depth_count_ + 1, kTransformFields, identityTransform);
  widen(between_, 1, kBetweenFields, [](std::size_t) { return 0.0f; });
  // Tables: one row per driver (or collider) of one entry per copy.
  const auto widen_rows = [&](std::vector<float>& v, std::size_t rows, float fill) {
    std::vector<float> wider(rows * capacity, fill);
    for (std::size_t row = 0; row < rows; ++row) {
      for (std::size_t k = 0; k < old_capacity; ++k) wider[row * capacity + k] = v[row * old_capacity + k];
    }
    staged.emplace_back(&v, std::move(wider));
  };
  const std::size_t driver_rows = rig_constants_->rig.drivers.size() + 1;
  for (auto* v : {&drivers_.px, &drivers_.py, &drivers_.pz, &drivers_.qx, &drivers_.qy, &drivers_.qz}) {
    widen_rows(*v, driver_rows, 0.0f);
  }
  for (auto* v : {&drivers_.qw, &drivers_.s}) widen_rows(*v, driver_rows, 1.0f);
  for (auto* v : {&colliders_.x0, &colliders_.y0, &colliders_.z0, &colliders_.x1, &colliders_.y1, &colliders_.z1,
                  &colliders_.radius}) {
    widen_rows(*v, collider_count_, 0.0f);
  }
  for (auto* v : {&wind_x_, &wind_y_, &wind_z_}) widen_rows(*v, 1, 0.0f);
  copy_rotations_.reserve(capacity);
  free_copies_.reserve(free_copies_.size() + (capacity - old_capacity));
  // Nothing below allocates.
  for (auto& [target, wider] : staged) target->swap(wider);
  colliders_.count = collider_count_ * capacity;
  copy_rotations_.resize(capacity, nullptr);
  for (std::size_t k = capacity; k-- > old_capacity;) free_copies_.push_back(k);  // lowest last, taken first
  copy_capacity_ = capacity;
  lane_capacity_ = lanes_per_copy_ * capacity;
  blocks_per_row_ = blocks;
}

std::size_t SpringLanes::addCopy(float* rotations) {
  if (free_copies_.empty()) growTo(copy_capacity_ + 1);
  // Reserved before the copy is taken: a failed allocation must not leave a copy in use whose
  // instance was never made.
  queued_.reserve(copy_capacity_);
  queued_runs_.reserve(copy_capacity_);
  const std::size_t copy = free_copies_.back();
  free_copies_.pop_back();
  copy_rotations_[copy] = rotations;
  setWind(copy, glm::vec3(0.0f));
  return copy;
}

void SpringLanes::runQueued() {
  std::sort(queued_.begin(), queued_.end());
  for (std::size_t a = 0; a < queued_.size();) {
    queued_runs_.clear();
    std::size_t b = a;
    for (; b < queued_.size() && queued_[b].h == queued_[a].h; ++b) {
      if (!queued_runs_.empty() && queued_runs_.back().end == queued_[b].copy) {
        queued_runs_.back().end = queued_[b].copy + 1;
      } else {
        queued_runs_.push_back({queued_[b].copy, queued_[b].copy + 1});
      }
    }
    run(queued_runs_.data(), queued_runs_.size(), queued_[a].h, /*seed=*/false);
    a = b;
  }
  queued_.clear();
}

void SpringLanes::releaseCopy(std::size_t copy) {
  if (copy >= copy_capacity_ || copy_rotations_[copy] == nullptr) return;
  copy_rotations_[copy] = nullptr;
  free_copies_.push_back(copy);
  // The lowest free copy is taken first, so the copies in use stay packed at the front and scenes
  // step long runs.
  std::sort(free_copies_.begin(), free_copies_.end(), std::greater<std::size_t>());
}

void SpringLanes::jointWorld(std::size_t copy, std::size_t joint, glm::vec3& position, glm::quat& rotation,
                             float& scale) const {
  const std::size_t row = joint_depth_[joint] + 1, lane = joint_lane_[joint] * copy_capacity_ + copy;
  const auto at = [&](std::size_t field) { return world_[worldIndex(field, row, lane)]; };
  position = glm::vec3(at(kPx), at(kPy), at(kPz));
  rotation = glm::quat(at(kQw), at(kQx), at(kQy), at(kQz));
  scale = at(kS);
}

void SpringLanes::tailState(std::size_t copy, std::size_t joint, glm::vec3& current, glm::vec3& previous) const {
  const std::size_t row = joint_depth_[joint], lane = joint_lane_[joint] * copy_capacity_ + copy;
  const auto at = [&](std::size_t field) { return slots_[slotIndex(field, row, lane)]; };
  current = glm::vec3(at(kCx), at(kCy), at(kCz));
  previous = glm::vec3(at(kOx), at(kOy), at(kOz));
}

void SpringLanes::setTailState(std::size_t copy, std::size_t joint, const glm::vec3& current,
                               const glm::vec3& previous) {
  const std::size_t row = joint_depth_[joint], lane = joint_lane_[joint] * copy_capacity_ + copy;
  const auto at = [&](std::size_t field) -> float& { return slots_[slotIndex(field, row, lane)]; };
  at(kCx) = current.x;
  at(kCy) = current.y;
  at(kCz) = current.z;
  at(kOx) = previous.x;
  at(kOy) = previous.y;
  at(kOz) = previous.z;
}

void SpringLanes::writeRotations(std::size_t first_copy, std::size_t end_copy) {
  // Joint by joint, the copies in lane order: within a block the slot advances by one.
  for (std::size_t j = 0; j < joint_lane_.size(); ++j) {
    const float* const row = slots_.data() + joint_depth_[j] * blocks_per_row_ * kSlotBlock + kOutX * kBlockLanes;
    const std::size_t base_lane = joint_lane_[j] * copy_capacity_;
    for (std::size_t k = first_copy; k < end_copy; ++k) {
      float* const rotations = copy_rotations_[k];
      if (!rotations) continue;
      const std::size_t lane = base_lane + k;
      const float* from = row + (lane / kBlockLanes) * kSlotBlock + lane % kBlockLanes;
      float* out = rotations + 4 * j;
      out[0] = from[0];
      out[1] = from[kBlockLanes];
      out[2] = from[2 * kBlockLanes];
      out[3] = from[3 * kBlockLanes];
    }
  }
}

void SpringLanes::run(const CopyRange* ranges, std::size_t range_count, float h, bool seed) {
  for (std::size_t r = 0; r < range_count; ++r) {
    std::size_t first = ranges[r].first, end = std::min(ranges[r].end, copy_capacity_);
    if (first >= end) continue;
    // Free copies next to the run, up to whole blocks, are stepped along rather than left for
    // the lane-by-lane path: nothing reads them, and their values stay finite.
    while (first % kBlockLanes != 0 && copy_rotations_[first - 1] == nullptr) --first;
    while (end % kBlockLanes != 0 && copy_rotations_[end] == nullptr) ++end;
    for (std::size_t d = 0; d < depth_count_; ++d) {
      beginLanes(d, first, end);
      for (int lane : lanes_at_[d]) {
        runSlotFor(seed, any_center_, constants_[d * lanes_per_copy_ + lane].continues, d,
                   static_cast<std::size_t>(lane), first, end, h);
      }
    }
    writeRotations(first, end);
  }
}

// Lanes that begin at this depth hang from a driver or from the joint they branch off (computed
// at the previous depth): that transform goes into their parent row.
void SpringLanes::beginLanes(std::size_t depth, std::size_t first_copy, std::size_t end_copy) {
  const std::size_t row = depth;
  for (const LaneStart& start : starts_[depth]) {
    for (std::size_t k = first_copy; k < end_copy; ++k) {
      float* to = world_.data() + worldIndex(kPx, row, start.lane * copy_capacity_ + k);
      if (start.parent_lane >= 0) {
        const float* from = world_.data() + worldIndex(kPx, row, start.parent_lane * copy_capacity_ + k);
        for (std::size_t f = 0; f < kTransformFields; ++f) to[f * kBlockLanes] = from[f * kBlockLanes];
      } else {
        const std::size_t d = driverIndex(k, start.parent_driver);
        to[kPx * kBlockLanes] = drivers_.px[d];
        to[kPy * kBlockLanes] = drivers_.py[d];
        to[kPz * kBlockLanes] = drivers_.pz[d];
        to[kQx * kBlockLanes] = drivers_.qx[d];
        to[kQy * kBlockLanes] = drivers_.qy[d];
        to[kQz * kBlockLanes] = drivers_.qz[d];
        to[kQw * kBlockLanes] = drivers_.qw[d];
        to[kS * kBlockLanes] = drivers_.s[d];
      }
    }
  }
}

// One per collider of a slot: move the tail out of (or into) the shape, then restore the bone
// length. The shapes are per copy: row `collider` of the collider table, read at the copy. The kind
// is the rig's, so each collider runs the loop of its kind only. Rig::collider_passes times (1 but
// with the body preset): a pass without a push moves no lane, so running them all gives what the
// general path's stop at such a pass gives. Not inlined: one copy of the three vectorised collider
// loops serves every instantiation of runSlot (a copy in each cost the module kilobytes).
SPRINGBONES_NOINLINE void SpringLanes::collideSlot(std::uint32_t mask, float hit_radius, std::size_t base_lane,
                                                   std::size_t begin, std::size_t end) {
  float* const between_row = between_.data();
  for (int pass = 0; pass < collider_passes_; ++pass) {
    for (std::size_t collider = 0; collider < collider_count_; ++collider) {
      if ((mask & (1u << collider)) == 0) continue;
      const std::size_t shape_at = collider * copy_capacity_;
      switch (collider_kinds_[collider]) {
        case ColliderKind::kOutside:
          collideLanes<ColliderKind::kOutside>(colliders_, shape_at, between_row, base_lane, begin, end, hit_radius);
          break;
        case ColliderKind::kInside:
          collideLanes<ColliderKind::kInside>(colliders_, shape_at, between_row, base_lane, begin, end, hit_radius);
          break;
        case ColliderKind::kPlane:
          collideLanes<ColliderKind::kPlane>(colliders_, shape_at, between_row, base_lane, begin, end, hit_radius);
          break;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The kernel: one rig slot (depth, rig lane) for a run of copies.

// Seeding happens once per copy, so it takes the joint's head from the parent's transform always
// (one kernel less in the module) rather than from the parent's tail.
//
// Each case its own kernel, the three choices compile-time constants, so that each loop body has
// only its own arithmetic: what a crowd runs. The runtime module's copy of this file (wasm/,
// SPRINGBONES_ONE_SLOT_KERNEL) has one kernel that chooses as it goes: a preview steps a few
// dozen joints, and five kernels less are bytes on its first load. The choices select between
// values the same operations computed, so both give the same bits.
void SpringLanes::runSlotFor(bool seed, bool center, bool continues, std::size_t depth, std::size_t lane,
                             std::size_t first_copy, std::size_t end_copy, float h) {
#if SPRINGBONES_ONE_SLOT_KERNEL
  runSlot(seed, center, continues && !seed, depth, lane, first_copy, end_copy, h);
#else
  using Yes = std::true_type;
  using No = std::false_type;
  if (seed) {
    center ? runSlot(Yes{}, Yes{}, No{}, depth, lane, first_copy, end_copy, h)
           : runSlot(Yes{}, No{}, No{}, depth, lane, first_copy, end_copy, h);
  } else if (continues) {
    center ? runSlot(No{}, Yes{}, Yes{}, depth, lane, first_copy, end_copy, h)
           : runSlot(No{}, No{}, Yes{}, depth, lane, first_copy, end_copy, h);
  } else {
    center ? runSlot(No{}, Yes{}, No{}, depth, lane, first_copy, end_copy, h)
           : runSlot(No{}, No{}, No{}, depth, lane, first_copy, end_copy, h);
  }
#endif
}

template <typename Seed, typename Center, typename Continues>
void SpringLanes::runSlot(Seed seed, Center center, Continues continues, std::size_t depth, std::size_t lane,
                          std::size_t first_copy, std::size_t end_copy, float h) {
  const SlotConstants c = constants_[depth * lanes_per_copy_ + lane];
  const std::size_t base_lane = lane * copy_capacity_;  // copy k is lane base_lane + k
  const std::size_t begin = base_lane + first_copy, end = base_lane + end_copy;
  const std::size_t row_blocks = depth * blocks_per_row_;
  float* const slot_row = slots_.data() + row_blocks * kSlotBlock;
  const float* const parent_row = world_.data() + row_blocks * kTransformBlock;               // the parents' world
  float* const joint_row = world_.data() + (row_blocks + blocks_per_row_) * kTransformBlock;  // the joints'
  float* const between_row = between_.data();
  // The center's transform per copy: its driver table row, read at the copy (lane - base_lane).
  const std::size_t center_at = c.center * copy_capacity_;
  const float* __restrict cpx = drivers_.px.data() + center_at;
  const float* __restrict cpy = drivers_.py.data() + center_at;
  const float* __restrict cpz = drivers_.pz.data() + center_at;
  const float* __restrict cqx = drivers_.qx.data() + center_at;
  const float* __restrict cqy = drivers_.qy.data() + center_at;
  const float* __restrict cqz = drivers_.qz.data() + center_at;
  const float* __restrict cqw = drivers_.qw.data() + center_at;
  const float* __restrict cs = drivers_.s.data() + center_at;
  const float* __restrict windx = wind_x_.data();
  const float* __restrict windy = wind_y_.data();
  const float* __restrict windz = wind_z_.data();
  constexpr std::size_t B = kBlockLanes;

  // First pass: the rest transform under the parent, then Verlet inertia (center space) with
  // drag, the stiffness, gravity and wind impulses, and the bone length. Seeding stops at the rest tail.
  // Out, between the passes: the head, the bone's world length and scale, the new tail (world).
  forEachLane(begin, end, [&](std::size_t block, std::size_t i) SPRINGBONES_ALWAYS_INLINE {
    const float* __restrict s = slot_row + block * kSlotBlock + i;
    const float* __restrict p = parent_row + block * kTransformBlock + i;
    float* __restrict t = between_row + block * kBetweenBlock + i;
    const std::size_t l = block * B + i - base_lane;  // the copy
    const float pqx = p[kQx * B], pqy = p[kQy * B], pqz = p[kQz * B], pqw = p[kQw * B], ps = p[kS * B];
    float hx, hy, hz;
    if (continues) {
      // The parent turned its rest axis, the direction of this joint's rest translation, onto
      // its new tail at this bone's length: the joint sits on that tail (the lane's previous
      // depth left it here). Equal to the transform below up to rounding, which would be about a
      // quarter of this pass's arithmetic.
      hx = t[kTailX * B];
      hy = t[kTailY * B];
      hz = t[kTailZ * B];
    } else {
      rotate(pqx, pqy, pqz, pqw, c.tx, c.ty, c.tz, hx, hy, hz);
      hx = p[kPx * B] + ps * hx;
      hy = p[kPy * B] + ps * hy;
      hz = p[kPz * B] + ps * hz;
    }
    const float scale = ps * c.rs;
    const float length = scale * c.tail_distance;
    float dx, dy, dz;  // rest direction, world
    rotate(pqx, pqy, pqz, pqw, c.bx, c.by, c.bz, dx, dy, dz);
    float sx = hx + dx * length, sy = hy + dy * length, sz = hz + dz * length;
    if (!seed) {
      const float cx = s[kCx * B], cy = s[kCy * B], cz = s[kCz * B];
      const float vx = cx + (cx - s[kOx * B]) * c.keep;
      const float vy = cy + (cy - s[kOy * B]) * c.keep;
      const float vz = cz + (cz - s[kOz * B]) * c.keep;
      float wx = vx, wy = vy, wz = vz;
      if (center) {
        rotate(cqx[l], cqy[l], cqz[l], cqw[l], vx, vy, vz, wx, wy, wz);
        wx = cpx[l] + cs[l] * wx;
        wy = cpy[l] + cs[l] * wy;
        wz = cpz[l] + cs[l] * wz;
      }
      const float k = c.stiffness * h;
      const float g = c.gravity_power * h;
      // The wind's step after gravity's: adding a zero wind changes no bit.
      wx = wx + dx * k + c.gx * g + windx[l];
      wy = wy + dy * k + c.gy * g + windy[l];
      wz = wz + dz * k + c.gz * g + windz[l];
      // Back onto the sphere of the bone length; a tail lost on the head restarts at rest.
      const float fx = wx - hx, fy = wy - hy, fz = wz - hz;
      const float offset_length = std::sqrt(fx * fx + fy * fy + fz * fz);
      const bool usable = offset_length > kMinLength && offset_length < 1e30f;
      const float to_length = length / offset_length;
      sx = usable ? hx + fx * to_length : sx;
      sy = usable ? hy + fy * to_length : sy;
      sz = usable ? hz + fz * to_length : sz;
    }
    t[kHeadX * B] = hx;
    t[kHeadY * B] = hy;
    t[kHeadZ * B] = hz;
    t[kLength * B] = length;
    t[kScale * B] = scale;
    t[kTailX * B] = sx;
    t[kTailY * B] = sy;
    t[kTailZ * B] = sz;
  });

  // Between the passes: the slot's colliders (collideSlot).
  if (!seed && c.collider_mask != 0) collideSlot(c.collider_mask, c.hit_radius, base_lane, begin, end);

  // Second pass: store the tail (center space), turn the joint toward it, and write the local
  // rotation and the joint's world transform for the next depth. (Two passes with the tail handed
  // over in memory rather than one: a single loop body made V8 spill more than the hand-over
  // costs, about 15% slower in Node 20.)
  forEachLane(begin, end, [&](std::size_t block, std::size_t i) SPRINGBONES_ALWAYS_INLINE {
    float* __restrict s = slot_row + block * kSlotBlock + i;
    const float* __restrict p = parent_row + block * kTransformBlock + i;
    const float* __restrict t = between_row + block * kBetweenBlock + i;
    float* __restrict w = joint_row + block * kTransformBlock + i;
    const std::size_t l = block * B + i - base_lane;  // the copy
    const float hx = t[kHeadX * B], hy = t[kHeadY * B], hz = t[kHeadZ * B];
    const float length = t[kLength * B];
    float sx = t[kTailX * B], sy = t[kTailY * B], sz = t[kTailZ * B];
    const float fx = sx - hx, fy = sy - hy, fz = sz - hz;
    if (center) {
      float ux, uy, uz;
      rotate(-cqx[l], -cqy[l], -cqz[l], cqw[l], sx - cpx[l], sy - cpy[l], sz - cpz[l], ux, uy, uz);
      sx = ux / cs[l];
      sy = uy / cs[l];
      sz = uz / cs[l];
    }
    s[kOx * B] = seed ? sx : s[kCx * B];
    s[kOy * B] = seed ? sy : s[kCy * B];
    s[kOz * B] = seed ? sz : s[kCz * B];
    s[kCx * B] = sx;
    s[kCy * B] = sy;
    s[kCz * B] = sz;

    // The bone in the parent's frame, |f| = length: the shortest turn of the rest axis onto it,
    // (b x f, |b||f| + b.f) normalized, applied after the rest rotation.
    const float pqx = p[kQx * B], pqy = p[kQy * B], pqz = p[kQz * B], pqw = p[kQw * B];
    float fpx, fpy, fpz;
    rotate(-pqx, -pqy, -pqz, pqw, fx, fy, fz, fpx, fpy, fpz);
    const float dot = c.bx * fpx + c.by * fpy + c.bz * fpz;
    const bool opposite = dot < kOppositeDot * length;
    const float tqx = opposite ? c.nx : c.by * fpz - c.bz * fpy;
    const float tqy = opposite ? c.ny : c.bz * fpx - c.bx * fpz;
    const float tqz = opposite ? c.nz : c.bx * fpy - c.by * fpx;
    const float tqw = opposite ? 0.0f : length + dot;
    const float inv_turn = 1.0f / std::sqrt(tqx * tqx + tqy * tqy + tqz * tqz + tqw * tqw);
    // Both factors are unit quaternions (the loader normalizes rest rotations), so is the product.
    float mx, my, mz, mw;
    multiply(tqx * inv_turn, tqy * inv_turn, tqz * inv_turn, tqw * inv_turn, c.rx, c.ry, c.rz, c.rw, mx, my, mz, mw);
    // Seeding, a zero-length bone or a lost direction (NaN fails the comparison) keep the rest.
    const bool moving = !seed && length > kMinLength && inv_turn < 1e30f;
    const float lqx = moving ? mx : c.rx;
    const float lqy = moving ? my : c.ry;
    const float lqz = moving ? mz : c.rz;
    const float lqw = moving ? mw : c.rw;
    s[kOutX * B] = lqx;
    s[kOutY * B] = lqy;
    s[kOutZ * B] = lqz;
    s[kOutW * B] = lqw;
    float jx, jy, jz, jw;
    multiply(pqx, pqy, pqz, pqw, lqx, lqy, lqz, lqw, jx, jy, jz, jw);
    w[kQx * B] = jx;
    w[kQy * B] = jy;
    w[kQz * B] = jz;
    w[kQw * B] = jw;
    w[kPx * B] = hx;
    w[kPy * B] = hy;
    w[kPz * B] = hz;
    w[kS * B] = t[kScale * B];
  });
}

}  // namespace springbones
