#include "simulation/lane_kernel.h"

#include "springbones/boundary.h"

namespace springbones {
namespace {

// Constant-initialised (null until installed), so the installer's static initializer may run
// before or after any other.
const LaneKernel* installed_kernel = nullptr;

}  // namespace

const LaneKernel* laneKernel() { return installed_kernel; }

void installLaneKernel(const LaneKernel* kernel) { installed_kernel = kernel; }

bool laneKernelLinked() { return installed_kernel != nullptr; }

}  // namespace springbones
