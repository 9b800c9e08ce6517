// The walk plan overlays' server side (tools/view/src/plan.cc) against closed forms: the capture
// point of a CoM at rest is its ground projection and of one moving at v is c + v sqrt(z / g);
// the plan frame's columns and the registration onto the soles move every point rigidly; the
// footsteps are the starting soles and each landing, rectangles of the sizes given.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/scratch.h"
#include "view/plan.h"

namespace ohrp::view {
namespace {

namespace fs = std::filesystem;

TEST(CapturePoint, AtRestIsTheGroundProjection) {
  const double c[3] = {0.3, -0.2, 0.8}, v[2] = {0, 0};
  const auto cp = CapturePoint(c, v, 0.1);
  EXPECT_EQ(cp[0], 0.3);
  EXPECT_EQ(cp[1], -0.2);
}

TEST(CapturePoint, MovingIsAheadByVelocityOverOmega) {
  const double c[3] = {0.3, -0.2, 0.8}, v[2] = {0.4, -0.1};
  const auto cp = CapturePoint(c, v, 0.1);  // height 0.7 m over the ground
  const double over_omega = std::sqrt(0.7 / kPlanGravity);
  EXPECT_NEAR(cp[0], 0.3 + 0.4 * over_omega, 1e-12);
  EXPECT_NEAR(cp[1], -0.2 - 0.1 * over_omega, 1e-12);
}

TEST(Planar, TwoPointsGoOntoTheirImages) {
  const double a[3] = {0, 0.1, 0}, b[3] = {0, -0.1, 0};
  // the pair turned by 90 deg and moved to (1, 2, 0.05)
  const double A[3] = {0.9, 2, 0.05}, B[3] = {1.1, 2, 0.05};
  const Planar p = FitTwoPoints(a, b, A, B);
  EXPECT_NEAR(p.yaw, M_PI / 2, 1e-12);
  const auto pa = p.Apply(a), pb = p.Apply(b);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(pa[k], A[k], 1e-12);
    EXPECT_NEAR(pb[k], B[k], 1e-12);
  }
}

class Plan : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = ohrp::testing::ScratchFolder("plan"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// 301 rows, 10 ms apart: the CoM reference at 0.7 m moves along x at 0.2 m/s from t = 1 to 2 s
// (at rest before and after); the left sole lifts at t = 0.8 s and lands 0.2 m ahead at 1.2 s;
// the right lifts at 1.6 s and lands 0.2 m ahead at 2.2 s; the plan frame moves by 0.1 m along
// y from t = 2.5 s; the desired ZMP is the left sole's position
std::string WriteWalk(const fs::path& dir) {
  const std::string path = (dir / "walk.csv").string();
  std::ofstream f(path);
  f << "t,com_ref_x,com_ref_y,com_ref_z,zmp_des_x,zmp_des_y,dcm_x,dcm_y,left_x,left_y,left_z,left_yaw,"
       "right_x,right_y,right_z,right_yaw,support_left,support_right,frame_x,frame_y,frame_yaw\n";
  for (int i = 0; i <= 300; ++i) {
    const double t = 3.0 + 0.01 * i;  // the walk starts at t = 3 s of the run
    // by row (not by time: no rounding at the edges)
    const double cx = i < 100 ? 0 : i < 200 ? 0.2 * 0.01 * (i - 100) : 0.2;
    const double lx = i < 120 ? 0 : 0.2, rx = i < 220 ? 0 : 0.2;
    const bool sl = !(i >= 80 && i < 120), sr = !(i >= 160 && i < 220);
    f << t << "," << cx << ",0,0.7," << lx << ",0.1," << cx << ",0," << lx << ",0.1,0,0," << rx << ",-0.1,0,0,"
      << sl << "," << sr << ",0," << (i >= 250 ? 0.1 : 0) << ",0\n";
  }
  return path;
}

TEST_F(Plan, MissingColumnsAreNamed) {
  {
    std::ofstream f(dir_ / "walk.csv");
    f << "t,com_ref_x,com_ref_y\n0,0,0\n";
  }
  std::string error;
  auto plan = WalkPlan::Load((dir_ / "walk.csv").string(), &error);
  ASSERT_TRUE(plan) << error;
  const nlohmann::json m = plan->Missing();
  EXPECT_EQ(m["desired_zmp"], nlohmann::json({"zmp_des_x", "zmp_des_y"}));
  EXPECT_EQ(m["dcm"][0], "com_ref_z");
  EXPECT_EQ(m["footsteps"].size(), 10u);
  EXPECT_TRUE(plan->At(0)["zmp_des"].is_null());
  EXPECT_TRUE(plan->Footsteps(nullptr).empty());
  std::ofstream(dir_ / "bad.csv") << "x,y\n1,2\n";
  EXPECT_FALSE(WalkPlan::Load((dir_ / "bad.csv").string(), &error));
  EXPECT_NE(error.find("no 't' column"), std::string::npos) << error;
}

TEST_F(Plan, MarkersAndFootstepsInTheWorld) {
  std::string error;
  auto plan = WalkPlan::Load(WriteWalk(dir_), &error);
  ASSERT_TRUE(plan) << error;
  const nlohmann::json missing = plan->Missing();
  for (const auto& [k, v] : missing.items()) EXPECT_TRUE(v.empty()) << k << v;
  EXPECT_TRUE(plan->At(2.99).is_null());  // before the walk
  // the soles in the world: the plan's (0, +-0.1, 0) turned by 90 deg, at (1, 2), 0.05 m up
  const double left_W[3] = {0.9, 2, 0.05}, right_W[3] = {1.1, 2, 0.05};
  plan->Register(left_W, right_W);
  auto world = [](double x, double y) { return std::array<double, 2>{1 - y, 2 + x}; };
  // at rest (t = 3.5): the capture point is the CoM reference's projection, the DCM the
  // logged one, the desired ZMP the left sole, all at the soles' height
  nlohmann::json a = plan->At(3.5);
  EXPECT_NEAR(a["cp"][0].get<double>(), world(0, 0)[0], 1e-9);
  EXPECT_NEAR(a["cp"][1].get<double>(), world(0, 0)[1], 1e-9);
  EXPECT_NEAR(a["cp"][2].get<double>(), 0.05, 1e-9);
  EXPECT_NEAR(a["zmp_des"][0].get<double>(), left_W[0], 1e-9);
  EXPECT_NEAR(a["zmp_des"][1].get<double>(), left_W[1], 1e-9);
  EXPECT_EQ(a["support"], nlohmann::json({true, true}));
  // moving at 0.2 m/s along the plan's x (t = 4.5, CoM at 0.1): the capture point 0.2 / omega
  // ahead, omega = sqrt(g / 0.7); the stabilizer's DCM column as logged (the CoM's x)
  const double ahead = 0.2 * std::sqrt(0.7 / kPlanGravity);
  a = plan->At(4.5);
  EXPECT_NEAR(a["cp"][0].get<double>(), world(0.1 + ahead, 0)[0], 1e-6);
  EXPECT_NEAR(a["cp"][1].get<double>(), world(0.1 + ahead, 0)[1], 1e-6);
  EXPECT_NEAR(a["dcm"][1].get<double>(), world(0.1, 0)[1], 1e-6);
  // t = 5.0: the right foot in the air, the left landed 0.2 m ahead (the desired ZMP there)
  a = plan->At(5.0);
  EXPECT_EQ(a["support"], nlohmann::json({true, false}));
  EXPECT_NEAR(a["zmp_des"][1].get<double>(), world(0.2, 0.1)[1], 1e-9);
  // t = 5.8: the plan frame moved 0.1 m along the plan's y: a point fixed in the plan moves
  // 0.1 m along the estimator's -y, i.e. the world's +x (the 90 deg turn)
  a = plan->At(5.8);
  EXPECT_NEAR(a["zmp_des"][0].get<double>(), world(0.2, 0.1)[0] + 0.1, 1e-9);
  EXPECT_NEAR(a["zmp_des"][1].get<double>(), world(0.2, 0.1)[1], 1e-9);

  // the footsteps: the two starting soles, then the left landing (t = 4.2), the right (5.2)
  const double half[2][2] = {{0.125, 0.07}, {0.125, 0.07}};
  const nlohmann::json steps = plan->Footsteps(half);
  ASSERT_EQ(steps.size(), 4u) << steps;
  EXPECT_EQ(steps[2]["side"], "left");
  EXPECT_NEAR(steps[2]["t"].get<double>(), 4.2, 1e-9);
  EXPECT_EQ(steps[3]["side"], "right");
  EXPECT_NEAR(steps[3]["t"].get<double>(), 5.2, 1e-9);
  EXPECT_NEAR(steps[3]["center"][0].get<double>(), world(0.2, -0.1)[0], 1e-9);
  EXPECT_NEAR(steps[3]["center"][1].get<double>(), world(0.2, -0.1)[1], 1e-9);
  EXPECT_NEAR(steps[0]["center"][0].get<double>(), left_W[0], 1e-9);
  EXPECT_NEAR(steps[0]["center"][2].get<double>(), left_W[2], 1e-9);
  // each a rectangle 0.25 x 0.14 m turned by the registration's 90 deg: 0.25 m along world y
  for (const auto& s : steps) {
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (const auto& c : s["corners"]) {
      x0 = std::min(x0, c[0].get<double>()); x1 = std::max(x1, c[0].get<double>());
      y0 = std::min(y0, c[1].get<double>()); y1 = std::max(y1, c[1].get<double>());
    }
    EXPECT_NEAR(x1 - x0, 0.14, 1e-9) << s;
    EXPECT_NEAR(y1 - y0, 0.25, 1e-9) << s;
  }
  // the cost of a frame's plan (printed, not checked): At() and its JSON's size
  const auto start = std::chrono::steady_clock::now();
  size_t bytes = 0;
  for (int i = 0; i < 10000; ++i) bytes += plan->At(3.0 + 3.0 * i / 10000).dump().size();
  const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  std::printf("WalkPlan::At and its JSON: %.2f us a frame, %.0f bytes\n", us / 10000, bytes / 10000.0);
}

}  // namespace
}  // namespace ohrp::view
