// One frame of an instance's driver matrices, checked and taken apart for the solver.
//
// Every avatar's drivers (chain-root parents, centers, collider nodes) arrive as world matrices
// each frame. The lane path needs them as similarities (position, rotation, uniform scale); the
// general path needs the matrices. This reads a frame once: a driver with a non-finite entry, or
// one beyond kMaxDriverEntry (springbones.h), keeps its last good pose, and the similarity test
// and decomposition run branch-free over structure-of-arrays, four drivers per SIMD vector in
// WebAssembly (same bits as scalar code).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/glm_interop.h"

namespace springbones {

struct DriverTable;

/// How far from a similarity a driver matrix may be and still take the lane path: well above
/// float rounding of a composed three.js matrixWorld, well below any visible shear.
inline constexpr float kSimilarityTolerance = 1e-4f;

/// The rotation at fraction t from a to b (x, y, z, w): normalized lerp along the shorter arc,
/// b itself if the mix vanishes. Not slerp: slerp's acos and sin round differently in the native
/// libm and Emscripten's, and native and WebAssembly builds must give the same bits; between two
/// consecutive frames the angle is small and nlerp's speed error is far below float noise.
/// Branch-free, so the driver loops that call it vectorise.
inline void nlerpRotation(float ax, float ay, float az, float aw, float bx, float by, float bz, float bw, float t,
                          float& ox, float& oy, float& oz, float& ow) {
  const float flip = ax * bx + ay * by + az * bz + aw * bw < 0.0f ? -1.0f : 1.0f;
  const float cx = flip * bx, cy = flip * by, cz = flip * bz, cw = flip * bw;
  const float mx = ax + (cx - ax) * t, my = ay + (cy - ay) * t, mz = az + (cz - az) * t, mw = aw + (cw - aw) * t;
  const float length = std::sqrt(mx * mx + my * my + mz * mz + mw * mw);
  const bool usable = length > 0.0f;
  ox = usable ? mx / length : bx;
  oy = usable ? my / length : by;
  oz = usable ? mz / length : bz;
  ow = usable ? mw / length : bw;
}

/// Jump detection's thresholds for one frame (Instance's): a driver jumped when it moved farther
/// than its limit, or turned farther, between the frame's previous poses and its new ones.
struct JumpLimits {
  bool check_distance = false;  // a distance threshold of 0 is not tested
  bool check_angle = false;     // nor an angle of 0, nor one whose half reaches a right angle
  float moved_limit_squared = 0.0f;
  float min_dot = -1.0f;  // |a.b| of two unit rotations below this: turned farther than the limit
};

/// The limits of a frame of `steps` fixed steps (at least one is assumed) for thresholds of
/// `distance` and `angle` radians per step.
JumpLimits jumpLimits(int steps, float distance, float angle);

class DriverPoses {
 public:
  void resize(std::size_t drivers);
  std::size_t size() const { return count_; }

  /// Reads `input` (column-major 4x4, 16 floats per driver). A matrix with an entry that is not
  /// a number within ±kMaxDriverEntry is replaced by `previous`'s pose of that driver (its last
  /// good one). Returns whether a driver jumped from `previous` beyond `limits` (none by default):
  /// the same answer as driversJumped(previous, *this, ...), tested in the same pass as the
  /// reading, while each driver's columns are in registers.
  bool read(const float* input, const DriverPoses& previous, const JumpLimits& limits = {});

  /// Whether every driver is a similarity (a positive uniform scale, orthogonal axes, no
  /// projective part, not mirrored).
  bool allSimilar() const { return all_similar_; }
  bool similar(std::size_t d) const { return flags_[d] != 0; }
  glm::mat4 matrix(std::size_t d) const;
  glm::vec3 position(std::size_t d) const { return glm::vec3(at(kPx, d), at(kPy, d), at(kPz, d)); }
  glm::quat rotation(std::size_t d) const { return glm::quat(at(kQw, d), at(kQx, d), at(kQy, d), at(kQz, d)); }
  float scale(std::size_t d) const { return at(kScale, d); }
  /// Translation, rotation and scale: the similarity's, or a decomposition of a general matrix.
  Transform transform(std::size_t d) const;

  /// The similarities at fraction t of the way from `from` to `to` (positions and scales mixed,
  /// rotations by normalized lerp along the shorter arc), written to the table at
  /// first + d * stride for driver d. Both frames must be allSimilar().
  static void blend(const DriverPoses& from, const DriverPoses& to, float t, DriverTable& table, std::size_t first,
                    std::size_t stride);

 private:
  std::size_t count_ = 0;
  bool all_similar_ = true;
  // Columns of one value per driver, padded to whole SIMD vectors, in one allocation (an array
  // each was ~25 scattered allocations per instance): the matrix as read (a non-finite one
  // replaced), one column per entry (column-major index) for the vector loop; then the
  // similarity.
  enum Column : std::size_t { kEntry0 = 0, kPx = 16, kPy, kPz, kQx, kQy, kQz, kQw, kScale, kColumns };
  float* column(std::size_t c) { return columns_.data() + c * padded_; }
  const float* column(std::size_t c) const { return columns_.data() + c * padded_; }
  float at(std::size_t c, std::size_t d) const { return columns_[c * padded_ + d]; }

  std::size_t padded_ = 0;
  std::vector<float> columns_;
  // Per driver, padded: whether it is a similarity, then (from padded_ on) whether it was finite.
  std::vector<std::int32_t> flags_;
};

/// Whether a driver moved, between two frames' poses, beyond `limits`: the rule of jump detection,
/// for every driver. DriverPoses::read applies it to the drivers that are similarities in both
/// frames in its own pass, and this to the others.
bool driversJumped(const DriverPoses& from, const DriverPoses& to, const JumpLimits& limits);

}  // namespace springbones
