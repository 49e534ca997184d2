// Rig data (src/boundary/rig_data.cpp): the bytes a rig crosses between the WebAssembly modules
// in (loadVrm's rig, built by the readers module and run by the runtime) give back the same rig,
// field for field and rotation for rotation, and bytes in another layout are refused, never read
// past their end.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "springbones/boundary.h"
#include "springbones/readers.h"
#include "springbones/springbones.h"
#include "springbones/vrm.h"
#include "test_helpers.h"

namespace springbones {
namespace {

std::vector<std::uint8_t> dataOf(const Rig& rig, VrmSpringFormat format) {
  std::vector<std::uint8_t> bytes;
  writeRigData(rig, format, bytes);
  return bytes;
}

Error readBack(const std::vector<std::uint8_t>& bytes, std::shared_ptr<const Rig>& rig, VrmSpringFormat& format) {
  return readRigData(TypedBytes{bytes.data(), bytes.size()}, rig, format);
}

// The rotations of an instance after frames of a driver moving sideways, bit for bit.
std::vector<float> rotationsOf(const std::shared_ptr<const Rig>& rig) {
  Instance instance(rig);
  for (int frame = 0; frame < 40; ++frame) {
    for (std::size_t d = 0; d < instance.driverCount(); ++d) instance.driverMatrices()[d * 16 + 12] += 0.01f;
    instance.step(1.0 / 60.0);
  }
  return std::vector<float>(instance.rotations(), instance.rotations() + instance.jointCount() * 4);
}

std::shared_ptr<const Rig> vrmFixture(const std::string& name, VrmSpringFormat& format) {
  const std::vector<std::uint8_t> bytes = test::readFixture(name);
  std::shared_ptr<const Rig> rig;
  const Error e = loadVrm(bytes.data(), bytes.size(), rig, &format);
  EXPECT_FALSE(e) << name << ": " << e.message;
  return rig;
}

TEST(RigData, EveryVrmFixtureComesBackTheSameRig) {
  for (const char* name : {"vrm10_springs.vrm", "vrm0_springs.vrm", "vrm10_extended_colliders.vrm"}) {
    SCOPED_TRACE(name);
    VrmSpringFormat format = VrmSpringFormat::kNone;
    const std::shared_ptr<const Rig> rig = vrmFixture(name, format);
    ASSERT_TRUE(rig);
    ASSERT_FALSE(rig->joints.empty());
    const std::vector<std::uint8_t> bytes = dataOf(*rig, format);

    std::shared_ptr<const Rig> back;
    VrmSpringFormat back_format = VrmSpringFormat::kNone;
    const Error e = readBack(bytes, back, back_format);
    ASSERT_FALSE(e) << e.message;
    ASSERT_TRUE(back);
    EXPECT_EQ(back_format, format);
    // Every field is in the layout, so the same bytes again means the same fields.
    EXPECT_EQ(dataOf(*back, back_format), bytes);
    EXPECT_EQ(describeRig(*back, "", "vrm"), describeRig(*rig, "", "vrm"));
    const std::vector<float> expected = rotationsOf(rig);
    const std::vector<float> actual = rotationsOf(back);
    ASSERT_EQ(actual.size(), expected.size());
    EXPECT_EQ(std::memcmp(actual.data(), expected.data(), actual.size() * sizeof(float)), 0);
  }
}

TEST(RigData, ADecentralandRigWithEveryColliderShapeAndLimitComesBackTheSame) {
  RigOptions options;
  options.preset = ColliderPreset::kDclBody;
  options.colliders.push_back(test::capsuleSpec("Avatar_Head", Vec3{0, 0.1f, 0}, Vec3{0, 0.2f, 0}, 0.05f));
  options.hit_radius = 0.02f;
  JointLimit cone;
  cone.kind = JointLimit::Kind::kCone;
  cone.angle = 0.5f;
  options.limits["SpringBone_hair_left"] = cone;
  ModelEntry model;
  std::vector<Warning> warnings;
  ASSERT_FALSE(parseSpringBonesText(test::readFixtureText("avatar_hair.metadata.json"),
                                    test::metadataKeyOf("avatar_hair.glb"), model, warnings));
  const std::shared_ptr<const Rig> rig =
      buildRig(test::loadFixtureSkeleton("avatar_hair.glb"), model, warnings, options);
  ASSERT_FALSE(rig->joints.empty());
  const std::vector<std::uint8_t> bytes = dataOf(*rig, VrmSpringFormat::kNone);
  std::shared_ptr<const Rig> back;
  VrmSpringFormat format = VrmSpringFormat::kVrm0;
  ASSERT_FALSE(readBack(bytes, back, format));
  EXPECT_EQ(format, VrmSpringFormat::kNone);
  EXPECT_EQ(dataOf(*back, format), bytes);
  EXPECT_EQ(back->collider_passes, rig->collider_passes);
  EXPECT_EQ(back->colliders.size(), rig->colliders.size());
}

TEST(RigData, BytesInAnotherLayoutAreRefusedWithoutReadingPastThem) {
  VrmSpringFormat format = VrmSpringFormat::kNone;
  const std::shared_ptr<const Rig> rig = vrmFixture("vrm10_springs.vrm", format);
  ASSERT_TRUE(rig);
  const std::vector<std::uint8_t> bytes = dataOf(*rig, format);
  std::shared_ptr<const Rig> back;
  VrmSpringFormat back_format = VrmSpringFormat::kNone;

  auto refused = [&](const std::vector<std::uint8_t>& changed) {
    const Error e = readBack(changed, back, back_format);
    return e.code == ErrorCode::kInvalidArgument && !back && back_format == VrmSpringFormat::kNone;
  };
  EXPECT_TRUE(refused({}));
  EXPECT_EQ(readRigData(TypedBytes{nullptr, 16}, back, back_format).code, ErrorCode::kInvalidArgument);
  // Every length short of the whole (sampled), and one byte more.
  for (std::size_t size = 0; size < bytes.size(); size += 1 + bytes.size() / 500) {
    EXPECT_TRUE(refused(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + size))) << size;
  }
  std::vector<std::uint8_t> longer = bytes;
  longer.push_back(0);
  EXPECT_TRUE(refused(longer));
  // Another version of the layout.
  std::vector<std::uint8_t> other = bytes;
  other[4] += 1;
  EXPECT_TRUE(refused(other));
  // A count no rest of the bytes can hold (the node count, after magic and version).
  std::vector<std::uint8_t> huge = bytes;
  test::writeU32(huge, 8, 0xffffffffu);
  EXPECT_TRUE(refused(huge));
  // An index past the list it points into: a joint of a node the skeleton does not have.
  Rig small;
  small.skeleton.nodes.resize(1);
  small.skeleton.parents_first = {0};
  small.joints.resize(1);
  small.joints[0].node = 0;
  small.chain_roots = {0};
  EXPECT_FALSE(readBack(dataOf(small, format), back, back_format));
  small.joints[0].node = 1;
  EXPECT_TRUE(refused(dataOf(small, format)));
}

}  // namespace
}  // namespace springbones
