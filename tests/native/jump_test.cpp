// Jumps: a teleport or a snap turn of the drivers is carried across (no whip), on the lane path,
// the general path and the XPBD integrator; detection thresholds, jump() and the count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "springbones/springbones.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using nlohmann::json;

// A three-joint chain hanging from Avatar_Hips, 0.1 m bones pointing back and down, with gravity
// and some stiffness. A non-uniform scale on the root bone sends the rig to the general path.
std::shared_ptr<const Rig> hangingChain(bool general_path) {
  const json scale = general_path ? json{1.0, 1.0, 1.02} : json{1.0, 1.0, 1.0};
  json nodes = {{{"name", "Avatar_Hips"}, {"children", {1}}},
                {{"name", "springbone_a"}, {"translation", {0, 0.2, -0.1}}, {"scale", scale}, {"children", {2}}},
                {{"name", "springbone_b"}, {"translation", {0, -0.07, -0.07}}, {"children", {3}}},
                {{"name", "springbone_c"}, {"translation", {0, -0.07, -0.07}}, {"children", {4}}},
                {{"name", "springbone_tip"}, {"translation", {0, -0.07, -0.07}}}};
  return test::rigFromJson(
      nodes,
      {{"springbone_a",
        {{"isRoot", true}, {"stiffness", 1}, {"gravityPower", 0.5}, {"gravityDir", {0, -1, 0}}, {"drag", 0.3}}}});
}

// The hips of a walk: forward at 1.4 m/s with a bob, a sway and a yaw swing, at time t.
glm::mat4 walkingHips(double t) {
  const float x = static_cast<float>(0.04 * std::sin(2 * M_PI * t));
  const float y = static_cast<float>(1.0 + 0.03 * std::sin(4 * M_PI * t));
  const float z = static_cast<float>(1.4 * t);
  const float yaw = static_cast<float>(0.15 * std::sin(2 * M_PI * t));
  return glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(x, y, z)), yaw, glm::vec3(0, 1, 0));
}

float turnBetween(const float* a, const float* b) {
  const float dot = std::abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
  return 2.0f * std::acos(std::min(1.0f, dot));
}

struct Motion {
  float walking = 0;  // largest per-frame turn of any joint while walking
  float after = 0;    // largest per-frame turn of any joint in the second after the jump
  int jumps = 0;
};

// Walks for 6 s (the first second settles from rest), then `jump` (applied to the hips from then on) and one more
// second of walking.
Motion walkAndJump(const std::shared_ptr<const Rig>& rig, InstanceOptions options, const glm::mat4& jump) {
  Instance instance(rig, options);
  const double dt = 1.0 / 60.0;
  std::vector<float> last(instance.rotations(), instance.rotations() + 4 * instance.jointCount());
  Motion run;
  for (int frame = 0; frame < 420; ++frame) {
    const double t = frame * dt;
    const glm::mat4 hips = frame >= 360 ? jump * walkingHips(t) : walkingHips(t);
    std::memcpy(instance.driverMatrices(), &hips[0][0], sizeof(float) * 16);
    instance.step(dt);
    for (std::size_t j = 0; j < instance.jointCount(); ++j) {
      const float turn = turnBetween(&last[4 * j], instance.rotations() + 4 * j);
      EXPECT_TRUE(std::isfinite(turn));
      if (frame >= 60 && frame < 360) run.walking = std::max(run.walking, turn);  // settled first
      if (frame >= 360) run.after = std::max(run.after, turn);
    }
    std::copy(instance.rotations(), instance.rotations() + last.size(), last.begin());
  }
  run.jumps = instance.jumps();
  return run;
}

InstanceOptions withIntegrator(Integrator integrator) {
  InstanceOptions options;
  options.integrator = integrator;
  return options;
}

const glm::mat4 kTeleport = glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0));
const glm::mat4 kSnapTurn = glm::rotate(glm::mat4(1.0f), static_cast<float>(M_PI), glm::vec3(0, 1, 0));

struct Case {
  const char* name;
  bool general_path;
  Integrator integrator;
};

class JumpTest : public ::testing::TestWithParam<Case> {};

TEST_P(JumpTest, TeleportAndSnapTurnMoveNoJointFasterThanWalking) {
  const Case& c = GetParam();
  const auto rig = hangingChain(c.general_path);
  ASSERT_EQ(rig->joints.size(), 3u);
  for (const glm::mat4& jump : {kTeleport, kSnapTurn}) {
    const Motion run = walkAndJump(rig, withIntegrator(c.integrator), jump);
    EXPECT_GT(run.walking, 0.001f) << "the walk moves the chain";
    EXPECT_LE(run.after, run.walking) << c.name;
    EXPECT_EQ(run.jumps, 1) << c.name;
  }
}

TEST_P(JumpTest, WithDetectionOffTheSameJumpWhips) {
  // What the test above guards against: the same teleport read as velocity.
  const Case& c = GetParam();
  InstanceOptions options = withIntegrator(c.integrator);
  options.jump_distance = 0;
  options.jump_angle = 0;
  for (const glm::mat4& jump : {kTeleport, kSnapTurn}) {
    const Motion run = walkAndJump(hangingChain(c.general_path), options, jump);
    EXPECT_GT(run.after, 2 * run.walking) << c.name;
    EXPECT_EQ(run.jumps, 0);
  }
}

TEST_P(JumpTest, ExplicitJumpCarriesAChangeBelowTheThresholds) {
  // An animation starting moves the hips 0.3 m in one frame: under the threshold, but jump()
  // says it is a discontinuity.
  const Case& c = GetParam();
  const auto rig = hangingChain(c.general_path);
  const glm::mat4 cut = glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, 0, 0));
  for (bool announced : {false, true}) {
    Instance instance(rig, withIntegrator(c.integrator));
    const glm::mat4 still = walkingHips(0);
    float largest = 0;
    for (int frame = 0; frame < 120; ++frame) {
      const glm::mat4 hips = frame >= 60 ? cut * still : still;
      std::memcpy(instance.driverMatrices(), &hips[0][0], sizeof(float) * 16);
      if (frame == 60 && announced) instance.jump();
      std::vector<float> before(instance.rotations(), instance.rotations() + 12);
      instance.step(1.0 / 60.0);
      if (frame >= 60) {
        for (int j = 0; j < 3; ++j)
          largest = std::max(largest, turnBetween(&before[4 * j], instance.rotations() + 4 * j));
      }
    }
    EXPECT_EQ(instance.jumps(), announced ? 1 : 0);
    if (announced) {
      EXPECT_LT(largest, 1e-3f) << c.name << ": carried, a chain at rest stays at rest";
    } else {
      EXPECT_GT(largest, 0.05f) << c.name << ": read as velocity, the chain swings";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Paths, JumpTest,
                         ::testing::Values(Case{"lanes", false, Integrator::kVrm},
                                           Case{"general", true, Integrator::kVrm},
                                           Case{"xpbd", false, Integrator::kXpbd}),
                         [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST(JumpThresholds, BadValuesTurnDetectionOffAndResetForgetsARequest) {
  const auto rig = hangingChain(false);
  InstanceOptions options;
  options.jump_distance = NAN;
  options.jump_angle = -1;
  Instance instance(rig, options);
  EXPECT_EQ(instance.options().jump_distance, 0.0f);
  EXPECT_EQ(instance.options().jump_angle, 0.0f);
  instance.setJumpThresholds(INFINITY, 0.25f);
  EXPECT_EQ(instance.options().jump_distance, 0.0f);
  EXPECT_EQ(instance.options().jump_angle, 0.25f);
  EXPECT_EQ(Instance(rig).options().jump_distance, kDefaultJumpDistance);
  instance.step(1.0 / 60.0);
  instance.jump();
  instance.reset();
  instance.step(1.0 / 60.0);
  EXPECT_EQ(instance.jumps(), 0) << "reset() re-seeds; the request does not survive it";
}

TEST(JumpThresholds, AreStatedPerStep) {
  // 0.4 m in one frame of one step is under 0.5 m per step; 0.8 m is over; 0.8 m in a frame of
  // two steps is 0.4 m per step again.
  const auto rig = hangingChain(false);
  for (const auto& [moved, dt, expected] :
       {std::tuple{0.4f, 1.0 / 60.0, 0}, std::tuple{0.8f, 1.0 / 60.0, 1}, std::tuple{0.8f, 2.0 / 60.0, 0}}) {
    Instance instance(rig);
    instance.step(1.0 / 60.0);
    const glm::mat4 hips = glm::translate(glm::mat4(1.0f), glm::vec3(moved, 0, 0));
    std::memcpy(instance.driverMatrices(), &hips[0][0], sizeof(float) * 16);
    instance.step(dt);
    EXPECT_EQ(instance.jumps(), expected) << moved << " m in " << dt << " s";
  }
}

}  // namespace
}  // namespace springbones
