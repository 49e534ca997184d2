// libFuzzer entry point for typed input (the bytes a page's parse becomes, src/common/typed_value.h)
// through every typed entry point of the runtime. The body is runTyped in fuzz_harness.h, shared
// with tests/native/fuzz_regressions_test.cpp.
#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return springbones::fuzz::abortIfBroken(springbones::fuzz::runTyped(data, size));
}
