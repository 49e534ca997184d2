// libFuzzer entry point for the simulation: the input is a byte program (skeleton, parameters,
// options, then 100 frames of driver matrices and dt). The body is runSimulation in
// fuzz_harness.h, shared with tests/native/fuzz_regressions_test.cpp.
#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return springbones::fuzz::abortIfBroken(springbones::fuzz::runSimulation(data, size));
}
