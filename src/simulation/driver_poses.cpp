// Driver matrices in, similarities out: the per-frame front of the solver. The loops over drivers
// have no branches in their bodies (selects only) so clang vectorises them for WebAssembly SIMD;
// with -ffp-contract=off every operation rounds alike in vector and scalar code.
#include "simulation/driver_poses.h"

#include <algorithm>
#include <cmath>

#include "common/transform_math.h"
#include "simulation/spring_lanes.h"

namespace springbones {
namespace {

constexpr std::size_t kVector = 4;  // drivers per SIMD vector; arrays are padded to a multiple

// cos x for x in [0, pi/2] by its Taylor series (the last term is below 1e-16 there): std::cos
// would bring libm's argument reduction and its tables into the module, about 7 KB gzip.
double cosine(double x) {
  double term = 1.0, sum = 1.0;
  for (int k = 1; k <= 12; ++k) {
    term *= -x * x / ((2 * k - 1) * (2 * k));
    sum += term;
  }
  return sum;
}

// The position and rotation of driver d: the similarity's, or its general matrix decomposed.
void poseOf(const DriverPoses& poses, std::size_t d, glm::vec3& position, glm::quat& rotation) {
  if (poses.similar(d)) {
    position = poses.position(d);
    rotation = poses.rotation(d);
    return;
  }
  const Transform t = decomposeTransform(poses.matrix(d));
  position = toGlm(t.translation);
  rotation = toGlm(t.rotation);
}

// Whether driver d moved beyond `limits` between the two frames. DriverPoses::read computes the
// same expressions, in the same order, for the drivers that are similarities in both frames.
bool driverJumped(const DriverPoses& from, const DriverPoses& to, std::size_t d, const JumpLimits& limits) {
  glm::vec3 pa, pb;
  glm::quat ra, rb;
  poseOf(from, d, pa, ra);
  poseOf(to, d, pb, rb);
  const glm::vec3 moved = pb - pa;
  return (limits.check_distance && glm::dot(moved, moved) > limits.moved_limit_squared) ||
         (limits.check_angle && std::abs(glm::dot(ra, rb)) < limits.min_dot);
}

}  // namespace

void DriverPoses::resize(std::size_t drivers) {
  count_ = drivers;
  padded_ = (drivers + kVector - 1) / kVector * kVector;
  columns_.assign(kColumns * padded_, 0.0f);
  // Identities until read.
  for (std::size_t c :
       {std::size_t{0}, std::size_t{5}, std::size_t{10}, std::size_t{15}, std::size_t{kQw}, std::size_t{kScale}}) {
    std::fill(column(c), column(c) + padded_, 1.0f);
  }
  flags_.assign(2 * padded_, 1);
  all_similar_ = true;
}

glm::mat4 DriverPoses::matrix(std::size_t d) const {
  glm::mat4 m;
  for (std::size_t k = 0; k < 16; ++k) m[k / 4][k % 4] = at(kEntry0 + k, d);
  return m;
}

Transform DriverPoses::transform(std::size_t d) const {
  if (similar(d)) return Transform{fromGlm(position(d)), fromGlm(rotation(d)), fromGlm(glm::vec3(scale(d)))};
  return decomposeTransform(matrix(d));
}

JumpLimits jumpLimits(int steps, float distance, float angle) {
  const float per = static_cast<float>(std::max(1, steps));
  const float moved_limit = distance * per;
  const float half_angle = 0.5f * angle * per;
  JumpLimits limits;
  limits.check_distance = moved_limit > 0.0f;
  limits.check_angle = half_angle > 0.0f && half_angle < 1.5707963f;
  limits.moved_limit_squared = moved_limit * moved_limit;
  // The turn between two unit rotations is 2 acos|a.b|: beyond the threshold when |a.b| is below
  // the cosine of half of it.
  limits.min_dot = limits.check_angle ? static_cast<float>(cosine(half_angle)) : -1.0f;
  return limits;
}

bool DriverPoses::read(const float* input, const DriverPoses& previous, const JumpLimits& limits) {
  // The matrices taken apart, one array per entry, for the vector loop.
  float* entries[16];
  for (std::size_t k = 0; k < 16; ++k) entries[k] = column(kEntry0 + k);
  for (std::size_t d = 0; d < count_; ++d) {
    for (std::size_t k = 0; k < 16; ++k) entries[k][d] = input[16 * d + k];
  }

  const std::size_t padded = padded_;
  const float* __restrict e[16];
  for (std::size_t k = 0; k < 16; ++k) e[k] = entries[k];
  float* __restrict px = column(kPx);
  float* __restrict py = column(kPy);
  float* __restrict pz = column(kPz);
  float* __restrict qx = column(kQx);
  float* __restrict qy = column(kQy);
  float* __restrict qz = column(kQz);
  float* __restrict qw = column(kQw);
  float* __restrict sc = column(kScale);
  std::int32_t* __restrict similar = flags_.data();
  std::int32_t* __restrict finite = flags_.data() + padded_;
  std::int32_t any_non_finite = 0;
  // Jump detection on the drivers that are similarities in both frames, from the poses just
  // computed and the previous frame's columns; the others (rare: sheared, projective or
  // non-finite matrices) are left to driverJumped after the loop.
  const float* __restrict ppx = previous.column(kPx);
  const float* __restrict ppy = previous.column(kPy);
  const float* __restrict ppz = previous.column(kPz);
  const float* __restrict pqx = previous.column(kQx);
  const float* __restrict pqy = previous.column(kQy);
  const float* __restrict pqz = previous.column(kQz);
  const float* __restrict pqw = previous.column(kQw);
  const std::int32_t* __restrict previous_similar = previous.flags_.data();
  const bool check_distance = limits.check_distance, check_angle = limits.check_angle;
  const float moved_limit_squared = limits.moved_limit_squared, min_dot = limits.min_dot;
  std::int32_t any_jumped = 0, any_left = 0;
#if defined(__clang__)
#pragma clang loop vectorize(assume_safety) vectorize_width(4) interleave_count(1)
#endif
  for (std::size_t d = 0; d < padded; ++d) {
    // Usable: every entry within ±kMaxDriverEntry (a NaN fails the comparison too). Beyond it the
    // products and squares the steps take of a driver (its axes' lengths, a bone's world offset,
    // a determinant) overflow float, and a world matrix would come out infinite.
    bool is_finite = true;
    for (std::size_t k = 0; k < 16; ++k) is_finite = is_finite & (std::fabs(e[k][d]) <= kMaxDriverEntry);
    // Mij: row i, column j (column-major entries: x, y, z are the columns).
    const float m00 = e[0][d], m10 = e[1][d], m20 = e[2][d];
    const float m01 = e[4][d], m11 = e[5][d], m21 = e[6][d];
    const float m02 = e[8][d], m12 = e[9][d], m22 = e[10][d];
    const bool affine = e[3][d] == 0.0f && e[7][d] == 0.0f && e[11][d] == 0.0f && e[15][d] == 1.0f;
    // A positive uniform scale and orthogonal axes, not mirrored. The axis lengths are compared
    // squared: |a|^2 - |x|^2 is about 2 |x| (|a| - |x|), hence the doubled tolerance.
    const float xx = m00 * m00 + m10 * m10 + m20 * m20;
    const float yy = m01 * m01 + m11 * m11 + m21 * m21;
    const float zz = m02 * m02 + m12 * m12 + m22 * m22;
    const float xy = m00 * m01 + m10 * m11 + m20 * m21;
    const float yz = m01 * m02 + m11 * m12 + m21 * m22;
    const float zx = m02 * m00 + m12 * m10 + m22 * m20;
    const float handed = (m10 * m21 - m20 * m11) * m02 + (m20 * m01 - m00 * m21) * m12 + (m00 * m11 - m10 * m01) * m22;
    const float tolerance = kSimilarityTolerance * xx;
    const bool ok = is_finite && affine && xx > 1e-24f && std::fabs(yy - xx) <= 2.0f * tolerance &&
                    std::fabs(zz - xx) <= 2.0f * tolerance && std::fabs(xy) <= tolerance &&
                    std::fabs(yz) <= tolerance && std::fabs(zx) <= tolerance && handed > 0.0f;
    // With M = s R, (1 + trace R) s = s + trace M = 4 s w^2 and, e.g., M21 - M12 = 4 s w x: the
    // components scaled alike come straight from M, and one normalization removes the common
    // factor. The largest of the four candidates is used, to stay far from cancellation.
    const float s = std::sqrt(xx);
    const float tw = s + m00 + m11 + m22, tx = s + m00 - m11 - m22, ty = s - m00 + m11 - m22, tz = s - m00 - m11 + m22;
    const bool by_w = tw >= tx && tw >= ty && tw >= tz;
    const bool by_x = !by_w && tx >= ty && tx >= tz;
    const bool by_y = !by_w && !by_x && ty >= tz;
    const float a = m21 - m12, b = m02 - m20, c = m10 - m01;  // 4 s w (x, y, z)
    const float f = m10 + m01, g = m02 + m20, h = m21 + m12;  // 4 s (xy, xz, yz)
    const float w = by_w ? tw : (by_x ? a : (by_y ? b : c));
    const float x = by_w ? a : (by_x ? tx : (by_y ? f : g));
    const float y = by_w ? b : (by_x ? f : (by_y ? ty : h));
    const float z = by_w ? c : (by_x ? g : (by_y ? h : tz));
    const float inverse = 1.0f / std::sqrt(w * w + x * x + y * y + z * z);
    // A driver that is no similarity gets the identity here: the lane path never reads it, and
    // nothing non-finite is left behind.
    const float npx = ok ? e[12][d] : 0.0f, npy = ok ? e[13][d] : 0.0f, npz = ok ? e[14][d] : 0.0f;
    const float nqx = ok ? x * inverse : 0.0f, nqy = ok ? y * inverse : 0.0f, nqz = ok ? z * inverse : 0.0f;
    const float nqw = ok ? w * inverse : 1.0f;
    px[d] = npx;
    py[d] = npy;
    pz[d] = npz;
    qx[d] = nqx;
    qy[d] = nqy;
    qz[d] = nqz;
    qw[d] = nqw;
    sc[d] = ok ? s : 1.0f;
    similar[d] = ok ? 1 : 0;
    finite[d] = is_finite ? 1 : 0;
    any_non_finite |= is_finite ? 0 : 1;
    // driverJumped's expressions in glm's order: (x x + y y) + z z for the move, (w w + x x) +
    // (y y + z z) for the rotations' dot product, so the answer is the same bit for bit.
    const float mx = npx - ppx[d], my = npy - ppy[d], mz = npz - ppz[d];
    const float moved_squared = (mx * mx + my * my) + mz * mz;
    const float dot = (pqw[d] * nqw + pqx[d] * nqx) + (pqy[d] * nqy + pqz[d] * nqz);
    const bool both_similar = ok & (previous_similar[d] != 0);
    const bool jumped =
        (check_distance & (moved_squared > moved_limit_squared)) | (check_angle & (std::fabs(dot) < min_dot));
    any_jumped |= both_similar & jumped ? 1 : 0;
    any_left |= both_similar ? 0 : 1;
  }
  // A matrix with a non-finite entry, or one beyond kMaxDriverEntry, is ignored: the driver keeps
  // its last good pose.
  if (any_non_finite) {
    for (std::size_t d = 0; d < count_; ++d) {
      if (finite[d]) continue;
      for (std::size_t c = 0; c < kColumns; ++c) columns_[c * padded_ + d] = previous.at(c, d);
      similar[d] = previous.flags_[d];
    }
  }
  all_similar_ = true;
  for (std::size_t d = 0; d < count_; ++d) all_similar_ = all_similar_ && similar[d] != 0;
  if (any_jumped || !any_left || !(check_distance || check_angle)) return any_jumped != 0;
  // The drivers the loop left: no similarity in one of the two frames, or a matrix that kept its
  // last good pose. The rule driver by driver, on the poses as they are now (nothing to test when
  // both thresholds are off).
  for (std::size_t d = 0; d < count_; ++d) {
    if (finite[d] && similar[d] && previous.flags_[d]) continue;  // tested in the loop
    if (driverJumped(previous, *this, d, limits)) return true;
  }
  return false;
}

void DriverPoses::blend(const DriverPoses& from, const DriverPoses& to, float t, DriverTable& table, std::size_t first,
                        std::size_t stride) {
  const std::size_t count = to.count_;
  const float *fx = from.column(kPx), *fy = from.column(kPy), *fz = from.column(kPz), *fqx = from.column(kQx),
              *fqy = from.column(kQy), *fqz = from.column(kQz), *fqw = from.column(kQw), *fs = from.column(kScale);
  const float *tx = to.column(kPx), *ty = to.column(kPy), *tz = to.column(kPz), *tqx = to.column(kQx),
              *tqy = to.column(kQy), *tqz = to.column(kQz), *tqw = to.column(kQw), *ts = to.column(kScale);
  for (std::size_t d = 0, at = first; d < count; ++d, at += stride) {
    if (t >= 1.0f) {
      table.px[at] = tx[d];
      table.py[at] = ty[d];
      table.pz[at] = tz[d];
      table.qx[at] = tqx[d];
      table.qy[at] = tqy[d];
      table.qz[at] = tqz[d];
      table.qw[at] = tqw[d];
      table.s[at] = ts[d];
      continue;
    }
    table.px[at] = fx[d] * (1.0f - t) + tx[d] * t;
    table.py[at] = fy[d] * (1.0f - t) + ty[d] * t;
    table.pz[at] = fz[d] * (1.0f - t) + tz[d] * t;
    table.s[at] = fs[d] + (ts[d] - fs[d]) * t;
    nlerpRotation(fqx[d], fqy[d], fqz[d], fqw[d], tqx[d], tqy[d], tqz[d], tqw[d], t, table.qx[at], table.qy[at],
                  table.qz[at], table.qw[at]);
  }
}

bool driversJumped(const DriverPoses& from, const DriverPoses& to, const JumpLimits& limits) {
  for (std::size_t d = 0; d < to.size(); ++d) {
    if (driverJumped(from, to, d, limits)) return true;
  }
  return false;
}

}  // namespace springbones
