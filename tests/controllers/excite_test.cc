// Tests the excite controller in process: its signals against their closed forms, the
// references kept inside the limits and the rate bound, the rest of the body held, a joint that
// leaves its band failing the run, the log, and its refusals.
#include "controllers/excite.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "common/scratch.h"

namespace ohrp::controllers {
namespace {

constexpr double kPeriod = 0.005;

shm::SegmentHeader Header() {
  shm::SegmentHeader h{};
  h.njoint = 3;
  h.control_period = kPeriod;
  for (int j = 0; j < 3; ++j) {
    std::snprintf(h.joint_names[j], shm::kNameLen, "J%d", j);
    h.q_min[j] = -1.0;
    h.q_max[j] = 1.0;
    h.default_kp[j] = 100.0;
    h.default_kd[j] = 10.0;
  }
  return h;
}

TEST(ExciteSignal, TheChirpSweepsItsBandAndStepsAndPrbsAreTheirClosedForms) {
  ExciteOptions o;
  o.f_min = 0.5, o.f_max = 4.5, o.duration = 8.0;
  const std::vector<int8_t> none;
  // chirp: inside the fades sin(2 pi (f_min t + (f_max - f_min) t^2 / 2T))
  for (double t : {1.0, 2.3, 4.0, 7.1}) {
    const double phase = 2 * M_PI * (0.5 * t + 4.0 * t * t / 16.0);
    EXPECT_NEAR(ExciteSignalValue(ExciteSignal::kChirp, o, none, t), std::sin(phase), 1e-12) << t;
  }
  // the instantaneous frequency, from the zero crossings of a second: f_min + (f_max-f_min) t/T
  auto crossings = [&](double a, double b) {
    int n = 0;
    double last = ExciteSignalValue(ExciteSignal::kChirp, o, none, a);
    for (double t = a + 1e-4; t <= b; t += 1e-4) {
      const double v = ExciteSignalValue(ExciteSignal::kChirp, o, none, t);
      n += (v > 0) != (last > 0);
      last = v;
    }
    return n;
  };
  EXPECT_NEAR(crossings(1.0, 2.0) / 2.0, 0.5 + 4.0 * 1.5 / 8.0, 0.51);
  EXPECT_NEAR(crossings(6.0, 7.0) / 2.0, 0.5 + 4.0 * 6.5 / 8.0, 0.51);
  EXPECT_EQ(ExciteSignalValue(ExciteSignal::kChirp, o, none, 0.0), 0.0);  // faded in
  EXPECT_EQ(ExciteSignalValue(ExciteSignal::kChirp, o, none, -0.1), 0.0);
  EXPECT_EQ(ExciteSignalValue(ExciteSignal::kChirp, o, none, 8.1), 0.0);
  // steps: +1, -1 in turn, each 1 / (2 f_min) = 1 s
  EXPECT_EQ(ExciteSignalValue(ExciteSignal::kSteps, o, none, 0.5), 1.0);
  EXPECT_EQ(ExciteSignalValue(ExciteSignal::kSteps, o, none, 1.5), -1.0);
  EXPECT_EQ(ExciteSignalValue(ExciteSignal::kSteps, o, none, 2.5), 1.0);
  // prbs: a maximal-length sequence: 256 ones and 255 minus ones, and its circular
  // autocorrelation -1 at every lag but 0
  const std::vector<int8_t> bits = PrbsBits(1);
  ASSERT_EQ(bits.size(), 511u);
  int sum = 0;
  for (int8_t b : bits) sum += b;
  EXPECT_EQ(sum, 1);
  for (int lag : {1, 2, 7, 100, 255, 510}) {
    int c = 0;
    for (int i = 0; i < 511; ++i) c += bits[i] * bits[(i + lag) % 511];
    EXPECT_EQ(c, -1) << lag;
  }
  // each bit held 0.44 / f_max
  const double bit = kPrbsBitFactor / o.f_max;
  for (int k : {0, 1, 2, 3, 50})
    EXPECT_EQ(ExciteSignalValue(ExciteSignal::kPrbs, o, bits, (k + 0.5) * bit), bits[k]) << k;
}

// A robot whose joints follow their references exactly, one cycle late; `push` adds to J1.
struct FollowingRobot {
  ExciteController c;
  shm::SensorBlock s{};
  shm::CommandBlock cmd{};
  explicit FollowingRobot(const ExciteOptions& o, double q_start = 0.1) : c(o) {
    EXPECT_TRUE(c.configure(Header()).ok());
    for (int j = 0; j < 3; ++j) s.q[j] = q_start;
    cmd.njoint = 3;
    EXPECT_TRUE(c.activate(s));
  }
  void Step(double push = 0) {
    ASSERT_TRUE(c.update(s, &cmd));
    s.time += kPeriod;
    for (int j = 0; j < 3; ++j) s.q[j] = cmd.joint[j].q_ref + (j == 1 ? push : 0);
  }
};

TEST(ExciteController, DrivesOnlyItsJointsWithinTheLimitsAndTheRateBound) {
  ExciteOptions o;
  o.joints = {"J1"};
  o.signal = "steps";
  o.amplitude = 1.0;  // from 0.1: +1 would pass the limit 1.0
  o.f_min = 0.25;     // each step 2 s
  o.duration = 4.0;
  o.start = 0.5;
  o.max_velocity = 1.0;
  o.margin = 0.05;
  o.band = 0.1;
  FollowingRobot r(o);
  double max_rate = 0, max_q = -1, min_q = 1;
  double prev = r.s.q[1];
  for (int k = 0; k < static_cast<int>(7.0 / kPeriod); ++k) {
    r.Step();
    max_rate = std::fmax(max_rate, std::fabs(r.cmd.joint[1].q_ref - prev) / kPeriod);
    prev = r.cmd.joint[1].q_ref;
    max_q = std::fmax(max_q, prev);
    min_q = std::fmin(min_q, prev);
    EXPECT_EQ(r.cmd.joint[0].q_ref, 0.1);  // the others held
    EXPECT_EQ(r.cmd.joint[2].q_ref, 0.1);
    EXPECT_EQ(r.cmd.joint[0].kp, 100.0);
    if (k * kPeriod < 0.5) {
      EXPECT_EQ(prev, 0.1);  // held during --start
    }
  }
  EXPECT_LE(max_rate, 1.0 + 1e-9);
  EXPECT_NEAR(max_q, 1.0 - 0.05, 1e-12);  // +1 kept --margin inside the limit
  EXPECT_NEAR(min_q, 0.1 - 1.0, 1e-12);   // -1 reachable
  EXPECT_NEAR(prev, 0.1, 1e-12);          // back at the start after the signal
  EXPECT_GT(r.c.limited_cycles(), 0u);
  EXPECT_EQ(r.c.failure(), "");
}

TEST(ExciteController, AJointLeavingItsBandFailsTheRunAndStopsTheExcitation) {
  ExciteOptions o;
  o.joints = {"J1"};
  o.amplitude = 0.1, o.band = 0.05, o.duration = 4.0, o.start = 0;
  FollowingRobot r(o, 0.0);
  for (int k = 0; k < 200; ++k) r.Step(k > 100 ? 0.2 : 0.0);  // pushed off by 0.2 rad
  const std::string f = r.c.failure();
  EXPECT_NE(f.find("joint J1 left its band"), std::string::npos) << f;
  for (int k = 0; k < 200; ++k) r.Step();
  EXPECT_NEAR(r.cmd.joint[1].q_ref, 0.0, 1e-9);  // back to where it started, held
}

TEST(ExciteController, TheLogHasOneRowPerCycleWithReferenceAndMeasurement) {
  ExciteOptions o;
  o.joints = {"J2", "J0"};
  o.duration = 1.0, o.start = 0;
  o.log_file = ohrp::testing::ScratchPath("excite", ".csv");
  FollowingRobot r(o);
  for (int k = 0; k < 50; ++k) r.Step();
  std::ostringstream out;
  r.c.report(out);
  std::ifstream in(o.log_file);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "time,J2_ref,J2_q,J2_dq,J2_tau,J0_ref,J0_q,J0_dq,J0_tau");
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 50);
  EXPECT_NE(out.str().find("50 rows"), std::string::npos) << out.str();
}

// a log that cannot be written whole (a full disk: /dev/full) fails the run, naming the file
TEST(ExciteController, ALogNotWrittenFailsTheRun) {
  ExciteOptions o;
  o.joints = {"J1"};
  o.duration = 1.0, o.start = 0;
  o.log_file = "/dev/full";
  FollowingRobot r(o);
  for (int k = 0; k < 50; ++k) r.Step();
  std::ostringstream out;
  r.c.report(out);
  EXPECT_NE(out.str().find("excite: log NOT written: cannot write '/dev/full'"), std::string::npos) << out.str();
  EXPECT_EQ(r.c.failure().rfind("--log: cannot write '/dev/full': ", 0), 0u) << r.c.failure();
}

TEST(ExciteController, BadOptionsAndUnknownJointsAreRefused) {
  ExciteOptions o;
  EXPECT_NE(CheckExciteOptions(o).find("--joints"), std::string::npos);
  o.joints = {"J1"};
  EXPECT_EQ(CheckExciteOptions(o), "");
  ExciteOptions bad = o;
  bad.f_min = 3, bad.f_max = 2;
  EXPECT_NE(CheckExciteOptions(bad).find("f_min < f_max"), std::string::npos);
  bad = o;
  bad.signal = "noise";
  EXPECT_NE(CheckExciteOptions(bad).find("chirp, steps or prbs"), std::string::npos);
  bad = o;
  bad.amplitude = -0.1;
  EXPECT_NE(CheckExciteOptions(bad).find("--amplitude"), std::string::npos);
  bad = o;
  bad.joints = {"J1", "J9"};
  ExciteController c(bad);
  const ConfigStatus s = c.configure(Header());
  EXPECT_EQ(s.code, ConfigError::kUnknownJoint);
  EXPECT_NE(s.message.find("no joint 'J9' (it has J0, J1, J2)"), std::string::npos) << s.message;
}

}  // namespace
}  // namespace ohrp::controllers
