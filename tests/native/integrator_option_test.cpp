// InstanceOptions::integrator: an Instance created with Integrator::kXpbd runs the XPBD solver
// under Instance's own frame rules (accumulator, substep cap, driver interpolation), with the
// same inputs and outputs as the default integrator.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "simulation/xpbd_solver.h"
#include "springbones/springbones.h"
#include "test_helpers.h"
#include "xpbd_runner.h"

namespace springbones {
namespace {

using nlohmann::json;

// Avatar_Hips holding a three-joint chain along +X, drooping under gravity.
std::shared_ptr<const Rig> chainRig() {
  const json nodes = json::array({
      {{"name", "Avatar_Hips"}, {"children", {1}}},
      {{"name", "springbone_a"}, {"children", {2}}},
      {{"name", "springbone_b"}, {"translation", {0.1, 0, 0}}, {"children", {3}}},
      {{"name", "springbone_c"}, {"translation", {0.1, 0, 0}}, {"children", {4}}},
      {{"name", "springbone_tip"}, {"translation", {0.1, 0, 0}}},
  });
  const json bones = {{"springbone_a", {{"isRoot", true}, {"stiffness", 0.5}, {"gravityPower", 1.5}, {"drag", 0.2}}}};
  return test::rigFromJson(nodes, bones);
}

glm::mat4 swayingHips(double t) {
  return glm::rotate(glm::translate(glm::mat4(1), glm::vec3(0.3f * float(std::sin(4 * t)), 0, 0)),
                     float(std::sin(3 * t)), glm::vec3(0, 0, 1));
}

InstanceOptions xpbdOptions() {
  InstanceOptions options;
  options.integrator = Integrator::kXpbd;
  options.step_hz = kXpbdDefaultStepHz;
  options.max_substeps = 8;
  return options;
}

TEST(IntegratorOption, XpbdInstanceMatchesTheSolverDrivenDirectly) {
  // Frames of exactly one substep: no interpolation, so the two owners feed the solver the same
  // matrices and must produce the same bits.
  const auto rig = chainRig();
  Instance instance(rig, xpbdOptions());
  test::XpbdRunner runner(rig);
  const double dt = 1.0 / kXpbdDefaultStepHz;
  for (int f = 0; f < 240; ++f) {
    const glm::mat4 hips = swayingHips(f * dt);
    std::memcpy(instance.driverMatrices(), &hips[0][0], sizeof(float) * 16);
    runner.drivers()[0] = hips;
    instance.step(dt);
    runner.step(dt);
    ASSERT_EQ(0, std::memcmp(instance.rotations(), runner.rotations(), sizeof(float) * 4 * rig->joints.size()))
        << "frame " << f;
  }
}

TEST(IntegratorOption, XpbdKeepsBoneLengthsWhereTheDefaultMovesDifferently) {
  const auto rig = chainRig();
  Instance xpbd(rig, xpbdOptions());
  Instance vrm(rig);
  const double dt = 1.0 / 30.0;
  double max_length_error = 0.0, max_difference = 0.0;
  for (int f = 0; f < 300; ++f) {
    const glm::mat4 hips = swayingHips(f * dt);
    std::memcpy(xpbd.driverMatrices(), &hips[0][0], sizeof(float) * 16);
    std::memcpy(vrm.driverMatrices(), &hips[0][0], sizeof(float) * 16);
    xpbd.step(dt);
    vrm.step(dt);
    const float* world = xpbd.worldMatrices();
    for (std::size_t j = 0; j + 1 < rig->joints.size(); ++j) {
      const glm::vec3 head(world[16 * j + 12], world[16 * j + 13], world[16 * j + 14]);
      const glm::vec3 next(world[16 * (j + 1) + 12], world[16 * (j + 1) + 13], world[16 * (j + 1) + 14]);
      max_length_error = std::max(max_length_error, std::fabs(double(glm::length(next - head)) - 0.1));
    }
    for (std::size_t i = 0; i < 4 * rig->joints.size(); ++i) {
      ASSERT_TRUE(std::isfinite(xpbd.rotations()[i]));
      max_difference = std::max(max_difference, double(std::fabs(xpbd.rotations()[i] - vrm.rotations()[i])));
    }
  }
  EXPECT_LT(max_length_error, 1e-5);
  // The option really switches the integrator: the two motions are not the same.
  EXPECT_GT(max_difference, 1e-3);
}

TEST(IntegratorOption, DefaultsArePerIntegrator) {
  // Options left at 0 take the integrator's defaults: 60 Hz / 4 substeps for the VRM update,
  // 120 Hz / 8 for XPBD, the same the JS API gets (it passes 0 for an option not given).
  InstanceOptions xpbd_defaults;
  xpbd_defaults.integrator = Integrator::kXpbd;
  Instance xpbd(chainRig(), xpbd_defaults);
  EXPECT_EQ(xpbd.options().step_hz, 120.0);
  EXPECT_EQ(xpbd.options().max_substeps, 8);
  EXPECT_EQ(xpbd.options().xpbd_iterations, 4);
  Instance vrm(chainRig());
  EXPECT_EQ(vrm.options().step_hz, 60.0);
  EXPECT_EQ(vrm.options().max_substeps, 4);
  // A value given is kept, the other still defaults.
  InstanceOptions given = xpbd_defaults;
  given.step_hz = 90.0;
  Instance mixed(chainRig(), given);
  EXPECT_EQ(mixed.options().step_hz, 90.0);
  EXPECT_EQ(mixed.options().max_substeps, 8);
  // The defaults move the joints as the same values given explicitly, bit for bit.
  Instance explicit_xpbd(chainRig(), xpbdOptions());
  for (int f = 0; f < 60; ++f) {
    const glm::mat4 hips = swayingHips(f / 30.0);
    std::memcpy(xpbd.driverMatrices(), &hips[0][0], sizeof(float) * 16);
    std::memcpy(explicit_xpbd.driverMatrices(), &hips[0][0], sizeof(float) * 16);
    xpbd.step(1.0 / 30.0);
    explicit_xpbd.step(1.0 / 30.0);
  }
  EXPECT_EQ(0, std::memcmp(xpbd.rotations(), explicit_xpbd.rotations(), sizeof(float) * 4 * xpbd.jointCount()));
}

TEST(IntegratorOption, OutOfRangeIterationsAreClamped) {
  InstanceOptions options = xpbdOptions();
  options.xpbd_iterations = 0;
  Instance low(chainRig(), options);
  EXPECT_EQ(low.options().xpbd_iterations, 1);
  options.xpbd_iterations = 1000000;
  Instance high(chainRig(), options);
  EXPECT_EQ(high.options().xpbd_iterations, 64);
}

}  // namespace
}  // namespace springbones
