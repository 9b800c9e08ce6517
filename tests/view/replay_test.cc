// ohrp_view on a run folder (tools/view/src/replay.cc): headless Chromium shows the robot in
// the 3D canvas and the plots, and moving the timeline slider moves the robot; a folder that
// does not exist or has no log is refused with a clear message and exit code 2.
#include <gtest/gtest.h>

#include <cmath>

#include "browser.h"
#include "common/scratch.h"
#include "view_process.h"

namespace ohrp::view::testing {
namespace {

class Replay : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ohrp::testing::ScratchFolder("replay");
    fs::create_directories(dir_ / "run");
    // a run whose base rises from 0.7235 m to 0.8735 m in 2 s (the robot floats up, nothing hides
    // it), the right knee bends, 300 N per ankle
    std::ofstream(dir_ / "run/sim_summary.json") << "{\"scene\": \"" << kScene << "\"}\n";
    std::ofstream log(dir_ / "run/log.csv");
    log << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,q_RLEG_KNEE,qref_RLEG_KNEE,"
           "rfsensor_fz,lfsensor_fz\n";
    for (int i = 0; i <= 400; ++i) {
      const double t = 0.005 * i;
      log << t << ",0,0," << 0.7235 + 0.15 * t / 2 << ",1,0,0,0," << 0.5 * t << ","
          << 0.5 * t << ",300,300\n";
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// the robot's pixels in the 3D canvas of a screenshot
PixelCount RobotPixels(Browser* b, const std::string& png) {
  const nlohmann::json r = nlohmann::json::parse(b->Eval(
      "JSON.stringify(document.getElementById('view3d').getBoundingClientRect())").get<std::string>());
  return CountPixels(png, r["left"].get<int>(), r["top"].get<int>(), r["right"].get<int>(),
                     r["bottom"].get<int>(), RobotGreen);
}

TEST_F(Replay, ShowsTheRobotAndTheSliderMovesIt) {
  Viewer viewer;
  StartViewer(&viewer, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer.txt").string());
  ASSERT_FALSE(viewer.url.empty()) << ReadFile(viewer.out_file);
  // the page paused at t = 0
  Browser browser(viewer.url + "?t=0");
  ASSERT_TRUE(browser.ok()) << browser.error();
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  const std::string out = OutputDir("replay");
  ASSERT_TRUE(browser.Screenshot(out + "/t0.png"));
  const PixelCount at0 = RobotPixels(&browser, out + "/t0.png");
  EXPECT_GT(at0.n, 2000) << "the robot's colours should fill part of the canvas (" << out << "/t0.png)";
  // every plot has its curves: knee q and qref, two ankle forces
  EXPECT_GT(browser.Eval("Number(document.getElementById('state').dataset.points)").get<double>(), 1000);
  // a run folder has no camera images: the page says so, without a camera panel
  EXPECT_EQ(browser.Eval("document.getElementById('cameras').textContent").get<std::string>(),
            "no images in a run folder");
  EXPECT_TRUE(browser.Eval("document.getElementById('images_toggle').hidden").get<bool>());

  // the slider to the end: the robot is drawn higher
  browser.Eval("const s = document.getElementById('slider'); s.value = 2; s.dispatchEvent(new Event('input'));");
  ASSERT_TRUE(browser.WaitTrue("Math.abs(document.getElementById('state').dataset.t - 2) < 1e-6"));
  ASSERT_TRUE(browser.Screenshot(out + "/t2.png"));
  const PixelCount at2 = RobotPixels(&browser, out + "/t2.png");
  EXPECT_GT(at2.n, 1000) << out << "/t2.png";
  // (its head leaves the canvas: the feet, its lowest pixels, tell)
  EXPECT_LT(at2.y_max, at0.y_max - 20) << "the robot should move up the image when its base rises 15 cm";
  // the plots' cursor follows the slider
  EXPECT_NEAR(browser.Eval("cursorT").get<double>(), 2.0, 1e-9);
}

TEST_F(Replay, AFolderWithoutLogIsRefused) {
  fs::remove(dir_ / "run/log.csv");
  const std::string out = (dir_ / "viewer.txt").string();
  const pid_t pid = Start("ohrp_view", {(dir_ / "run").string()}, out);
  EXPECT_EQ(shm::testing::WaitExit(pid, 20.0), 2);
  EXPECT_NE(ReadFile(out).find("has no log.csv"), std::string::npos) << ReadFile(out);
}

TEST_F(Replay, AMissingFolderIsRefused) {
  const std::string out = (dir_ / "viewer.txt").string();
  const pid_t pid = Start("ohrp_view", {(dir_ / "nowhere").string()}, out);
  EXPECT_EQ(shm::testing::WaitExit(pid, 20.0), 2);
  EXPECT_NE(ReadFile(out).find("no run folder"), std::string::npos) << ReadFile(out);
}

}  // namespace
}  // namespace ohrp::view::testing
