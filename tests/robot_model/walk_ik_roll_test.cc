// WalkIk with the base's roll free, for legs without an ankle roll (issue 31: menagerie's H1,
// 5-joint legs), against what the solution must satisfy: the supporting soles flat and where
// they were asked, the CoM where it was asked, the roll within its limit; a robot with 6-joint
// legs is solved upright as before; the solve allocates nothing. A binary of its own: it counts
// heap allocations (count_allocations.h).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "count_allocations.h"
#include "robot_model/kinematics.h"
#include "robot_model/model.h"
#include "test_models.h"
#include "walking/walk_ik.h"

namespace ohrp::walking {
namespace {

std::string Repo() { return OHRP_SOURCE_DIR; }
bool HaveH1() {
  return std::filesystem::exists(Repo() + "/../shared/external/menagerie/unitree_h1/scene.xml");
}

// the sole's roll about its target's forward axis
double SoleRoll(const model::Kinematics& k, int sole, const Eigen::Matrix3d& R_target) {
  const Eigen::Matrix3d R = R_target.transpose() * k.R_WSole(sole);
  return std::atan2(R(2, 1), R(2, 2));
}

struct H1Stance {
  std::unique_ptr<model::Kinematics> kin;
  std::unique_ptr<WalkIk> ik;
  std::vector<double> q;
  Eigen::Vector3d p_WB, com, p_WS[2];
  Eigen::Matrix3d R_WS[2];
};

// H1 through its profile at the profile's stand key
void StandH1(H1Stance* s) {
  std::string error;
  s->kin = model::Kinematics::Load(Repo() + "/robots/h1.yaml", &error);
  ASSERT_TRUE(s->kin) << error;
  s->ik = WalkIk::Create(s->kin.get(), &error);
  ASSERT_TRUE(s->ik) << error;
  std::vector<std::pair<std::string, double>> stand;
  ASSERT_TRUE(model::KeyframeJointPositions(s->kin->m(), "stand", &stand, &error)) << error;
  s->q.assign(s->kin->njoint(), 0.0);
  for (const auto& [name, v] : stand) s->q[s->kin->JointId(name)] = v;
  const mjModel* m = s->kin->m();
  const int key = mj_name2id(m, mjOBJ_KEY, "stand");
  s->p_WB = Eigen::Vector3d(0, 0, m->key_qpos[key * m->nq + 2]);
  s->kin->SetBasePose(s->p_WB, Eigen::Quaterniond::Identity());
  s->kin->SetJointPositions(s->q.data());
  s->kin->Update();
  s->com = s->kin->p_WCoM();
  for (int i = 0; i < 2; ++i) {
    s->p_WS[i] = s->kin->p_WSole(s->ik->sole(i));
    s->R_WS[i] = s->kin->R_WSole(s->ik->sole(i));
  }
}

TEST(WalkIkRoll, SixJointLegsStayUpright) {
  std::string error;
  auto kin = model::testing::Hrp1s(&error);
  ASSERT_TRUE(kin) << error;
  auto ik = WalkIk::Create(kin.get(), &error);
  ASSERT_TRUE(ik) << error;
  EXPECT_FALSE(ik->rolls_base());
}

// on one foot (the left), the CoM asked 2 cm towards it: the base rolls (the upper body over
// the stance hip), the left sole stays flat where it was, the CoM is met
TEST(WalkIkRoll, H1OnOneFootRollsTheBaseWithTheSoleFlat) {
  if (!HaveH1()) GTEST_SKIP() << "no ../shared/external beside the repository";
  H1Stance s;
  StandH1(&s);
  ASSERT_TRUE(s.ik->rolls_base()) << "H1's legs have 5 joints";
  const double weights[3] = {1.0, 0.0, 1.0};
  const Eigen::Vector3d com = s.com + Eigen::Vector3d(0, 0.02, 0);
  Eigen::Vector3d p_WS[2] = {s.p_WS[0], s.p_WS[1] + Eigen::Vector3d(0, 0, 0.03)};  // right lifted
  double roll = 0;
  WalkIkResult r;
  for (int cycle = 0; cycle < 20 && !r.ok; ++cycle)
    r = s.ik->Solve(com, Eigen::Quaterniond::Identity(), p_WS, s.R_WS, weights, s.q.data(), &s.p_WB,
                    &roll);
  ASSERT_TRUE(r.ok) << "com error " << r.com_error;
  s.kin->SetBasePose(s.p_WB, Eigen::Quaterniond(Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX())));
  s.kin->SetJointPositions(s.q.data());
  s.kin->Update();
  EXPECT_LT(std::abs(SoleRoll(*s.kin, s.ik->sole(0), s.R_WS[0])), 1e-3);
  EXPECT_LT((s.kin->p_WSole(s.ik->sole(0)) - p_WS[0]).norm(), 1e-4);
  EXPECT_LT((s.kin->p_WCoM() - com).norm(), 1e-3);
  // the upper body leans left: a negative roll about the forward axis, within the limit
  EXPECT_LT(roll, -0.01);
  EXPECT_LE(std::abs(roll), s.ik->max_roll);
}

// on both feet, the CoM asked 15 cm sideways, beyond what the roll can carry: both soles in
// place and nearly flat, the roll at its limit, the CoM as near as that allows (short of the ask)
TEST(WalkIkRoll, H1OnBothFeetKeepsBothSolesFlatAndTheRollWithinItsLimit) {
  if (!HaveH1()) GTEST_SKIP() << "no ../shared/external beside the repository";
  H1Stance s;
  StandH1(&s);
  const double weights[3] = {1.0, 1.0, 1.0};
  const Eigen::Vector3d com = s.com + Eigen::Vector3d(0, -0.15, 0);
  double roll = 0;
  WalkIkResult r;
  for (int cycle = 0; cycle < 40 && !r.ok; ++cycle)
    r = s.ik->Solve(com, Eigen::Quaterniond::Identity(), s.p_WS, s.R_WS, weights, s.q.data(),
                    &s.p_WB, &roll);
  ASSERT_TRUE(r.ok);
  s.kin->SetBasePose(s.p_WB, Eigen::Quaterniond(Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX())));
  s.kin->SetJointPositions(s.q.data());
  s.kin->Update();
  EXPECT_NEAR(roll, s.ik->max_roll, 1e-9);  // towards the right: positive
  const double moved = s.com.y() - s.kin->p_WCoM().y();
  EXPECT_GT(moved, 0.01);
  EXPECT_LT(moved, 0.15);
  // the soles first: what is left short of the CoM's ask tilts them by less than a tenth of a
  // mrad per mm (the weighting's trade, walk_ik.cc kSoleFirst), against the 0.1 rad that would
  // carry it there with equal weights
  const double short_mm = 1000 * (0.15 - moved);
  for (int i = 0; i < 2; ++i) {
    EXPECT_LT(std::abs(SoleRoll(*s.kin, s.ik->sole(i), s.R_WS[i])), 1e-4 * short_mm) << i;
    EXPECT_LT((s.kin->p_WSole(s.ik->sole(i)) - s.p_WS[i]).norm(), 1e-4) << i;
  }
}

TEST(WalkIkRoll, TheRollingSolveAllocatesNothing) {
#ifndef OHRP_CAN_COUNT
  GTEST_SKIP() << "heap allocations cannot be counted in this build (count_allocations.h)";
#else
  if (!HaveH1()) GTEST_SKIP() << "no ../shared/external beside the repository";
  H1Stance s;
  StandH1(&s);
  const double weights[3] = {1.0, 0.5, 1.0};
  double roll = 0;
  const long n = testing::Allocations([&] {
    for (int cycle = 0; cycle < 5; ++cycle) {
      const Eigen::Vector3d com = s.com + Eigen::Vector3d(0, 0.004 * cycle, 0);
      s.ik->Solve(com, Eigen::Quaterniond::Identity(), s.p_WS, s.R_WS, weights, s.q.data(), &s.p_WB,
                  &roll);
    }
  });
  EXPECT_EQ(n, 0);
#endif
}

}  // namespace
}  // namespace ohrp::walking
