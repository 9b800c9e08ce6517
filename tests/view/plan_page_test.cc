// ohrp_view's walk-plan overlays in the page (tools/view/web/plan.js, tools/view/src/plan.cc): a
// replayed HRP-1S log beside a walk.csv written in a plan frame turned by 30 deg and moved by
// (3, -1) m from the world; read back from the page (window.ohrpPlan.state()) at chosen times:
// the starting footsteps cover the soles the balance overlay's support polygon outlines, a
// landing is 0.2 m ahead of its starting sole, the desired ZMP is on the sole the file puts it
// on, the capture point is the CoM reference moved by v / omega (omega = sqrt(g / 0.7 m)); the
// next landing and the supporting soles are bright. Without walk.csv, or without its columns,
// the boxes are greyed out with the reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>

#include "browser.h"
#include "common/scratch.h"
#include "view/geometry.h"
#include "view/plan.h"
#include "view_process.h"
#include "viewer_page.h"

namespace ohrp::view::testing {
namespace {

constexpr double kYaw = M_PI / 6;          // the plan frame's turn from the world
constexpr double kShift[2] = {3.0, -1.0};  // and its shift [m]
constexpr double kV = 0.1;                 // the CoM reference's speed along world x [m/s]
constexpr double kHeight = 0.7;            // the CoM reference above the soles [m]

// world -> plan
std::array<double, 2> ToPlan(double x, double y) {
  const double c = std::cos(kYaw), s = std::sin(kYaw);
  return {c * x - s * y + kShift[0], s * x + c * y + kShift[1]};
}

// the log: 401 rows, 10 ms apart, the robot standing upright (joints at 0), both feet 300 N
void WriteLog(const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "sim_summary.json") << "{\"scene\": \"" << kScene << "\"}\n";
  std::ofstream log(dir / "log.csv");
  log << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,q_RLEG_KNEE";
  for (const char* s : {"rfsensor", "lfsensor"})
    for (const char* a : {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"}) log << "," << s << a;
  log << "\n";
  for (int i = 0; i <= 400; ++i) log << 0.01 * i << ",0,0,0.7235,1,0,0,0,0,0,0,300,0,0,0,0,0,300,0,0,0\n";
}

// where the soles stand in the world (their bottom faces' centres), left then right
std::array<std::array<double, 3>, 2> Soles() {
  std::string error;
  auto g = SceneGeometry::Load(kScene, &error);
  EXPECT_TRUE(g) << error;
  RobotState s;
  s.p_WB[2] = 0.7235;
  s.q.assign(g->robot().joints.size(), 0.0);
  g->Poses(s);
  const std::array<int, 2> soles = LeftRightSoles(g->model());
  return {g->BoxBottom(soles[0]), g->BoxBottom(soles[1])};
}

// walk.csv, rows from t = 1 to 3 s (10 ms): the CoM reference from the soles' middle at kV along
// world x; the left sole lifts at 1.5 s and lands 0.2 m ahead at 2.0 s; the desired ZMP on the
// left sole; no DCM columns (the page draws the capture point alone)
void WriteWalk(const fs::path& dir, const std::array<std::array<double, 3>, 2>& w, bool with_zmp_des = true) {
  std::ofstream f(dir / "walk.csv");
  f << std::setprecision(12);
  f << "t,com_ref_x,com_ref_y,com_ref_z," << (with_zmp_des ? "zmp_des_x,zmp_des_y," : "")
    << "left_x,left_y,left_z,left_yaw,right_x,right_y,right_z,right_yaw,support_left,support_right,"
       "frame_x,frame_y,frame_yaw\n";
  for (int i = 100; i <= 300; ++i) {
    const double lx = w[0][0] + (i >= 200 ? 0.2 : 0);
    const auto c = ToPlan((w[0][0] + w[1][0]) / 2 + kV * 0.01 * (i - 100), (w[0][1] + w[1][1]) / 2);
    const auto l = ToPlan(lx, w[0][1]), r = ToPlan(w[1][0], w[1][1]);
    f << 0.01 * i << "," << c[0] << "," << c[1] << "," << w[0][2] + kHeight << ",";
    if (with_zmp_des) f << l[0] << "," << l[1] << ",";
    f << l[0] << "," << l[1] << "," << w[0][2] << "," << kYaw << "," << r[0] << "," << r[1] << "," << w[1][2]
      << "," << kYaw << "," << !(i >= 150 && i < 200) << ",1,0,0,0\n";
  }
}

class PlanPage : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = ohrp::testing::ScratchFolder("plan_page"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// the page at time t: what the plan overlays and the balance overlays draw there
std::pair<nlohmann::json, nlohmann::json> At(Browser* b, double t) {
  // asked as the slider asks (the slider itself would round t to its step)
  const std::string ts = std::to_string(t);
  b->Eval("(() => { replay.playing = false; seek(" + ts + "); })()");
  EXPECT_TRUE(b->WaitTrue("Math.abs(document.getElementById('state').dataset.t - " + ts + ") < 1e-6"));
  return {nlohmann::json::parse(b->Eval("JSON.stringify(ohrpPlan.state())").get<std::string>()),
          nlohmann::json::parse(b->Eval("JSON.stringify(ohrpOverlay.state())").get<std::string>())};
}

void Range(const nlohmann::json& points, double r[4]) {  // x0, x1, y0, y1
  r[0] = r[2] = 1e9;
  r[1] = r[3] = -1e9;
  for (const auto& p : points) {
    r[0] = std::min(r[0], p[0].get<double>()); r[1] = std::max(r[1], p[0].get<double>());
    r[2] = std::min(r[2], p[1].get<double>()); r[3] = std::max(r[3], p[1].get<double>());
  }
}

TEST_F(PlanPage, MarkersAndFootstepsWhereThePlanPutsThem) {
  const auto w = Soles();
  WriteLog(dir_ / "run");
  WriteWalk(dir_ / "run", w);
  ViewerPage page;
  OpenPage(&page, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));

  // before the walk: no markers; the footsteps drawn, none landed or bright
  auto [p0, b0] = At(&browser, 0.5);
  for (const char* k : {"desired_zmp", "dcm", "footsteps"}) EXPECT_TRUE(p0["enabled"][k].get<bool>()) << k << p0;
  EXPECT_TRUE(p0["zmpDes"].is_null() && p0["cp"].is_null() && p0["dcm"].is_null()) << p0;
  ASSERT_EQ(p0["steps"].size(), 3u) << p0["steps"];
  EXPECT_TRUE(p0["steps"][0]["visible"].get<bool>());

  // t = 1.2: the starting soles' rectangles span the balance overlay's support polygon (both
  // soles' outer corners, from the log and the model alone)
  auto [p1, b1] = At(&browser, 1.2);
  nlohmann::json start = p1["steps"][0]["corners"];
  for (const auto& c : p1["steps"][1]["corners"]) start.push_back(c);
  double rs[4], rp[4];
  Range(start, rs);
  ASSERT_TRUE(b1["polygon"].is_array()) << b1;
  Range(b1["polygon"], rp);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(rs[k], rp[k], 1e-6) << k;
  // the desired ZMP on the left sole, at its height
  ASSERT_TRUE(p1["zmpDes"].is_array()) << p1;
  EXPECT_NEAR(p1["zmpDes"][0].get<double>(), w[0][0], 1e-6);
  EXPECT_NEAR(p1["zmpDes"][1].get<double>(), w[0][1], 1e-6);
  EXPECT_NEAR(p1["zmpDes"][2].get<double>(), w[0][2] + 0.005, 1e-6);  // drawn 5 mm up
  // the capture point: the CoM reference (0.02 m past the soles' middle) plus kV / omega
  ASSERT_TRUE(p1["cp"].is_array()) << p1;
  const double ahead = kV * std::sqrt(kHeight / kPlanGravity);
  EXPECT_NEAR(p1["cp"][0].get<double>(), (w[0][0] + w[1][0]) / 2 + kV * 0.2 + ahead, 1e-5);
  EXPECT_NEAR(p1["cp"][1].get<double>(), (w[0][1] + w[1][1]) / 2, 1e-5);
  EXPECT_TRUE(p1["dcm"].is_null());  // no dcm_x, dcm_y in this walk.csv
  // the next landing (the left foot's, at 2.0 s) and the supporting soles are bright
  EXPECT_EQ(p1["next"], 2);
  EXPECT_NEAR(p1["steps"][2]["t"].get<double>(), 2.0, 1e-9);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(p1["steps"][k]["bright"].get<bool>()) << k;

  // t = 2.5: the left sole landed 0.2 m ahead, the desired ZMP on it; its starting step dim
  auto [p2, b2] = At(&browser, 2.5);
  EXPECT_NEAR(p2["steps"][2]["center"][0].get<double>(), w[0][0] + 0.2, 1e-6);
  EXPECT_NEAR(p2["steps"][2]["center"][1].get<double>(), w[0][1], 1e-6);
  EXPECT_NEAR(p2["steps"][2]["yaw"].get<double>(), 0, 1e-9);
  EXPECT_NEAR(p2["zmpDes"][0].get<double>(), w[0][0] + 0.2, 1e-6);
  EXPECT_EQ(p2["next"], -1);
  EXPECT_FALSE(p2["steps"][0]["bright"].get<bool>());
  EXPECT_TRUE(p2["steps"][1]["bright"].get<bool>());  // the right sole, still supporting

  // unticked, the footsteps go
  browser.Eval("document.getElementById('pl_footsteps').click()");
  EXPECT_FALSE(At(&browser, 2.5).first["steps"][0]["visible"].get<bool>());
  browser.Eval("document.getElementById('pl_footsteps').click()");
  At(&browser, 1.7);
  usleep(300000);  // the next browser frame
  EXPECT_TRUE(browser.Screenshot(OutputDir("plan") + "/plan.png"));
}

TEST_F(PlanPage, WithoutWalkCsvOrItsColumnsTheBoxesAreGreyedOut) {
  WriteLog(dir_ / "run");
  {
    ViewerPage page;
    OpenPage(&page, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
    ASSERT_FALSE(HasFatalFailure());
    Browser& browser = *page.browser;
    ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
    for (const char* k : {"pl_desired_zmp", "pl_dcm", "pl_footsteps"})
      EXPECT_TRUE(browser.Eval(std::string("document.getElementById('") + k + "').disabled").get<bool>()) << k;
    const std::string note = browser.Eval("document.getElementById('plan_note').textContent").get<std::string>();
    EXPECT_NE(note.find("no walk.csv"), std::string::npos) << note;
  }
  WriteWalk(dir_ / "run", Soles(), false);
  ViewerPage page;
  OpenPage(&page, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer2.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  EXPECT_TRUE(browser.Eval("document.getElementById('pl_desired_zmp').disabled").get<bool>());
  EXPECT_FALSE(browser.Eval("document.getElementById('pl_footsteps').disabled").get<bool>());
  EXPECT_FALSE(browser.Eval("document.getElementById('pl_dcm').disabled").get<bool>());
  const std::string note = browser.Eval("document.getElementById('plan_note').textContent").get<std::string>();
  EXPECT_NE(note.find("desired ZMP: no zmp_des_x, zmp_des_y in walk.csv"), std::string::npos) << note;
}

// a real walk: walk_side (HRP-1S, 1 m to the left, soft soles) run here; each planned landing is
// compared with the sole the log shows 0.3 s after it (landed and loaded), and the desired ZMP
// with the supporting soles' planned rectangles. The plan is what the robot believes (its
// estimator, never the simulation's truth): a landing lies on its sole when their centres are
// within half a sole width (7 cm) and their headings within 5 deg; the desired ZMP, clamped by
// the stabilizer to the supporting soles (less a margin), lies in their rectangles within 1 cm
TEST_F(PlanPage, ARealWalksLandingsLieOnItsSoles) {
  const std::string out = (dir_ / "walk_side").string();
  const pid_t run = Start("ohrp_run", {kSource + "/scenarios/walk_side.yaml", "--out", out, "--no-plot", "-q"},
                          (dir_ / "run.txt").string());
  ASSERT_EQ(ohrp::testing::WaitExit(run, 120.0), 0) << ReadFile((dir_ / "run.txt").string());
  ASSERT_TRUE(fs::exists(out + "/walk.csv"));
  ViewerPage page;
  OpenPage(&page, {out, "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  const nlohmann::json steps = At(&browser, 0).first["steps"];
  ASSERT_GE(steps.size(), 8u) << "1 m in side steps of at most 0.2 m: at least 5 landings per foot";
  double worst = 0, worst_yaw = 0;
  int landings = 0;
  for (size_t i = 2; i < steps.size(); ++i) {
    const double t = steps[i]["t"].get<double>() + 0.3;
    At(&browser, t);
    const std::string sensor = steps[i]["side"] == "left" ? "lfsensor" : "rfsensor";
    const nlohmann::json feet = nlohmann::json::parse(
        browser.Eval("JSON.stringify(lastOverlayFrame.balance.feet)").get<std::string>());
    for (const auto& f : feet) {
      if (f["sensor"] != sensor) continue;
      const auto& c = f["corners"];
      ASSERT_EQ(c.size(), 4u);
      double cx = 0, cy = 0;
      for (const auto& p : c) { cx += p[0].get<double>() / 4; cy += p[1].get<double>() / 4; }
      const double yaw = std::atan2(c[0][1].get<double>() - c[3][1].get<double>(), c[0][0].get<double>() - c[3][0].get<double>());
      const double d = std::hypot(cx - steps[i]["center"][0].get<double>(), cy - steps[i]["center"][1].get<double>());
      const double dyaw = std::abs(std::remainder(yaw - steps[i]["yaw"].get<double>(), 2 * M_PI));
      EXPECT_LT(d, 0.07) << "landing " << i << " at t = " << t;
      EXPECT_LT(dyaw, 5 * M_PI / 180) << "landing " << i;
      worst = std::max(worst, d);
      worst_yaw = std::max(worst_yaw, dyaw);
      ++landings;
    }
  }
  EXPECT_EQ(landings, static_cast<int>(steps.size()) - 2);
  std::printf("walk_side: %d landings planned; the sole stands within %.1f mm and %.2f deg of its plan\n",
              landings, worst * 1e3, worst_yaw * 180 / M_PI);
  // the desired ZMP in the bright (supporting) rectangles, every 0.25 s of the walk
  const double t0 = steps[0]["t"].get<double>(), t1 = steps.back()["t"].get<double>() + 1.0;
  double worst_out = 0;
  int samples = 0;
  for (double t = t0 + 0.05; t < t1; t += 0.25) {
    const nlohmann::json p = At(&browser, t).first;
    if (!p["zmpDes"].is_array()) continue;
    const double zx = p["zmpDes"][0], zy = p["zmpDes"][1];
    // the supporting soles' planned rectangles (bright and landed by t)
    std::vector<nlohmann::json> sup;
    for (const auto& st : p["steps"])
      if (st["bright"].get<bool>() && st["t"].get<double>() <= t) sup.push_back(st);
    ASSERT_FALSE(sup.empty()) << t;
    double out_by;  // how far outside the clamp's region (0 inside)
    if (sup.size() == 1) {  // one sole: its rectangle, in its own frame
      const double c = std::cos(sup[0]["yaw"].get<double>()), sn = std::sin(sup[0]["yaw"].get<double>());
      const double dx = zx - sup[0]["center"][0].get<double>(), dy = zy - sup[0]["center"][1].get<double>();
      const double u = std::abs(c * dx + sn * dy) - 0.125, v = std::abs(-sn * dx + c * dy) - 0.07;
      out_by = std::hypot(std::max(u, 0.0), std::max(v, 0.0));
    } else {  // both: the bounding box of their corners (the walk heads along x here)
      nlohmann::json corners = nlohmann::json::array();
      for (const auto& st : sup)
        for (const auto& c : st["corners"]) corners.push_back(c);
      double r[4];
      Range(corners, r);
      out_by = std::hypot(std::max({r[0] - zx, zx - r[1], 0.0}), std::max({r[2] - zy, zy - r[3], 0.0}));
    }
    worst_out = std::max(worst_out, out_by);
    ++samples;
  }
  std::printf("walk_side: the desired ZMP at %d times: at most %.1f mm outside the supporting soles' plan\n",
              samples, worst_out * 1e3);
  EXPECT_GT(samples, 20);
  EXPECT_LT(worst_out, 0.01);
  // a picture mid-walk, the camera from the front
  At(&browser, (t0 + t1) / 2);
  browser.Eval("orbit.azimuth = 0.3; orbit.elevation = 0.5; render()");
  usleep(300000);
  EXPECT_TRUE(browser.Screenshot(OutputDir("plan") + "/walk_side.png"));
}

// reach's plan (tools/view/web/reach.js, tools/view/src/replay_reach.cc) from a real run of
// reach_scene_sequence (three goals, --plan-log): the box is on, three goals in time order, the
// goal under way the bright one, each goal's hand path starting near where the previous one's
// ended (each is planned from where the last one held; each path is placed with the base pose
// at its own motion's start, and balance moves the base as the arm's mass moves: within 3 cm; the
// paths themselves are checked in closed form in view_reach_plan_test); a run without plan.csv
// greys the box with the reason
TEST_F(PlanPage, AReachRunsPlanIsDrawnGoalByGoal) {
  const std::string out = (dir_ / "reach_sequence").string();
  const pid_t run = Start("ohrp_run", {kSource + "/scenarios/reach_scene_sequence.yaml", "--out", out, "--no-plot", "-q"},
                          (dir_ / "run.txt").string());
  ASSERT_EQ(ohrp::testing::WaitExit(run, 120.0), 0) << ReadFile((dir_ / "run.txt").string());
  ViewerPage page;
  OpenPage(&page, {out, "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  auto state = [&](double t) {
    const std::string ts = std::to_string(t);
    browser.Eval("(() => { replay.playing = false; seek(" + ts + "); })()");
    EXPECT_TRUE(browser.WaitTrue("Math.abs(document.getElementById('state').dataset.t - " + ts + ") < 1e-6"));
    return nlohmann::json::parse(browser.Eval("JSON.stringify(ohrpReach.state())").get<std::string>());
  };
  const nlohmann::json s = state(0.5);
  ASSERT_TRUE(s["enabled"].get<bool>()) << s.dump();
  const nlohmann::json& goals = s["goals"];
  ASSERT_EQ(goals.size(), 3u) << s.dump();
  EXPECT_EQ(s["current"], 0) << "before the first motion the next goal is the bright one";
  for (size_t k = 0; k < goals.size(); ++k) {
    EXPECT_TRUE(goals[k]["visible"].get<bool>());
    EXPECT_GT(goals[k]["t_end"].get<double>(), goals[k]["t_start"].get<double>());
    if (k == 0) continue;
    EXPECT_GT(goals[k]["t_start"].get<double>(), goals[k - 1]["t_end"].get<double>() - 1e-6);
    double gap = 0;
    for (int c = 0; c < 3; ++c)
      gap += std::pow(goals[k]["first"][0][c].get<double>() - goals[k - 1]["last"][0][c].get<double>(), 2);
    EXPECT_LT(std::sqrt(gap), 0.03) << "goal " << k + 1 << " starts where goal " << k << " ended";
  }
  const double mid2 = 0.5 * (goals[1]["t_start"].get<double>() + goals[1]["t_end"].get<double>());
  EXPECT_EQ(state(mid2)["current"], 1);
  std::printf("reach_scene_sequence: goals at %.2f-%.2f, %.2f-%.2f, %.2f-%.2f s\n",
              goals[0]["t_start"].get<double>(), goals[0]["t_end"].get<double>(),
              goals[1]["t_start"].get<double>(), goals[1]["t_end"].get<double>(),
              goals[2]["t_start"].get<double>(), goals[2]["t_end"].get<double>());
}

TEST_F(PlanPage, WithoutPlanCsvTheReachBoxIsGreyedOut) {
  WriteLog(dir_);
  ViewerPage page;
  OpenPage(&page, {dir_.string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  const nlohmann::json s = nlohmann::json::parse(browser.Eval("JSON.stringify(ohrpReach.state())").get<std::string>());
  EXPECT_TRUE(s["disabled"].get<bool>());
  EXPECT_EQ(s["note"], "no plan.csv in the run folder (reach --plan-log)");
}

}  // namespace
}  // namespace ohrp::view::testing
