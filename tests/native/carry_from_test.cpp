// Instance::carryFrom: an instance of a rig rebuilt from the same skeleton (an edit of the
// parameters or chains, as the Builder's live tuning makes) takes over the previous instance's
// motion. Checked on the lane path, the general path and XPBD: an unchanged rebuild continues
// exactly as the old instance would have; an edited one changes no rotation at the edit by more
// than an ordinary frame does; joints new to the rig start at rest; nothing is carried from an
// instance that never stepped.
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

// Two chains under Avatar_Head: a three-joint tail and a one-joint lock. A non-uniform scale on
// the first bone sends the rig to the general path.
json skeletonNodes(bool general_path) {
  const json scale = general_path ? json{1.0, 1.0, 1.02} : json{1.0, 1.0, 1.0};
  return {{{"name", "Avatar_Head"}, {"children", {1, 5}}},
          {{"name", "springbone_a"}, {"translation", {0, 0.2, -0.1}}, {"scale", scale}, {"children", {2}}},
          {{"name", "springbone_b"}, {"translation", {0, -0.07, -0.07}}, {"children", {3}}},
          {{"name", "springbone_c"}, {"translation", {0, -0.07, -0.07}}, {"children", {4}}},
          {{"name", "springbone_tip"}, {"translation", {0, -0.07, -0.07}}},
          {{"name", "springbone_lock"}, {"translation", {0.1, 0.1, 0}}, {"children", {6}}},
          {{"name", "springbone_lock_tip"}, {"translation", {0, -0.1, 0}}}};
}

json tailEntry(double stiffness) {
  return {{"isRoot", true}, {"stiffness", stiffness}, {"gravityPower", 0.5}, {"gravityDir", {0, -1, 0}}, {"drag", 0.3}};
}

// The head of a nodding, turning avatar at time t.
glm::mat4 head(double t) {
  const float x = static_cast<float>(0.15 * std::sin(3 * t));
  const float yaw = static_cast<float>(0.6 * std::sin(2.1 * t));
  return glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(x, 1.6f, 0.0f)), yaw, glm::vec3(0, 1, 0));
}

constexpr double kDt = 1.0 / 60.0;

void drive(Instance& instance, int frame) {
  const glm::mat4 m = head(frame * kDt);
  std::memcpy(instance.driverMatrices(), &m[0][0], sizeof(float) * 16);
}

float turnBetween(const float* a, const float* b) {
  const float dot = std::abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
  return 2.0f * std::acos(std::min(1.0f, dot));
}

// The rotation of the joint on node `node`, or rest when the rig has no joint there.
std::vector<float> rotationOfNode(const Instance& instance, int node) {
  const auto& joints = instance.rig().joints;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (joints[j].node == node) return {instance.rotations() + 4 * j, instance.rotations() + 4 * j + 4};
  }
  const Quat q = instance.rig().skeleton.nodes[node].rest_local.rotation;
  return {q.x, q.y, q.z, q.w};
}

struct Case {
  const char* name;
  bool general_path;
  Integrator integrator;
};

class CarryFrom : public testing::TestWithParam<Case> {
 protected:
  InstanceOptions options() const {
    InstanceOptions o;
    o.integrator = GetParam().integrator;
    return o;
  }
  std::shared_ptr<const Rig> rig(const json& bones) const {
    return test::rigFromJson(skeletonNodes(GetParam().general_path), bones);
  }
};

TEST_P(CarryFrom, AnUnchangedRebuildContinuesAsTheOldInstanceWould) {
  const json bones = {{"springbone_a", tailEntry(1.0)}, {"springbone_lock", tailEntry(2.0)}};
  Instance old(rig(bones), options());
  for (int f = 0; f < 90; ++f) {
    drive(old, f);
    old.step(kDt);
  }
  Instance rebuilt(rig(bones), options());
  drive(rebuilt, 89);  // the pose old last stepped under
  rebuilt.carryFrom(old);
  for (std::size_t i = 0; i < 4 * old.jointCount(); ++i) EXPECT_EQ(rebuilt.rotations()[i], old.rotations()[i]);
  for (int f = 90; f < 150; ++f) {
    drive(old, f);
    old.step(kDt);
    drive(rebuilt, f);
    rebuilt.step(kDt);
    for (std::size_t i = 0; i < 4 * old.jointCount(); ++i) {
      ASSERT_NEAR(rebuilt.rotations()[i], old.rotations()[i], 1e-6f) << "frame " << f << ", float " << i;
    }
  }
}

TEST_P(CarryFrom, AnEditLeavesUntouchedChainsAsTheyWereAndDoesNotRestartTheEditedOne) {
  Instance old(rig({{"springbone_a", tailEntry(1.0)}, {"springbone_lock", tailEntry(2.0)}}), options());
  for (int f = 0; f < 90; ++f) {
    drive(old, f);
    old.step(kDt);
  }
  const int nodes = static_cast<int>(old.rig().skeleton.nodes.size());
  std::vector<std::vector<float>> last(nodes);
  float displaced = 0.0f;
  for (int n = 0; n < nodes; ++n) {
    last[n] = rotationOfNode(old, n);
    const Quat rest = old.rig().skeleton.nodes[n].rest_local.rotation;
    const float r[4] = {rest.x, rest.y, rest.z, rest.w};
    displaced = std::max(displaced, turnBetween(last[n].data(), r));
  }
  ASSERT_GT(displaced, 0.1f) << "the chains swing away from rest (a restart would pop by that much)";
  Instance edited(rig({{"springbone_a", tailEntry(1.3)}, {"springbone_lock", tailEntry(2.0)}}), options());
  drive(edited, 89);
  edited.carryFrom(old);
  for (int f = 90; f < 120; ++f) {
    drive(old, f);
    old.step(kDt);
    drive(edited, f);
    edited.step(kDt);
    const int lock = test::nodeIndex(old.rig().skeleton, "springbone_lock");
    const std::vector<float> a = rotationOfNode(old, lock), b = rotationOfNode(edited, lock);
    for (int i = 0; i < 4; ++i) ASSERT_NEAR(a[i], b[i], 1e-6f) << "the untouched chain, frame " << f;
    if (f == 90) {
      for (int n = 0; n < nodes; ++n) {
        EXPECT_LT(turnBetween(last[n].data(), rotationOfNode(edited, n).data()), displaced / 10) << "node " << n;
      }
    }
  }
}

TEST_P(CarryFrom, JointsNewToTheRigStartAtRestUnderTheCurrentDrivers) {
  Instance old(rig({{"springbone_a", tailEntry(1.0)}}), options());
  for (int f = 0; f < 60; ++f) {
    drive(old, f);
    old.step(kDt);
  }
  Instance added(rig({{"springbone_a", tailEntry(1.0)}, {"springbone_lock", tailEntry(2.0)}}), options());
  drive(added, 59);
  added.carryFrom(old);
  const int lock = test::nodeIndex(added.rig().skeleton, "springbone_lock");
  const Quat rest = added.rig().skeleton.nodes[lock].rest_local.rotation;
  const float r[4] = {rest.x, rest.y, rest.z, rest.w};
  EXPECT_LT(turnBetween(rotationOfNode(added, lock).data(), r), 1e-6f);
  drive(added, 60);
  added.step(kDt);
  EXPECT_LT(turnBetween(rotationOfNode(added, lock).data(), r), 0.05f) << "one step from rest, no pop";
}

TEST_P(CarryFrom, NothingIsCarriedFromAnInstanceThatNeverStepped) {
  const json bones = {{"springbone_a", tailEntry(1.0)}};
  Instance fresh(rig(bones), options());
  Instance carried(rig(bones), options());
  Instance never(rig(bones), options());
  carried.carryFrom(never);
  carried.carryFrom(carried);  // itself: nothing
  for (int f = 0; f < 30; ++f) {
    drive(fresh, f);
    fresh.step(kDt);
    drive(carried, f);
    carried.step(kDt);
  }
  for (std::size_t i = 0; i < 4 * fresh.jointCount(); ++i) EXPECT_EQ(carried.rotations()[i], fresh.rotations()[i]);
}

INSTANTIATE_TEST_SUITE_P(Paths, CarryFrom,
                         testing::Values(Case{"LanePath", false, Integrator::kVrm},
                                         Case{"GeneralPath", true, Integrator::kVrm},
                                         Case{"Xpbd", false, Integrator::kXpbd}),
                         [](const testing::TestParamInfo<Case>& info) { return info.param.name; });

}  // namespace
}  // namespace springbones
