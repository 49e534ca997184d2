// The lane kernel: the spring update of solver.cpp written on plain floats in structure-of-arrays
// form, one loop over the lanes of a run of copies per depth. The loop bodies have no branches
// (selects only) and no calls, so clang vectorises them for WebAssembly SIMD; every operation is
// a single IEEE operation with -ffp-contract=off, so vectorised and scalar code produce the same
// bits, whichever lanes of a vector a joint falls in.
#include "spring_lanes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <type_traits>
#include <utility>

#if defined(__GNUC__)
#define SPRINGBONES_ALWAYS_INLINE __attribute__((always_inline))
#else
#define SPRINGBONES_ALWAYS_INLINE
#endif

namespace springbones {
namespace {

constexpr float kMinLength = 1e-6f;
constexpr float kOppositeDot = -0.999999f;  // rest axis and target nearly opposite

// v' = v + w t + q x t with t = 2 (q x v): the rotation of v by the unit quaternion (x, y, z, w).
inline void rotate(float qx, float qy, float qz, float qw, float vx, float vy, float vz, float& ox,
                   float& oy, float& oz) {
  const float tx = 2.0f * (qy * vz - qz * vy);
  const float ty = 2.0f * (qz * vx - qx * vz);
  const float tz = 2.0f * (qx * vy - qy * vx);
  ox = vx + qw * tx + (qy * tz - qz * ty);
  oy = vy + qw * ty + (qz * tx - qx * tz);
  oz = vz + qw * tz + (qx * ty - qy * tx);
}

// (a * b), Hamilton product.
inline void multiply(float ax, float ay, float az, float aw, float bx, float by, float bz, float bw,
                     float& ox, float& oy, float& oz, float& ow) {
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
  kTx, kTy, kTz,               // rest translation
  kRx, kRy, kRz, kRw,          // rest rotation
  kRs,                         // rest uniform scale
  kBx, kBy, kBz,               // unit tail axis at rest, in the parent's frame
  kNx, kNy, kNz,               // a unit axis perpendicular to it (180-degree turns)
  kTailDistance,               // |tail_local|, 0 keeps the joint at rest
  kStiffness, kGravityPower, kKeep,  // keep = 1 - drag
  kGx, kGy, kGz,               // unit gravity direction
  kHitRadius,
  kCx, kCy, kCz, kOx, kOy, kOz,  // current and previous tail, center space
  kOutX, kOutY, kOutZ, kOutW,    // local rotation
  kSlotFields
};
enum TransformField : std::size_t { kPx, kPy, kPz, kQx, kQy, kQz, kQw, kS, kTransformFields };
enum BetweenField : std::size_t { kHeadX, kHeadY, kHeadZ, kLength, kScale, kTailX, kTailY, kTailZ, kBetweenFields };
constexpr std::size_t kSlotBlock = kSlotFields * kBlockLanes;
constexpr std::size_t kTransformBlock = kTransformFields * kBlockLanes;
constexpr std::size_t kBetweenBlock = kBetweenFields * kBlockLanes;

// What a lane holds before a copy fills it: a zero-length bone at rest under identities, which
// computes harmless finite values.
float paddingSlot(std::size_t field) {
  switch (field) {
    case kRw: case kRs: case kBy: case kNz: case kOutW: return 1.0f;
    case kGy: return -1.0f;
    default: return 0.0f;
  }
}
float paddingTransform(std::size_t field) { return field == kQw || field == kS ? 1.0f : 0.0f; }

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

void DriverTable::resize(std::size_t slots) {
  for (auto* v : {&px, &py, &pz, &qx, &qy, &qz}) v->resize(slots, 0.0f);
  qw.resize(slots, 1.0f);
  s.resize(slots, 1.0f);
}

// ---------------------------------------------------------------------------------------------
// The pool

std::shared_ptr<SpringLanes> SpringLanes::acquire(const std::shared_ptr<const Rig>& rig) {
  // One pool per rig alive; entries of freed pools are dropped as we go.
  static std::vector<std::pair<const Rig*, std::weak_ptr<SpringLanes>>> pools;
  std::shared_ptr<SpringLanes> found;
  for (std::size_t i = 0; i < pools.size();) {
    std::shared_ptr<SpringLanes> pool = pools[i].second.lock();
    if (!pool) {
      pools[i] = pools.back();
      pools.pop_back();
      continue;
    }
    if (pools[i].first == rig.get()) found = std::move(pool);
    ++i;
  }
  if (found) return found;
  auto pool = std::make_shared<SpringLanes>(rig);
  pools.emplace_back(rig.get(), pool);
  return pool;
}

SpringLanes::SpringLanes(std::shared_ptr<const Rig> rig) : rig_(std::move(rig)) {
  const auto& joints = rig_->joints;
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
  driver_block_ = rig_->drivers.size() + 1;
  collider_block_ = std::min(rig_->colliders.size(), kMaxLaneColliders);
  starts_.resize(depth_count_);
  template_joint_.assign(depth_count_ * lanes_per_copy_, -1);
  std::vector<bool> started(lanes_per_copy_, false);
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const int lane = joint_lane_[j];
    template_joint_[joint_depth_[j] * lanes_per_copy_ + lane] = static_cast<int>(j);
    any_center_ = any_center_ || joint.center_driver >= 0;
    if (started[lane]) continue;
    started[lane] = true;
    LaneStart start;
    start.lane = lane;
    start.parent_lane = joint.parent_joint >= 0 ? joint_lane_[joint.parent_joint] : -1;
    start.parent_driver = joint.parent_joint >= 0 ? -1 : joint.parent_driver;
    starts_[joint_depth_[j]].push_back(start);
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
  const std::size_t capacity = std::max<std::size_t>(copies, 2 * copy_capacity_);
  const std::size_t old_lanes = lane_capacity_, old_blocks = blocks_per_row_;
  const std::size_t blocks = (capacity * lanes_per_copy_ + kBlockLanes - 1) / kBlockLanes;
  const std::size_t lanes = blocks * kBlockLanes;
  const std::size_t rows = depth_count_;
  // Every value keeps its (row, lane) in the wider rows; new lanes are padding.
  const auto widen = [&](std::vector<float>& v, std::size_t row_count, std::size_t fields, float (*fill)(std::size_t)) {
    std::vector<float> wider(row_count * blocks * fields * kBlockLanes);
    for (std::size_t row = 0; row < row_count; ++row) {
      for (std::size_t block = 0; block < blocks; ++block) {
        float* to = wider.data() + (row * blocks + block) * fields * kBlockLanes;
        if (block < old_blocks) {
          const float* from = v.data() + (row * old_blocks + block) * fields * kBlockLanes;
          std::copy(from, from + fields * kBlockLanes, to);
        } else {
          for (std::size_t f = 0; f < fields; ++f) std::fill(to + f * kBlockLanes, to + (f + 1) * kBlockLanes, fill(f));
        }
      }
    }
    v.swap(wider);
  };
  widen(slots_, rows, kSlotFields, paddingSlot);
  widen(world_, rows + 1, kTransformFields, paddingTransform);
  widen(centers_, 1, kTransformFields, paddingTransform);
  widen(between_, 1, kBetweenFields, [](std::size_t) { return 0.0f; });
  const auto widen_plain = [&](auto& v, auto fill) {
    std::remove_reference_t<decltype(v)> wider(rows * lanes, fill);
    for (std::size_t row = 0; row < rows; ++row) {
      std::copy(v.begin() + row * old_lanes, v.begin() + (row + 1) * old_lanes, wider.begin() + row * lanes);
    }
    v.swap(wider);
  };
  widen_plain(center_, 0);
  widen_plain(collider_mask_, 0u);
  drivers_.resize(capacity * driver_block_);
  colliders_.count = capacity * collider_block_;
  for (auto* v : {&colliders_.x0, &colliders_.y0, &colliders_.z0, &colliders_.x1, &colliders_.y1, &colliders_.z1,
                  &colliders_.radius}) {
    v->resize(colliders_.count, 0.0f);
  }
  copy_rotations_.resize(capacity, nullptr);
  for (std::size_t k = capacity; k-- > copy_capacity_;) free_copies_.push_back(k);  // lowest last, taken first
  copy_capacity_ = capacity;
  lane_capacity_ = lanes;
  blocks_per_row_ = blocks;
}

std::size_t SpringLanes::addCopy(float* rotations) {
  if (free_copies_.empty()) growTo(copy_capacity_ + 1);
  const std::size_t copy = free_copies_.back();
  free_copies_.pop_back();
  copy_rotations_[copy] = rotations;
  const std::size_t first_lane = copy * lanes_per_copy_;
  const auto& joints = rig_->joints;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const std::size_t row = joint_depth_[j], lane = first_lane + joint_lane_[j];
    const auto set = [&](std::size_t field, float value) { slots_[slotIndex(field, row, lane)] = value; };
    center_[row * lane_capacity_ + lane] = static_cast<int>(copy * driver_block_) + joint.center_driver + 1;
    const Transform& rest = joint.rest_local;
    set(kTx, rest.translation.x);
    set(kTy, rest.translation.y);
    set(kTz, rest.translation.z);
    set(kRx, rest.rotation.x);
    set(kRy, rest.rotation.y);
    set(kRz, rest.rotation.z);
    set(kRw, rest.rotation.w);
    set(kRs, rest.scale.x);
    const float distance = glm::length(joint.tail_local);
    const glm::vec3 axis = distance > kMinLength ? joint.tail_local / distance : glm::vec3(0, 1, 0);
    // The tail axis and its perpendicular turned by the rest rotation: the kernel aims in the
    // parent's frame, where the rest rotation is already applied.
    const glm::vec3 axis_in_parent = glm::normalize(glm::normalize(rest.rotation) * axis);
    const glm::vec3 perpendicular = perpendicularTo(axis_in_parent);
    set(kBx, axis_in_parent.x);
    set(kBy, axis_in_parent.y);
    set(kBz, axis_in_parent.z);
    set(kNx, perpendicular.x);
    set(kNy, perpendicular.y);
    set(kNz, perpendicular.z);
    set(kTailDistance, distance > kMinLength ? distance : 0.0f);
    set(kStiffness, joint.params.stiffness);
    set(kGravityPower, joint.params.gravity_power);
    set(kKeep, 1.0f - joint.params.drag);
    set(kGx, joint.params.gravity_dir.x);
    set(kGy, joint.params.gravity_dir.y);
    set(kGz, joint.params.gravity_dir.z);
    set(kHitRadius, joint.hit_radius);
    std::uint32_t mask = 0;
    for (int c : joint.colliders) {
      if (c >= 0 && c < static_cast<int>(kMaxLaneColliders)) mask |= 1u << c;
    }
    collider_mask_[row * lane_capacity_ + lane] = mask;
  }
  return copy;
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
  const std::size_t row = joint_depth_[joint] + 1, lane = copy * lanes_per_copy_ + joint_lane_[joint];
  const auto at = [&](std::size_t field) { return world_[worldIndex(field, row, lane)]; };
  position = glm::vec3(at(kPx), at(kPy), at(kPz));
  rotation = glm::quat(at(kQw), at(kQx), at(kQy), at(kQz));
  scale = at(kS);
}

void SpringLanes::writeRotations(std::size_t first_copy, std::size_t end_copy) {
  // Slot order, one depth at a time, walking the blocks as the lanes go: no index arithmetic per
  // joint beyond a step to the next lane.
  for (std::size_t depth = 0; depth < depth_count_; ++depth) {
    const float* const row = slots_.data() + depth * blocks_per_row_ * kSlotBlock + kOutX * kBlockLanes;
    const int* const joint_at = template_joint_.data() + depth * lanes_per_copy_;
    std::size_t block = first_copy * lanes_per_copy_ / kBlockLanes;
    std::size_t i = first_copy * lanes_per_copy_ % kBlockLanes;
    for (std::size_t k = first_copy; k < end_copy; ++k) {
      float* const rotations = copy_rotations_[k];
      for (std::size_t lane = 0; lane < lanes_per_copy_; ++lane) {
        const int j = joint_at[lane];
        if (j >= 0 && rotations) {
          const float* from = row + block * kSlotBlock + i;
          float* out = rotations + 4 * j;
          out[0] = from[0];
          out[1] = from[kBlockLanes];
          out[2] = from[2 * kBlockLanes];
          out[3] = from[3 * kBlockLanes];
        }
        if (++i == kBlockLanes) {
          i = 0;
          ++block;
        }
      }
    }
  }
}

void SpringLanes::run(const CopyRange* ranges, std::size_t range_count, float h, bool seed) {
  const bool colliders = collider_block_ > 0 && !seed;
  for (std::size_t r = 0; r < range_count; ++r) {
    const std::size_t first = ranges[r].first, end = std::min(ranges[r].end, copy_capacity_);
    if (first >= end) continue;
    for (std::size_t d = 0; d < depth_count_; ++d) {
      beginLanes(d, first, end);
      if (seed) {
        any_center_ ? runDepth<true, true, false>(d, first, end, h) : runDepth<true, false, false>(d, first, end, h);
      } else if (colliders) {
        any_center_ ? runDepth<false, true, true>(d, first, end, h) : runDepth<false, false, true>(d, first, end, h);
      } else {
        any_center_ ? runDepth<false, true, false>(d, first, end, h) : runDepth<false, false, false>(d, first, end, h);
      }
    }
    writeRotations(first, end);
  }
}

// One driver table slot into a lane of a block of transforms (`to`: its first field).
void SpringLanes::copyDriver(std::size_t slot, float* to) const {
  to[kPx * kBlockLanes] = drivers_.px[slot];
  to[kPy * kBlockLanes] = drivers_.py[slot];
  to[kPz * kBlockLanes] = drivers_.pz[slot];
  to[kQx * kBlockLanes] = drivers_.qx[slot];
  to[kQy * kBlockLanes] = drivers_.qy[slot];
  to[kQz * kBlockLanes] = drivers_.qz[slot];
  to[kQw * kBlockLanes] = drivers_.qw[slot];
  to[kS * kBlockLanes] = drivers_.s[slot];
}

// Lanes that begin at this depth hang from a driver or from the joint they branch off (computed
// at the previous depth): that transform goes into their parent row.
void SpringLanes::beginLanes(std::size_t depth, std::size_t first_copy, std::size_t end_copy) {
  const std::size_t row = depth;
  for (std::size_t k = first_copy; k < end_copy; ++k) {
    const std::size_t first_lane = k * lanes_per_copy_;
    for (const LaneStart& start : starts_[depth]) {
      float* to = world_.data() + worldIndex(kPx, row, first_lane + start.lane);
      if (start.parent_lane >= 0) {
        const float* from = world_.data() + worldIndex(kPx, row, first_lane + start.parent_lane);
        for (std::size_t f = 0; f < kTransformFields; ++f) to[f * kBlockLanes] = from[f * kBlockLanes];
      } else {
        copyDriver(k * driver_block_ + 1 + start.parent_driver, to);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The kernel

template <bool kSeed, bool kCenter, bool kColliders>
void SpringLanes::runDepth(std::size_t depth, std::size_t first_copy, std::size_t end_copy, float h) {
  const std::size_t begin = first_copy * lanes_per_copy_, end = end_copy * lanes_per_copy_;
  const std::size_t row_blocks = depth * blocks_per_row_;

  if (kCenter) {
    for (std::size_t l = begin; l < end; ++l) {
      copyDriver(static_cast<std::size_t>(center_[depth * lane_capacity_ + l]),
                 centers_.data() + (l / kBlockLanes) * kTransformBlock + l % kBlockLanes);
    }
  }

  float* const slot_row = slots_.data() + row_blocks * kSlotBlock;
  const float* const parent_row = world_.data() + row_blocks * kTransformBlock;  // the parents' world
  float* const joint_row = world_.data() + (row_blocks + blocks_per_row_) * kTransformBlock;  // the joints'
  const float* const center_row = centers_.data();
  float* const between_row = between_.data();

  // First half: the rest transform under the parent, then Verlet inertia (center space) with
  // drag, the stiffness and gravity impulses, and the bone length. Seeding stops at the rest tail.
  // Out: the head, the bone's world length and scale, the new tail (world).
  const auto integrate = [&](std::size_t block, std::size_t i, float& hx, float& hy, float& hz, float& length,
                             float& scale, float& sx, float& sy, float& sz) SPRINGBONES_ALWAYS_INLINE {
    const float* __restrict s = slot_row + block * kSlotBlock + i;
    const float* __restrict p = parent_row + block * kTransformBlock + i;
    const float* __restrict c = center_row + block * kTransformBlock + i;
    constexpr std::size_t B = kBlockLanes;
    const float pqx = p[kQx * B], pqy = p[kQy * B], pqz = p[kQz * B], pqw = p[kQw * B], ps = p[kS * B];
    rotate(pqx, pqy, pqz, pqw, s[kTx * B], s[kTy * B], s[kTz * B], hx, hy, hz);
    hx = p[kPx * B] + ps * hx;
    hy = p[kPy * B] + ps * hy;
    hz = p[kPz * B] + ps * hz;
    scale = ps * s[kRs * B];
    length = scale * s[kTailDistance * B];
    float dx, dy, dz;  // rest direction, world
    rotate(pqx, pqy, pqz, pqw, s[kBx * B], s[kBy * B], s[kBz * B], dx, dy, dz);
    sx = hx + dx * length;
    sy = hy + dy * length;
    sz = hz + dz * length;
    if (!kSeed) {
      const float cx = s[kCx * B], cy = s[kCy * B], cz = s[kCz * B], keep = s[kKeep * B];
      const float vx = cx + (cx - s[kOx * B]) * keep;
      const float vy = cy + (cy - s[kOy * B]) * keep;
      const float vz = cz + (cz - s[kOz * B]) * keep;
      float wx = vx, wy = vy, wz = vz;
      if (kCenter) {
        rotate(c[kQx * B], c[kQy * B], c[kQz * B], c[kQw * B], vx, vy, vz, wx, wy, wz);
        wx = c[kPx * B] + c[kS * B] * wx;
        wy = c[kPy * B] + c[kS * B] * wy;
        wz = c[kPz * B] + c[kS * B] * wz;
      }
      const float k = s[kStiffness * B] * h;
      const float g = s[kGravityPower * B] * h;
      wx = wx + dx * k + s[kGx * B] * g;
      wy = wy + dy * k + s[kGy * B] * g;
      wz = wz + dz * k + s[kGz * B] * g;
      // Back onto the sphere of the bone length; a tail lost on the head restarts at rest.
      const float fx = wx - hx, fy = wy - hy, fz = wz - hz;
      const float offset_length = std::sqrt(fx * fx + fy * fy + fz * fz);
      const bool usable = offset_length > kMinLength && offset_length < 1e30f;
      const float to_length = length / offset_length;
      sx = usable ? hx + fx * to_length : sx;
      sy = usable ? hy + fy * to_length : sy;
      sz = usable ? hz + fz * to_length : sz;
    }
  };

  // Second half: store the tail (center space), turn the joint toward it, and write the local
  // rotation and the joint's world transform for the next depth.
  const auto aim = [&](std::size_t block, std::size_t i, float hx, float hy, float hz, float length, float scale,
                       float sx, float sy, float sz) SPRINGBONES_ALWAYS_INLINE {
    float* __restrict s = slot_row + block * kSlotBlock + i;
    const float* __restrict p = parent_row + block * kTransformBlock + i;
    const float* __restrict c = center_row + block * kTransformBlock + i;
    float* __restrict w = joint_row + block * kTransformBlock + i;
    constexpr std::size_t B = kBlockLanes;
    const float fx = sx - hx, fy = sy - hy, fz = sz - hz;
    if (kCenter) {
      float ux, uy, uz;
      rotate(-c[kQx * B], -c[kQy * B], -c[kQz * B], c[kQw * B], sx - c[kPx * B], sy - c[kPy * B], sz - c[kPz * B], ux,
             uy, uz);
      sx = ux / c[kS * B];
      sy = uy / c[kS * B];
      sz = uz / c[kS * B];
    }
    s[kOx * B] = kSeed ? sx : s[kCx * B];
    s[kOy * B] = kSeed ? sy : s[kCy * B];
    s[kOz * B] = kSeed ? sz : s[kCz * B];
    s[kCx * B] = sx;
    s[kCy * B] = sy;
    s[kCz * B] = sz;

    // The bone in the parent's frame, |f| = length: the shortest turn of the rest axis onto it,
    // (b x f, |b||f| + b.f) normalized, applied after the rest rotation.
    const float pqx = p[kQx * B], pqy = p[kQy * B], pqz = p[kQz * B], pqw = p[kQw * B];
    float fpx, fpy, fpz;
    rotate(-pqx, -pqy, -pqz, pqw, fx, fy, fz, fpx, fpy, fpz);
    const float bx = s[kBx * B], by = s[kBy * B], bz = s[kBz * B];
    const float dot = bx * fpx + by * fpy + bz * fpz;
    const bool opposite = dot < kOppositeDot * length;
    const float tqx = opposite ? s[kNx * B] : by * fpz - bz * fpy;
    const float tqy = opposite ? s[kNy * B] : bz * fpx - bx * fpz;
    const float tqz = opposite ? s[kNz * B] : bx * fpy - by * fpx;
    const float tqw = opposite ? 0.0f : length + dot;
    const float inv_turn = 1.0f / std::sqrt(tqx * tqx + tqy * tqy + tqz * tqz + tqw * tqw);
    // Both factors are unit quaternions (the loader normalizes rest rotations), so is the product.
    const float rx = s[kRx * B], ry = s[kRy * B], rz = s[kRz * B], rw = s[kRw * B];
    float mx, my, mz, mw;
    multiply(tqx * inv_turn, tqy * inv_turn, tqz * inv_turn, tqw * inv_turn, rx, ry, rz, rw, mx, my, mz, mw);
    // Seeding, a zero-length bone or a lost direction (NaN fails the comparison) keep the rest.
    const bool moving = !kSeed && length > kMinLength && inv_turn < 1e30f;
    const float lqx = moving ? mx : rx;
    const float lqy = moving ? my : ry;
    const float lqz = moving ? mz : rz;
    const float lqw = moving ? mw : rw;
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
    w[kS * B] = scale;
  };


  // Two loops with the tail handed over in memory, rather than one: the register pressure of a
  // single loop body made V8 spill more than the hand-over costs (about 15% slower in Node 20).
  constexpr std::size_t B = kBlockLanes;
  forEachLane(begin, end, [&](std::size_t block, std::size_t i) SPRINGBONES_ALWAYS_INLINE {
    float* __restrict t = between_row + block * kBetweenBlock + i;
    integrate(block, i, t[kHeadX * B], t[kHeadY * B], t[kHeadZ * B], t[kLength * B], t[kScale * B], t[kTailX * B],
              t[kTailY * B], t[kTailZ * B]);
  });

  // Between them, one pass per copy and collider: push the tail out of the shape (closest point
  // on the capsule segment, or the sphere center), then restore the bone length.
  const std::uint32_t* const mask_row = collider_mask_.data() + depth * lane_capacity_;
  for (std::size_t k = first_copy; kColliders && k < end_copy; ++k) {
    for (std::size_t c = 0; c < collider_block_; ++c) {
      const std::size_t shape = k * collider_block_ + c;
      const float ax0 = colliders_.x0[shape], ay0 = colliders_.y0[shape], az0 = colliders_.z0[shape];
      const float sgx = colliders_.x1[shape] - ax0, sgy = colliders_.y1[shape] - ay0, sgz = colliders_.z1[shape] - az0;
      const float segment2 = sgx * sgx + sgy * sgy + sgz * sgz;
      const float inv_segment2 = segment2 > 0.0f ? 1.0f / segment2 : 0.0f;
      const float radius = colliders_.radius[shape];
      const std::uint32_t bit = 1u << c;
      forEachLane(k * lanes_per_copy_, (k + 1) * lanes_per_copy_, [&](std::size_t block, std::size_t i)
                                                                       SPRINGBONES_ALWAYS_INLINE {
        float* __restrict t = between_row + block * kBetweenBlock + i;
        const float* __restrict s = slot_row + block * kSlotBlock + i;
        const float tx = t[kTailX * B], ty = t[kTailY * B], tz = t[kTailZ * B];
        const float vx = tx - ax0, vy = ty - ay0, vz = tz - az0;
        float along = (vx * sgx + vy * sgy + vz * sgz) * inv_segment2;
        along = along < 0.0f ? 0.0f : (along > 1.0f ? 1.0f : along);
        const float dx = vx - sgx * along, dy = vy - sgy * along, dz = vz - sgz * along;
        const float distance = std::sqrt(dx * dx + dy * dy + dz * dz);
        const float penetration = radius + s[kHitRadius * B] - distance;
        const bool pushed = (mask_row[block * B + i] & bit) != 0 && penetration > 0.0f && distance > kMinLength;
        const float push = pushed ? penetration / distance : 0.0f;
        const float px = tx + dx * push, py = ty + dy * push, pz = tz + dz * push;
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
  }

  forEachLane(begin, end, [&](std::size_t block, std::size_t i) SPRINGBONES_ALWAYS_INLINE {
    const float* __restrict t = between_row + block * kBetweenBlock + i;
    aim(block, i, t[kHeadX * B], t[kHeadY * B], t[kHeadZ * B], t[kLength * B], t[kScale * B], t[kTailX * B],
        t[kTailY * B], t[kTailZ * B]);
  });
}

}  // namespace springbones
