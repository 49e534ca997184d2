// libFuzzer entry point for the springBones entries layout (readSpringBonesEntries): bytes as
// web/springbones.js would hand over a springBones object, checked against the JSON text reader.
// The body is runEntries in fuzz_harness.h, shared with tests/native/fuzz_regressions_test.cpp.
// A broken invariant aborts, so libFuzzer keeps and reports the input.
#include <cstdio>
#include <cstdlib>

#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string failure = springbones::fuzz::runEntries(data, size);
  if (!failure.empty()) {
    std::fprintf(stderr, "springbones invariant broken: %s\n", failure.c_str());
    std::abort();
  }
  return 0;
}
