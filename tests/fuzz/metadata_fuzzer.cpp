// libFuzzer entry point for data.springBones text alone: the runtime reader, the deploy-time
// validator and Builder edits. The body is runMetadata in fuzz_harness.h, shared with
// tests/native/fuzz_regressions_test.cpp.
#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return springbones::fuzz::abortIfBroken(springbones::fuzz::runMetadata(data, size));
}
