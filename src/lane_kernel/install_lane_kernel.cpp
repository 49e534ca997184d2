// Links the lane kernel into what links this file, and installs it before anything runs
// (simulation/lane_kernel.h): the native library and the crowd module. Its own folder, so that the
// runtime library's sources (every .cpp of src/simulation/) leave it out and the preview module
// cannot pull it in.
#include <memory>
#include <utility>

#include "simulation/lane_integrator.h"
#include "simulation/lane_kernel.h"
#include "simulation/spring_lanes.h"

namespace springbones {
namespace {

std::unique_ptr<SpringIntegrator> makeLaneIntegrator(std::shared_ptr<const RigConstants> constants) {
  return std::make_unique<LaneIntegrator>(std::move(constants));
}

void runQueued(SpringLanes& pool) { pool.runQueued(); }

constexpr LaneKernel kLaneKernel{makeLaneIntegrator, runQueued};

// Runs before main() natively, and in the module's constructors (before any binding is called).
const bool installed = (installLaneKernel(&kLaneKernel), true);

}  // namespace
}  // namespace springbones
