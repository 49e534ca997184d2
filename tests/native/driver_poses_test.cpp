// DriverPoses: the per-frame similarity test and decomposition of driver matrices (vectorised,
// branch-free), the last good pose kept for a non-finite matrix, and jump detection folded into
// the same pass (the same answer as the rule driver by driver, driversJumped).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "simulation/driver_poses.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using namespace test;

std::vector<float> flatten(const std::vector<glm::mat4>& matrices) {
  std::vector<float> out;
  for (const glm::mat4& m : matrices) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) out.push_back(m[c][r]);
    }
  }
  return out;
}

glm::mat4 similarity(glm::vec3 position, float angle, glm::vec3 axis, float scale) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), position);
  m = glm::rotate(m, angle, glm::normalize(axis));
  return glm::scale(m, glm::vec3(scale));
}

TEST(DriverPoses, DecomposesSimilaritiesInEveryQuadrantOfTheQuaternion) {
  // Rotations near 0 and near 180 degrees about each axis pick each of the four largest
  // candidates; five drivers also leave a partly filled SIMD vector.
  const std::vector<glm::mat4> matrices = {
      similarity({1, 2, 3}, 0.3f, {0, 1, 0}, 1.0f), similarity({0, 0, 0}, 3.1f, {1, 0, 0}, 2.0f),
      similarity({-1, 0, 5}, 3.0f, {0, 1, 0.1f}, 0.5f), similarity({0, 1, 0}, 3.13f, {0.1f, 0, 1}, 0.01f),
      similarity({4, 4, 4}, 1.7f, {1, 1, 1}, 3.0f)};
  DriverPoses previous, poses;
  previous.resize(matrices.size());
  poses.resize(matrices.size());
  const std::vector<float> input = flatten(matrices);
  poses.read(input.data(), previous);
  ASSERT_TRUE(poses.allSimilar());
  for (std::size_t d = 0; d < matrices.size(); ++d) {
    const glm::mat4& m = matrices[d];
    const float scale = glm::length(glm::vec3(m[0]));
    const glm::quat expected = glm::quat_cast(glm::mat3(m) / scale);
    EXPECT_NEAR(poses.scale(d), scale, 1e-5f * scale) << d;
    EXPECT_TRUE(vecNear(poses.position(d), glm::vec3(m[3]), 1e-6f)) << d;
    // q and -q are the same rotation.
    const float agreement = std::fabs(glm::dot(poses.rotation(d), expected));
    EXPECT_NEAR(agreement, 1.0f, 1e-5f) << d;
    EXPECT_NEAR(glm::length(poses.rotation(d)), 1.0f, 1e-6f) << d;
  }
}

TEST(DriverPoses, ShearMirrorNonUniformScaleAndProjectionAreNoSimilarities) {
  glm::mat4 sheared = similarity({0, 0, 0}, 0.4f, {0, 0, 1}, 1.0f);
  sheared[1][0] += 0.01f;  // far above the 1e-4 tolerance
  glm::mat4 slightly = similarity({0, 0, 0}, 0.4f, {0, 0, 1}, 1.0f);
  slightly[1][0] += 1e-6f;  // float noise of a composed matrix: still a similarity
  glm::mat4 mirrored = glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1));
  glm::mat4 stretched = glm::scale(glm::mat4(1.0f), glm::vec3(1, 1.5f, 1));
  glm::mat4 projective(1.0f);
  projective[0][3] = 0.1f;
  const glm::mat4 zero(0.0f);
  const std::vector<glm::mat4> matrices = {sheared, slightly, mirrored, stretched, projective, zero};
  DriverPoses previous, poses;
  previous.resize(matrices.size());
  poses.resize(matrices.size());
  const std::vector<float> input = flatten(matrices);
  poses.read(input.data(), previous);
  EXPECT_FALSE(poses.allSimilar());
  const bool expected[] = {false, true, false, false, false, false};
  for (std::size_t d = 0; d < matrices.size(); ++d) {
    EXPECT_EQ(poses.similar(d), expected[d]) << d;
    // Whatever it is, what the lane path could read stays finite.
    EXPECT_TRUE(std::isfinite(poses.scale(d)) && std::isfinite(poses.rotation(d).w)) << d;
    // The general path gets the matrix as given.
    EXPECT_EQ(poses.matrix(d), matrices[d]) << d;
  }
}

TEST(DriverPoses, ANonFiniteMatrixKeepsThePreviousPoseOfThatDriverOnly) {
  const glm::mat4 first = similarity({1, 0, 0}, 0.5f, {0, 1, 0}, 1.0f);
  const glm::mat4 second = similarity({2, 0, 0}, 0.7f, {0, 1, 0}, 1.0f);
  DriverPoses poses[2];
  for (DriverPoses& p : poses) p.resize(3);
  const std::vector<float> good = flatten({first, first, first});
  poses[0].read(good.data(), poses[1]);
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    glm::mat4 broken = second;
    broken[2][1] = bad;
    const std::vector<float> next = flatten({second, broken, second});
    poses[1].read(next.data(), poses[0]);
    EXPECT_TRUE(poses[1].allSimilar());
    EXPECT_EQ(poses[1].matrix(0), second);
    EXPECT_EQ(poses[1].matrix(1), first) << "the last good matrix";
    EXPECT_EQ(poses[1].position(1), poses[0].position(1));
    EXPECT_EQ(poses[1].rotation(1), poses[0].rotation(1));
    EXPECT_EQ(poses[1].matrix(2), second);
  }
}


// A pose a little away from `m`: moved by up to `reach` and turned by up to `turn` radians.
glm::mat4 nudged(const glm::mat4& m, std::mt19937& random, float reach, float turn) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  const glm::vec3 axis(unit(random), unit(random), unit(random) + 2.0f);
  glm::mat4 out = glm::translate(glm::mat4(1.0f), reach * glm::vec3(unit(random), unit(random), unit(random))) * m;
  return out * glm::rotate(glm::mat4(1.0f), turn * unit(random), glm::normalize(axis));
}

TEST(DriverPoses, ReadTellsAJumpExactlyAsTheRuleDriverByDriver) {
  // Frames of nine drivers (two SIMD vectors and one more) whose moves straddle the thresholds,
  // with now and then a sheared, projective or non-finite matrix among them: the drivers the read
  // pass leaves to the general rule. Each frame's answer must be driversJumped's on the same
  // poses, for thresholds of distance alone, angle alone, both and neither, and several step
  // counts.
  std::mt19937 random(38);
  std::uniform_int_distribution<int> kind(0, 35);  // 0-2: a matrix the read pass leaves to the rule
  const std::size_t drivers = 9;
  std::vector<glm::mat4> matrices;
  for (std::size_t d = 0; d < drivers; ++d) {
    matrices.push_back(similarity({0.1f * d, 1, 0}, 0.2f * d, {0, 1, 0.3f}, 1.0f + 0.1f * d));
  }
  DriverPoses poses[2];
  for (DriverPoses& p : poses) p.resize(drivers);
  std::vector<float> input = flatten(matrices);
  poses[0].read(input.data(), poses[1]);
  const float thresholds[][2] = {{0.05f, 0.2f}, {0.05f, 0.0f}, {0.0f, 0.2f}, {0.0f, 0.0f}, {1e-4f, 1e-4f}};
  int jumps = 0, frames = 0, general = 0;
  for (int frame = 0; frame < 4000; ++frame) {
    std::vector<glm::mat4> given(drivers);
    for (std::size_t d = 0; d < drivers; ++d) {
      matrices[d] = nudged(matrices[d], random, 0.06f, 0.25f);
      given[d] = matrices[d];
      const int k = kind(random);
      if (k == 0) given[d][1][0] += 0.05f;  // sheared
      if (k == 1) given[d][2][3] = 0.01f;   // projective
      if (k == 2) given[d][3][1] = std::numeric_limits<float>::quiet_NaN();
      if (k <= 2) ++general;
    }
    input = flatten(given);
    const auto& thresholds_now = thresholds[frame % 5];
    const int steps = 1 + frame % 3;
    const JumpLimits limits = jumpLimits(steps, thresholds_now[0], thresholds_now[1]);
    DriverPoses& now = poses[(frame + 1) % 2];
    const DriverPoses& before = poses[frame % 2];
    const bool folded = now.read(input.data(), before, limits);
    EXPECT_EQ(folded, driversJumped(before, now, limits)) << "frame " << frame;
    jumps += folded;
    ++frames;
  }
  // Both answers came up often enough for the comparison to mean something.
  EXPECT_GT(jumps, frames / 10);
  EXPECT_LT(jumps, frames - frames / 10);
  EXPECT_GT(general, 1000);
}

TEST(DriverPoses, ReadWithoutLimitsTellsNoJump) {
  DriverPoses poses[2];
  for (DriverPoses& p : poses) p.resize(2);
  const std::vector<float> here =
      flatten({similarity({0, 0, 0}, 0, {0, 1, 0}, 1), similarity({0, 0, 0}, 0, {0, 1, 0}, 1)});
  const std::vector<float> far =
      flatten({similarity({9, 0, 0}, 3, {0, 1, 0}, 1), similarity({0, 9, 0}, 2, {1, 0, 0}, 1)});
  poses[0].read(here.data(), poses[1]);
  EXPECT_FALSE(poses[1].read(far.data(), poses[0]));
  EXPECT_TRUE(poses[0].read(here.data(), poses[1], jumpLimits(1, 1.0f, 0.0f)));
}

}  // namespace
}  // namespace springbones
