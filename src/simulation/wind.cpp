// Wind (springbones.h Wind, simulation/wind.h windAt): the pull on every tail at a moment of simulated time.
//
// Gusts are smooth value noise: a value in [0, 1] hashed from the seed at every whole multiple of
// 1 / gust_frequency seconds, eased between neighbours with 3s^2 - 2s^3, so the pull changes
// without jumps and keeps its long-run average. Only +, -, *, /, floor and integer hashing: no
// sin or exp, whose libm results differ between the native C library and Emscripten's, so a seed
// gives the same bits everywhere.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "simulation/wind.h"

namespace springbones {
namespace {

// A 32-bit hash of (seed, knot), each bit of the inputs reaching every bit of the output
// (the mixing steps of a well-known integer finaliser).
std::uint32_t mix(std::uint32_t seed, std::int64_t knot) {
  std::uint64_t h = (static_cast<std::uint64_t>(seed) << 32) ^ static_cast<std::uint64_t>(knot);
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return static_cast<std::uint32_t>(h);
}

// The knot's value in [0, 1).
double knotValue(std::uint32_t seed, std::int64_t knot) { return (mix(seed, knot) >> 8) * (1.0 / 16777216.0); }

}  // namespace

glm::vec3 windAt(const Wind& wind, double time) {
  if (!(wind.strength > 0.0f) || !std::isfinite(wind.strength)) return glm::vec3(0.0f);
  const glm::vec3 d = toGlm(wind.direction);
  if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z))) return glm::vec3(0.0f);
  double gust = 1.0;
  const double x = time * static_cast<double>(wind.gust_frequency);
  // 2^52 knots: beyond that a double cannot tell one knot from the next, so the wind holds.
  if (wind.gust_frequency > 0.0f && x >= 0.0 && x < 4503599627370496.0) {
    const double knot = std::floor(x);
    const double s = x - knot;
    const double ease = s * s * (3.0 - 2.0 * s);
    const std::int64_t k = static_cast<std::int64_t>(knot);
    const double a = knotValue(wind.seed, k), b = knotValue(wind.seed, k + 1);
    gust = 0.5 + 0.5 * (a + (b - a) * ease);
  }
  return d * static_cast<float>(static_cast<double>(wind.strength) * gust);
}

bool unitDirection(const Vec3& direction, Vec3& out) {
  double v[3] = {direction.x, direction.y, direction.z};
  const double largest = std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
  if (!(largest > 0.0) || !std::isfinite(largest)) return false;  // NaN fails the first test
  for (double& c : v) c /= largest;
  // sqrt is correctly rounded in IEEE arithmetic: the same bits natively and in WebAssembly.
  const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  out = Vec3{static_cast<float>(v[0] / length), static_cast<float>(v[1] / length), static_cast<float>(v[2] / length)};
  return true;
}

}  // namespace springbones
