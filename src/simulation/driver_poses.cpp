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

void DriverPoses::read(const float* input, const DriverPoses& previous) {
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
    px[d] = ok ? e[12][d] : 0.0f;
    py[d] = ok ? e[13][d] : 0.0f;
    pz[d] = ok ? e[14][d] : 0.0f;
    qx[d] = ok ? x * inverse : 0.0f;
    qy[d] = ok ? y * inverse : 0.0f;
    qz[d] = ok ? z * inverse : 0.0f;
    qw[d] = ok ? w * inverse : 1.0f;
    sc[d] = ok ? s : 1.0f;
    similar[d] = ok ? 1 : 0;
    finite[d] = is_finite ? 1 : 0;
    any_non_finite |= is_finite ? 0 : 1;
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

bool driversJumped(const DriverPoses& from, const DriverPoses& to, int steps, float distance, float angle) {
  const float per = static_cast<float>(std::max(1, steps));
  const float moved_limit = distance * per;
  const float half_angle = 0.5f * angle * per;
  const bool check_distance = moved_limit > 0.0f, check_angle = half_angle > 0.0f && half_angle < 1.5707963f;
  // The turn between two unit rotations is 2 acos|a.b|: beyond the threshold when |a.b| is below
  // the cosine of half of it.
  const float min_dot = check_angle ? static_cast<float>(cosine(half_angle)) : -1.0f;
  for (std::size_t d = 0; d < to.size(); ++d) {
    glm::vec3 pa, pb;
    glm::quat ra, rb;
    poseOf(from, d, pa, ra);
    poseOf(to, d, pb, rb);
    const glm::vec3 moved = pb - pa;
    if (check_distance && glm::dot(moved, moved) > moved_limit * moved_limit) return true;
    if (check_angle && std::abs(glm::dot(ra, rb)) < min_dot) return true;
  }
  return false;
}

}  // namespace springbones
