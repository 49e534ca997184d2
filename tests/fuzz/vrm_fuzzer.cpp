// libFuzzer entry point for .vrm avatars (VRMC_springBone 1.0 and VRM 0.x secondaryAnimation): any
// bytes through loadVrm, then an Instance stepped at rest. The body is runVrm in
// fuzz_harness.h, shared with tests/native/fuzz_regressions_test.cpp.
#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return springbones::fuzz::abortIfBroken(springbones::fuzz::runVrm(data, size));
}
