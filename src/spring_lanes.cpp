// The lane kernel: the spring update of solver.cpp written on plain floats in structure-of-arrays
// form, one loop over the lanes of a run of copies per depth. The loop bodies have no branches
// (selects only) and no calls, so clang vectorises them for WebAssembly SIMD; every operation is
// a single IEEE operation with -ffp-contract=off, so vectorised and scalar code produce the same
// bits, whichever lanes of a vector a joint falls in.
#include "spring_lanes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
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

glm::vec3 perpendicularTo(const glm::vec3& axis) {
  glm::vec3 p = glm::cross(glm::vec3(1, 0, 0), axis);
  if (glm::dot(p, p) < 1e-12f) p = glm::cross(glm::vec3(0, 1, 0), axis);
  return glm::normalize(p);
}

// Lays `rows` rows of `old_width` values out again as rows of `new_width` (new_width >=
// old_width), filling the new columns with `fill`.
template <typename T>
void widenRows(std::vector<T>& v, std::size_t rows, std::size_t old_width, std::size_t new_width, T fill) {
  std::vector<T> wider(rows * new_width, fill);
  for (std::size_t r = 0; r < rows; ++r) {
    std::copy(v.begin() + r * old_width, v.begin() + (r + 1) * old_width, wider.begin() + r * new_width);
  }
  v.swap(wider);
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

void DriverTable::set(std::size_t slot, const glm::vec3& p, const glm::quat& q, float scale) {
  px[slot] = p.x;
  py[slot] = p.y;
  pz[slot] = p.z;
  qx[slot] = q.x;
  qy[slot] = q.y;
  qz[slot] = q.z;
  qw[slot] = q.w;
  s[slot] = scale;
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

void SpringLanes::growTo(std::size_t copies) {
  if (copies <= copy_capacity_) return;
  const std::size_t capacity = std::max<std::size_t>(copies, 2 * copy_capacity_);
  const std::size_t old_width = lane_capacity_, width = capacity * lanes_per_copy_;
  const std::size_t rows = depth_count_;
  // New lanes are padding until a copy fills them: a zero-length bone at rest under identities,
  // which computes harmless finite values.
  for (auto* v : {&tx_, &ty_, &tz_, &rx_, &ry_, &rz_, &bx_, &bz_, &nx_, &ny_, &tail_distance_, &stiffness_,
                  &gravity_power_, &keep_, &gx_, &gz_, &hit_radius_, &cx_, &cy_, &cz_, &ox_, &oy_, &oz_, &out_x_,
                  &out_y_, &out_z_}) {
    widenRows(*v, rows, old_width, width, 0.0f);
  }
  for (auto* v : {&rw_, &rs_, &by_, &nz_, &out_w_}) widenRows(*v, rows, old_width, width, 1.0f);
  widenRows(gy_, rows, old_width, width, -1.0f);
  widenRows(center_, rows, old_width, width, 0);
  widenRows(collider_mask_, rows, old_width, width, 0u);
  for (auto* v : {&wpx_, &wpy_, &wpz_, &wqx_, &wqy_, &wqz_}) widenRows(*v, rows + 1, old_width, width, 0.0f);
  for (auto* v : {&wqw_, &ws_}) widenRows(*v, rows + 1, old_width, width, 1.0f);
  for (auto* v : {&cpx_, &cpy_, &cpz_, &cqx_, &cqy_, &cqz_, &hx_, &hy_, &hz_, &len_, &sx_, &sy_, &sz_}) {
    v->resize(width, 0.0f);
  }
  for (auto* v : {&cqw_, &cs_, &scale_}) v->resize(width, 1.0f);
  drivers_.resize(capacity * driver_block_);
  colliders_.count = capacity * collider_block_;
  for (auto* v : {&colliders_.x0, &colliders_.y0, &colliders_.z0, &colliders_.x1, &colliders_.y1, &colliders_.z1,
                  &colliders_.radius}) {
    v->resize(colliders_.count, 0.0f);
  }
  copy_rotations_.resize(capacity, nullptr);
  for (std::size_t k = capacity; k-- > copy_capacity_;) free_copies_.push_back(k);  // lowest first
  copy_capacity_ = capacity;
  lane_capacity_ = width;
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
    const std::size_t slot = joint_depth_[j] * lane_capacity_ + first_lane + joint_lane_[j];
    center_[slot] = static_cast<int>(copy * driver_block_) + joint.center_driver + 1;
    const Transform& rest = joint.rest_local;
    tx_[slot] = rest.translation.x;
    ty_[slot] = rest.translation.y;
    tz_[slot] = rest.translation.z;
    rx_[slot] = rest.rotation.x;
    ry_[slot] = rest.rotation.y;
    rz_[slot] = rest.rotation.z;
    rw_[slot] = rest.rotation.w;
    rs_[slot] = rest.scale.x;
    const float distance = glm::length(joint.tail_local);
    const glm::vec3 axis = distance > kMinLength ? joint.tail_local / distance : glm::vec3(0, 1, 0);
    // The tail axis and its perpendicular turned by the rest rotation: the kernel aims in the
    // parent's frame, where the rest rotation is already applied.
    const glm::quat rest_rotation = glm::normalize(rest.rotation);
    const glm::vec3 axis_in_parent = glm::normalize(rest_rotation * axis);
    const glm::vec3 perpendicular = perpendicularTo(axis_in_parent);
    bx_[slot] = axis_in_parent.x;
    by_[slot] = axis_in_parent.y;
    bz_[slot] = axis_in_parent.z;
    nx_[slot] = perpendicular.x;
    ny_[slot] = perpendicular.y;
    nz_[slot] = perpendicular.z;
    tail_distance_[slot] = distance > kMinLength ? distance : 0.0f;
    stiffness_[slot] = joint.params.stiffness;
    gravity_power_[slot] = joint.params.gravity_power;
    keep_[slot] = 1.0f - joint.params.drag;
    gx_[slot] = joint.params.gravity_dir.x;
    gy_[slot] = joint.params.gravity_dir.y;
    gz_[slot] = joint.params.gravity_dir.z;
    hit_radius_[slot] = joint.hit_radius;
    std::uint32_t mask = 0;
    for (int c : joint.colliders) {
      if (c >= 0 && c < static_cast<int>(kMaxLaneColliders)) mask |= 1u << c;
    }
    collider_mask_[slot] = mask;
  }
  return copy;
}

void SpringLanes::releaseCopy(std::size_t copy) {
  if (copy >= copy_capacity_ || copy_rotations_[copy] == nullptr) return;
  copy_rotations_[copy] = nullptr;
  free_copies_.push_back(copy);
  // Lowest first, so the copies in use stay packed at the front and scenes step long runs.
  std::sort(free_copies_.begin(), free_copies_.end(), std::greater<std::size_t>());
}

void SpringLanes::jointWorld(std::size_t copy, std::size_t joint, glm::vec3& position, glm::quat& rotation,
                             float& scale) const {
  const std::size_t slot =
      (joint_depth_[joint] + 1) * lane_capacity_ + copy * lanes_per_copy_ + joint_lane_[joint];
  position = glm::vec3(wpx_[slot], wpy_[slot], wpz_[slot]);
  rotation = glm::quat(wqw_[slot], wqx_[slot], wqy_[slot], wqz_[slot]);
  scale = ws_[slot];
}

void SpringLanes::writeRotations(std::size_t copy) {
  float* rotations = copy_rotations_[copy];
  const std::size_t first_lane = copy * lanes_per_copy_;
  for (std::size_t j = 0; j < joint_lane_.size(); ++j) {
    const std::size_t slot = joint_depth_[j] * lane_capacity_ + first_lane + joint_lane_[j];
    float* out = rotations + 4 * j;
    out[0] = out_x_[slot];
    out[1] = out_y_[slot];
    out[2] = out_z_[slot];
    out[3] = out_w_[slot];
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
    for (std::size_t k = first; k < end; ++k) {
      if (copy_rotations_[k]) writeRotations(k);
    }
  }
}

// Lanes that begin at this depth hang from a driver or from the joint they branch off (computed
// at the previous depth): that transform goes into their parent row.
void SpringLanes::beginLanes(std::size_t depth, std::size_t first_copy, std::size_t end_copy) {
  const std::size_t row = depth * lane_capacity_;
  for (std::size_t k = first_copy; k < end_copy; ++k) {
    const std::size_t first_lane = k * lanes_per_copy_;
    for (const LaneStart& start : starts_[depth]) {
      const std::size_t to = row + first_lane + start.lane;
      if (start.parent_lane >= 0) {
        const std::size_t from = row + first_lane + start.parent_lane;
        wpx_[to] = wpx_[from];
        wpy_[to] = wpy_[from];
        wpz_[to] = wpz_[from];
        wqx_[to] = wqx_[from];
        wqy_[to] = wqy_[from];
        wqz_[to] = wqz_[from];
        wqw_[to] = wqw_[from];
        ws_[to] = ws_[from];
      } else {
        const std::size_t d = k * driver_block_ + 1 + start.parent_driver;
        wpx_[to] = drivers_.px[d];
        wpy_[to] = drivers_.py[d];
        wpz_[to] = drivers_.pz[d];
        wqx_[to] = drivers_.qx[d];
        wqy_[to] = drivers_.qy[d];
        wqz_[to] = drivers_.qz[d];
        wqw_[to] = drivers_.qw[d];
        ws_[to] = drivers_.s[d];
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The kernel

template <bool kSeed, bool kCenter, bool kColliders>
void SpringLanes::runDepth(std::size_t depth, std::size_t first_copy, std::size_t end_copy, float h) {
  const std::size_t begin = first_copy * lanes_per_copy_, end = end_copy * lanes_per_copy_;
  const std::size_t base = depth * lane_capacity_;  // this depth's slots; also its parent row
  const std::size_t next = base + lane_capacity_;   // the world row of this depth's joints

  if (kCenter) {
    for (std::size_t l = begin; l < end; ++l) {
      const int c = center_[base + l];
      cpx_[l] = drivers_.px[c];
      cpy_[l] = drivers_.py[c];
      cpz_[l] = drivers_.pz[c];
      cqx_[l] = drivers_.qx[c];
      cqy_[l] = drivers_.qy[c];
      cqz_[l] = drivers_.qz[c];
      cqw_[l] = drivers_.qw[c];
      cs_[l] = drivers_.s[c];
    }
  }

  // The parents' world transforms (in) and the joints' (out): two rows of the same arrays.
  const float* __restrict ppx = wpx_.data() + base;
  const float* __restrict ppy = wpy_.data() + base;
  const float* __restrict ppz = wpz_.data() + base;
  const float* __restrict pqx = wqx_.data() + base;
  const float* __restrict pqy = wqy_.data() + base;
  const float* __restrict pqz = wqz_.data() + base;
  const float* __restrict pqw = wqw_.data() + base;
  const float* __restrict ps = ws_.data() + base;
  float* __restrict wpx = wpx_.data() + next;
  float* __restrict wpy = wpy_.data() + next;
  float* __restrict wpz = wpz_.data() + next;
  float* __restrict wqx = wqx_.data() + next;
  float* __restrict wqy = wqy_.data() + next;
  float* __restrict wqz = wqz_.data() + next;
  float* __restrict wqw = wqw_.data() + next;
  float* __restrict ws = ws_.data() + next;
  const float* __restrict cpx = cpx_.data();
  const float* __restrict cpy = cpy_.data();
  const float* __restrict cpz = cpz_.data();
  const float* __restrict cqx = cqx_.data();
  const float* __restrict cqy = cqy_.data();
  const float* __restrict cqz = cqz_.data();
  const float* __restrict cqw = cqw_.data();
  const float* __restrict cs = cs_.data();
  // Per slot constants and state of this depth.
  const float* __restrict tx = tx_.data() + base;
  const float* __restrict ty = ty_.data() + base;
  const float* __restrict tz = tz_.data() + base;
  const float* __restrict rx = rx_.data() + base;
  const float* __restrict ry = ry_.data() + base;
  const float* __restrict rz = rz_.data() + base;
  const float* __restrict rw = rw_.data() + base;
  const float* __restrict rs = rs_.data() + base;
  const float* __restrict bx = bx_.data() + base;
  const float* __restrict by = by_.data() + base;
  const float* __restrict bz = bz_.data() + base;
  const float* __restrict nx = nx_.data() + base;
  const float* __restrict ny = ny_.data() + base;
  const float* __restrict nz = nz_.data() + base;
  const float* __restrict td = tail_distance_.data() + base;
  const float* __restrict stiffness = stiffness_.data() + base;
  const float* __restrict gravity_power = gravity_power_.data() + base;
  const float* __restrict keep = keep_.data() + base;
  const float* __restrict gx = gx_.data() + base;
  const float* __restrict gy = gy_.data() + base;
  const float* __restrict gz = gz_.data() + base;
  float* __restrict cx = cx_.data() + base;
  float* __restrict cy = cy_.data() + base;
  float* __restrict cz = cz_.data() + base;
  float* __restrict ox = ox_.data() + base;
  float* __restrict oy = oy_.data() + base;
  float* __restrict oz = oz_.data() + base;
  float* __restrict out_x = out_x_.data() + base;
  float* __restrict out_y = out_y_.data() + base;
  float* __restrict out_z = out_z_.data() + base;
  float* __restrict out_w = out_w_.data() + base;

  // First half: the rest transform under the parent, then Verlet inertia (center space) with
  // drag, the stiffness and gravity impulses, and the bone length. Seeding stops at the rest tail.
  // Out: the head, the bone's world length and scale, the new tail (world).
  const auto integrate = [&](std::size_t l, float& hx, float& hy, float& hz, float& length, float& scale,
                             float& sx, float& sy, float& sz) SPRINGBONES_ALWAYS_INLINE {
    rotate(pqx[l], pqy[l], pqz[l], pqw[l], tx[l], ty[l], tz[l], hx, hy, hz);
    hx = ppx[l] + ps[l] * hx;
    hy = ppy[l] + ps[l] * hy;
    hz = ppz[l] + ps[l] * hz;
    scale = ps[l] * rs[l];
    length = scale * td[l];
    float dx, dy, dz;  // rest direction, world
    rotate(pqx[l], pqy[l], pqz[l], pqw[l], bx[l], by[l], bz[l], dx, dy, dz);
    sx = hx + dx * length;
    sy = hy + dy * length;
    sz = hz + dz * length;
    if (!kSeed) {
      const float vx = cx[l] + (cx[l] - ox[l]) * keep[l];
      const float vy = cy[l] + (cy[l] - oy[l]) * keep[l];
      const float vz = cz[l] + (cz[l] - oz[l]) * keep[l];
      float wx = vx, wy = vy, wz = vz;
      if (kCenter) {
        rotate(cqx[l], cqy[l], cqz[l], cqw[l], vx, vy, vz, wx, wy, wz);
        wx = cpx[l] + cs[l] * wx;
        wy = cpy[l] + cs[l] * wy;
        wz = cpz[l] + cs[l] * wz;
      }
      const float k = stiffness[l] * h;
      const float g = gravity_power[l] * h;
      wx = wx + dx * k + gx[l] * g;
      wy = wy + dy * k + gy[l] * g;
      wz = wz + dz * k + gz[l] * g;
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
  const auto aim = [&](std::size_t l, float hx, float hy, float hz, float length, float scale, float sx, float sy,
                       float sz) SPRINGBONES_ALWAYS_INLINE {
    const float fx = sx - hx, fy = sy - hy, fz = sz - hz;
    if (kCenter) {
      float ux, uy, uz;
      rotate(-cqx[l], -cqy[l], -cqz[l], cqw[l], sx - cpx[l], sy - cpy[l], sz - cpz[l], ux, uy, uz);
      sx = ux / cs[l];
      sy = uy / cs[l];
      sz = uz / cs[l];
    }
    ox[l] = kSeed ? sx : cx[l];
    oy[l] = kSeed ? sy : cy[l];
    oz[l] = kSeed ? sz : cz[l];
    cx[l] = sx;
    cy[l] = sy;
    cz[l] = sz;

    // The bone in the parent's frame, |f| = length: the shortest turn of the rest axis onto it,
    // (b x f, |b||f| + b.f) normalized, applied after the rest rotation.
    float fpx, fpy, fpz;
    rotate(-pqx[l], -pqy[l], -pqz[l], pqw[l], fx, fy, fz, fpx, fpy, fpz);
    const float dot = bx[l] * fpx + by[l] * fpy + bz[l] * fpz;
    const bool opposite = dot < kOppositeDot * length;
    const float tqx = opposite ? nx[l] : by[l] * fpz - bz[l] * fpy;
    const float tqy = opposite ? ny[l] : bz[l] * fpx - bx[l] * fpz;
    const float tqz = opposite ? nz[l] : bx[l] * fpy - by[l] * fpx;
    const float tqw = opposite ? 0.0f : length + dot;
    const float inv_turn = 1.0f / std::sqrt(tqx * tqx + tqy * tqy + tqz * tqz + tqw * tqw);
    // Both factors are unit quaternions (the loader normalizes rest rotations), so is the product.
    float mx, my, mz, mw;
    multiply(tqx * inv_turn, tqy * inv_turn, tqz * inv_turn, tqw * inv_turn, rx[l], ry[l], rz[l], rw[l], mx, my, mz,
             mw);
    // Seeding, a zero-length bone or a lost direction (NaN fails the comparison) keep the rest.
    const bool moving = !kSeed && length > kMinLength && inv_turn < 1e30f;
    const float lqx = moving ? mx : rx[l];
    const float lqy = moving ? my : ry[l];
    const float lqz = moving ? mz : rz[l];
    const float lqw = moving ? mw : rw[l];
    out_x[l] = lqx;
    out_y[l] = lqy;
    out_z[l] = lqz;
    out_w[l] = lqw;
    multiply(pqx[l], pqy[l], pqz[l], pqw[l], lqx, lqy, lqz, lqw, wqx[l], wqy[l], wqz[l], wqw[l]);
    wpx[l] = hx;
    wpy[l] = hy;
    wpz[l] = hz;
    ws[l] = scale;
  };

  if (!kColliders) {
#if defined(__clang__)
#pragma clang loop vectorize(assume_safety) vectorize_width(4) interleave_count(1)
#endif
    for (std::size_t l = begin; l < end; ++l) {
      float hx, hy, hz, length, scale, sx, sy, sz;
      integrate(l, hx, hy, hz, length, scale, sx, sy, sz);
      aim(l, hx, hy, hz, length, scale, sx, sy, sz);
    }
    return;
  }

  float* __restrict hx = hx_.data();
  float* __restrict hy = hy_.data();
  float* __restrict hz = hz_.data();
  float* __restrict len = len_.data();
  float* __restrict scl = scale_.data();
  float* __restrict sx = sx_.data();
  float* __restrict sy = sy_.data();
  float* __restrict sz = sz_.data();
#if defined(__clang__)
#pragma clang loop vectorize(assume_safety) vectorize_width(4) interleave_count(1)
#endif
  for (std::size_t l = begin; l < end; ++l) integrate(l, hx[l], hy[l], hz[l], len[l], scl[l], sx[l], sy[l], sz[l]);

  // One loop per copy and collider (so each loop vectorises): push the tail out of the shape
  // (closest point on the capsule segment, or the sphere center), then restore the bone length.
  const float* __restrict hit = hit_radius_.data() + base;
  const std::uint32_t* __restrict mask = collider_mask_.data() + base;
  for (std::size_t k = first_copy; k < end_copy; ++k) {
    for (std::size_t c = 0; c < collider_block_; ++c) {
      const std::size_t shape = k * collider_block_ + c;
      const float ax0 = colliders_.x0[shape], ay0 = colliders_.y0[shape], az0 = colliders_.z0[shape];
      const float sgx = colliders_.x1[shape] - ax0, sgy = colliders_.y1[shape] - ay0, sgz = colliders_.z1[shape] - az0;
      const float segment2 = sgx * sgx + sgy * sgy + sgz * sgz;
      const float inv_segment2 = segment2 > 0.0f ? 1.0f / segment2 : 0.0f;
      const float radius = colliders_.radius[shape];
      const std::uint32_t bit = 1u << c;
#if defined(__clang__)
#pragma clang loop vectorize(assume_safety) vectorize_width(4) interleave_count(1)
#endif
      for (std::size_t l = k * lanes_per_copy_; l < (k + 1) * lanes_per_copy_; ++l) {
        const float vx = sx[l] - ax0, vy = sy[l] - ay0, vz = sz[l] - az0;
        float t = (vx * sgx + vy * sgy + vz * sgz) * inv_segment2;
        t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
        const float dx = vx - sgx * t, dy = vy - sgy * t, dz = vz - sgz * t;
        const float distance = std::sqrt(dx * dx + dy * dy + dz * dz);
        const float penetration = radius + hit[l] - distance;
        const bool pushed = (mask[l] & bit) != 0 && penetration > 0.0f && distance > kMinLength;
        const float push = pushed ? penetration / distance : 0.0f;
        const float px = sx[l] + dx * push, py = sy[l] + dy * push, pz = sz[l] + dz * push;
        const float fx = px - hx[l], fy = py - hy[l], fz = pz - hz[l];
        const float offset_length = std::sqrt(fx * fx + fy * fy + fz * fz);
        const bool usable = pushed && offset_length > kMinLength && offset_length < 1e30f;
        const float to_length = len[l] / offset_length;
        sx[l] = usable ? hx[l] + fx * to_length : sx[l];
        sy[l] = usable ? hy[l] + fy * to_length : sy[l];
        sz[l] = usable ? hz[l] + fz * to_length : sz[l];
      }
    }
  }

#if defined(__clang__)
#pragma clang loop vectorize(assume_safety) vectorize_width(4) interleave_count(1)
#endif
  for (std::size_t l = begin; l < end; ++l) aim(l, hx[l], hy[l], hz[l], len[l], scl[l], sx[l], sy[l], sz[l]);
}

}  // namespace springbones
