// Determinism: the rotations of a fixture after a scripted 600-step scenario hash to a constant.
// tests/wasm/determinism.test.mjs runs the same scenario in the WebAssembly build and compares the
// same constant, so a change in either build's arithmetic shows up in both suites.
//
// The scenario (keep both files in step): avatar_hair.glb with its metadata; the instance's initial
// driver matrices (each driver's rest world matrix) are kept as `rest`; for frame f = 1..600 every
// driver gets `rest` with its x translation plus tri(f) / 256, tri(f) = f % 60 < 30 ? f % 60 :
// 60 - f % 60 (a multiple of 2^-8, so the sum rounds the same in JavaScript and C++); then
// step(1/60). The hash is FNV-1a (32-bit) over the bytes of the rotation floats after the last step.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "test_helpers.h"

namespace springbones {
namespace {

using namespace test;

std::uint32_t fnv1a(const void* data, std::size_t size) {
  std::uint32_t hash = 2166136261u;
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 16777619u;
  }
  return hash;
}

TEST(Determinism, FixtureRotationsAfter600StepsHashToTheRecordedConstant) {
  Skeleton skeleton = loadFixtureSkeleton("avatar_hair.glb");
  ModelEntry model;
  std::vector<Warning> warnings;
  ASSERT_FALSE(parseSpringBonesText(readFixtureText("avatar_hair.metadata.json"), metadataKeyOf("avatar_hair.glb"),
                                    model, warnings));
  Instance instance(buildRig(std::move(skeleton), model, warnings));
  ASSERT_GT(instance.jointCount(), 10u);
  const std::vector<float> rest(instance.driverMatrices(), instance.driverMatrices() + 16 * instance.driverCount());
  for (int f = 1; f <= 600; ++f) {
    const int phase = f % 60;
    const float offset = static_cast<float>(phase < 30 ? phase : 60 - phase) / 256.0f;
    for (std::size_t d = 0; d < instance.driverCount(); ++d) {
      float* m = instance.driverMatrices() + 16 * d;
      std::memcpy(m, rest.data() + 16 * d, sizeof(float) * 16);
      m[12] = rest[16 * d + 12] + offset;
    }
    instance.step(1.0 / 60.0);
  }
  const std::uint32_t hash = fnv1a(instance.rotations(), sizeof(float) * 4 * instance.jointCount());
  // Recorded from this build; the WebAssembly test expects the same value.
  EXPECT_EQ(hash, 0x390f0db5u) << "hash 0x" << std::hex << hash;
}

}  // namespace
}  // namespace springbones
