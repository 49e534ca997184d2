// Settle, grab and inertia (Instance::settle, grab / release, setInertia): the springs brought to
// rest without frames, a chain held toward a point and let go, and how much of its driver's
// motion a chain feels; on the lane path, the general path and the XPBD integrator.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "springbones/springbones.h"
#include "springbones/vrm.h"
#include "test_helpers.h"

namespace springbones {
namespace {

using nlohmann::json;

// A three-joint chain hanging from Avatar_Hips, 0.1 m bones pointing back and down, with gravity
// and some stiffness (jump_test.cpp's). A non-uniform scale on the root bone sends the rig to the
// general path. With `second_chain`, a second, identical chain beside it.
std::shared_ptr<const Rig> hangingChain(bool general_path, bool second_chain = false, RigOptions options = {}) {
  const json scale = general_path ? json{1.0, 1.0, 1.02} : json{1.0, 1.0, 1.0};
  json nodes = {{{"name", "Avatar_Hips"}, {"children", second_chain ? json{1, 5} : json{1}}},
                {{"name", "springbone_a"}, {"translation", {0, 0.2, -0.1}}, {"scale", scale}, {"children", {2}}},
                {{"name", "springbone_b"}, {"translation", {0, -0.07, -0.07}}, {"children", {3}}},
                {{"name", "springbone_c"}, {"translation", {0, -0.07, -0.07}}, {"children", {4}}},
                {{"name", "springbone_tip"}, {"translation", {0, -0.07, -0.07}}}};
  json bones = {
      {"springbone_a",
       {{"isRoot", true}, {"stiffness", 1}, {"gravityPower", 0.5}, {"gravityDir", {0, -1, 0}}, {"drag", 0.3}}}};
  if (second_chain) {
    nodes.push_back({{"name", "springbone_2a"}, {"translation", {0.1, 0.2, -0.1}}, {"children", {6}}});
    nodes.push_back({{"name", "springbone_2b"}, {"translation", {0, -0.07, -0.07}}, {"children", {7}}});
    nodes.push_back({{"name", "springbone_2tip"}, {"translation", {0, -0.07, -0.07}}});
    bones["springbone_2a"] = bones["springbone_a"];
  }
  const std::string gltf = test::gltfWithNodes(nodes);
  Skeleton skeleton;
  EXPECT_FALSE(test::loadText(gltf, skeleton));
  ModelEntry model;
  std::vector<Warning> warnings;
  const json metadata = {{"version", 1}, {"models", {{"h", bones}}}};
  EXPECT_FALSE(parseSpringBonesText(metadata.dump(), "h", model, warnings));
  return buildRig(std::move(skeleton), model, std::move(warnings), options);
}

std::shared_ptr<const Rig> vrmFixture(const std::string& name) {
  const std::vector<std::uint8_t> bytes = test::readFixture(name);
  std::shared_ptr<const Rig> rig;
  EXPECT_FALSE(loadVrm(bytes.data(), bytes.size(), rig));
  return rig;
}

std::shared_ptr<const Rig> hairFixture() {
  const std::vector<std::uint8_t> bytes = test::readFixture("avatar_hair.glb");
  Skeleton skeleton;
  EXPECT_FALSE(test::loadBytes(bytes, skeleton));
  ModelEntry model;
  std::vector<Warning> warnings;
  EXPECT_FALSE(parseSpringBonesText(test::readFixtureText("avatar_hair.metadata.json"),
                                    test::metadataKeyOf("avatar_hair.glb"), model, warnings));
  return buildRig(std::move(skeleton), model, std::move(warnings));
}

InstanceOptions withIntegrator(Integrator integrator) {
  InstanceOptions options;
  options.integrator = integrator;
  return options;
}

float turnBetween(const float* a, const float* b) {
  const glm::quat qa(a[3], a[0], a[1], a[2]), qb(b[3], b[0], b[1], b[2]);
  const glm::quat d = glm::conjugate(qa) * qb;
  return 2.0f * std::atan2(glm::length(glm::vec3(d.x, d.y, d.z)), std::fabs(d.w));
}

float largestTurn(const std::vector<float>& before, const float* after, std::size_t joints) {
  float turn = 0.0f;
  for (std::size_t j = 0; j < joints; ++j) turn = std::max(turn, turnBetween(&before[4 * j], after + 4 * j));
  return turn;
}

std::vector<float> rotationsOf(const Instance& instance) {
  return std::vector<float>(instance.rotations(), instance.rotations() + 4 * instance.jointCount());
}

// Every driver set to `m` times its rest world matrix: the whole avatar moved by m.
void moveDrivers(Instance& instance, const glm::mat4& m) {
  const Rig& rig = instance.rig();
  for (std::size_t d = 0; d < rig.drivers.size(); ++d) {
    const int node = rig.drivers[d].node;
    glm::mat4 rest(1.0f);
    if (node >= 0) std::memcpy(&rest[0][0], rig.skeleton.nodes[node].rest_world.m, sizeof(float) * 16);
    const glm::mat4 moved = m * rest;
    std::memcpy(instance.driverMatrices() + 16 * d, &moved[0][0], sizeof(float) * 16);
  }
}

// A pose far from the rest pose: the avatar bent forward and turned, so every chain has to fall
// into a new balance.
glm::mat4 bentPose() {
  return glm::rotate(
      glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, 1.0f, -0.2f)), 0.9f, glm::vec3(1, 0, 0)), 0.6f,
      glm::vec3(0, 1, 0));
}

struct SettleCase {
  std::string name;
  std::shared_ptr<const Rig> rig;
};

std::vector<SettleCase> settleCases() {
  return {{"lane path chain", hangingChain(false)},
          {"general path chain", hangingChain(true)},
          {"avatar_hair.glb", hairFixture()},
          {"vrm0_springs.vrm", vrmFixture("vrm0_springs.vrm")},
          {"vrm10_springs.vrm", vrmFixture("vrm10_springs.vrm")},
          {"vrm10_extended_colliders.vrm", vrmFixture("vrm10_extended_colliders.vrm")}};
}

// ---------------------------------------------------------------------------------------------
// Settle

TEST(Settle, TheNextFrameTurnsNoJointByMoreThanAMilliradian) {
  float unsettled = 0.0f;  // the same frame without settling first: the test can fail
  for (const SettleCase& c : settleCases()) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      SCOPED_TRACE(c.name + (integrator == Integrator::kXpbd ? " xpbd" : " vrm"));
      ASSERT_GT(c.rig->joints.size(), 0u);
      Instance instance(c.rig, withIntegrator(integrator));
      moveDrivers(instance, bentPose());
      const int steps = instance.settle();
      EXPECT_GT(steps, 0);
      EXPECT_LE(steps, static_cast<int>(std::ceil(2.0 * instance.options().step_hz)));
      const std::vector<float> settled = rotationsOf(instance);
      instance.step(1.0 / 60.0);
      EXPECT_LE(largestTurn(settled, instance.rotations(), instance.jointCount()), 1e-3f);

      Instance fresh(c.rig, withIntegrator(integrator));
      moveDrivers(fresh, bentPose());
      fresh.step(1.0 / 60.0);
      const std::vector<float> first = rotationsOf(fresh);
      fresh.step(1.0 / 60.0);
      unsettled = std::max(unsettled, largestTurn(first, fresh.rotations(), fresh.jointCount()));
    }
  }
  EXPECT_GT(unsettled, 1e-2f);
}

TEST(Settle, FindsTheBalanceALongSimulationReaches) {
  for (const SettleCase& c : settleCases()) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      SCOPED_TRACE(c.name + (integrator == Integrator::kXpbd ? " xpbd" : " vrm"));
      Instance settled(c.rig, withIntegrator(integrator)), simulated(c.rig, withIntegrator(integrator));
      moveDrivers(settled, bentPose());
      moveDrivers(simulated, bentPose());
      settled.settle();
      for (int frame = 0; frame < 60 * 30; ++frame) simulated.step(1.0 / 60.0);
      // The swinging run ends at the same balance the settling found (both from rest).
      EXPECT_LE(largestTurn(rotationsOf(settled), simulated.rotations(), settled.jointCount()), 2e-3f);
    }
  }
}

TEST(Settle, IsDeterministicWhateverCameBefore) {
  for (bool general : {false, true}) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      const auto rig = hangingChain(general);
      Instance walked(rig, withIntegrator(integrator)), fresh(rig, withIntegrator(integrator));
      for (int frame = 0; frame < 90; ++frame) {
        moveDrivers(walked, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 0.02f * frame)));
        walked.step(1.0 / 60.0);
      }
      moveDrivers(walked, bentPose());
      moveDrivers(fresh, bentPose());
      const int a = walked.settle(), b = fresh.settle();
      EXPECT_EQ(a, b);
      EXPECT_EQ(rotationsOf(walked), rotationsOf(fresh));
    }
  }
}

TEST(Settle, ClampsItsTime) {
  const auto rig = hangingChain(false);
  Instance instance(rig);
  moveDrivers(instance, bentPose());
  EXPECT_EQ(instance.settle(0.0), 0);
  // No steps: the rest pose under the drivers.
  for (std::size_t j = 0; j < instance.jointCount(); ++j) {
    const float* r = instance.rotations() + 4 * j;
    EXPECT_TRUE(test::quatNear(glm::quat(r[3], r[0], r[1], r[2]), toGlm(rig->joints[j].rest_local.rotation)));
  }
  EXPECT_EQ(instance.settle(std::nan("")), 0);
  EXPECT_EQ(instance.settle(-1.0), 0);
  EXPECT_EQ(instance.settle(1.0 / 60.0), 1);
  // Beyond the most: the most, which this chain does not need (its balance is found at once).
  const int steps = instance.settle(1e12);
  const std::vector<float> long_settled = rotationsOf(instance);
  EXPECT_EQ(steps, instance.settle(kMaxSettleSeconds));
  EXPECT_EQ(long_settled, rotationsOf(instance));
  EXPECT_GE(steps, 1);
  Instance empty(std::make_shared<const Rig>());
  EXPECT_EQ(empty.settle(), 0);
}

// ---------------------------------------------------------------------------------------------
// Grab

glm::vec3 tailWorld(Instance& instance, std::size_t joint) {
  glm::mat4 m;
  std::memcpy(&m[0][0], instance.worldMatrices() + 16 * joint, sizeof(float) * 16);
  return glm::vec3(m * glm::vec4(toGlm(instance.rig().joints[joint].tail_local), 1.0f));
}

glm::vec3 headWorld(Instance& instance, std::size_t joint) {
  return glm::vec3(instance.worldMatrices()[16 * joint + 12], instance.worldMatrices()[16 * joint + 13],
                   instance.worldMatrices()[16 * joint + 14]);
}

// Grabs the chain's last joint at `point` for 2 s of frames.
void holdFor(Instance& instance, const glm::vec3& point, int frames = 120) {
  for (int frame = 0; frame < frames; ++frame) {
    instance.grab(2, fromGlm(point));
    instance.step(1.0 / 60.0);
  }
}

TEST(Grab, TheTailReachesAPointWithinReachAndKeepsItsBoneLengths) {
  for (bool general : {false, true}) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      SCOPED_TRACE(std::string(general ? "general" : "lanes") + (integrator == Integrator::kXpbd ? " xpbd" : " vrm"));
      const auto rig = hangingChain(general);
      Instance instance(rig, withIntegrator(integrator));
      instance.settle();
      const glm::vec3 root = headWorld(instance, 0);
      std::vector<float> lengths;
      for (std::size_t j = 0; j < 3; ++j)
        lengths.push_back(glm::distance(headWorld(instance, j), tailWorld(instance, j)));
      // 0.2 m to the side and up of the root: inside the reach of 0.3 m, far from the rest pose.
      const glm::vec3 point = root + glm::vec3(0.15f, 0.1f, 0.05f);
      holdFor(instance, point);
      EXPECT_EQ(instance.grabbedJoint(), 2);
      EXPECT_LT(glm::distance(tailWorld(instance, 2), point), 2e-3f);
      // Bone lengths, where the rig's scales are uniform (under the general rig's non-uniform root
      // scale a child's world length changes with its turn by design, grabbed or not).
      for (std::size_t j = 0; !general && j < 3; ++j) {
        EXPECT_NEAR(glm::distance(headWorld(instance, j), tailWorld(instance, j)), lengths[j], 1e-4f);
      }
      EXPECT_LT(glm::distance(headWorld(instance, 1), tailWorld(instance, 0)), 1e-4f);

      // Beyond the reach: stretched straight toward it, the reach short of it.
      const glm::vec3 far = root + glm::vec3(1.0f, 0.5f, 0.0f);
      holdFor(instance, far);
      const float reach = lengths[0] + lengths[1] + lengths[2];
      EXPECT_NEAR(glm::distance(tailWorld(instance, 2), far), glm::distance(root, far) - reach, 2e-3f);
    }
  }
}

TEST(Grab, CollidersStillHold) {
  for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
    SCOPED_TRACE(integrator == Integrator::kXpbd ? "xpbd" : "vrm");
    RigOptions options;
    options.hit_radius = 0.01f;
    // A 5 cm ball 0.25 m in front of and level with the chain root (hips at the origin).
    options.colliders.push_back(test::sphereSpec("Avatar_Hips", Vec3{0.0f, 0.2f, 0.15f}, 0.05f));
    const auto rig = hangingChain(false, false, options);
    Instance instance(rig, withIntegrator(integrator));
    instance.settle();
    const glm::vec3 ball(0.0f, 0.2f, 0.15f);
    float closest = 1.0f;
    // Dragged into the ball, 1 cm from its centre.
    for (int frame = 0; frame < 120; ++frame) {
      instance.grab(2, fromGlm(ball + glm::vec3(0.01f, 0.0f, 0.0f)));
      instance.step(1.0 / 60.0);
      for (std::size_t j = 0; j < 3; ++j) closest = std::min(closest, glm::distance(tailWorld(instance, j), ball));
    }
    EXPECT_GE(closest, 0.06f - 1e-4f);
    // It was pulled to the ball: the tail rests against it.
    EXPECT_LT(glm::distance(tailWorld(instance, 2), ball), 0.07f);
  }
}

TEST(Grab, ReleaseSwingsBackWithoutAJolt) {
  for (bool general : {false, true}) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      SCOPED_TRACE(std::string(general ? "general" : "lanes") + (integrator == Integrator::kXpbd ? " xpbd" : " vrm"));
      const auto rig = hangingChain(general);
      Instance instance(rig, withIntegrator(integrator));
      instance.settle();
      const std::vector<float> rest = rotationsOf(instance);
      const glm::vec3 root = headWorld(instance, 0);
      // Dragged round a circle below the root, then let go mid-motion.
      glm::vec3 last = tailWorld(instance, 2), held_velocity(0.0f);
      for (int frame = 0; frame < 120; ++frame) {
        const float a = 0.04f * frame;
        instance.grab(2, fromGlm(root + glm::vec3(0.12f * std::cos(a), -0.2f, 0.12f * std::sin(a))));
        instance.step(1.0 / 60.0);
        held_velocity = tailWorld(instance, 2) - last;
        last = tailWorld(instance, 2);
      }
      const float away = largestTurn(rest, instance.rotations(), 3);
      instance.release();
      EXPECT_EQ(instance.grabbedJoint(), -1);
      std::vector<float> before = rotationsOf(instance);
      instance.step(1.0 / 60.0);
      const glm::vec3 released_velocity = tailWorld(instance, 2) - last;
      // No kick: the tail's velocity changes by at most what the update adds in a frame to it and
      // to the two joints it hangs from, the stiffness and gravity pulls (world units per second,
      // times the frame); drag only slows it. (A tail restarting from a stale state jumps by
      // about a bone length, 10 cm.)
      const BoneParams& p = rig->joints[2].params;
      EXPECT_GT(glm::length(held_velocity), 3e-3f);
      EXPECT_LT(glm::distance(released_velocity, held_velocity), 3.0f * (p.stiffness + p.gravity_power) / 60.0f);
      // And the swing back speeds up from there rather than starting at its fastest.
      const float first = largestTurn(before, instance.rotations(), 3);
      float later = 0.0f;
      for (int frame = 0; frame < 10; ++frame) {
        before = rotationsOf(instance);
        instance.step(1.0 / 60.0);
        later = std::max(later, largestTurn(before, instance.rotations(), 3));
      }
      EXPECT_LE(first, later);
      for (int frame = 0; frame < 600; ++frame) instance.step(1.0 / 60.0);
      // And back to rest.
      EXPECT_GT(away, 0.2f);
      EXPECT_LT(largestTurn(rest, instance.rotations(), 3), 0.1f * away);
    }
  }
}

TEST(Grab, AnyIndexOrPointIsSafe) {
  const auto rig = hangingChain(false);
  Instance instance(rig);
  instance.grab(3, Vec3{0, 0, 0});  // the rig has joints 0..2
  instance.grab(static_cast<std::size_t>(-1), Vec3{0, 0, 0});
  EXPECT_EQ(instance.grabbedJoint(), -1);
  instance.grab(1, Vec3{std::nanf(""), 0, 0});
  instance.grab(1, Vec3{INFINITY, 0, 0});
  EXPECT_EQ(instance.grabbedJoint(), -1);
  instance.grab(1, Vec3{1e30f, 1e30f, 1e30f});
  EXPECT_EQ(instance.grabbedJoint(), 1);
  for (int frame = 0; frame < 10; ++frame) instance.step(1.0 / 60.0);
  for (std::size_t k = 0; k < 12; ++k) EXPECT_TRUE(std::isfinite(instance.rotations()[k]));
  instance.release();
  instance.release();
  Instance empty(std::make_shared<const Rig>());
  empty.grab(0, Vec3{});
  EXPECT_EQ(empty.grabbedJoint(), -1);
}

// ---------------------------------------------------------------------------------------------
// Inertia

// The hips as an avatar in a vehicle: a pure translation that speeds up, brakes and sways, at time t.
glm::mat4 vehicle(double t) {
  const float x = static_cast<float>(0.3 * std::sin(3.0 * t));
  const float z = static_cast<float>(2.0 * t * t);
  return glm::translate(glm::mat4(1.0f), glm::vec3(x, 0.1f * std::sin(5.0 * t), z));
}

// The largest per-frame turn of any joint (or of chain `only`'s, by its root joint) over 2 s of `motion`.
template <typename Motion>
float ride(Instance& instance, const Motion& motion, int only_root = -1) {
  moveDrivers(instance, motion(0.0));
  instance.settle();
  std::vector<float> last = rotationsOf(instance);
  float turn = 0.0f;
  for (int frame = 1; frame <= 120; ++frame) {
    moveDrivers(instance, motion(frame / 60.0));
    instance.step(1.0 / 60.0);
    for (std::size_t j = 0; j < instance.jointCount(); ++j) {
      if (only_root >= 0 && instance.rig().joints[j].chain != only_root) continue;
      turn = std::max(turn, turnBetween(&last[4 * j], instance.rotations() + 4 * j));
    }
    last = rotationsOf(instance);
  }
  return turn;
}

TEST(Inertia, OneIsTheUpdateAsItWasBitForBit) {
  for (const SettleCase& c : settleCases()) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      SCOPED_TRACE(c.name);
      InstanceOptions options = withIntegrator(integrator);
      Instance plain(c.rig, options);
      options.inertia = 1.0f;
      Instance one(c.rig, options);
      Instance set_back(c.rig, options);
      set_back.setInertia(0.25f);
      set_back.setInertia(1.0f);
      for (int frame = 1; frame <= 240; ++frame) {
        const glm::mat4 m = glm::rotate(vehicle(frame / 60.0), 0.3f * std::sin(frame / 20.0f), glm::vec3(0, 1, 0));
        for (Instance* i : {&plain, &one, &set_back}) {
          moveDrivers(*i, m);
          i->step(1.0 / 60.0);
        }
        ASSERT_EQ(rotationsOf(plain), rotationsOf(one)) << "frame " << frame;
        ASSERT_EQ(rotationsOf(plain), rotationsOf(set_back)) << "frame " << frame;
      }
    }
  }
}

TEST(Inertia, ZeroKeepsAChainAtRestUnderAPureTranslation) {
  for (bool general : {false, true}) {
    for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
      SCOPED_TRACE(std::string(general ? "general" : "lanes") + (integrator == Integrator::kXpbd ? " xpbd" : " vrm"));
      const auto rig = hangingChain(general);
      InstanceOptions options = withIntegrator(integrator);
      Instance full(rig, options);
      options.inertia = 0.5f;
      Instance half(rig, options);
      options.inertia = 0.0f;
      Instance none(rig, options);
      const float moved = ride(full, vehicle), halfway = ride(half, vehicle), still = ride(none, vehicle);
      EXPECT_GT(moved, 1e-2f);
      EXPECT_LT(halfway, moved);
      EXPECT_GT(halfway, still);
      EXPECT_LT(still, 1e-4f);
    }
  }
}

TEST(Inertia, ZeroKeepsAChainAtRestWhenTheAvatarTurns) {
  const auto turning = [](double t) {
    return glm::rotate(vehicle(t), static_cast<float>(1.5 * std::sin(2.0 * t)), glm::vec3(0, 1, 0));
  };
  for (Integrator integrator : {Integrator::kVrm, Integrator::kXpbd}) {
    const auto rig = hangingChain(false);
    InstanceOptions options = withIntegrator(integrator);
    Instance full(rig, options);
    options.inertia = 0.0f;
    Instance none(rig, options);
    EXPECT_GT(ride(full, turning), 1e-2f);
    EXPECT_LT(ride(none, turning), 1e-4f);
  }
}

TEST(Inertia, IsSetPerChainAndClamped) {
  const auto rig = hangingChain(false, true);
  ASSERT_EQ(rig->chain_roots.size(), 2u);
  Instance instance(rig);
  instance.setInertia(0.0f, 0);
  EXPECT_EQ(instance.inertia(0), 0.0f);
  EXPECT_EQ(instance.inertia(1), 1.0f);
  const int first = rig->chain_roots[0], second = rig->chain_roots[1];
  Instance other(rig);
  other.setInertia(0.0f, 0);
  EXPECT_LT(ride(instance, vehicle, first), 1e-4f);
  EXPECT_GT(ride(other, vehicle, second), 1e-2f);

  instance.setInertia(2.0f, 1);
  EXPECT_EQ(instance.inertia(1), 1.0f);
  instance.setInertia(-1.0f, 1);
  EXPECT_EQ(instance.inertia(1), 0.0f);
  instance.setInertia(std::nanf(""), 1);
  EXPECT_EQ(instance.inertia(1), 1.0f);
  instance.setInertia(0.5f, 2);  // no chain 2: nothing
  EXPECT_EQ(instance.inertia(0), 0.0f);
  EXPECT_EQ(instance.inertia(1), 1.0f);
  EXPECT_EQ(instance.inertia(7), kDefaultInertia);
  instance.setInertia(0.25f);
  EXPECT_EQ(instance.inertia(0), 0.25f);
  EXPECT_EQ(instance.inertia(1), 0.25f);
  EXPECT_EQ(instance.options().inertia, 0.25f);
  InstanceOptions options;
  options.inertia = 7.0f;
  EXPECT_EQ(Instance(rig, options).options().inertia, 1.0f);
}

// An instance leaving the lane path for a frame (inertia a hair below 1) and coming back carries
// its motion across both changes: it keeps moving as one that stayed.
TEST(Inertia, ChangingPathKeepsTheMotion) {
  const auto rig = hangingChain(false);
  Instance stays(rig), moves(rig);
  float largest = 0.0f;
  for (int frame = 1; frame <= 240; ++frame) {
    if (frame == 60) moves.setInertia(0.99999f);
    if (frame == 120) moves.setInertia(1.0f);
    const glm::mat4 m = glm::rotate(vehicle(frame / 60.0), 0.3f * std::sin(frame / 20.0f), glm::vec3(0, 1, 0));
    moveDrivers(stays, m);
    moveDrivers(moves, m);
    stays.step(1.0 / 60.0);
    moves.step(1.0 / 60.0);
    largest = std::max(largest, largestTurn(rotationsOf(stays), moves.rotations(), 3));
  }
  EXPECT_LT(largest, 1e-3f);
}

}  // namespace
}  // namespace springbones
