// libFuzzer entry point for the springBones entries layout (readSpringBonesEntries): bytes as
// web/springbones.js would hand over a springBones object, checked against the JSON text reader.
// The body is runEntries in fuzz_harness.h, shared with tests/native/fuzz_regressions_test.cpp.
#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return springbones::fuzz::abortIfBroken(springbones::fuzz::runEntries(data, size));
}
