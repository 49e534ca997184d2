// Whether an instance may step on the lane kernel (spring_lanes.h, lane_integrator.h), which only
// pays when many copies of a rig step together, and is the larger part of the runtime's code.
// The kernel is installed by linking src/lane_kernel/install_lane_kernel.cpp (a static
// initializer): the native library and the crowd module (springbones_crowd.wasm) do; the preview
// module (springbones_wasm.wasm) does not, so that the linker leaves the kernel out of it and every
// instance there steps on the general path, which computes the same bits (tests/wasm/crowd.test.mjs).
#pragma once

#include <memory>

namespace springbones {

struct RigConstants;
class SpringIntegrator;
class SpringLanes;

/// What an instance needs of the kernel: its integrator, and running a pool's queued steps
/// (Instance::stepAll). Function pointers, so that nothing the runtime always links names the kernel.
struct LaneKernel {
  std::unique_ptr<SpringIntegrator> (*make_integrator)(std::shared_ptr<const RigConstants> constants);
  void (*run_queued)(SpringLanes& pool);
};

/// The installed kernel, or null: every instance then steps on the general path.
const LaneKernel* laneKernel();
/// Installs the kernel for the instances made from then on (install_lane_kernel.cpp).
void installLaneKernel(const LaneKernel* kernel);

}  // namespace springbones
