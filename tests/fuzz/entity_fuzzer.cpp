// libFuzzer entry point for an entity or Builder item as JSON text: the GLB hash loadRig and the
// Builder edits take from it, the validator, a Builder edit through it. The body is runEntity in
// fuzz_harness.h, shared with tests/native/fuzz_regressions_test.cpp.
#include "fuzz_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return springbones::fuzz::abortIfBroken(springbones::fuzz::runEntity(data, size));
}
