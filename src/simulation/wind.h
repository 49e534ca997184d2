// The gust function behind Wind (springbones.h): private to the solvers and their tests.
#pragma once

#include "common/glm_interop.h"

namespace springbones {

/// The wind's pull at `time` seconds of simulated time: direction x strength x a gust factor in
/// [0.5, 1] (1 when gust_frequency is 0). Zero for a wind with no usable direction or strength.
/// Arithmetic only (no libm), so native and WebAssembly builds agree to the bit.
glm::vec3 windAt(const Wind& wind, double time);

/// `direction` made unit, in double precision and scaled by its largest component first, so that
/// a finite direction whose float squared length overflows ((1e20, 0, 0)) or underflows
/// ((1e-25, 0, 0)) keeps it. False (and `out` untouched) for a zero or non-finite one.
bool unitDirection(const Vec3& direction, Vec3& out);

}  // namespace springbones
