// The gust function behind Wind (springbones.h): private to the solvers and their tests.
#pragma once

#include "common/glm_interop.h"

namespace springbones {

/// The wind's pull at `time` seconds of simulated time: direction x strength x a gust factor in
/// [0.5, 1] (1 when gust_frequency is 0). Zero for a wind with no usable direction or strength.
/// Arithmetic only (no libm), so native and WebAssembly builds agree to the bit.
glm::vec3 windAt(const Wind& wind, double time);

}  // namespace springbones
