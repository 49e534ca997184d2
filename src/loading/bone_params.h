// The spring-bone parameter table of ADR-316 in one place: defaults, inclusive ranges and the
// runtime's clamp. The metadata reader clamps with these; the deploy-time validator rejects
// against the same numbers.
#pragma once

#include <string_view>

namespace springbones {

struct ParamRange {
  std::string_view key;  ///< JSON key in a bone entry
  float min;
  float max;
  float fallback;  ///< default when missing or unreadable
};

inline constexpr ParamRange kStiffnessRange{"stiffness", 0.0f, 4.0f, 2.0f};        ///< m/s
inline constexpr ParamRange kGravityPowerRange{"gravityPower", 0.0f, 2.0f, 0.0f};  ///< m/s
inline constexpr ParamRange kDragRange{"drag", 0.0f, 1.0f, 0.5f};                  ///< per step
inline constexpr float kGravityDirComponentLimit = 10.0f;                          ///< schema bound of each component

}  // namespace springbones
