// libFuzzer entry point for GLB + metadata loading. An input is GLB (or glTF JSON) bytes, then,
// after the last "\n@@springBones@@\n", the data.springBones JSON text. The body is
// runGlbAndMetadata in fuzz_harness.h, shared with tests/native/fuzz_regressions_test.cpp.
#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return springbones::fuzz::abortIfBroken(springbones::fuzz::runGlbAndMetadata(data, size));
}
