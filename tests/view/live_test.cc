// ohrp_view on a running segment (tools/view/src/live.cc): headless Chromium shows HRP-1S
// standing under sim_host + posture, and its plots advance with simulated time; a viewer that
// is stopped (SIGSTOP) or killed never slows or breaks the lock-step run; a segment that does
// not exist is refused with a clear message and exit code 2.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <thread>

#include "browser.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "shm_bridge/bridge.h"
#include "view_process.h"

namespace ohrp::view::testing {
namespace {

class Live : public ::testing::Test {
 protected:
  void SetUp() override {
    segment_ = shm::testing::UniqueSegment("view");
    shm::testing::RemoveSegment(segment_);
    dir_ = fs::temp_directory_path() / ("ohrp_view_live_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    for (pid_t p : children_) {
      kill(p, SIGCONT);
      kill(p, SIGKILL);
      shm::testing::WaitExit(p, 5.0);
    }
    shm::testing::RemoveSegment(segment_);
    fs::remove_all(dir_);
  }
  // sim_host on the flat floor (lock-step unless `realtime`); it waits for posture
  pid_t StartSim(double duration, bool realtime) {
    std::vector<std::string> args{kScene, "--segment", segment_, "--duration", std::to_string(duration),
                                  "--progress", "0", "--wait-controller", "20"};
    if (realtime) args.push_back("--realtime");
    const pid_t sim = Start("sim_host", args, (dir_ / "sim_host.txt").string());
    children_.push_back(sim);
    return sim;
  }
  pid_t StartPosture() {
    const pid_t posture = Start("posture", {"--segment", segment_, "--attach-timeout", "20"},
                                (dir_ / "posture.txt").string());
    children_.push_back(posture);
    return posture;
  }
  std::string segment_;
  fs::path dir_;
  std::vector<pid_t> children_;
};

TEST_F(Live, ShowsTheRobotAndThePlotsAdvanceWithSimulatedTime) {
  StartSim(60, true);
  StartPosture();
  Viewer viewer;
  StartViewer(&viewer, {segment_, "--port", "0", "--attach-timeout", "20"}, (dir_ / "viewer.txt").string());
  ASSERT_FALSE(viewer.url.empty()) << ReadAll(viewer.out_file);
  Browser browser(viewer.url);
  ASSERT_TRUE(browser.ok()) << browser.error();
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.points > 20"));
  const double t1 = browser.Eval("Number(document.getElementById('state').dataset.t)").get<double>();
  const double p1 = browser.Eval("Number(document.getElementById('state').dataset.points)").get<double>();
  const double f1 = browser.Eval("Number(document.getElementById('state').dataset.frames)").get<double>();
  const double w1 = shm::testing::Now();
  usleep(2000000);
  const double rate = (browser.Eval("Number(document.getElementById('state').dataset.frames)").get<double>() - f1) /
                      (shm::testing::Now() - w1);
  std::printf("frames drawn by the page: %.1f per second (the viewer sends at most 30)\n", rate);
  EXPECT_GT(rate, 5.0);
  const double t2 = browser.Eval("Number(document.getElementById('state').dataset.t)").get<double>();
  const double p2 = browser.Eval("Number(document.getElementById('state').dataset.points)").get<double>();
  // real time: about 2 s of simulated time in 2 s, and more points in the plots
  EXPECT_GT(t2, t1 + 1.0);
  EXPECT_GT(p2, p1);
  EXPECT_NE(browser.Eval("document.getElementById('status').textContent").get<std::string>().find("simulated"),
            std::string::npos);
  EXPECT_EQ(browser.Eval("document.getElementById('base').textContent").get<std::string>(),
            "base pose: ground truth");
  // the robot in the canvas
  const std::string out = OutputDir("live");
  ASSERT_TRUE(browser.Screenshot(out + "/live.png"));
  const nlohmann::json r = nlohmann::json::parse(browser.Eval(
      "JSON.stringify(document.getElementById('view3d').getBoundingClientRect())").get<std::string>());
  const PixelCount robot = CountPixels(out + "/live.png", r["left"].get<int>(), r["top"].get<int>(),
                                       r["right"].get<int>(), r["bottom"].get<int>(), RobotGreen);
  EXPECT_GT(robot.n, 2000) << out << "/live.png";
}

TEST_F(Live, AStoppedOrKilledViewerDoesNotSlowTheLockStep) {
  // the same lock-step run without a viewer, then with one stopped and one killed before the
  // controller starts (the run's time is taken from then)
  auto run = [&](bool viewers) {
    const pid_t sim = StartSim(30.0, false);
    Viewer stopped, killed;
    if (viewers) {
      StartViewer(&stopped, {segment_, "--port", "0", "--attach-timeout", "20"}, (dir_ / "v1.txt").string());
      StartViewer(&killed, {segment_, "--port", "0", "--attach-timeout", "20"}, (dir_ / "v2.txt").string());
      EXPECT_FALSE(stopped.url.empty() || killed.url.empty()) << ReadAll(dir_ / "v1.txt");
      kill(stopped.pid, SIGSTOP);
      kill(killed.pid, SIGKILL);
    }
    const double t0 = shm::testing::Now();
    const pid_t posture = StartPosture();
    EXPECT_EQ(shm::testing::WaitExit(sim, 60.0), 0) << ReadAll(dir_ / "sim_host.txt");
    EXPECT_EQ(shm::testing::WaitExit(posture, 10.0), 0) << ReadAll(dir_ / "posture.txt");
    return shm::testing::Now() - t0;
  };
  const double alone = run(false);
  const double watched = run(true);
  std::printf("lock-step 30 s run: %.2f s alone, %.2f s with a stopped and a killed viewer\n", alone, watched);
  EXPECT_LT(watched, 1.5 * alone + 1.0);
}

// a hardware producer (no ground truth): the base pose comes from the IMU and the page says so
TEST_F(Live, AHardwareProducersBaseIsLabelledAsEstimatedFromTheImu) {
  std::string error;
  auto scene = model::Scene::Load(kScene, &error);
  ASSERT_TRUE(scene) << error;
  model::RobotMap robot;
  ASSERT_TRUE(model::MapRobot(scene->m(), &robot, &error)) << error;
  shm::ProducerConfig config = model::MakeProducerConfig(robot, scene->m(), segment_, 0.0, 0.005);
  config.kind = shm::ProducerKind::kHardware;
  shm::Status status;
  auto producer = shm::Producer::Create(config, &status);
  ASSERT_TRUE(producer) << status.message;
  // sensor blocks at 200 Hz: straight joints, the IMU tilted 20 deg about x, no kSimulated
  std::atomic<bool> stop{false};
  std::thread publisher([&] {
    for (uint64_t k = 0; !stop; ++k) {
      shm::SensorBlock& s = producer->BeginSensors();
      s.cycle = k;
      s.time = 0.005 * k;
      s.status = shm::status::kRunning | shm::status::kNoController;
      const double half = 10.0 * M_PI / 180;
      s.imu[0].quat_WI[0] = std::cos(half);
      s.imu[0].quat_WI[1] = std::sin(half);
      producer->PublishSensors();
      usleep(5000);
    }
  });
  Viewer viewer;
  StartViewer(&viewer, {segment_, "--port", "0"}, (dir_ / "viewer.txt").string());
  EXPECT_FALSE(viewer.url.empty()) << ReadAll(viewer.out_file);
  if (!viewer.url.empty()) {
    Browser browser(viewer.url);
    EXPECT_TRUE(browser.ok()) << browser.error();
    EXPECT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 2"));
    EXPECT_EQ(browser.Eval("document.getElementById('base').textContent").get<std::string>(),
              "base pose: estimated from IMU");
    EXPECT_EQ(browser.Eval("document.getElementById('title').textContent").get<std::string>(),
              "segment " + segment_ + " (hardware)");
    browser.Screenshot(OutputDir("live") + "/hardware_imu.png");
  }
  stop = true;
  publisher.join();
}

// ohrp_run --view: a viewer on the run's segment, which prints its URL and ends with the run
TEST_F(Live, RunWithViewStartsAViewerThatEndsWithTheRun) {
  std::ofstream(dir_ / "short.yaml") << "name: short\nscene: " << kScene
                                     << "\nduration: 1.0\ncontrollers:\n  - program: posture\n"
                                     << "checks:\n  - {type: not_fallen}\n";
  const std::string out = (dir_ / "run.txt").string();
  const pid_t run = Start("ohrp_run", {(dir_ / "short.yaml").string(), "--view", "--realtime", "--no-plot",
                                       "-q", "--out", (dir_ / "out").string()}, out);
  EXPECT_EQ(shm::testing::WaitExit(run, 60.0), 0) << ReadAll(out);
  EXPECT_NE(ReadAll(out).find("ohrp_view: serving http://127.0.0.1:"), std::string::npos) << ReadAll(out);
}

// a one-joint robot on the segment, HRP-1S in the viewer's (default) scene: refused by the hash
TEST_F(Live, AnotherRobotsSceneIsRefused) {
  std::ofstream(dir_ / "pendulum.xml") << R"(<mujoco model="pendulum"><option timestep="0.001"/><worldbody>
    <geom type="plane" size="5 5 0.1"/>
    <body name="base" pos="0 0 1"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/>
      <body name="link"><joint name="j1" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.03" mass="0.5"/></body></body>
    </worldbody><actuator><motor joint="j1" ctrllimited="true" ctrlrange="-10 10"/></actuator></mujoco>)";
  const pid_t sim = Start("sim_host", {(dir_ / "pendulum.xml").string(), "--segment", segment_, "--realtime",
                                       "--duration", "30", "--wait-controller", "0", "--progress", "0"},
                          (dir_ / "sim_host.txt").string());
  children_.push_back(sim);
  const std::string out = (dir_ / "viewer.txt").string();
  const pid_t pid = Start("ohrp_view", {segment_, "--attach-timeout", "20"}, out);
  EXPECT_EQ(shm::testing::WaitExit(pid, 30.0), 2) << ReadAll(out) << ReadAll(dir_ / "sim_host.txt");
  EXPECT_NE(ReadAll(out).find("does not hold the robot of segment"), std::string::npos) << ReadAll(out);
}

TEST_F(Live, ANonexistentSegmentIsRefused) {
  const std::string out = (dir_ / "viewer.txt").string();
  const pid_t pid = Start("ohrp_view", {segment_}, out);
  EXPECT_EQ(shm::testing::WaitExit(pid, 20.0), 2);
  EXPECT_NE(ReadAll(out).find("no segment '" + segment_ + "'"), std::string::npos) << ReadAll(out);
}

}  // namespace
}  // namespace ohrp::view::testing
