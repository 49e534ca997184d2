// Jumps of an instance's drivers (Instance::jump, docs/semantics.md "Jumps"): the arithmetic that
// carries a chain's tails across one. Kept out of the per-frame files (instance.cpp and its
// neighbours are built at -O3 for WebAssembly): a jump is rare, and inlined there its matrix code
// cost 7 KB of the module. Telling a jump from motion runs every frame, in the pass that reads the
// driver poses (DriverPoses::read, driver_poses.h).
#pragma once

#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "simulation/driver_poses.h"

namespace springbones {

class JumpCarry {
 public:
  void resize(std::size_t drivers);

  /// Each driver's jump over the last frame: what its pose changed from `from` to `to` beyond its
  /// last motion (`older` to `from`) continued, D = to x (last motion x from)^-1.
  void prepare(const DriverPoses& older, const DriverPoses& from, const DriverPoses& to);

  /// A stored tail (in the space of driver `center`'s last pose, or world space for -1) carried by
  /// driver `carrier`'s jump (-1: none) and stored again in the center's carried space.
  glm::vec3 carry(const glm::vec3& stored, int carrier, int center) const;

  /// Each driver's last pose carried by its jump, 16 floats per driver (DriverPoses::read's input).
  const float* carriedPoses() const { return carried_.data(); }

 private:
  std::vector<glm::mat4> delta_;       // per driver: D
  std::vector<glm::mat4> from_;        // per driver: its last pose
  std::vector<glm::mat4> carried_to_;  // per driver: the inverse of its carried last pose
  std::vector<unsigned char> valid_;   // per driver: both poses had an inverse
  std::vector<float> carried_;         // per driver: D x its last pose
};

}  // namespace springbones
