// ohrp_view on a running segment (tools/view/src/live.cc): headless Chromium shows HRP-1S
// standing under sim_host + posture, and its plots advance with simulated time; a viewer that
// is stopped (SIGSTOP) or killed never slows or breaks the lock-step run; a segment that does
// not exist is refused with a clear message and exit code 2; the camera images are shown only
// while a page asks, and then they are the segment's pixels; a robot of meshes is drawn.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <functional>
#include <thread>
#include <vector>

#include "browser.h"
#include "common/scratch.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "shm_bridge/bridge.h"
#include "shm_bridge/observer.h"
#include "view_process.h"

namespace ohrp::view::testing {
namespace {

class Live : public ::testing::Test {
 protected:
  void SetUp() override {
    segment_ = shm::testing::UniqueSegment("view");
    shm::testing::RemoveSegment(segment_);
    dir_ = ohrp::testing::ScratchFolder("live");
  }
  void TearDown() override {
    for (pid_t p : children_) ohrp::testing::Kill(p);
    shm::testing::RemoveSegment(segment_);
    fs::remove_all(dir_);
  }
  // sim_host on the flat floor (lock-step unless `realtime`); it waits for posture
  pid_t StartSim(double duration, bool realtime, const std::string& scene = kScene,
                 const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args{scene, "--segment", segment_, "--duration", std::to_string(duration),
                                  "--progress", "0", "--wait-controller", "20"};
    if (realtime) args.push_back("--realtime");
    args.insert(args.end(), extra.begin(), extra.end());
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
  ASSERT_FALSE(viewer.url.empty()) << ReadFile(viewer.out_file);
  Browser browser(viewer.url);
  ASSERT_TRUE(browser.ok()) << browser.error();
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.points > 20"));
  const double t1 = browser.Eval("Number(document.getElementById('state').dataset.t)").get<double>();
  const double p1 = browser.Eval("Number(document.getElementById('state').dataset.points)").get<double>();
  const double f1 = browser.Eval("Number(document.getElementById('state').dataset.frames)").get<double>();
  const double w1 = MonotonicSeconds();
  usleep(2000000);
  const double rate = (browser.Eval("Number(document.getElementById('state').dataset.frames)").get<double>() - f1) /
                      (MonotonicSeconds() - w1);
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
  // the balance overlays live (docs/view.md, "Balance in 3D"): the robot stands on both feet,
  // so both arrows are drawn, and the ZMP and the CoM's ground projection lie in the support
  // polygon (a standing robot's; counter-clockwise corners)
  const nlohmann::json ov = nlohmann::json::parse(browser.Eval("JSON.stringify(ohrpOverlay.state())").get<std::string>());
  ASSERT_TRUE(ov["polygon"].is_array() && ov["zmp"].is_array() && ov["comGround"].is_array()) << ov;
  for (const auto& a : ov["arrows"]) EXPECT_TRUE(a["visible"].get<bool>()) << ov;
  auto inside = [&](const nlohmann::json& q) {
    const nlohmann::json& P = ov["polygon"];
    for (size_t i = 0; i < P.size(); ++i) {
      const nlohmann::json &a = P[i], &b = P[(i + 1) % P.size()];
      const double cross = (b[0].get<double>() - a[0].get<double>()) * (q[1].get<double>() - a[1].get<double>()) -
                           (b[1].get<double>() - a[1].get<double>()) * (q[0].get<double>() - a[0].get<double>());
      if (cross < 0) return false;
    }
    return true;
  };
  std::printf("live overlays: zmp %s, CoM on the floor %s, arrows %.3f + %.3f m, polygon %zu corners\n",
              ov["zmp"].dump().c_str(), ov["comGround"].dump().c_str(), ov["arrows"][0]["length"].get<double>(),
              ov["arrows"][1]["length"].get<double>(), ov["polygon"].size());
  EXPECT_TRUE(inside(ov["zmp"])) << ov;
  EXPECT_TRUE(inside(ov["comGround"])) << ov;
  // the walk's plan is replay-only (walk.csv is written when the walk ends): greyed out, said
  const nlohmann::json plan = nlohmann::json::parse(browser.Eval("JSON.stringify(ohrpPlan.state())").get<std::string>());
  for (const char* k : {"desired_zmp", "dcm", "footsteps"}) EXPECT_FALSE(plan["enabled"][k].get<bool>()) << plan;
  EXPECT_NE(plan["note"].get<std::string>().find("replay only"), std::string::npos) << plan;
}

// the ball's red (scene_ball.xml: rgba 0.9 0.1 0.1, shaded by the headlight)
bool BallRed(int r, int g, int b) { return r > 100 && r > 3 * g && r > 3 * b; }

TEST_F(Live, ShowsTheCameraImagesOnlyWhileAPageAsks) {
  const std::string ball = kSource + "/mjcf/hrp1s/scene_ball.xml";
  const double camera_rate = 20;
  StartSim(120, true, ball, {"--camera-size", "320x240", "--camera-rate", "20"});
  StartPosture();
  Viewer viewer;
  StartViewer(&viewer, {segment_, "--port", "0", "--attach-timeout", "20", "--scene", ball},
              (dir_ / "viewer.txt").string());
  ASSERT_FALSE(viewer.url.empty()) << ReadFile(viewer.out_file);
  // the test's own observer, which never asks: it sees the frames somebody else asked for
  shm::Observer reference;
  ASSERT_TRUE(reference.open(segment_).ok());
  ASSERT_EQ(reference.header().ncamera, 2);
  auto slot = std::make_unique<shm::ImageSlot>();
  Browser browser(viewer.url);
  ASSERT_TRUE(browser.ok()) << browser.error();
  auto num = [&](const std::string& key) {
    return browser.Eval("Number(document.getElementById('state').dataset." + key + ")").get<double>();
  };
  // a page open, its camera box not ticked: the producer is not asked, nothing is rendered
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 5"));
  EXPECT_FALSE(browser.Eval("document.getElementById('images_toggle').hidden").get<bool>());
  usleep(1500000);
  EXPECT_EQ(reference.read_image(0, 0, slot.get()), shm::ImageResult::kNoFrame);
  EXPECT_EQ(num("images"), 0);

  // ticked: images arrive, and their frame counter follows simulated time at the camera rate
  const double w0 = MonotonicSeconds();
  browser.Eval("document.getElementById('show_images').click()");
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.images > 4", 30.0))
      << ReadFile(viewer.out_file);
  // the last image's frame counter and capture time, read together (in one evaluation)
  auto last_image = [&](double* frame, double* t) {
    const nlohmann::json j = browser.Eval(
        "(() => { const d = document.getElementById('state').dataset; return [Number(d.imageFrame), Number(d.imageT)]; })()");
    *frame = j[0].get<double>();
    *t = j[1].get<double>();
  };
  double f1, t1, f2, t2;
  const double n1 = num("images"), w1 = MonotonicSeconds();
  last_image(&f1, &t1);
  // at least 3 s of wall time, and until 0.3 s of simulated time has passed between the two
  // images (a loaded machine slows the real-time run's rendering and the page's drawing)
  usleep(3000000);
  last_image(&f2, &t2);
  for (int i = 0; i < 270 && !(t2 > t1 + 0.3); ++i) {
    usleep(100000);
    last_image(&f2, &t2);
  }
  const double n2 = num("images"), w2 = MonotonicSeconds();
  std::printf("camera images drawn by the page: %.1f per second since it asked, %.1f in the last "
              "%.1f s (2 cameras, at most 10 each sent); simulated time %.2f s in that time\n",
              n2 / (w2 - w0), (n2 - n1) / (w2 - w1), w2 - w1, t2 - t1);
  EXPECT_GT(t2, t1 + 0.3);
  EXPECT_NEAR(f2 - f1, camera_rate * (t2 - t1), 1.5);
  // the viewer sends at most --image-rate (10) per camera per second of wall time; the page may
  // draw a backlog faster, but never more than was sent since it asked
  EXPECT_LE(n2, 2 * (10 * (w2 - w0) + 1));
  EXPECT_NE(browser.Eval("document.getElementById('camcap0').textContent").get<std::string>().find("LeftCamera: frame"),
            std::string::npos);

  // the page's pixels are the segment's: the ball's red where the segment's frame has it
  ASSERT_EQ(reference.read_image(0, 0, slot.get()), shm::ImageResult::kOk);
  const int w = slot->width, h = slot->height;
  double u = 0, v = 0;
  int n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = slot->rgb + 3 * (y * w + x);
      if (BallRed(p[0], p[1], p[2])) { u += x; v += y; ++n; }
    }
  ASSERT_GT(n, 20) << "no ball in the segment's left camera image";
  u /= n;
  v /= n;
  EXPECT_LT(u, w / 2.0) << "the ball lies 20 deg to the left of the optical axis";
  const std::string out = OutputDir("live");
  ASSERT_TRUE(browser.Screenshot(out + "/camera_images.png"));
  const nlohmann::json r = nlohmann::json::parse(browser.Eval(
      "JSON.stringify(document.getElementById('camimg0').getBoundingClientRect())").get<std::string>());
  const double left = r["left"].get<double>(), top = r["top"].get<double>();
  const double sx = r["width"].get<double>() / w, sy = r["height"].get<double>() / h;
  const PixelCount red = CountPixels(out + "/camera_images.png", int(left), int(top), int(left + sx * w),
                                     int(top + sy * h), BallRed);
  ASSERT_GT(red.n, 5) << out << "/camera_images.png";
  // the robot stands still (posture): a few pixels of the 320 x 240 image
  EXPECT_NEAR((red.x - left) / sx, u, 4.0) << out << "/camera_images.png";
  EXPECT_NEAR((red.y - top) / sy, v, 4.0) << out << "/camera_images.png";

  // unticked: the request is withdrawn, no new frame is rendered
  browser.Eval("document.getElementById('show_images').click()");
  usleep(1500000);
  uint64_t last = 0;
  if (reference.read_image(0, 0, slot.get()) == shm::ImageResult::kOk) last = slot->frame;
  usleep(1500000);
  EXPECT_EQ(reference.read_image(0, last, slot.get()), shm::ImageResult::kNoFrame)
      << "frames still rendered after the page stopped asking";
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
      EXPECT_FALSE(stopped.url.empty() || killed.url.empty()) << ReadFile(dir_ / "v1.txt");
      kill(stopped.pid, SIGSTOP);
      kill(killed.pid, SIGKILL);
    }
    const double t0 = MonotonicSeconds();
    const pid_t posture = StartPosture();
    EXPECT_EQ(shm::testing::WaitExit(sim, 60.0), 0) << ReadFile(dir_ / "sim_host.txt");
    EXPECT_EQ(shm::testing::WaitExit(posture, 10.0), 0) << ReadFile(dir_ / "posture.txt");
    return MonotonicSeconds() - t0;
  };
  const double alone = run(false);
  const double watched = run(true);
  std::printf("lock-step 30 s run: %.2f s alone, %.2f s with a stopped and a killed viewer\n", alone, watched);
  EXPECT_LT(watched, 1.5 * alone + 1.0);
}

// ohrp_run --view: a viewer on the run's segment, which prints its URL and ends with the run
TEST_F(Live, RunWithViewStartsAViewerThatEndsWithTheRun) {
  std::ofstream(dir_ / "short.yaml") << "name: short\nscene: " << kScene
                                     << "\nduration: 1.0\ncontrollers:\n  - program: posture\n"
                                     << "checks:\n  - {type: not_fallen}\n";
  const std::string out = (dir_ / "run.txt").string();
  const pid_t run = Start("ohrp_run", {(dir_ / "short.yaml").string(), "--view", "--realtime", "--no-plot",
                                       "-q", "--out", (dir_ / "out").string()}, out);
  EXPECT_EQ(shm::testing::WaitExit(run, 60.0), 0) << ReadFile(out);
  EXPECT_NE(ReadFile(out).find("ohrp_view: serving http://127.0.0.1:"), std::string::npos) << ReadFile(out);
}

// `scene` under sim_host (real time, no controller) watched live: the pixels of the 3D view
// that `match` in a screenshot (build/tests/view_output/NAME/NAME.png); -1 when a step failed
int RobotPixels(const std::string& segment, const fs::path& dir, std::vector<pid_t>* children,
                const std::string& scene, const std::string& name,
                const std::function<bool(int, int, int)>& match) {
  children->push_back(Start("sim_host", {scene, "--segment", segment, "--realtime", "--duration", "60",
                                         "--wait-controller", "0", "--progress", "0"},
                            (dir / "sim_host.txt").string()));
  Viewer viewer;
  StartViewer(&viewer, {segment, "--scene", scene, "--port", "0", "--attach-timeout", "20"},
              (dir / "viewer.txt").string());
  EXPECT_FALSE(viewer.url.empty()) << ReadFile(viewer.out_file) << ReadFile(dir / "sim_host.txt");
  if (viewer.url.empty()) return -1;
  Browser browser(viewer.url);
  EXPECT_TRUE(browser.ok()) << browser.error();
  if (!browser.ok() || !browser.WaitTrue("Number(document.getElementById('state').dataset.frames) > 5"))
    return -1;
  const std::string png = OutputDir(name) + "/" + name + ".png";
  if (!browser.Screenshot(png)) return -1;
  const nlohmann::json r = nlohmann::json::parse(browser.Eval(
      "JSON.stringify(document.getElementById('view3d').getBoundingClientRect())").get<std::string>());
  return CountPixels(png, r["left"].get<int>(), r["top"].get<int>(), r["right"].get<int>(),
                     r["bottom"].get<int>(), match).n;
}

// a robot drawn by meshes only (menagerie's H1 is): a green cube mesh on a free base with a
// hinged mesh arm, live under sim_host; the page draws them from the description's meshes
TEST_F(Live, ARobotOfMeshesIsDrawn) {
  const fs::path scene = dir_ / "meshes.xml";
  std::ofstream(scene) << R"(<mujoco model="meshes"><option timestep="0.001" gravity="0 0 0"/>
    <asset><mesh name="cube" vertex="-1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1"
                 scale="0.15 0.15 0.15"/></asset>
    <worldbody><geom type="plane" size="5 5 0.1"/>
      <body name="base" pos="0 0 0.6"><freejoint/>
        <geom type="mesh" mesh="cube" rgba="0.2 0.8 0.2 1" mass="5"/>
        <body name="arm" pos="0 0.3 0"><joint name="j1" type="hinge" axis="0 1 0"/>
          <geom type="mesh" mesh="cube" rgba="0.2 0.8 0.2 1" mass="1"/></body></body>
    </worldbody><actuator><motor joint="j1" ctrllimited="true" ctrlrange="-1 1"/></actuator></mujoco>)";
  EXPECT_GT(RobotPixels(segment_, dir_, &children_, scene.string(), "meshes", RobotGreen), 2000);
}

// a height field (MuJoCo's binary format: int32 rows, int32 columns, float32 samples) with a
// magenta ridge in front of a small robot: the page draws it from the description's samples
TEST_F(Live, AHeightFieldIsDrawn) {
  const int nrow = 20, ncol = 30;
  std::vector<float> samples;
  for (int r = 0; r < nrow; ++r)
    for (int c = 0; c < ncol; ++c) samples.push_back(std::exp(-0.02f * (c - 15) * (c - 15)));
  {
    std::ofstream bin(dir_ / "ridge.bin", std::ios::binary);
    bin.write(reinterpret_cast<const char*>(&nrow), sizeof nrow);
    bin.write(reinterpret_cast<const char*>(&ncol), sizeof ncol);
    bin.write(reinterpret_cast<const char*>(samples.data()), samples.size() * sizeof(float));
  }
  const fs::path scene = dir_ / "ridge.xml";
  std::ofstream(scene) << R"(<mujoco model="ridge"><option timestep="0.001" gravity="0 0 0"/>
    <asset><hfield name="ridge" file="ridge.bin" size="1.5 1 0.3 0.05"/></asset>
    <worldbody><geom type="hfield" hfield="ridge" rgba="0.9 0.1 0.9 1"/>
      <body name="base" pos="0 0 0.6"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="5"/>
        <body name="arm" pos="0 0.3 0"><joint name="j1" type="hinge" axis="0 1 0"/>
          <geom type="box" size="0.05 0.05 0.05" mass="1"/></body></body>
    </worldbody><actuator><motor joint="j1" ctrllimited="true" ctrlrange="-1 1"/></actuator></mujoco>)";
  EXPECT_GT(RobotPixels(segment_, dir_, &children_, scene.string(), "hfield",
                        [](int r, int g, int b) { return r > g + 60 && b > g + 60; }),
            2000);
}

// menagerie's H1 (../shared/external beside the repository), hung as in its scenario: its
// visual geoms are black meshes (0.1 0.1 0.1, shaded: darker than the floor and the sky)
TEST_F(Live, MenageriesH1IsDrawnByItsMeshes) {
  if (!fs::exists(kSource + "/../shared/external/menagerie/unitree_h1/h1.xml"))
    GTEST_SKIP() << "menagerie's H1 is not beside the repository";
  EXPECT_GT(RobotPixels(segment_, dir_, &children_, kSource + "/scenarios/scenes/h1_hung.xml", "h1",
                        [](int r, int g, int b) { return std::max({r, g, b}) < 40; }),
            2000);
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
  EXPECT_EQ(shm::testing::WaitExit(pid, 30.0), 2) << ReadFile(out) << ReadFile(dir_ / "sim_host.txt");
  EXPECT_NE(ReadFile(out).find("does not hold the robot of segment"), std::string::npos) << ReadFile(out);
}

TEST_F(Live, ANonexistentSegmentIsRefused) {
  const std::string out = (dir_ / "viewer.txt").string();
  const pid_t pid = Start("ohrp_view", {segment_}, out);
  EXPECT_EQ(shm::testing::WaitExit(pid, 20.0), 2);
  EXPECT_NE(ReadFile(out).find("no segment '" + segment_ + "'"), std::string::npos) << ReadFile(out);
}

}  // namespace
}  // namespace ohrp::view::testing
