// libFuzzer entry point for .vrm avatars (VRMC_springBone 1.0 and VRM 0.x secondaryAnimation): any
// bytes through loadVrmRig, then an Instance stepped at rest. The body is runVrm in
// fuzz_harness.h, shared with tests/native/fuzz_regressions_test.cpp.
// A broken invariant aborts, so libFuzzer keeps and reports the input.
#include <cstdio>
#include <cstdlib>

#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string failure = springbones::fuzz::runVrm(data, size);
  if (!failure.empty()) {
    std::fprintf(stderr, "springbones invariant broken: %s\n", failure.c_str());
    std::abort();
  }
  return 0;
}
