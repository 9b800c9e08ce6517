// ohrp_view's balance overlays in 3D (tools/view/web/overlays.js, tools/view/src/balance.cc):
// a replayed HRP-1S log with both sole sensors' six columns; at chosen times the page's drawn
// objects (window.ohrpOverlay.state()) are compared with closed forms of the log's values: the
// arrow's length |f| x 1 mm/N, the ZMP between the sensors weighted by their fz and moved by a
// torque -ty / fz, an unloaded foot without an arrow, the support polygon as the loaded sole's
// rectangle (the MJCF's 0.25 x 0.14 m box, 0.055 m ahead of its sensor), the CoM moving with the
// base. A log without the torque columns greys the ZMP's box out and names the columns.
#include <gtest/gtest.h>

#include <cmath>

#include "browser.h"
#include "common/scratch.h"
#include "view_process.h"
#include "viewer_page.h"

namespace ohrp::view::testing {
namespace {

constexpr double kF = 300;   // each foot's fz [N] while loaded
constexpr double kTy = 15;   // the left sensor's ty from t = 0.6 to 0.8 s [N m]

// the log: 101 rows, 10 ms apart, the base upright at 0.7235 m, the joints at 0
//   t < 0.6   both feet fz = 300 N, no torque; 0.25-0.35 s the right force is (40, -30, 300) N
//   0.6-0.8   the left sensor's ty = 15 N m
//   0.8-0.96  the left foot carries 5 N (unloaded: below the page's 10 N)
//   t = 1.0   the base 0.1 m ahead (x), both feet at 300 N
void WriteLog(const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "sim_summary.json") << "{\"scene\": \"" << kScene << "\"}\n";
  std::ofstream log(dir / "log.csv");
  log << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,q_RLEG_KNEE";
  for (const char* s : {"rfsensor", "lfsensor"})
    for (const char* a : {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"}) log << "," << s << a;
  log << "\n";
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.01 * i;
    const bool push = i >= 25 && i <= 35, torque = i >= 60 && i < 80, lifted = i >= 80 && i < 96;
    log << t << "," << (i == 100 ? 0.1 : 0) << ",0,0.7235,1,0,0,0,0,";
    log << (push ? 40 : 0) << "," << (push ? -30 : 0) << "," << kF << ",0,0,0,";
    log << "0,0," << (lifted ? 5 : kF) << ",0," << (torque ? kTy : 0) << ",0\n";
  }
}

class Balance : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = ohrp::testing::ScratchFolder("balance"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// the page at time t, and what it draws there
nlohmann::json At(Browser* b, double t) {
  const std::string ts = std::to_string(t);
  b->Eval("(() => { const s = document.getElementById('slider'); s.value = " + ts +
          "; s.dispatchEvent(new Event('input')); })()");
  EXPECT_TRUE(b->WaitTrue("Math.abs(document.getElementById('state').dataset.t - " + ts + ") < 1e-6"));
  return nlohmann::json::parse(b->Eval("JSON.stringify(ohrpOverlay.state())").get<std::string>());
}

nlohmann::json Arrow(const nlohmann::json& s, const std::string& sensor) {
  for (const auto& a : s["arrows"])
    if (a["sensor"] == sensor) return a;
  ADD_FAILURE() << "no arrow for " << sensor << ": " << s;
  return nlohmann::json::object();
}

TEST_F(Balance, OverlaysMatchTheLog) {
  WriteLog(dir_ / "run");
  ViewerPage page;
  OpenPage(&page, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  // every overlay has its columns: all ticked, none greyed out, no note
  const nlohmann::json s0 = At(&browser, 0.5);
  for (const char* k : {"forces", "zmp", "com", "polygon"}) EXPECT_TRUE(s0["enabled"][k].get<bool>()) << k;
  EXPECT_EQ(browser.Eval("document.getElementById('overlay_note').textContent").get<std::string>(), "");

  // t = 0.5: no torque, so each arrow starts at its sensor (the centre of pressure), 300 mm long,
  // straight up; the ZMP is halfway between the sensors
  const nlohmann::json r = Arrow(s0, "rfsensor"), l = Arrow(s0, "lfsensor");
  ASSERT_TRUE(r["visible"].get<bool>() && l["visible"].get<bool>()) << s0;
  const double xr = r["origin"][0], yr = r["origin"][1], xl = l["origin"][0], yl = l["origin"][1];
  EXPECT_NEAR(r["length"].get<double>(), kF * 1e-3, 1e-5);  // float32 matrices: 10 um
  EXPECT_NEAR(r["tip"][2].get<double>() - r["origin"][2].get<double>(), kF * 1e-3, 1e-5);
  EXPECT_GT(std::abs(yr - yl), 0.1) << "the feet should be apart";
  ASSERT_FALSE(s0["zmp"].is_null()) << s0;
  EXPECT_NEAR(s0["zmp"][0].get<double>(), (xr + xl) / 2, 1e-9);
  EXPECT_NEAR(s0["zmp"][1].get<double>(), (yr + yl) / 2, 1e-9);
  // the support polygon: both soles' outer corners, a rectangle 0.25 m long and as wide as the
  // feet's distance plus one sole (0.14 m), containing the ZMP
  ASSERT_TRUE(s0["polygon"].is_array()) << s0;
  EXPECT_EQ(s0["polygon"].size(), 4u) << s0["polygon"];
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const auto& p : s0["polygon"]) {
    x0 = std::min(x0, p[0].get<double>()); x1 = std::max(x1, p[0].get<double>());
    y0 = std::min(y0, p[1].get<double>()); y1 = std::max(y1, p[1].get<double>());
  }
  EXPECT_NEAR(x1 - x0, 0.25, 1e-9);
  EXPECT_NEAR(x0, xr + 0.055 - 0.125, 1e-9);
  EXPECT_NEAR(y1 - y0, std::abs(yr - yl) + 0.14, 1e-9);
  // the CoM and its projection on the floor
  ASSERT_TRUE(s0["com"].is_array() && s0["comGround"].is_array()) << s0;
  EXPECT_NEAR(s0["comGround"][0].get<double>(), s0["com"][0].get<double>(), 1e-12);
  EXPECT_NEAR(s0["comGround"][1].get<double>(), s0["com"][1].get<double>(), 1e-12);
  EXPECT_GT(s0["com"][2].get<double>(), 0.3);

  // t = 0.3: the right force (40, -30, 300) N: an arrow of |f| x 1 mm/N along f
  const nlohmann::json s1 = At(&browser, 0.3), r1 = Arrow(s1, "rfsensor");
  const double norm = std::sqrt(40.0 * 40 + 30 * 30 + kF * kF);
  EXPECT_NEAR(r1["length"].get<double>(), norm * 1e-3, 1e-5);
  EXPECT_NEAR(r1["tip"][0].get<double>() - r1["origin"][0].get<double>(), 40e-3, 1e-5);
  EXPECT_NEAR(r1["tip"][1].get<double>() - r1["origin"][1].get<double>(), -30e-3, 1e-5);

  // t = 0.7: the left sensor's ty = 15 N m moves its centre of pressure by -ty / fz = -5 cm and
  // the ZMP by -ty / (2 fz)
  const nlohmann::json s2 = At(&browser, 0.7);
  EXPECT_NEAR(Arrow(s2, "lfsensor")["origin"][0].get<double>(), xl - kTy / kF, 1e-9);
  EXPECT_NEAR(s2["zmp"][0].get<double>(), (xr + xl) / 2 - kTy / (2 * kF), 1e-9);
  EXPECT_NEAR(s2["zmp"][1].get<double>(), (yr + yl) / 2, 1e-9);

  // t = 0.9: the left foot carries 5 N: no arrow; the polygon is the right sole alone; the ZMP
  // is the fz-weighted mean of the sensors
  const nlohmann::json s3 = At(&browser, 0.9);
  EXPECT_FALSE(Arrow(s3, "lfsensor")["visible"].get<bool>());
  EXPECT_TRUE(Arrow(s3, "rfsensor")["visible"].get<bool>());
  EXPECT_NEAR(s3["zmp"][1].get<double>(), (kF * yr + 5 * yl) / (kF + 5), 1e-9);
  ASSERT_EQ(s3["polygon"].size(), 4u) << s3;
  for (const auto& p : s3["polygon"]) {
    EXPECT_NEAR(std::abs(p[0].get<double>() - (xr + 0.055)), 0.125, 1e-9) << p;
    EXPECT_NEAR(std::abs(p[1].get<double>() - yr), 0.07, 1e-9) << p;
  }

  // t = 1.0: the base 0.1 m ahead, the joints unchanged: the CoM 0.1 m ahead
  const nlohmann::json s4 = At(&browser, 1.0);
  EXPECT_NEAR(s4["com"][0].get<double>() - s0["com"][0].get<double>(), 0.1, 1e-9);
  EXPECT_NEAR(s4["com"][1].get<double>(), s0["com"][1].get<double>(), 1e-9);

  // a box unticked hides its overlay
  browser.Eval("document.getElementById('ov_zmp').click()");
  EXPECT_TRUE(At(&browser, 0.5)["zmp"].is_null());
  const std::string out = OutputDir("balance");
  browser.Eval("document.getElementById('ov_zmp').click()");
  usleep(300000);  // the next browser frame
  EXPECT_TRUE(browser.Screenshot(out + "/overlays.png"));
}

// a log with only fz: the arrows (fx, fy) and the ZMP (tx, ty) are greyed out and the note names
// the missing columns; the support polygon and the CoM (base) stay
TEST_F(Balance, AnOverlayWithoutItsColumnsIsGreyedOutWithANote) {
  fs::create_directories(dir_ / "fz");
  std::ofstream(dir_ / "fz/sim_summary.json") << "{\"scene\": \"" << kScene << "\"}\n";
  {
    std::ofstream log(dir_ / "fz/log.csv");
    log << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,q_RLEG_KNEE,rfsensor_fz,lfsensor_fz\n";
    for (int i = 0; i <= 10; ++i) log << 0.1 * i << ",0,0,0.7235,1,0,0,0,0,300,300\n";
  }
  ViewerPage page;
  OpenPage(&page, {(dir_ / "fz").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  EXPECT_TRUE(browser.Eval("document.getElementById('ov_forces').disabled").get<bool>());
  EXPECT_TRUE(browser.Eval("document.getElementById('ov_zmp').disabled").get<bool>());
  EXPECT_FALSE(browser.Eval("document.getElementById('ov_polygon').disabled").get<bool>());
  EXPECT_FALSE(browser.Eval("document.getElementById('ov_com').disabled").get<bool>());
  const std::string note = browser.Eval("document.getElementById('overlay_note').textContent").get<std::string>();
  EXPECT_NE(note.find("contact forces: no rfsensor_fx"), std::string::npos) << note;
  EXPECT_NE(note.find("ZMP: no rfsensor_tx"), std::string::npos) << note;
  const nlohmann::json s = At(&browser, 0.5);
  EXPECT_TRUE(s["zmp"].is_null()) << s;
  EXPECT_FALSE(Arrow(s, "rfsensor")["visible"].get<bool>());
  EXPECT_EQ(s["polygon"].size(), 4u) << s;
}

}  // namespace
}  // namespace ohrp::view::testing
