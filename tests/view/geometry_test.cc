// The viewer's scene geometry (tools/view/src/geometry.cc): the description of HRP-1S's flat
// scene, the geoms' world poses by forward kinematics, and the ZMP from the sole sensors
// against closed forms.
#include "view/geometry.h"

#include <gtest/gtest.h>

namespace ohrp::view {
namespace {

const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";

class Geometry : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    geometry_ = SceneGeometry::Load(kScene, &error);
    ASSERT_TRUE(geometry_) << error;
    state_.q.assign(geometry_->robot().joints.size(), 0.0);
    state_.p_WB[2] = 0.7235;
    state_.ft.assign(geometry_->robot().forces.size(), shm::ForceTorque{});
  }
  int Sensor(const std::string& name) const {
    const auto& f = geometry_->robot().forces;
    for (size_t i = 0; i < f.size(); ++i)
      if (f[i].name == name) return static_cast<int>(i);
    return -1;
  }
  std::unique_ptr<SceneGeometry> geometry_;
  RobotState state_;
};

TEST_F(Geometry, DescribesTheFloorAndTheRobotsGeoms) {
  const nlohmann::json& d = geometry_->Describe();
  ASSERT_EQ(d["static"].size(), 1u);
  EXPECT_EQ(d["static"][0]["type"], "plane");
  EXPECT_GT(d["moving"].size(), 40u);
  EXPECT_EQ(d["joints"].size(), 29u);
  EXPECT_EQ(geometry_->Poses(state_).size(), d["moving"].size());
}

TEST_F(Geometry, PosesFollowTheBase) {
  const nlohmann::json a = geometry_->Poses(state_);
  state_.p_WB[0] += 1.0;
  const nlohmann::json b = geometry_->Poses(state_);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(b[i][0].get<double>() - a[i][0].get<double>(), 1.0, 1e-9);
    EXPECT_NEAR(b[i][2].get<double>(), a[i][2].get<double>(), 1e-9);
  }
}

// two ankles carrying 300 N each, straight up, no moment: the ZMP is midway between the
// sensors; a moment -6 N m about each sensor's y moves it 2 cm forward (x = -M_y / F_z); a
// wrist sensor's force is not a foot's and changes nothing
TEST_F(Geometry, ZmpFromTheSoleSensorsMatchesTheClosedForm) {
  const int r = Sensor("rfsensor"), l = Sensor("lfsensor"), h = Sensor("rhsensor");
  ASSERT_GE(r, 0);
  ASSERT_GE(l, 0);
  ASSERT_GE(h, 0);
  geometry_->Poses(state_);
  const mjModel* m = geometry_->model();
  // the sensors' positions, from a fresh kinematics of the same state
  mjData* d = mj_makeData(m);
  for (int k = 0; k < 3; ++k) d->qpos[geometry_->robot().base_qpos + k] = state_.p_WB[k];
  mj_kinematics(m, d);
  const double* pr = d->site_xpos + 3 * geometry_->robot().forces[r].site_id;
  const double* pl = d->site_xpos + 3 * geometry_->robot().forces[l].site_id;
  const double mid_x = 0.5 * (pr[0] + pl[0]), mid_y = 0.5 * (pr[1] + pl[1]);
  state_.ft[r].force[2] = state_.ft[l].force[2] = 300;
  state_.ft[h].force[2] = 500;
  double zmp[2];
  ASSERT_TRUE(geometry_->Zmp(state_, zmp));
  EXPECT_NEAR(zmp[0], mid_x, 1e-9);
  EXPECT_NEAR(zmp[1], mid_y, 1e-9);
  state_.ft[r].torque[1] = state_.ft[l].torque[1] = -6;
  ASSERT_TRUE(geometry_->Zmp(state_, zmp));
  EXPECT_NEAR(zmp[0], mid_x + 0.02, 1e-9);
  // in the air: no ZMP
  state_.ft[r].force[2] = state_.ft[l].force[2] = 5;
  EXPECT_FALSE(geometry_->Zmp(state_, zmp));
  mj_deleteData(d);
}

}  // namespace
}  // namespace ohrp::view
