// The lane kernel: the spring update of solver.cpp written on plain floats in structure-of-arrays
// form, one loop over lanes per depth. The loop body has no branches (selects only) and no calls,
// so clang vectorises it for WebAssembly SIMD; every operation is a single IEEE operation with
// -ffp-contract=off, so vectorised and scalar builds produce the same bits.
#include "spring_lanes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace springbones {
namespace {

constexpr std::size_t kLaneMultiple = 4;  // one WebAssembly SIMD register of floats: no remainder loop
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

inline void normalize(float& x, float& y, float& z, float& w) {
  const float inv = 1.0f / std::sqrt(x * x + y * y + z * z + w * w);
  x *= inv;
  y *= inv;
  z *= inv;
  w *= inv;
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
  for (auto* v : {&px, &py, &pz, &qx, &qy, &qz, &qw, &s}) v->assign(slots, 0.0f);
  set(0, glm::vec3(0.0f), glm::quat(1, 0, 0, 0), 1.0f);
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

SpringLanes::SpringLanes(const Rig& rig) {
  const auto& joints = rig.joints;
  const auto& nodes = rig.skeleton.nodes;
  // Lanes and depths: a joint continues its parent's lane when it is the parent's tail.
  std::vector<int> lane_of(joints.size(), -1), depth_of(joints.size(), 0);
  int lanes = 0;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const int parent = joint.parent_joint;
    if (parent >= 0 && joints[parent].tail_node == joint.node) {
      lane_of[j] = lane_of[parent];
    } else {
      lane_of[j] = lanes++;
    }
    depth_of[j] = parent >= 0 ? depth_of[parent] + 1 : 0;
    depth_count_ = std::max<std::size_t>(depth_count_, depth_of[j] + 1);
  }
  lane_count_ = (static_cast<std::size_t>(lanes) + kLaneMultiple - 1) / kLaneMultiple * kLaneMultiple;
  const std::size_t slots = lane_count_ * depth_count_;

  lane_start_depth_.assign(lane_count_, -1);
  lane_parent_driver_.assign(lane_count_, 0);  // padding lanes read the identity
  lane_parent_slot_.assign(lane_count_, -1);
  slot_joint_.assign(slots, -1);
  joint_slot_.assign(joints.size(), -1);
  center_.assign(slots, 0);
  // Padding slots get harmless constants: identity rotations, a zero-length bone.
  for (auto* v : {&tx_, &ty_, &tz_, &rx_, &ry_, &rz_, &ax_, &az_, &px_, &py_, &tail_distance_, &stiffness_,
                  &gravity_power_, &keep_, &gx_, &gz_}) {
    v->assign(slots, 0.0f);
  }
  for (auto* v : {&rw_, &rs_, &ay_, &pz_}) v->assign(slots, 1.0f);
  gy_.assign(slots, -1.0f);
  for (auto* v : {&cx_, &cy_, &cz_, &ox_, &oy_, &oz_, &wpx_, &wpy_, &wpz_, &wqx_, &wqy_, &wqz_, &out_x_, &out_y_,
                  &out_z_}) {
    v->assign(slots, 0.0f);
  }
  for (auto* v : {&wqw_, &ws_, &out_w_}) v->assign(slots, 1.0f);
  hit_radius_.assign(slots, 0.0f);
  collider_mask_.assign(slots, 0u);
  for (auto* v : {&ppx_, &ppy_, &ppz_, &pqx_, &pqy_, &pqz_, &cpx_, &cpy_, &cpz_, &cqx_, &cqy_, &cqz_, &hx_, &hy_,
                  &hz_, &qx_, &qy_, &qz_, &len_, &nx_w_, &ny_w_, &nz_w_}) {
    v->assign(lane_count_, 0.0f);
  }
  for (auto* v : {&pqw_, &ps_, &cqw_, &cs_, &qw_, &scale_}) v->assign(lane_count_, 1.0f);

  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    const int lane = lane_of[j];
    const std::size_t slot = static_cast<std::size_t>(depth_of[j]) * lane_count_ + lane;
    slot_joint_[slot] = static_cast<int>(j);
    joint_slot_[j] = static_cast<int>(slot);
    if (lane_start_depth_[lane] < 0) {
      lane_start_depth_[lane] = depth_of[j];
      lane_parent_driver_[lane] = joint.parent_joint < 0 ? joint.parent_driver + 1 : -1;
      lane_parent_slot_[lane] = joint.parent_joint >= 0 ? joint_slot_[joint.parent_joint] : -1;
    }
    center_[slot] = joint.center_driver + 1;
    any_center_ = any_center_ || joint.center_driver >= 0;
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
    const glm::vec3 perpendicular = perpendicularTo(axis);
    ax_[slot] = axis.x;
    ay_[slot] = axis.y;
    az_[slot] = axis.z;
    px_[slot] = perpendicular.x;
    py_[slot] = perpendicular.y;
    pz_[slot] = perpendicular.z;
    hit_radius_[slot] = joint.hit_radius;
    std::uint32_t mask = 0;
    for (int c : joint.colliders) {
      if (c >= 0 && c < static_cast<int>(kMaxLaneColliders)) mask |= 1u << c;
    }
    collider_mask_[slot] = mask;
    tail_distance_[slot] = distance > kMinLength ? distance : 0.0f;
    stiffness_[slot] = joint.params.stiffness;
    gravity_power_[slot] = joint.params.gravity_power;
    keep_[slot] = 1.0f - joint.params.drag;
    gx_[slot] = joint.params.gravity_dir.x;
    gy_[slot] = joint.params.gravity_dir.y;
    gz_[slot] = joint.params.gravity_dir.z;
  }
  (void)nodes;
}

void SpringLanes::run(const DriverTable& drivers, const ColliderTable& colliders, float h, bool seed,
                      float* rotations) {
  for (std::size_t d = 0; d < depth_count_; ++d) {
    if (seed) {
      any_center_ ? runDepth<true, true>(d, drivers, colliders, h) : runDepth<true, false>(d, drivers, colliders, h);
    } else {
      any_center_ ? runDepth<false, true>(d, drivers, colliders, h)
                  : runDepth<false, false>(d, drivers, colliders, h);
    }
  }
  for (std::size_t slot = 0; slot < slot_joint_.size(); ++slot) {
    const int j = slot_joint_[slot];
    if (j < 0) continue;
    float* out = rotations + 4 * j;
    out[0] = out_x_[slot];
    out[1] = out_y_[slot];
    out[2] = out_z_[slot];
    out[3] = out_w_[slot];
  }
}

void SpringLanes::jointWorld(std::size_t joint, glm::vec3& position, glm::quat& rotation, float& scale) const {
  const std::size_t slot = static_cast<std::size_t>(joint_slot_[joint]);
  position = glm::vec3(wpx_[slot], wpy_[slot], wpz_[slot]);
  rotation = glm::quat(wqw_[slot], wqx_[slot], wqy_[slot], wqz_[slot]);
  scale = ws_[slot];
}

template <bool kSeed, bool kCenter>
void SpringLanes::runDepth(std::size_t depth, const DriverTable& drivers, const ColliderTable& colliders, float h) {
  const std::size_t lanes = lane_count_;
  const std::size_t base = depth * lanes;

  // Lanes that begin here take their parent transform from a driver or from the joint they
  // branch off (computed at the previous depth); the others carry on from their last joint.
  for (std::size_t l = 0; l < lanes; ++l) {
    if (lane_start_depth_[l] != static_cast<int>(depth)) continue;
    const int parent_slot = lane_parent_slot_[l];
    if (parent_slot >= 0) {
      ppx_[l] = wpx_[parent_slot];
      ppy_[l] = wpy_[parent_slot];
      ppz_[l] = wpz_[parent_slot];
      pqx_[l] = wqx_[parent_slot];
      pqy_[l] = wqy_[parent_slot];
      pqz_[l] = wqz_[parent_slot];
      pqw_[l] = wqw_[parent_slot];
      ps_[l] = ws_[parent_slot];
    } else {
      const int d = lane_parent_driver_[l];
      ppx_[l] = drivers.px[d];
      ppy_[l] = drivers.py[d];
      ppz_[l] = drivers.pz[d];
      pqx_[l] = drivers.qx[d];
      pqy_[l] = drivers.qy[d];
      pqz_[l] = drivers.qz[d];
      pqw_[l] = drivers.qw[d];
      ps_[l] = drivers.s[d];
    }
  }
  if (kCenter) {
    for (std::size_t l = 0; l < lanes; ++l) {
      const int c = center_[base + l];
      cpx_[l] = drivers.px[c];
      cpy_[l] = drivers.py[c];
      cpz_[l] = drivers.pz[c];
      cqx_[l] = drivers.qx[c];
      cqy_[l] = drivers.qy[c];
      cqz_[l] = drivers.qz[c];
      cqw_[l] = drivers.qw[c];
      cs_[l] = drivers.s[c];
    }
  }

  // Per lane: the parent transform (in), then the joint's world transform (out).
  float* __restrict ppx = ppx_.data();
  float* __restrict ppy = ppy_.data();
  float* __restrict ppz = ppz_.data();
  float* __restrict pqx = pqx_.data();
  float* __restrict pqy = pqy_.data();
  float* __restrict pqz = pqz_.data();
  float* __restrict pqw = pqw_.data();
  float* __restrict ps = ps_.data();
  const float* __restrict cpx = cpx_.data();
  const float* __restrict cpy = cpy_.data();
  const float* __restrict cpz = cpz_.data();
  const float* __restrict cqx = cqx_.data();
  const float* __restrict cqy = cqy_.data();
  const float* __restrict cqz = cqz_.data();
  const float* __restrict cqw = cqw_.data();
  const float* __restrict cs = cs_.data();
  // Per lane scratch between the passes: head, rest world rotation, length, new tail (world).
  float* __restrict hx = hx_.data();
  float* __restrict hy = hy_.data();
  float* __restrict hz = hz_.data();
  float* __restrict qx = qx_.data();
  float* __restrict qy = qy_.data();
  float* __restrict qz = qz_.data();
  float* __restrict qw = qw_.data();
  float* __restrict len = len_.data();
  float* __restrict scl = scale_.data();
  float* __restrict nx = nx_w_.data();
  float* __restrict ny = ny_w_.data();
  float* __restrict nz = nz_w_.data();
  // Per slot constants and state of this depth.
  const float* __restrict tx = tx_.data() + base;
  const float* __restrict ty = ty_.data() + base;
  const float* __restrict tz = tz_.data() + base;
  const float* __restrict rx = rx_.data() + base;
  const float* __restrict ry = ry_.data() + base;
  const float* __restrict rz = rz_.data() + base;
  const float* __restrict rw = rw_.data() + base;
  const float* __restrict rs = rs_.data() + base;
  const float* __restrict ax = ax_.data() + base;
  const float* __restrict ay = ay_.data() + base;
  const float* __restrict az = az_.data() + base;
  const float* __restrict px = px_.data() + base;
  const float* __restrict py = py_.data() + base;
  const float* __restrict pz = pz_.data() + base;
  const float* __restrict td = tail_distance_.data() + base;
  const float* __restrict stiffness = stiffness_.data() + base;
  const float* __restrict gravity_power = gravity_power_.data() + base;
  const float* __restrict keep = keep_.data() + base;
  const float* __restrict gx = gx_.data() + base;
  const float* __restrict gy = gy_.data() + base;
  const float* __restrict gz = gz_.data() + base;
  const float* __restrict hit = hit_radius_.data() + base;
  const std::uint32_t* __restrict mask = collider_mask_.data() + base;
  float* __restrict cx = cx_.data() + base;
  float* __restrict cy = cy_.data() + base;
  float* __restrict cz = cz_.data() + base;
  float* __restrict ox = ox_.data() + base;
  float* __restrict oy = oy_.data() + base;
  float* __restrict oz = oz_.data() + base;
  float* __restrict wpx = wpx_.data() + base;
  float* __restrict wpy = wpy_.data() + base;
  float* __restrict wpz = wpz_.data() + base;
  float* __restrict wqx = wqx_.data() + base;
  float* __restrict wqy = wqy_.data() + base;
  float* __restrict wqz = wqz_.data() + base;
  float* __restrict wqw = wqw_.data() + base;
  float* __restrict ws = ws_.data() + base;
  float* __restrict out_x = out_x_.data() + base;
  float* __restrict out_y = out_y_.data() + base;
  float* __restrict out_z = out_z_.data() + base;
  float* __restrict out_w = out_w_.data() + base;

  // Pass 1: the rest transform under the parent, then Verlet inertia (center space) with drag,
  // the stiffness and gravity impulses, and the bone length. Seeding stops at the rest tail.
#if defined(__clang__)
#pragma clang loop vectorize(assume_safety) vectorize_width(4) interleave_count(1)
#endif
  for (std::size_t l = 0; l < lanes; ++l) {
    float headx, heady, headz;
    rotate(pqx[l], pqy[l], pqz[l], pqw[l], tx[l], ty[l], tz[l], headx, heady, headz);
    headx = ppx[l] + ps[l] * headx;
    heady = ppy[l] + ps[l] * heady;
    headz = ppz[l] + ps[l] * headz;
    float rqx, rqy, rqz, rqw;  // rest world rotation
    multiply(pqx[l], pqy[l], pqz[l], pqw[l], rx[l], ry[l], rz[l], rw[l], rqx, rqy, rqz, rqw);
    const float scale = ps[l] * rs[l];
    const float length = scale * td[l];
    float dx, dy, dz;  // rest direction, world
    rotate(rqx, rqy, rqz, rqw, ax[l], ay[l], az[l], dx, dy, dz);
    float sx = headx + dx * length, sy = heady + dy * length, sz = headz + dz * length;
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
      const float fx = wx - headx, fy = wy - heady, fz = wz - headz;
      const float offset_length = std::sqrt(fx * fx + fy * fy + fz * fz);
      const bool usable = offset_length > kMinLength && offset_length < 1e30f;
      const float to_length = length / offset_length;
      sx = usable ? headx + fx * to_length : sx;
      sy = usable ? heady + fy * to_length : sy;
      sz = usable ? headz + fz * to_length : sz;
    }
    hx[l] = headx;
    hy[l] = heady;
    hz[l] = headz;
    qx[l] = rqx;
    qy[l] = rqy;
    qz[l] = rqz;
    qw[l] = rqw;
    len[l] = length;
    scl[l] = scale;
    nx[l] = sx;
    ny[l] = sy;
    nz[l] = sz;
  }

  // Pass 2, one loop per collider (so each loop vectorises): push the tail out of the shape
  // (closest point on the capsule segment, or the sphere center), then restore the bone length.
  if (!kSeed) {
    for (std::size_t c = 0; c < colliders.count; ++c) {
      const float ax0 = colliders.x0[c], ay0 = colliders.y0[c], az0 = colliders.z0[c];
      const float sgx = colliders.x1[c] - ax0, sgy = colliders.y1[c] - ay0, sgz = colliders.z1[c] - az0;
      const float segment2 = sgx * sgx + sgy * sgy + sgz * sgz;
      const float inv_segment2 = segment2 > 0.0f ? 1.0f / segment2 : 0.0f;
      const float radius = colliders.radius[c];
      const std::uint32_t bit = 1u << c;
#if defined(__clang__)
#pragma clang loop vectorize(assume_safety) vectorize_width(4) interleave_count(1)
#endif
      for (std::size_t l = 0; l < lanes; ++l) {
        const float vx = nx[l] - ax0, vy = ny[l] - ay0, vz = nz[l] - az0;
        float t = (vx * sgx + vy * sgy + vz * sgz) * inv_segment2;
        t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
        const float dx = vx - sgx * t, dy = vy - sgy * t, dz = vz - sgz * t;
        const float distance = std::sqrt(dx * dx + dy * dy + dz * dz);
        const float penetration = radius + hit[l] - distance;
        const bool pushed = (mask[l] & bit) != 0 && penetration > 0.0f && distance > kMinLength;
        const float push = pushed ? penetration / distance : 0.0f;
        const float sx = nx[l] + dx * push, sy = ny[l] + dy * push, sz = nz[l] + dz * push;
        const float fx = sx - hx[l], fy = sy - hy[l], fz = sz - hz[l];
        const float offset_length = std::sqrt(fx * fx + fy * fy + fz * fz);
        const bool usable = pushed && offset_length > kMinLength && offset_length < 1e30f;
        const float to_length = len[l] / offset_length;
        nx[l] = usable ? hx[l] + fx * to_length : nx[l];
        ny[l] = usable ? hy[l] + fy * to_length : ny[l];
        nz[l] = usable ? hz[l] + fz * to_length : nz[l];
      }
    }
  }

  // Pass 3: store the tail (center space), turn the joint toward it, and hand the joint's world
  // transform to the next depth of the lane.
#if defined(__clang__)
#pragma clang loop vectorize(assume_safety) vectorize_width(4) interleave_count(1)
#endif
  for (std::size_t l = 0; l < lanes; ++l) {
    float sx = nx[l], sy = ny[l], sz = nz[l];
    const float fx = sx - hx[l], fy = sy - hy[l], fz = sz - hz[l];
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

    // The rest axis turned toward the tail, in the joint's rest local frame.
    float lx, ly, lz;
    rotate(-qx[l], -qy[l], -qz[l], qw[l], fx, fy, fz, lx, ly, lz);
    const float inv_local = 1.0f / std::sqrt(lx * lx + ly * ly + lz * lz);
    lx *= inv_local;
    ly *= inv_local;
    lz *= inv_local;
    const float dot = ax[l] * lx + ay[l] * ly + az[l] * lz;
    const bool opposite = dot < kOppositeDot;
    float tqx = opposite ? px[l] : ay[l] * lz - az[l] * ly;
    float tqy = opposite ? py[l] : az[l] * lx - ax[l] * lz;
    float tqz = opposite ? pz[l] : ax[l] * ly - ay[l] * lx;
    float tqw = opposite ? 0.0f : 1.0f + dot;
    normalize(tqx, tqy, tqz, tqw);
    float mx, my, mz, mw;
    multiply(rx[l], ry[l], rz[l], rw[l], tqx, tqy, tqz, tqw, mx, my, mz, mw);
    normalize(mx, my, mz, mw);
    // Seeding, a zero-length bone or a lost direction (NaN fails the comparison) keep the rest.
    const bool moving = !kSeed && len[l] > kMinLength && inv_local < 1e30f;
    const float lqx = moving ? mx : rx[l];
    const float lqy = moving ? my : ry[l];
    const float lqz = moving ? mz : rz[l];
    const float lqw = moving ? mw : rw[l];
    out_x[l] = lqx;
    out_y[l] = lqy;
    out_z[l] = lqz;
    out_w[l] = lqw;
    float jx, jy, jz, jw;
    multiply(pqx[l], pqy[l], pqz[l], pqw[l], lqx, lqy, lqz, lqw, jx, jy, jz, jw);
    wpx[l] = ppx[l] = hx[l];
    wpy[l] = ppy[l] = hy[l];
    wpz[l] = ppz[l] = hz[l];
    wqx[l] = pqx[l] = jx;
    wqy[l] = pqy[l] = jy;
    wqz[l] = pqz[l] = jz;
    wqw[l] = pqw[l] = jw;
    ws[l] = ps[l] = scl[l];
  }
}

}  // namespace springbones
