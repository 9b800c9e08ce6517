// Tests sim_host's pushes on the base as a process, with the real binary: a push acts only while
// it lasts, impulses are exact and overlapping pushes add, bad pushes are refused before the
// segment exists (the fixture: host_process.h).
#include <algorithm>
#include <cmath>

#include "host_process.h"

namespace ohrp::sim {
namespace {

namespace fs = std::filesystem;
using testing::Clock;
using testing::SimHostProcess;
using testing::Since;

// the last logged value of a column of a sim_host data log
double LastLogged(const std::string& log, const std::string& column) {
  std::ifstream in(log);
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line)) last = line;
  std::stringstream hs(header), ls(last);
  std::string name, value;
  while (std::getline(hs, name, ',') && std::getline(ls, value, ','))
    if (name == column) return std::stod(value);
  return std::nan("");
}

// A push on the base of the robot held in its initial pose: the impulse F dt sets the base
// moving forward, by less than the impulse over the mass since the sticking soles resist.
TEST_F(SimHostProcess, PushActsOnTheBaseOnlyWhileItLasts) {
  scene_ = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  const std::string quiet_log = testing::WriteTemp("", ".csv");
  const std::string pushed_log = testing::WriteTemp("", ".csv");
  Start({"--wait-controller", "0", "--duration", "0.3", "--log", quiet_log});
  ASSERT_EQ(Wait(), 0) << Stderr();
  // 150 N forward for 0.1 s at t = 0.2 s: the base moves forward, then settles
  Start({"--wait-controller", "0", "--duration", "0.3", "--log", pushed_log, "--push",
         "0.2,0.3,150,0,0,0,0,0"});
  ASSERT_EQ(Wait(), 0) << Stderr();
  const double quiet = LastLogged(quiet_log, "base_vx");
  const double pushed = LastLogged(pushed_log, "base_vx");
  // an impulse of 15 N s on 130.8 kg gives at most 0.115 m/s; the sticking soles take part
  EXPECT_GT(pushed - quiet, 0.02) << "quiet " << quiet << ", pushed " << pushed;
  EXPECT_LT(pushed - quiet, 0.115);
}

// A free box (2 kg, no gravity, a weightless motorised arm so the segment has a joint): a
// push's impulse is F times its window, exactly, since explicit Euler integrates a constant
// force exactly; overlapping pushes add and nothing stays in xfrc_applied after them.
constexpr const char* kFreeBox = R"(
<mujoco model="freebox">
  <option timestep="0.001" integrator="Euler" gravity="0 0 0"/>
  <worldbody>
    <body name="box">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.1" mass="2" contype="0" conaffinity="0"/>
      <body name="arm">
        <joint name="j" type="hinge" axis="0 0 1" armature="1"/>
        <geom type="sphere" size="0.01" mass="1e-9" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor name="j" joint="j"/></actuator>
</mujoco>
)";

// the value of a column in the first row of a data log at or after `time`
double LoggedAt(const std::string& log, const std::string& column, double time) {
  std::ifstream in(log);
  std::string header, line;
  std::getline(in, header);
  std::vector<std::string> names;
  std::stringstream hs(header);
  for (std::string n; std::getline(hs, n, ',');) names.push_back(n);
  const size_t c = std::find(names.begin(), names.end(), column) - names.begin();
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::vector<double> row;
    for (std::string v; std::getline(ls, v, ',');) row.push_back(std::stod(v));
    if (row.size() > c && row[0] >= time - 1e-9) return row[c];
  }
  return std::nan("");
}

TEST_F(SimHostProcess, PushImpulsesAreExactAndOverlappingPushesAdd) {
  scene_ = testing::WriteTemp(kFreeBox);
  const std::string log = testing::WriteTemp("", ".csv");
  // 10 N along x over [0.1, 0.3) s and 20 N along x plus 4 N along y over [0.2, 0.25) s
  Start({"--wait-controller", "0", "--contact", "native", "--duration", "0.5", "--log", log,
         "--push", "0.1,0.3,10,0,0,0,0,0", "--push", "0.2,0.25,20,4,0,0,0,0"});
  ASSERT_EQ(Wait(), 0) << Stderr();
  constexpr double kMass = 2 + 1e-9;  // [kg]
  constexpr double kTol = 1e-9;       // [m/s] round-off of 500 Euler steps
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.1), 0.0, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.2), 10 * 0.1 / kMass, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.25), (10 * 0.15 + 20 * 0.05) / kMass, kTol);
  // after both windows: J = 10 x 0.2 + 20 x 0.05 = 3 N s along x, 4 x 0.05 = 0.2 N s along y,
  // and the velocity stays there (no wrench left behind)
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.3), 3.0 / kMass, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.5), 3.0 / kMass, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vy", 0.5), 0.2 / kMass, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vz", 0.5), 0.0, kTol);
}

TEST_F(SimHostProcess, BadPushesAreRefusedBeforeTheSegmentExists) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0.3,0.2,1,0,0,0,0,0", "0 <= t0 < t1"},   // the window ends before it starts
      {"0.2,0.2,1,0,0,0,0,0", "0 <= t0 < t1"},   // empty window
      {"-1,0.2,1,0,0,0,0,0", "0 <= t0 < t1"},    // before the start
      {"0.1,0.2,1,0,0", "5 values, expected 8"},  // too few
      {"0.1,0.2,1,0,0,0,0,0,0", "more than 8"},  // too many
      {"0.1,0.2,inf,0,0,0,0,0", "not finite"},
      {"0.1,0.2,nan,0,0,0,0,0", "not finite"},
      {"0.1,0.2,1x,0,0,0,0,0", "not a number"},
      {"0.1,,1,0,0,0,0,0", "not a number"}};
  for (const auto& [spec, message] : cases) {
    Start({"--wait-controller", "0", "--duration", "0.1", "--push", "0.1,0.2,1,0,0,0,0,0", "--push", spec});
    EXPECT_EQ(Wait(), 2) << spec;
    EXPECT_NE(Stderr().find(message), std::string::npos) << spec << ": " << Stderr();
    EXPECT_NE(Stderr().find("t0,t1,fx,fy,fz,tx,ty,tz"), std::string::npos) << Stderr();
    EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_))) << spec;
  }
  // the arm has no free base to push
  Start({"--wait-controller", "0", "--duration", "0.1", "--push", "0.1,0.2,1,0,0,0,0,0"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("no free joint"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
}

}  // namespace
}  // namespace ohrp::sim
