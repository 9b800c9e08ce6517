// Tests the push-recovery measures (tools/runner/src/recovery.cc) and the checks `standing`
// and `settles` on synthetic logs whose answers are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>

#include "common/scratch.h"
#include "runner/checks.h"
#include "runner/recovery.h"

namespace ohrp::runner {
namespace {

constexpr double kDt = 0.001;  // [s] log period of the synthetic logs

// one row of a synthetic log
struct Row {
  double x = 0, y = 0, z = 0.7;      // base [m]
  double tilt = 0;                   // [rad] about the y axis
  double rf_tx = 0, rf_ty = 0, lf_tx = 0, lf_ty = 0;  // [N m]
  double rf_fz = 0.5 * 96 * 9.81, lf_fz = 0.5 * 96 * 9.81;  // [N]
};

datalog::Table Log(double duration, const std::function<Row(double)>& at) {
  const std::string path = ohrp::testing::ScratchPath("recovery_log", ".csv");
  std::ofstream out(path);
  out << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,rf_fz,rf_tx,rf_ty,lf_fz,lf_tx,lf_ty\n";
  out.precision(17);
  for (int i = 0; i <= std::lround(duration / kDt); ++i) {
    const double t = i * kDt;
    const Row r = at(t);
    out << t << "," << r.x << "," << r.y << "," << r.z << "," << std::cos(r.tilt / 2) << ",0,"
        << std::sin(r.tilt / 2) << ",0," << r.rf_fz << "," << r.rf_tx << "," << r.rf_ty << ","
        << r.lf_fz << "," << r.lf_tx << "," << r.lf_ty << "\n";
  }
  out.close();
  datalog::Table t;
  std::string error;
  EXPECT_TRUE(t.Load(path, &error)) << error;
  return t;
}

// a 100 kg robot with 2 kg below each ankle sensor
const nlohmann::json kSim = {{"robot_mass", 100.0}, {"gravity", {0, 0, -9.81}},
                             {"mass_below", {{"rf", 2.0}, {"lf", 2.0}}}};

CheckSpec Spec(const std::string& type, std::map<std::string, std::string> p) {
  CheckSpec s;
  s.type = type;
  s.params = std::move(p);
  return s;
}

//---------------- standing ----------------

TEST(Standing, AnUprightRobotOnItsFeetStands) {
  // it sways 5 cm down and 10 deg after the push at 1 s, and is back by 2 s
  const datalog::Table t = Log(4, [](double s) {
    Row r;
    if (s > 1 && s < 2) {
      r.z = 0.7 - 0.05 * std::sin(M_PI * (s - 1));
      r.tilt = 10 * M_PI / 180 * std::sin(M_PI * (s - 1));
    }
    return r;
  });
  const auto r = Evaluate(Spec("standing", {{"stance_at", "1"}, {"after", "3"}, {"sensors", "rf,lf"}}), t, kSim);
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NEAR(r.value, 0.7, 1e-12);
  // from t = 1.5 s on the dip (0.65 m) is inside the window: still above 80 %, but not above
  // 95 %; a 5 deg bound sees the 10 deg sway
  EXPECT_TRUE(Evaluate(Spec("standing", {{"stance_at", "1"}, {"after", "1.5"}}), t, kSim).passed);
  EXPECT_FALSE(Evaluate(Spec("standing", {{"stance_at", "1"}, {"after", "1.5"}, {"min_height_fraction", "0.95"}}),
                        t, kSim).passed);
  const auto tilted = Evaluate(Spec("standing", {{"stance_at", "1"}, {"after", "1.5"}, {"max_tilt_deg", "5"}}), t, kSim);
  EXPECT_FALSE(tilted.passed);
  EXPECT_NE(tilted.detail.find("largest tilt 10.0 deg"), std::string::npos) << tilted.detail;
}

TEST(Standing, AFallenOrKneelingOrCutShortRobotDoesNotStand) {
  // fallen: the base ends at 0.3 m
  const datalog::Table fallen = Log(4, [](double s) {
    Row r;
    if (s > 1.5) r.z = std::max(0.3, 0.7 - 0.8 * (s - 1.5));
    return r;
  });
  auto r = Evaluate(Spec("standing", {{"stance_at", "1"}, {"after", "3"}}), fallen, kSim);
  EXPECT_FALSE(r.passed);
  EXPECT_NEAR(r.value, 0.3, 1e-12);
  // kneeling: upright and high enough, but the feet carry only 60 % of the weight
  const datalog::Table kneeling = Log(4, [](double) {
    Row r;
    r.rf_fz = r.lf_fz = 0.3 * 96 * 9.81;
    return r;
  });
  EXPECT_TRUE(Evaluate(Spec("standing", {{"stance_at", "1"}, {"after", "3"}}), kneeling, kSim).passed);
  r = Evaluate(Spec("standing", {{"stance_at", "1"}, {"after", "3"}, {"sensors", "rf,lf"}}), kneeling, kSim);
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("feet carry 60 %"), std::string::npos) << r.detail;
  // a log that ends before `after` (sim_host stopped) is not standing
  r = Evaluate(Spec("standing", {{"stance_at", "1"}, {"after", "5"}}), kneeling, kSim);
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("the log ends"), std::string::npos) << r.detail;
  // missing keys are named
  r = Evaluate(Spec("standing", {{"after", "3"}}), kneeling, kSim);
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("stance_at"), std::string::npos) << r.detail;
}

//---------------- settling ----------------

// push on [1, 1.1]; from its end the base returns as 2 cm e^(-s/0.2) (settles within 1 cm at
// s = 0.2 ln 2 = 0.1386 s) and the ankle torque deviation decays as 60 e^(-s/0.3) on rf_ty and
// 80 e^(-s/0.3) on lf_tx (norm 100 e^(-s/0.3); below 10 % at s = 0.3 ln 10 = 0.6908 s), on
// baselines of 5 and -3 N m that the measure must remove
Row Decaying(double t, double omega) {
  Row r;
  r.x = 0.3;
  r.y = -0.1;
  r.rf_ty = 5;
  r.lf_tx = -3;
  if (t >= 1.1) {
    const double s = t - 1.1;
    r.x += 0.02 * std::exp(-s / 0.2);
    const double c = omega > 0 ? std::cos(omega * s) : 1.0;
    r.rf_ty += 60 * std::exp(-s / 0.3) * c;
    r.lf_tx += 80 * std::exp(-s / 0.3) * c;
  }
  return r;
}

TEST(Settles, ExponentialReturnsSettleAtTheirClosedFormTimes) {
  const datalog::Table t = Log(4, [](double s) { return Decaying(s, 0); });
  SettleSpec spec;
  spec.at = 1;
  spec.sensors = {"rf", "lf"};
  SettleResult r;
  std::string error;
  ASSERT_TRUE(MeasureSettling(t, spec, &r, &error)) << error;
  EXPECT_NEAR(r.first_peak, 100, 1e-9);
  EXPECT_NEAR(r.base_excursion, 0.02, 1e-9);
  EXPECT_NEAR(r.base_time, 0.2 * std::log(2.0), kDt);      // one log period
  EXPECT_NEAR(r.torque_time, 0.3 * std::log(10.0), kDt);
  EXPECT_TRUE(r.settled);
  // the check: 0.69 s is over a 0.5 s bound
  const auto c = Evaluate(Spec("settles", {{"at", "1"}, {"sensors", "rf,lf"}, {"within", "0.5"}}), t, kSim);
  EXPECT_FALSE(c.passed);
  EXPECT_NEAR(c.value, 0.3 * std::log(10.0), kDt);
}

// an oscillation under the same envelope: crossing zero is not settling; the time is that of
// the last swing above 10 % of the first peak, within half a period before the envelope's time
TEST(Settles, AnOscillationSettlesWhenItsSwingsStayBelowTheFraction) {
  const double omega = 2 * M_PI * 3;  // [rad/s] 3 Hz
  const datalog::Table t = Log(4, [&](double s) { return Decaying(s, omega); });
  SettleSpec spec;
  spec.at = 1;
  spec.sensors = {"rf", "lf"};
  SettleResult r;
  std::string error;
  ASSERT_TRUE(MeasureSettling(t, spec, &r, &error)) << error;
  const double envelope_time = 0.3 * std::log(10.0);
  EXPECT_LE(r.torque_time, envelope_time + kDt);
  EXPECT_GE(r.torque_time, envelope_time - 0.5 * 2 * M_PI / omega);
  EXPECT_GT(r.torque_time, 0.5);  // far later than the first zero crossing (0.083 s)
}

TEST(Settles, ADriftThatNeverReturnsNeverSettles) {
  // the feet slid: the base ends 3 cm away and the torques on a new level
  const datalog::Table t = Log(3, [](double s) {
    Row r;
    if (s >= 1.1) {
      r.x = 0.03;
      r.rf_ty = 20;
    }
    return r;
  });
  SettleSpec spec;
  spec.at = 1;
  spec.sensors = {"rf", "lf"};
  SettleResult r;
  std::string error;
  ASSERT_TRUE(MeasureSettling(t, spec, &r, &error)) << error;
  EXPECT_TRUE(std::isinf(r.base_time));
  EXPECT_TRUE(std::isinf(r.torque_time));
  EXPECT_FALSE(r.settled);
  // no baseline before the push, or a missing sensor: errors, not figures
  spec.at = 0;
  EXPECT_FALSE(MeasureSettling(t, spec, &r, &error));
  spec.at = 1;
  spec.sensors = {"rf", "chest"};
  EXPECT_FALSE(MeasureSettling(t, spec, &r, &error));
  EXPECT_NE(error.find("chest_tx"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::runner
