// DriverPoses: the per-frame similarity test and decomposition of driver matrices (vectorised,
// branch-free), and the last good pose kept for a non-finite matrix.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

}  // namespace
}  // namespace springbones
