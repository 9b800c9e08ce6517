// ohrp_view on a run folder (tools/view/src/replay.cc): headless Chromium shows the robot in
// the 3D canvas and the plots, and moving the timeline slider moves the robot; a folder that
// does not exist or has no log is refused with a clear message and exit code 2.
#include <gtest/gtest.h>

#include <cmath>

#include "browser.h"
#include "common/scratch.h"
#include "view_process.h"
#include "viewer_page.h"

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
  // the page paused at t = 0
  ViewerPage page;
  OpenPage(&page, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  const std::string out = OutputDir("replay");
  ASSERT_TRUE(browser.Screenshot(out + "/t0.png"));
  const PixelCount at0 = RobotPixels(&browser, out + "/t0.png");
  EXPECT_GT(at0.n, 2000) << "the robot's colours should fill part of the canvas (" << out << "/t0.png)";
  // every plot has its curves: knee q and qref, two ankle forces
  EXPECT_GT(browser.Eval("Number(document.getElementById('state').dataset.points)").get<double>(), 1000);
  // a run folder without recorded images (sim_host --record-images): the page says so, without
  // a camera panel
  EXPECT_EQ(browser.Eval("document.getElementById('cameras').textContent").get<std::string>(),
            "no recorded images (sim_host --record-images DIR/images keeps them)");
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
  // the camera is framed from the robot's size: the risen robot is still whole in the canvas,
  // its head below the canvas's top (before, the camera looked at 0.5 m from 3 m: the head left it)
  const int top = browser.Eval("document.getElementById('view3d').getBoundingClientRect().top").get<int>();
  EXPECT_GT(at2.y_min, top + 3) << "the robot's head is cut off (" << out << "/t2.png)";
}

// menagerie's H1 (1.8 m tall, drawn by its meshes) replayed at its home keyframe: the camera is
// framed from its size, read back from the page: every corner of the robot's bounding box projects
// inside the view (its head included), its height fills about 70 % of the view's height, and the
// camera looks at its middle (not at the fixed 0.5 m of before)
TEST_F(Replay, H1IsFramedWhole) {
  const std::string scene = kSource + "/scenarios/scenes/h1_hung.xml";
  if (!fs::exists(kSource + "/../shared/external/menagerie/unitree_h1/h1.xml"))
    GTEST_SKIP() << "menagerie's H1 is not beside the repository";
  fs::create_directories(dir_ / "h1");
  std::ofstream(dir_ / "h1/sim_summary.json") << "{\"scene\": \"" << scene << "\"}\n";
  {
    std::ofstream log(dir_ / "h1/log.csv");
    log << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz";
    for (const char* side : {"left", "right"}) log << ",q_" << side << "_hip_pitch,q_" << side << "_knee,q_" << side << "_ankle";
    log << "\n";
    for (int i = 0; i <= 10; ++i) log << 0.1 * i << ",0,0,0.98,1,0,0,0,-0.4,0.8,-0.4,-0.4,0.8,-0.4\n";
  }
  ViewerPage page;
  OpenPage(&page, {(dir_ / "h1").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0.5");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0", 60.0));
  const nlohmann::json f = nlohmann::json::parse(browser.Eval(
      "(() => { const box = new THREE.Box3(); for (const o of moving) if (o) box.expandByObject(o);"
      " placeCamera(); camera.updateMatrixWorld(); const ndc = [];"
      " for (const x of [box.min.x, box.max.x]) for (const y of [box.min.y, box.max.y])"
      "  for (const z of [box.min.z, box.max.z]) { const v = new THREE.Vector3(x, y, z).project(camera); ndc.push([v.x, v.y]); }"
      " return JSON.stringify({ndc, top: box.max.z, bottom: box.min.z, target: orbit.target.z, distance: orbit.distance}); })()")
      .get<std::string>());
  EXPECT_GT(f["top"].get<double>(), 1.6) << "H1's head is about 1.7 m up: " << f;
  EXPECT_NEAR(f["target"].get<double>(), (f["top"].get<double>() + f["bottom"].get<double>()) / 2, 1e-6) << f;
  double y0 = 1, y1 = -1;
  for (const auto& p : f["ndc"]) {
    EXPECT_LT(std::abs(p[0].get<double>()), 1.0) << "a corner of the robot's box out of the view: " << f;
    EXPECT_LT(std::abs(p[1].get<double>()), 1.0) << "a corner of the robot's box out of the view: " << f;
    y0 = std::min(y0, p[1].get<double>());
    y1 = std::max(y1, p[1].get<double>());
  }
  // the box's corners nearer the camera than its middle project a little larger than 70 %
  EXPECT_GT((y1 - y0) / 2, 0.6) << f;
  EXPECT_LT((y1 - y0) / 2, 0.95) << f;
  std::printf("H1: box top %.3f m, camera %.2f m from %.3f m up; the box spans %.0f %% of the view's height\n",
              f["top"].get<double>(), f["distance"].get<double>(), f["target"].get<double>(), 50 * (y1 - y0));
  usleep(300000);
  EXPECT_TRUE(browser.Screenshot(OutputDir("replay") + "/h1.png"));
}

// a click on a plot (a user's press and release) shows the robot at the clicked time
TEST_F(Replay, ClickingAPlotSeeks) {
  ViewerPage page;
  OpenPage(&page, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  // the page's pixel of t = 1.5 s on the force plot, halfway up its plotting area
  const nlohmann::json at = browser.Eval(
      "(() => { const c = charts.fz, r = c.canvas.getBoundingClientRect();"
      " return [r.left + c.scales.x.getPixelForValue(1.5), r.top + (c.chartArea.top + c.chartArea.bottom) / 2]; })()");
  ASSERT_TRUE(at.is_array()) << at;
  browser.Click(at[0].get<double>(), at[1].get<double>());
  // within a pixel's worth of time (the plot is a few hundred pixels wide for 2 s)
  EXPECT_TRUE(browser.WaitTrue("Math.abs(document.getElementById('state').dataset.t - 1.5) < 0.02", 5.0))
      << "t shown: " << browser.Eval("document.getElementById('state').dataset.t");
  EXPECT_EQ(browser.Eval("replay.playing").get<bool>(), false);
}

// A run of 4001 rows (0.5 ms) plotted with at most 800 points per curve: the one-row spike of an
// impact (1234 N among 300 N) is in the force plot at its value (every-Nth-row decimation drew
// one row in 5 and lost it); a picked log column keeps it too
TEST_F(Replay, APeakOfOneRowIsPlotted) {
  fs::create_directories(dir_ / "impact");
  std::ofstream(dir_ / "impact/sim_summary.json") << "{\"scene\": \"" << kScene << "\"}\n";
  {
    std::ofstream log(dir_ / "impact/log.csv");
    log << "time,base_z,q_RLEG_KNEE,rfsensor_fz,lfsensor_fz\n";
    for (int i = 0; i <= 4000; ++i)
      log << 0.0005 * i << ",0.7235,0.1," << (i == 2467 ? 1234 : 300) << ",300\n";
  }
  ViewerPage page;
  OpenPage(&page, {(dir_ / "impact").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0&columns=rfsensor_fz");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  const std::string peak = "(c, label) => Math.max(...c.data.datasets.find((d) => d.label === label).data.map((p) => p.y))";
  const double in_fz = browser.Eval("(" + peak + ")(charts.fz, 'rfsensor')").get<double>();
  EXPECT_NEAR(in_fz, 1234, 12.34) << "the impact's peak is lost in the force plot";
  ASSERT_TRUE(browser.WaitTrue("charts.cols.data.datasets.length === 1", 5.0));
  const double in_cols = browser.Eval("(" + peak + ")(charts.cols, 'rfsensor_fz')").get<double>();
  EXPECT_NEAR(in_cols, 1234, 12.34) << "the impact's peak is lost in the picked column's plot";
  // at most 800 points a curve, and the peak at its time within one bucket (4001 rows / 400)
  EXPECT_LE(browser.Eval("charts.fz.data.datasets[0].data.length").get<int>(), 800);
  EXPECT_NEAR(browser.Eval("charts.fz.data.datasets.find((d) => d.label === 'rfsensor').data"
                           ".reduce((a, p) => (p.y > a.y ? p : a)).x").get<double>(),
              0.0005 * 2467, 0.0005 * 11);
}

// the column picker: any log column by name, typed in its box; a mistyped column or joint is
// said on the page, not dropped silently
TEST_F(Replay, PicksLogColumnsByNameAndSaysWhichAreNotThere) {
  ViewerPage page;
  OpenPage(&page, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0&joints=RLEG_KNEE,RLEG_KNEEE&columns=base_z,base_zz");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('column_note').textContent.includes('base_zz')", 5.0));
  const std::string note = browser.Eval("document.getElementById('column_note').textContent").get<std::string>();
  EXPECT_NE(note.find("no joint 'RLEG_KNEEE'"), std::string::npos) << note;
  EXPECT_NE(note.find("no column 'base_zz' in the log"), std::string::npos) << note;
  // the log's columns are offered for search
  EXPECT_EQ(browser.Eval("document.querySelectorAll('#column_list option').length").get<int>(), 11);
  // typed in the box and submitted as a user would (the form's button)
  browser.Eval("document.getElementById('column_name').value = 'qref_RLEG_KNEE';"
               "document.querySelector('#picker button').click();");
  ASSERT_TRUE(browser.WaitTrue("charts.cols.data.datasets.length === 2", 5.0));
  EXPECT_EQ(browser.Eval("charts.cols.data.datasets.map((d) => d.label).join()").get<std::string>(),
            "base_z,qref_RLEG_KNEE");
  // the curves are the log's: base_z rises 0.7235 -> 0.8735 m, qref 0 -> 1 rad
  EXPECT_NEAR(browser.Eval("charts.cols.data.datasets[0].data.at(-1).y").get<double>(), 0.8735, 1e-6);
  EXPECT_NEAR(browser.Eval("charts.cols.data.datasets[1].data.at(-1).y").get<double>(), 1.0, 1e-6);
}

// the camera: follow on (the default) keeps the robot in view as it walks 1 m; off, it stays
// where it was and the robot walks out of the middle; 'reset view' frames it again; shift-drag
// pans, a drag turns. The floor is
// a checker (walking progress shows against it).
TEST_F(Replay, TheCameraFollowsOrStaysAndResets) {
  fs::create_directories(dir_ / "walk");
  std::ofstream(dir_ / "walk/sim_summary.json") << "{\"scene\": \"" << kScene << "\"}\n";
  {
    std::ofstream log(dir_ / "walk/log.csv");
    log << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,q_RLEG_KNEE\n";
    for (int i = 0; i <= 200; ++i) log << 0.01 * i << "," << 0.5 * 0.01 * i << ",0,0.7235,1,0,0,0,0\n";
  }
  ViewerPage page;
  OpenPage(&page, {(dir_ / "walk").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  auto seek = [&](double t) {
    browser.Eval("(() => { const s = document.getElementById('slider'); s.value = " + std::to_string(t) +
                 "; s.dispatchEvent(new Event('input')); })()");
    return browser.WaitTrue("Math.abs(document.getElementById('state').dataset.t - " + std::to_string(t) + ") < 1e-6");
  };
  const std::string out = OutputDir("replay");
  ASSERT_TRUE(browser.Screenshot(out + "/walk_t0.png"));
  const PixelCount at0 = RobotPixels(&browser, out + "/walk_t0.png");
  // the floor's checker is in the picture: in the left quarter of the canvas's lower half
  // (floor only, away from the robot), both its light squares (106, 120, 134 lit) and its dark
  // ones (60, 70, 80 lit); the plain floor before was one shade (70, 82, 94 lit)
  const nlohmann::json r = nlohmann::json::parse(browser.Eval(
      "JSON.stringify(document.getElementById('view3d').getBoundingClientRect())").get<std::string>());
  const int left = r["left"].get<int>(), top = r["top"].get<int>(), right = r["right"].get<int>(),
            bottom = r["bottom"].get<int>();
  auto floor = [&](int r_min, int r_max) {
    return CountPixels(out + "/walk_t0.png", left, (top + bottom) / 2, left + (right - left) / 4, bottom,
                       [&](int R, int G, int B) { return R >= r_min && R < r_max && B > R + 5 && G > R && B > G; }).n;
  };
  const int light = floor(95, 150), dark = floor(40, 68);
  EXPECT_GT(light, 2000) << "no checker on the floor (" << out << "/walk_t0.png)";
  EXPECT_GT(dark, 2000) << "no checker on the floor (" << out << "/walk_t0.png)";
  // follow on: the camera looks at the base, 1 m on
  ASSERT_TRUE(seek(2));
  EXPECT_NEAR(browser.Eval("orbit.target.x").get<double>(), 1.0, 1e-6);
  // follow off: back to t = 0, the camera stays at x = 1 m, the robot is drawn off the middle
  browser.Eval("document.getElementById('follow').click()");
  ASSERT_TRUE(seek(0));
  EXPECT_NEAR(browser.Eval("orbit.target.x").get<double>(), 1.0, 1e-6);
  usleep(300000);  // the next browser frame
  ASSERT_TRUE(browser.Screenshot(out + "/walk_nofollow.png"));
  const PixelCount off = RobotPixels(&browser, out + "/walk_nofollow.png");
  EXPECT_GT(std::abs(off.x - at0.x), 30) << "the robot should leave the middle when the camera stays";
  // reset: framed again on the robot, follow back on
  browser.Eval("orbit.distance = 9; document.getElementById('reset_view').click()");
  EXPECT_NEAR(browser.Eval("orbit.target.x").get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(browser.Eval("orbit.distance").get<double>(),
              browser.Eval("Number(document.getElementById('state').dataset.frameDistance)").get<double>(), 1e-9);
  EXPECT_TRUE(browser.Eval("document.getElementById('follow').checked").get<bool>());
  // shift-drag 120 px to the right pans: the target moves 120 px' worth of metres (at its
  // distance) to the camera's left, horizontally here, and follow turns off
  const double metres_per_px = browser.Eval(
      "2 * orbit.distance * Math.tan(camera.fov * Math.PI / 360) / canvas.clientHeight").get<double>();
  const double cx = (left + right) / 2.0, cy = (top + bottom) / 2.0;
  browser.Drag(cx, cy, cx + 120, cy, 8);
  const double moved = browser.Eval("Math.hypot(orbit.target.x, orbit.target.y)").get<double>();
  EXPECT_NEAR(moved, 120 * metres_per_px, 0.02 * 120 * metres_per_px);
  EXPECT_FALSE(browser.Eval("document.getElementById('follow').checked").get<bool>());
  // a plain drag turns the camera instead: the target stays
  const double az = browser.Eval("orbit.azimuth").get<double>();
  browser.Drag(cx, cy, cx + 50, cy);
  EXPECT_NEAR(browser.Eval("orbit.azimuth").get<double>(), az - 0.5, 1e-9);
  EXPECT_NEAR(browser.Eval("Math.hypot(orbit.target.x, orbit.target.y)").get<double>(), moved, 1e-9);
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
