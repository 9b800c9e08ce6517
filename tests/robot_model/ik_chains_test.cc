// Tests robot_model/ik on legs of 5 and 7 joints (issue 31: balance and walk on any leg of 5-7
// joints), written inline, against their closed-form inverse:
//   5 joints (H1's: hip yaw, roll, pitch, knee, ankle pitch; no ankle roll): a target whose
//     roll the leg can take is met exactly; a flat-foot target (a roll the leg cannot take) is
//     converged with the position exact and the orientation no worse than the closed-form
//     pose's (the roll the hip gives), where today's solver said kUnreachable.
//   7 joints (two coaxial hip yaws, then a 6-joint leg): redundant, every pose met; the yaws'
//     sum and the other joints equal the 6-joint closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "robot_model/ik.h"
#include "test_models.h"

namespace ohrp::model {
namespace {

constexpr double kA = 0.40, kB = 0.38;  // thigh and shin lengths [m]

// the leg's bodies: hip (at the origin, its joints at the hip point), shin, foot (the ankle);
// `ankle_roll` adds the ankle roll, `second_yaw` a second hip yaw above the first
std::string LegXml(bool ankle_roll, bool second_yaw) {
  const std::string j = R"(limited="true" range="-2.5 2.5" armature="0.01")";
  std::string xml = R"(<mujoco model="leg"><compiler angle="radian"/><worldbody>)";
  if (second_yaw)
    xml += R"(<body name="yaw_link" pos="0 0 0.1"><joint name="hy0" axis="0 0 1" )" + j +
           R"(/><inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>)"
           R"(<body name="thigh" pos="0 0 -0.1">)";
  else
    xml += R"(<body name="thigh">)";
  xml += R"(<joint name="hy" axis="0 0 1" )" + j + R"(/><joint name="hr" axis="1 0 0" )" + j +
         R"(/><joint name="hp" axis="0 1 0" )" + j +
         R"(/><inertial pos="0 0 -0.2" mass="3" diaginertia="0.05 0.05 0.01"/>)"
         R"(<body name="shin" pos="0 0 -0.4"><joint name="knee" axis="0 1 0" limited="true" )"
         R"(range="0 2.6" armature="0.01"/><inertial pos="0 0 -0.2" mass="2" )"
         R"(diaginertia="0.03 0.03 0.01"/><body name="foot" pos="0 0 -0.38">)"
         R"(<joint name="ap" axis="0 1 0" )" + j + "/>";
  if (ankle_roll) xml += R"(<joint name="ar" axis="1 0 0" )" + j + "/>";
  xml += R"(<inertial pos="0.03 0 -0.04" mass="1" diaginertia="0.01 0.01 0.01"/>)"
         "</body></body></body>";
  if (second_yaw) xml += "</body>";
  xml += "</worldbody><actuator>";
  for (const char* name : {"hy0", "hy", "hr", "hp", "knee", "ap", "ar"}) {
    if ((name == std::string("hy0") && !second_yaw) || (name == std::string("ar") && !ankle_roll))
      continue;
    xml += std::string(R"(<motor joint=")") + name + R"("/>)";
  }
  return xml + "</actuator></mujoco>";
}

std::unique_ptr<Kinematics> Leg(bool ankle_roll, bool second_yaw) {
  std::string error;
  const std::string xml = LegXml(ankle_roll, second_yaw);
  mjModel* m = testing::LoadString(xml.c_str(), &error);
  EXPECT_TRUE(m) << error;
  if (!m) return nullptr;
  auto kin = Kinematics::FromModel(m, &error);
  mj_deleteModel(m);
  EXPECT_TRUE(kin) << error;
  return kin;
}

Eigen::Matrix3d Rx(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).matrix(); }
Eigen::Matrix3d Ry(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).matrix(); }
Eigen::Matrix3d Rz(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix(); }

// the closed form: the ankle at p (hip frame) with the foot's yaw psi and pitch theta, knee
// bent: hip yaw = psi; hip roll = atan2(y', -z') in the yawed frame; hip pitch and knee by the
// law of cosines in the leg's plane; ankle pitch = theta - hip pitch - knee
struct Closed { double hy, hr, hp, knee, ap; };
Closed ClosedForm(const Eigen::Vector3d& p, double psi, double theta) {
  const Eigen::Vector3d q = Rz(-psi) * p;
  Closed c;
  c.hy = psi;
  c.hr = std::atan2(q.y(), -q.z());
  const double down = std::hypot(q.y(), q.z()), x = q.x();
  c.knee = std::acos((x * x + down * down - kA * kA - kB * kB) / (2 * kA * kB));
  c.hp = std::atan2(-x, down) - std::atan2(kB * std::sin(c.knee), kA + kB * std::cos(c.knee));
  c.ap = theta - c.hp - c.knee;
  return c;
}

struct Target { Eigen::Vector3d p; double psi, theta; };
const Target kTargets[] = {{{0.10, 0.08, -0.65}, 0.3, 0.2},
                           {{-0.05, -0.12, -0.70}, -0.4, -0.1},
                           {{0.15, 0.0, -0.55}, 0.0, 0.35},
                           {{0.02, 0.15, -0.60}, 0.6, 0.0}};

double AngleBetween(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return Eigen::AngleAxisd(Eigen::Matrix3d(A.transpose() * B)).angle();
}

TEST(LimbIkChains, FiveJointLegMeetsAReachableTargetAsTheClosedForm) {
  auto kin = Leg(false, false);
  ASSERT_TRUE(kin);
  LimbIk ik(*kin, 0, kin->BodyId("foot"));
  ASSERT_EQ(ik.chain().size(), 5u);
  for (const Target& t : kTargets) {
    const Closed c = ClosedForm(t.p, t.psi, t.theta);
    // the orientation this leg takes at that position: the roll is the hip's
    const Eigen::Matrix3d R = Rz(t.psi) * Rx(c.hr) * Ry(t.theta);
    double q[5] = {c.hy + 0.1, c.hr - 0.1, c.hp + 0.15, c.knee - 0.15, c.ap + 0.1};
    const IkResult r = ik.Solve(*kin, t.p, R, q);
    EXPECT_EQ(r.status, IkStatus::kConverged) << IkStatusName(r.status);
    const double expected[5] = {c.hy, c.hr, c.hp, c.knee, c.ap};
    for (int k = 0; k < 5; ++k) EXPECT_NEAR(q[k], expected[k], 1e-4) << "joint " << k;
    EXPECT_LT(r.position_error, 1e-5);
  }
}

TEST(LimbIkChains, FiveJointLegGivesUpTheRollItCannotTakeAndKeepsThePosition) {
  auto kin = Leg(false, false);
  ASSERT_TRUE(kin);
  LimbIk ik(*kin, 0, kin->BodyId("foot"));
  for (const Target& t : kTargets) {
    const Closed c = ClosedForm(t.p, t.psi, t.theta);
    const Eigen::Matrix3d R_flat = Rz(t.psi) * Ry(t.theta);  // no roll: out of reach if hr != 0
    double q[5] = {c.hy + 0.1, c.hr - 0.1, c.hp + 0.15, c.knee - 0.15, c.ap + 0.1};
    const IkResult r = ik.Solve(*kin, t.p, R_flat, q);
    EXPECT_EQ(r.status, IkStatus::kConverged) << IkStatusName(r.status) << " roll " << c.hr;
    EXPECT_LT(r.position_error, 1e-5);
    // the least-squares best is no worse than the closed-form pose (rotation error |hr|) and
    // near it (the yaw and pitch as asked, to first order)
    EXPECT_LE(r.orientation_error, std::fabs(c.hr) + 1e-5);
    EXPECT_GT(r.orientation_error, 0.9 * std::fabs(c.hr) - 1e-6);
    EXPECT_LT((ik.p_WT(*kin) - t.p).norm(), 1e-5);
    std::printf("[ figures  ] 5-joint leg, flat target: roll left %.4f rad (hip roll %.4f), "
                "%d iterations\n", r.orientation_error, c.hr, r.iterations);
  }
}

TEST(LimbIkChains, SevenJointLegMeetsEveryPoseAsTheSixJointClosedForm) {
  auto kin = Leg(true, true);
  ASSERT_TRUE(kin);
  LimbIk ik(*kin, 0, kin->BodyId("foot"));
  ASSERT_EQ(ik.chain().size(), 7u);
  for (const Target& t : kTargets) {
    const Closed c = ClosedForm(t.p, t.psi, t.theta);
    const double rho = 0.15;  // the ankle roll asked on top
    const Eigen::Matrix3d R = Rz(t.psi) * Rx(c.hr) * Ry(t.theta) * Rx(rho);
    // joints: hy0, hy, hr, hp, knee, ap, ar
    double q[7] = {0.05, c.hy - 0.1, c.hr + 0.1, c.hp - 0.1, c.knee + 0.1, c.ap, rho - 0.1};
    const IkResult r = ik.Solve(*kin, t.p, R, q);
    EXPECT_EQ(r.status, IkStatus::kConverged) << IkStatusName(r.status);
    EXPECT_NEAR(q[0] + q[1], c.hy, 1e-4);
    const double expected[5] = {c.hr, c.hp, c.knee, c.ap, rho};
    for (int k = 0; k < 5; ++k) EXPECT_NEAR(q[k + 2], expected[k], 1e-4) << "joint " << k + 2;
    EXPECT_LT(AngleBetween(ik.R_WT(*kin), R), 1e-5);
    EXPECT_LT((ik.p_WT(*kin) - t.p).norm(), 1e-5);
  }
}

}  // namespace
}  // namespace ohrp::model
