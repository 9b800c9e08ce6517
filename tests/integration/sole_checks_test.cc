// Tests the sole checks cop_inside and foot_lifted (tools/runner/src/sole_checks.cc) on
// synthetic logs whose centre of pressure is known in closed form: a force f acting at a point p
// of the sole plane gives the moment n = p x f about the sensor origin.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>

#include "common/scratch.h"
#include "runner/checks.h"
#include "runner/sole_checks.h"

namespace ohrp::runner {
namespace {

constexpr double kDt = 0.01;  // [s] log period of the synthetic logs
constexpr double kExact = 1e-9;  // [m] the CoP is computed in closed form

// HRP-1S's sole seen from its ankle sensor (sim_host's summary): x in [-0.07, 0.18],
// y in [-0.07, 0.07], bottom face at z = 0
const SoleRect kSole = {{-0.07, 0.18}, {-0.07, 0.07}, 0.0};

// a foot below the sensor (HRP-1S's: 1.9 kg, 8 cm in front of and 4 cm above the sensor)
struct Foot {
  double mass = 0;
  double com[3] = {0, 0, 0};
};
const Foot kHrpFoot = {1.9, {0.08, 0.0, 0.04}};
constexpr double kG = 9.81;  // [m/s^2]

nlohmann::json Summary(double z = 0, const Foot& foot = {}) {
  nlohmann::json sole = {{"sole", "X_SOLE"}, {"x", {kSole.x[0], kSole.x[1]}},
                         {"y", {kSole.y[0], kSole.y[1]}}, {"z", z}};
  if (foot.mass > 0) {
    sole["foot_mass"] = foot.mass;
    sole["foot_com"] = {foot.com[0], foot.com[1], foot.com[2]};
  }
  return {{"robot_mass", 100.0}, {"gravity", {0, 0, -9.81}},
          {"soles", {{"lfsensor", sole}, {"rfsensor", sole}}}};
}

// one sensor's reading: force f at the point p = (px, py, z) of the sensor frame
struct Contact {
  double px = 0.055, py = 0, fz = 490;
  double fx = 0, fy = 0;
};

void Moment(const Contact& c, double z, double n[3]) {
  n[0] = c.py * c.fz - z * c.fy;
  n[1] = z * c.fx - c.px * c.fz;
  n[2] = c.px * c.fy - c.py * c.fx;
}

// a log of both ankle sensors, contacts given per time; the sensors read the ground's wrench
// plus the weight W = (0, 0, -m g) of `foot` at its centre of mass c: f = f_g + W,
// n = p x f_g + c x W
datalog::Table Log(double duration, double z, const std::function<std::pair<Contact, Contact>(double)>& at,
          const Foot& foot = {}) {
  const std::string path = ohrp::testing::ScratchPath("sole_log", ".csv");
  std::ofstream out(path);
  out << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz";
  for (const char* s : {"lfsensor", "rfsensor"})
    for (const char* k : {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"}) out << "," << s << k;
  out << "\n";
  out.precision(17);
  for (int i = 0; i <= std::lround(duration / kDt); ++i) {
    const double t = i * kDt;
    const auto [l, r] = at(t);
    out << t << ",0,0,0.7,1,0,0,0";
    for (const Contact& c : {l, r}) {
      double m[3];
      Moment(c, z, m);
      const double w = foot.mass * kG;  // c x W = (-c_y w, c_x w, 0)
      m[0] -= foot.com[1] * w;
      m[1] += foot.com[0] * w;
      out << "," << c.fx << "," << c.fy << "," << c.fz - w << "," << m[0] << "," << m[1] << "," << m[2];
    }
    out << "\n";
  }
  out.close();
  datalog::Table t;
  std::string error;
  EXPECT_TRUE(t.Load(path, &error)) << error;
  std::remove(path.c_str());
  return t;
}

CheckSpec Spec(const std::string& type, std::map<std::string, std::string> p) {
  CheckSpec s;
  s.type = type;
  s.params = std::move(p);
  return s;
}

//---------------- centre of pressure ----------------

TEST(CentreOfPressure, RecoversThePointOfAnInclinedForce) {
  // an inclined force on a sole plane 2 cm below the sensor
  for (double z : {0.0, -0.02, 0.015}) {
    const Contact c{0.123, -0.045, 310, 42, -17};
    double n[3];
    Moment(c, z, n);
    const double f[3] = {c.fx, c.fy, c.fz};
    double px = 0, py = 0;
    ASSERT_TRUE(CentreOfPressure(f, n, z, &px, &py));
    EXPECT_NEAR(px, c.px, kExact) << "z=" << z;
    EXPECT_NEAR(py, c.py, kExact) << "z=" << z;
  }
}

TEST(CentreOfPressure, NoPressureNoPoint) {
  const double f[3] = {1, 2, 0}, n[3] = {0, 0, 0};
  double px = 7, py = 7;
  EXPECT_FALSE(CentreOfPressure(f, n, 0, &px, &py));
  EXPECT_EQ(px, 7);
}

TEST(InsideDistance, NearestEdgeInsideNegativeOutside) {
  EXPECT_NEAR(InsideDistance(kSole, 0.055, 0), 0.07, kExact);        // the y edges are nearest
  EXPECT_NEAR(InsideDistance(kSole, 0.17, 0.01), 0.01, kExact);      // toe edge 1 cm away
  EXPECT_NEAR(InsideDistance(kSole, -0.08, 0), -0.01, kExact);       // 1 cm behind the heel
}

//---------------- cop_inside ----------------

TEST(CopInside, TheCheckComputesTheCopExactly) {
  // the right CoP 1.1 cm inside the toe edge with an inclined force, on a plane 2 cm below
  const double z = -0.02;
  const datalog::Table t = Log(1.0, z, [](double) {
    return std::make_pair(Contact{}, Contact{0.18 - 0.011, 0.0, 500, 30, -20});
  });
  const CheckResult r = Evaluate(Spec("cop_inside", {{"after", "0.2"}}), t, Summary(z));
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NEAR(r.value, 0.011, kExact);
  EXPECT_NE(r.detail.find("rfsensor"), std::string::npos) << r.detail;
}

TEST(CopInside, PassesAt11mmAndFailsAt9mmInside) {
  for (const double inside : {0.011, 0.009}) {
    // the left CoP near its left (+y) edge, the right one in the middle
    const datalog::Table t = Log(1.0, 0, [inside](double) {
      return std::make_pair(Contact{0.05, 0.07 - inside, 600, -10, 25}, Contact{});
    });
    const CheckResult r = Evaluate(Spec("cop_inside", {{"after", "0"}, {"margin", "0.01"}}), t, Summary());
    EXPECT_EQ(r.passed, inside > 0.01) << inside << ": " << r.detail;
    EXPECT_NEAR(r.value, inside, kExact);
  }
}

TEST(CopInside, FailsNamingTheSensorAndTheTimeOfTheWorstRow) {
  // both soles well inside, but at t = 0.5 s the right one stands on its heel edge
  const datalog::Table t = Log(1.0, 0, [](double t) {
    Contact r;
    if (std::fabs(t - 0.5) < 1e-6) r.px = -0.07 + 0.002;
    else if (std::fabs(t - 0.6) < 1e-6) r.px = -0.07 + 0.005;
    return std::make_pair(Contact{}, r);
  });
  const CheckResult r = Evaluate(Spec("cop_inside", {{"after", "0"}}), t, Summary());
  EXPECT_FALSE(r.passed);
  EXPECT_NEAR(r.value, 0.002, kExact);
  EXPECT_NE(r.detail.find("rfsensor, t=0.5 s"), std::string::npos) << r.detail;
  // the window can leave the bad rows out
  const CheckResult later = Evaluate(Spec("cop_inside", {{"after", "0.7"}}), t, Summary());
  EXPECT_TRUE(later.passed) << later.detail;
}

TEST(CopInside, ALiftedFootIsNotJudgedUnlessItMustBeLoaded) {
  // the left foot lifted (5 N, its "CoP" far outside) over [0.3, 0.7] s
  const datalog::Table t = Log(1.0, 0, [](double t) {
    Contact l;
    if (t > 0.3 && t < 0.7) l = Contact{0.5, 0.3, 5};
    return std::make_pair(l, Contact{});
  });
  const CheckResult r = Evaluate(Spec("cop_inside", {{"after", "0"}}), t, Summary());
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NEAR(r.value, 0.07, kExact);  // both soles centred: 7 cm from the y edges
  // a lighter threshold judges it, and it is outside
  const CheckResult judged = Evaluate(Spec("cop_inside", {{"after", "0"}, {"min_fz", "1"}}), t, Summary());
  EXPECT_FALSE(judged.passed);
  EXPECT_LT(judged.value, 0);
  EXPECT_NE(judged.detail.find("lfsensor"), std::string::npos) << judged.detail;
  // with require_loaded the lifted foot fails
  const CheckResult loaded =
      Evaluate(Spec("cop_inside", {{"after", "0"}, {"require_loaded", "true"}}), t, Summary());
  EXPECT_FALSE(loaded.passed);
  EXPECT_NE(loaded.detail.find("lfsensor carried less than 50 N"), std::string::npos) << loaded.detail;
  // only the right sensor asked for: passes
  const CheckResult right = Evaluate(
      Spec("cop_inside", {{"after", "0"}, {"sensors", "rfsensor"}, {"require_loaded", "true"}}), t, Summary());
  EXPECT_TRUE(right.passed) << right.detail;
}

TEST(CopInside, RefusesWhatItCannotJudge) {
  const datalog::Table t = Log(0.2, 0, [](double) { return std::make_pair(Contact{}, Contact{}); });
  EXPECT_FALSE(Evaluate(Spec("cop_inside", {{"after", "0"}}), t, nlohmann::json::object()).passed);
  EXPECT_FALSE(Evaluate(Spec("cop_inside", {{"after", "0"}, {"sensors", "lhsensor"}}), t, Summary()).passed);
  EXPECT_FALSE(Evaluate(Spec("cop_inside", {{"after", "5"}}), t, Summary()).passed);
  const datalog::Table air = Log(0.2, 0, [](double) { return std::make_pair(Contact{0, 0, 1}, Contact{0, 0, 1}); });
  const CheckResult r = Evaluate(Spec("cop_inside", {{"after", "0"}}), air, Summary());
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("no sole carried"), std::string::npos) << r.detail;
}

TEST(CopInside, CorrectsForTheFootsWeight) {
  // both soles 1.1 cm inside their heel edges, read through a 1.9 kg foot
  const datalog::Table t = Log(0.5, 0, [](double) {
    return std::make_pair(Contact{-0.07 + 0.011, 0.02, 600, 15, -8}, Contact{-0.07 + 0.011, -0.02, 600});
  }, kHrpFoot);
  const CheckResult r = Evaluate(Spec("cop_inside", {{"after", "0"}}), t, Summary(0, kHrpFoot));
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NEAR(r.value, 0.011, kExact);
  // not corrected, the foot's weight moves the CoP by m g (p_x - c_x) / f_z,log behind the heel
  const CheckResult raw = Evaluate(Spec("cop_inside", {{"after", "0"}, {"foot_weight", "false"}}), t, Summary(0, kHrpFoot));
  EXPECT_FALSE(raw.passed) << raw.detail;
  const double w = kHrpFoot.mass * kG;
  EXPECT_NEAR(raw.value, 0.011 + w * (-0.07 + 0.011 - kHrpFoot.com[0]) / (600 - w), kExact);
}

//---------------- foot_lifted ----------------

TEST(FootLifted, PassesWhileTheFootIsInTheAirOnly) {
  // the left foot in the air over [0.4, 0.8] s (2 N of sensor noise), loaded otherwise
  const datalog::Table t = Log(1.0, 0, [](double t) {
    Contact l;
    if (t > 0.35 && t < 0.85) l.fz = 2;
    return std::make_pair(l, Contact{});
  });
  const CheckResult in = Evaluate(Spec("foot_lifted", {{"sensor", "lfsensor"}, {"after", "0.4"}, {"until", "0.8"}}), t, Summary());
  EXPECT_TRUE(in.passed) << in.detail;
  EXPECT_NEAR(in.value, 2, 1e-12);
  EXPECT_EQ(in.name, "foot_lifted_lfsensor");
  const CheckResult wide = Evaluate(Spec("foot_lifted", {{"sensor", "lfsensor"}, {"after", "0.3"}, {"until", "0.8"}}), t, Summary());
  EXPECT_FALSE(wide.passed);
  EXPECT_NEAR(wide.value, 490, 1e-12);
  EXPECT_NE(wide.detail.find("t=0.3 s"), std::string::npos) << wide.detail;
  const CheckResult right = Evaluate(Spec("foot_lifted", {{"sensor", "rfsensor"}, {"after", "0.4"}, {"until", "0.8"}}), t, Summary());
  EXPECT_FALSE(right.passed);
  // a stricter bound below the noise fails
  EXPECT_FALSE(Evaluate(Spec("foot_lifted", {{"sensor", "lfsensor"}, {"after", "0.4"}, {"until", "0.8"}, {"max_fz", "1"}}), t, Summary()).passed);
}

TEST(FootLifted, ALogEndingBeforeTheWindowsEndFails) {
  const datalog::Table t = Log(1.0, 0, [](double) { return std::make_pair(Contact{0, 0, 0}, Contact{}); });
  EXPECT_TRUE(Evaluate(Spec("foot_lifted", {{"sensor", "lfsensor"}, {"after", "0.2"}, {"until", "1.0"}}), t, Summary()).passed);
  const CheckResult r = Evaluate(Spec("foot_lifted", {{"sensor", "lfsensor"}, {"after", "0.2"}, {"until", "2.0"}}), t, Summary());
  EXPECT_FALSE(r.passed);
  EXPECT_FALSE(Evaluate(Spec("foot_lifted", {{"sensor", "lfsensor"}, {"after", "0.2"}}), t, Summary()).passed);
  EXPECT_FALSE(Evaluate(Spec("foot_lifted", {{"sensor", "xx"}, {"after", "0.2"}, {"until", "0.5"}}), t, Summary()).passed);
}

}  // namespace
}  // namespace ohrp::runner
