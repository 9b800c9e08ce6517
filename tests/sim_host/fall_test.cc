// sim_host's fall watch as a process (issue 28 item 1; sim_host/fall.h): small robots on a floor,
// held by sim_host's servos (no controller), that tip over, sink, spin or stand; the exit code,
// the summary's "fall" and "events", --on-fall continue, allowed bodies, a harness; and absurd
// time steps refused before anything runs (item 6). Fixture: host_process.h.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "host_process.h"

namespace ohrp::sim {
namespace {

namespace fs = std::filesystem;
using testing::SimHostProcess;

constexpr int kExitFellCode = 6;  // sim_host/exit_codes.h kExitFell

// A rigid one-legged robot: a torso box (the free base) with a bar 0.6 m forward (arms held
// out), a leg capsule and a foot body with the sole box F_SOLE 0.55 m below the torso's origin,
// and a small motorised arm (the segment needs a joint). Tilted by `theta` about y with the
// sole's lowest corner 1 mm above the floor: tilted, the torso is ahead of the foot and the robot
// tips forward; the bar's end reaches the floor at about 44 deg from the vertical, the base then
// 0.44 m above the sole (the height limit is 0.28 m, the tilt limit 60 deg from the start).
std::string Tipper(double theta, double foot_half, bool floor = true, double gravity = -9.81,
                   const std::string& extra = "") {
  const double s = std::sin(theta), c = std::cos(theta);
  const double sole_z = 0.001 + s * foot_half + c * 0.01;  // the sole's centre above the floor
  const double px = 0.55 * s, pz = sole_z + 0.55 * c;       // the torso's origin
  char xml[2048];
  std::snprintf(xml, sizeof(xml), R"(
<mujoco model="tipper">
  <option timestep="0.001" integrator="Euler" gravity="0 0 %g"/>
  <worldbody>
    %s
    <body name="torso" pos="%.6f 0 %.6f" quat="%.9f 0 %.9f 0">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.1"/>
      <geom type="capsule" fromto="0 0 0 0.6 0 0" size="0.02"/>
      <body name="leg">
        <geom type="capsule" fromto="0 0 -0.1 0 0 -0.5" size="0.03" contype="0" conaffinity="0"/>
        <body name="foot" pos="0 0 -0.55">
          <geom name="F_SOLE" type="box" size="%g %g 0.01"/>
        </body>
      </body>
      <body name="arm" pos="0 0.15 0">
        <joint name="shoulder" type="hinge" axis="0 1 0" armature="0.1"/>
        <geom type="sphere" size="0.02" mass="0.1"/>
      </body>
    </body>
  </worldbody>
  %s
  <actuator><motor name="shoulder" joint="shoulder"/></actuator>
</mujoco>
)", gravity, floor ? R"(<geom name="floor" type="plane" size="5 5 0.1"/>)" : "", px, pz,
                std::cos(theta / 2), std::sin(theta / 2), foot_half, foot_half, extra.c_str());
  return xml;
}

// A torso (the free base, 10 kg) above a light foot on a frictionless passive slide: the foot
// stands on the floor and the torso drops freely, so the base's height above the sole is
// h(t) = 0.510 m - g t^2 / 2 (to the sole's millimetre in the floor).
constexpr const char* kSinker = R"(
<mujoco model="sinker">
  <option timestep="0.001" integrator="Euler"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="torso" pos="0 0 0.511">
      <freejoint/>
      <geom type="box" size="0.05 0.05 0.05" mass="10"/>
      <body name="foot" pos="0 0 -0.5">
        <joint name="sink" type="slide" axis="0 0 1" limited="true" range="0 0.45"/>
        <geom name="F_SOLE" type="box" size="0.1 0.1 0.01" mass="0.1"/>
      </body>
      <body name="arm" pos="0 0.1 0">
        <joint name="shoulder" type="hinge" axis="0 1 0" armature="0.1"/>
        <geom type="sphere" size="0.02" mass="0.1"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor name="shoulder" joint="shoulder"/></actuator>
</mujoco>
)";

class Falls : public SimHostProcess {
 protected:
  // sim_host on `xml` without a controller (the servo holds the start), native contact
  int Run(const std::string& xml, double duration, std::vector<std::string> extra = {}) {
    scene_ = testing::WriteTemp(xml);
    summary_ = testing::WriteTemp("", ".json");
    std::vector<std::string> args = {"--wait-controller", "0", "--contact", "native", "--duration",
                                     std::to_string(duration), "--summary", summary_};
    args.insert(args.end(), extra.begin(), extra.end());
    Start(args);
    return Wait(30);
  }
  nlohmann::json Summary() {
    std::ifstream in(summary_);
    nlohmann::json j;
    in >> j;
    return j;
  }
  // the summary's events of kind `kind`
  static std::vector<nlohmann::json> Events(const nlohmann::json& j, const std::string& kind) {
    std::vector<nlohmann::json> out;
    for (const auto& e : j["events"])
      if (e["event"] == kind) out.push_back(e);
    return out;
  }
  std::string summary_;
};

TEST_F(Falls, ATippingRobotEndsTheRunWithTheFallsExitCodeTimeAndCause) {
  ASSERT_EQ(Run(Tipper(0.2, 0.05), 5.0), kExitFellCode) << Stderr();
  const nlohmann::json j = Summary();
  EXPECT_EQ(j["outcome"], "fell");
  EXPECT_EQ(j["exit_code"], kExitFellCode);
  ASSERT_TRUE(j["fall"].is_object()) << j.dump(2);
  const auto& f = j["fall"];
  EXPECT_EQ(f["kind"], "contact");
  EXPECT_EQ(f["body"], "torso") << f.dump();
  // the bar touches at about 44 deg from the vertical, 32.5 deg from the start's 11.5
  EXPECT_GT(f["tilt_deg"].get<double>(), 29.0);
  EXPECT_LT(f["tilt_deg"].get<double>(), 36.0);
  EXPECT_EQ(f["ground"], "floor");
  // it tips from 11.5 deg: not at once, and well within the 5 s; the run ends at the fall
  EXPECT_GT(f["time"].get<double>(), 0.2);
  EXPECT_LT(f["time"].get<double>(), 3.0);
  EXPECT_NEAR(j["sim_time"].get<double>(), f["time"].get<double>(), 1e-9);
  EXPECT_NE(f["cause"].get<std::string>().find("touched floor"), std::string::npos) << f.dump();
  // one event "fall" with the same time and cycle, and the cause
  const auto falls = Events(j, "fall");
  ASSERT_EQ(falls.size(), 1u) << j["events"].dump();
  EXPECT_EQ(falls[0]["time"], f["time"]);
  EXPECT_EQ(falls[0]["cycle"], f["cycle"]);
  EXPECT_EQ(falls[0]["cause"], f["cause"]);
  EXPECT_NE(j["detail"].get<std::string>().find("the robot fell at t="), std::string::npos);
  EXPECT_NE(Stderr().find("FELL at t="), std::string::npos) << Stderr();
  EXPECT_EQ(Stderr().find(": completed:"), std::string::npos) << Stderr();
}

TEST_F(Falls, OnFallContinueKeepsSimulatingAndStillExitsWithTheFall) {
  ASSERT_EQ(Run(Tipper(0.2, 0.05), 3.0, {"--on-fall", "continue"}), kExitFellCode) << Stderr();
  const nlohmann::json j = Summary();
  EXPECT_EQ(j["outcome"], "fell");
  EXPECT_NEAR(j["sim_time"].get<double>(), 3.0, 1e-6);  // ran to the end
  ASSERT_TRUE(j["fall"].is_object());
  EXPECT_LT(j["fall"]["time"].get<double>(), 3.0);
  EXPECT_EQ(Events(j, "fall").size(), 1u);  // the first fall only
}

TEST_F(Falls, AStandingRobotDoesNotFall) {
  ASSERT_EQ(Run(Tipper(0.0, 0.2), 1.0), 0) << Stderr();
  const nlohmann::json j = Summary();
  EXPECT_EQ(j["outcome"], "completed");
  EXPECT_TRUE(j["fall"].is_null());
  EXPECT_TRUE(j["fall_watch"]["on"].get<bool>());
  EXPECT_TRUE(Events(j, "fall").empty());
  // the start height: the torso's origin above the sole's bottom, 0.55 + 0.01 m
  EXPECT_NEAR(j["fall_watch"]["start_height"].get<double>(), 0.56, 1e-9);
  EXPECT_NEAR(j["fall_watch"]["min_height"].get<double>(), 0.28, 1e-9);
}

TEST_F(Falls, TheBaseSinkingBelowHalfItsHeightIsAFallAtTheFreeFallsTime) {
  ASSERT_EQ(Run(kSinker, 2.0), kExitFellCode) << Stderr();
  const nlohmann::json j = Summary();
  const auto& f = j["fall"];
  ASSERT_TRUE(f.is_object()) << j.dump(2);
  EXPECT_EQ(f["kind"], "height");
  // h0 = 0.510 m; below 0.255 m when g t^2 / 2 > 0.256 m less the sole's depth in the floor
  // (0 to 2 mm): t in [0.2285, 0.2294] s; then up to one control period (2 ms) and one physics
  // step (the kinematics lag the state by a step) late, and Euler's drop slightly ahead
  EXPECT_NEAR(j["fall_watch"]["start_height"].get<double>(), 0.510, 1e-9);
  EXPECT_GT(f["time"].get<double>(), 0.2285 - 0.002);
  EXPECT_LT(f["time"].get<double>(), 0.2294 + 0.004);
  EXPECT_LT(f["height"].get<double>(), 0.255);
  EXPECT_GT(f["height"].get<double>(), 0.255 - 0.02);  // about g t dt of one cycle below
}

TEST_F(Falls, TiltingPastTheLimitIsAFall) {
  // no gravity, no floor: a torque about x spins the robot until its vertical passes 60 deg
  ASSERT_EQ(Run(Tipper(0.0, 0.05, false, 0.0), 2.0, {"--push", "0,0.3,0,0,0,20,0,0"}), kExitFellCode)
      << Stderr();
  const auto f = Summary()["fall"];
  ASSERT_TRUE(f.is_object());
  EXPECT_EQ(f["kind"], "tilt");
  EXPECT_GE(f["tilt_deg"].get<double>(), 60.0);
  EXPECT_LT(f["tilt_deg"].get<double>(), 65.0);  // seen within a cycle of the crossing
}

TEST_F(Falls, AnAllowedBodyMayTouchTheGround) {
  // the torso (and all below it) may touch: the robot tips onto its bar and leans there, 33 deg
  // from its start, well above the height limit: no fall
  ASSERT_EQ(Run(Tipper(0.2, 0.05), 2.0, {"--fall-allow-contact", "torso"}), 0) << Stderr();
  EXPECT_TRUE(Summary()["fall"].is_null());
  // an unknown body is refused before anything runs
  EXPECT_EQ(Run(Tipper(0.2, 0.05), 1.0, {"--fall-allow-contact", "hand"}), 2);
  EXPECT_NE(Stderr().find("'hand' is not a body of the robot"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
}

TEST_F(Falls, AHungRobotCannotFallAndSaysSo) {
  ASSERT_EQ(Run(Tipper(0.2, 0.05, true, -9.81, R"(<equality><weld body1="torso"/></equality>)"), 1.0), 0)
      << Stderr();
  const nlohmann::json j = Summary();
  EXPECT_FALSE(j["fall_watch"]["on"].get<bool>());
  EXPECT_TRUE(j["fall"].is_null());
  EXPECT_NE(Stderr().find("fall watch off: the robot is held to the world by the weld"), std::string::npos)
      << Stderr();
}

TEST_F(Falls, AbsurdTimeStepsAreRefusedBeforeAnythingRuns) {
  // sim_host on `scene` with `extra`, without the fixture's --physics-dt
  auto run = [&](const std::string& scene, std::vector<std::string> extra) {
    std::vector<std::string> args = {std::string(OHRP_BIN_DIR) + "/sim_host", "--scene", scene,
                                     "--segment", segment_, "--wait-controller", "0",
                                     "--duration", "1"};
    args.insert(args.end(), extra.begin(), extra.end());
    pid_ = ohrp::testing::Spawn(args, {.err = err_});
    return Wait();
  };
  // --physics-dt 1e-300
  EXPECT_EQ(run(testing::WriteTemp(Tipper(0.0, 0.2)), {"--physics-dt", "1e-300"}), 2);
  EXPECT_NE(Stderr().find("--physics-dt: 1e-300 is outside the plausible range"), std::string::npos)
      << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
  // a scene's timestep="1e308"
  std::string xml = Tipper(0.0, 0.2);
  xml.replace(xml.find("timestep=\"0.001\""), 16, "timestep=\"1e308\"");
  EXPECT_EQ(run(testing::WriteTemp(xml), {}), 2);
  EXPECT_NE(Stderr().find("<option timestep> = 1e+308 is outside the plausible range"), std::string::npos)
      << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
}

}  // namespace
}  // namespace ohrp::sim
