// ohrp view --control (docs/view.md "Control from the page"): headless Chromium on a live
// HRP-1S standing under walk (sim_host in real time with --control-socket, walk --socket):
// the page's pause stops simulated time, its step advances it by one control period, its push
// on the base changes the base's velocity in sim_host's log (more than standing does, less than
// impulse / mass), the arrow
// keys and space reach walk as commands, so does a game pad (a fake one given to the page before
// its scripts run: its left stick pushed forward, then its button 1), and a request without the
// run's token is refused (403).
#include <gtest/gtest.h>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "browser.h"
#include "common/scratch.h"
#include "view_process.h"

namespace ohrp::view::testing {
namespace {

// the values of `column` of a CSV log with the time in column "t", as (t, value) rows
std::vector<std::pair<double, double>> Column(const std::string& csv, const std::string& column) {
  std::ifstream in(csv);
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> head;
  for (std::istringstream h(line); std::getline(h, cell, ',');) head.push_back(cell);
  int ti = -1, ci = -1;
  for (size_t i = 0; i < head.size(); ++i) {
    if (head[i] == "t" || head[i] == "time") ti = static_cast<int>(i);
    if (head[i] == column) ci = static_cast<int>(i);
  }
  std::vector<std::pair<double, double>> rows;
  if (ti < 0 || ci < 0) return rows;
  while (std::getline(in, line)) {
    std::vector<std::string> v;
    for (std::istringstream r(line); std::getline(r, cell, ',');) v.push_back(cell);
    if (static_cast<int>(v.size()) > std::max(ti, ci)) rows.emplace_back(std::stod(v[ti]), std::stod(v[ci]));
  }
  return rows;
}

double At(const std::vector<std::pair<double, double>>& rows, double t) {
  for (const auto& r : rows)
    if (r.first >= t - 1e-9) return r.second;
  return NAN;
}

TEST(ViewControl, PausesStepsPushesAndWalksFromThePage) {
  const std::string segment = shm::testing::UniqueSegment("vctl");
  shm::testing::RemoveSegment(segment);
  const fs::path dir = ohrp::testing::ScratchFolder("view_control");
  fs::create_directories(dir);
  const std::string sim_sock = (dir / "sim.sock").string(), walk_sock = (dir / "walk.sock").string();
  std::vector<pid_t> children;
  children.push_back(Start("sim_host", {kScene, "--segment", segment, "--realtime", "--duration", "120",
                                        "--progress", "0", "--wait-controller", "20",
                                        "--control-socket", sim_sock, "--log", (dir / "log.csv").string(),
                                        "--summary", (dir / "sim_summary.json").string()},
                           (dir / "sim_host.txt").string()));
  children.push_back(Start("walk", {"--segment", segment, "--attach-timeout", "20", "--socket", walk_sock},
                           (dir / "walk.txt").string()));
  Viewer viewer;
  StartViewer(&viewer, {segment, "--attach-timeout", "20", "--port", "0", "--control", "--sim-socket",
                        sim_sock, "--walk-socket", walk_sock, "--control-record",
                        (dir / "view_actions.jsonl").string()}, (dir / "viewer.txt").string());
  ASSERT_NE(viewer.url.find("?token="), std::string::npos) << ReadFile(viewer.out_file);
  // the game pad: headless Chromium has none; this one's state is set by the test (none at first)
  Browser page(viewer.url, 1200, 700,
               "window.fakePad = null; Object.defineProperty(Navigator.prototype, 'getGamepads', "
               "{configurable: true, value: () => [window.fakePad, null, null, null]});");
  ASSERT_TRUE(page.ok()) << page.error();
  const std::string state = "document.getElementById('state').dataset";
  ASSERT_TRUE(page.WaitTrue(state + ".control === 'ready' && Number(" + state + ".t) > 1.5", 40))
      << ReadFile(dir / "sim_host.txt") << ReadFile(dir / "walk.txt") << ReadFile(viewer.out_file);
  auto replies = [&] { return page.Eval("Number(" + state + ".controlReplies || 0)").get<int>(); };
  auto reply = [&] { return page.Eval(state + ".controlReply").get<std::string>(); };
  auto t = [&] { return page.Eval("Number(" + state + ".t)").get<double>(); };
  // a click as a user's, in the middle of the button
  auto click = [&](const std::string& id) {
    const nlohmann::json r = page.Eval("(() => { const b = document.getElementById('" + id +
                                       "').getBoundingClientRect(); return [b.x + b.width / 2, b.y + b.height / 2]; })()");
    const int before = replies();
    page.Click(r[0].get<double>(), r[1].get<double>());
    EXPECT_TRUE(shm::testing::WaitFor([&] { return replies() > before; }, 15)) << id;
  };

  // pause: simulated time stops (the page keeps receiving the paused host's heartbeat blocks)
  click("c_pause");
  EXPECT_EQ(reply().rfind("ok: pause", 0), 0u) << reply();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const double paused_at = t();
  std::this_thread::sleep_for(std::chrono::seconds(3));  // longer than walk's --read-timeout (2 s)
  EXPECT_EQ(t(), paused_at);
  // the status line says so (the paused host's heartbeat blocks carry status::kPaused)
  EXPECT_TRUE(page.WaitTrue("document.getElementById('status').textContent.includes('paused')", 3));
  // step: one control period (5 ms) on
  click("c_step");
  EXPECT_EQ(reply().rfind("ok: step", 0), 0u) << reply();
  EXPECT_TRUE(shm::testing::WaitFor([&] { return t() != paused_at; }, 5));
  EXPECT_NEAR(t() - paused_at, 0.005, 1e-9);
  // a click on the robot in the middle of the 3D view picks a body of its trunk for the push
  page.Eval("document.getElementById('push_body').value = 'LLEG_ANKLE_R'");
  const nlohmann::json view = page.Eval("(() => { const b = document.getElementById('view3d')"
                                        ".getBoundingClientRect(); return [b.x + b.width / 2, b.y + b.height / 2]; })()");
  page.Click(view[0].get<double>(), view[1].get<double>());
  EXPECT_TRUE(page.WaitTrue("document.getElementById('push_body').value !== 'LLEG_ANKLE_R'", 3));
  std::printf("a click in the middle of the view picked %s\n",
              page.Eval("document.getElementById('push_body').value").dump().c_str());
  // a push on the base (WAIST): 20 N s along +x over 0.1 s, then resume
  page.Eval("document.getElementById('push_body').value = 'WAIST'");
  page.Eval("document.getElementById('push_impulse').value = '20'");
  click("c_push");
  EXPECT_EQ(reply().rfind("ok: push WAIST 200.000 0.000 0 0.1", 0), 0u) << reply();
  click("c_resume");
  EXPECT_EQ(reply().rfind("ok: resume", 0), 0u) << reply();
  EXPECT_TRUE(page.WaitTrue("!document.getElementById('status').textContent.includes('paused')", 3));
  EXPECT_TRUE(page.WaitTrue("Number(" + state + ".t) > " + std::to_string(paused_at + 1.0), 10));
  // keys: the up arrow starts walking forward, space stops
  int before = replies();
  page.Key("ArrowUp", "ArrowUp", 38);
  EXPECT_TRUE(shm::testing::WaitFor([&] { return replies() > before; }, 15));
  EXPECT_EQ(reply().rfind("ok: \"velocity 0.2 0 0", 0), 0u) << reply();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  before = replies();
  page.Key(" ", "Space", 32);
  EXPECT_TRUE(shm::testing::WaitFor([&] { return replies() > before; }, 15));
  EXPECT_EQ(reply(), "ok: stop");
  // the game pad (polled every 0.1 s): the left stick pushed fully forward (axis 1 at -1) is
  // 0.2 m/s forward, then button 1 stops
  auto pad = [&](double axis1, bool button1) {
    const int before_pad = replies();
    page.Eval("window.fakePad = {id: 'fake', connected: true, axes: [0, " + std::to_string(axis1) +
              ", 0, 0], buttons: [{pressed: false}, {pressed: " + (button1 ? "true" : "false") + "}]}");
    EXPECT_TRUE(shm::testing::WaitFor([&] { return replies() > before_pad; }, 15));
  };
  pad(-1.0, false);
  EXPECT_EQ(reply().rfind("ok: \"velocity 0.20 0 0", 0), 0u) << reply();
  std::this_thread::sleep_for(std::chrono::seconds(1));
  pad(-1.0, true);
  EXPECT_EQ(reply(), "ok: stop");
  // no token: refused
  page.Eval("fetch('/control?to=sim&line=pause').then((r) => { " + state + ".noToken = r.status; })");
  EXPECT_TRUE(page.WaitTrue(state + ".noToken === '403'", 10));
  page.Eval("fetch('/control?token=0123&to=sim&line=pause').then((r) => { " + state + ".badToken = r.status; })");
  EXPECT_TRUE(page.WaitTrue(state + ".badToken === '403'", 10));
  EXPECT_GT(t(), paused_at + 1.0);  // not paused by the refused requests

  // SIGTERM: sim_host writes its log and summary; walk then reports the producer's end
  for (pid_t p : children) ohrp::testing::Terminate(p, 10.0);
  // the actions in the run folder; the push's window as sim_host --push t0,t1,...
  const std::string actions = ReadFile(dir / "actions.jsonl");
  std::istringstream lines(actions);
  std::string line;
  double t0 = -1, t1 = -1;
  while (std::getline(lines, line)) {
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j.contains("sim_host_push"))
      std::sscanf(j["sim_host_push"].get<std::string>().c_str(), "%lf,%lf", &t0, &t1);
  }
  ASSERT_GT(t0, 1.0) << actions;
  EXPECT_NEAR(t1 - t0, 0.1, 1e-6) << actions;
  // the base's velocity along +x over the push: more than it changes over any 0.1 s while
  // standing before it (three times as much), and less than impulse / mass (the robot pivots
  // about its soles: the ground's reaction takes part of the impulse; the base is below the CoM)
  const nlohmann::json summary = nlohmann::json::parse(ReadFile(dir / "sim_summary.json"));
  const double kImpulse = 20;  // [N s] as set on the page
  const double mass = summary["robot_mass"].get<double>();
  const auto vx = Column((dir / "log.csv").string(), "base_vx");
  ASSERT_FALSE(vx.empty()) << "no base_vx in the log";
  const double dv = At(vx, t1) - At(vx, t0);
  double standing = 0;
  for (double a = 1.0; a + 0.1 < t0 - 0.05; a += 0.005)
    standing = std::max(standing, std::fabs(At(vx, a + 0.1) - At(vx, a)));
  std::printf("push %.0f N s on %.1f kg: base vx %+.4f -> %+.4f m/s (impulse/mass %.4f; standing: "
              "at most %.4f m/s in 0.1 s)\n", kImpulse, mass, At(vx, t0), At(vx, t1), kImpulse / mass, standing);
  EXPECT_GT(dv, 3 * standing);
  EXPECT_GT(dv, 0.0);
  EXPECT_LT(dv, kImpulse / mass);
  // the viewer's record: every line forwarded, walk's two with the simulated time they were sent
  std::istringstream forwarded(ReadFile(dir / "view_actions.jsonl"));
  std::vector<std::string> walk_lines;
  int sim_lines = 0;
  for (std::string l; std::getline(forwarded, l);) {
    const nlohmann::json j = nlohmann::json::parse(l);
    if (j["to"] == "walk") {
      walk_lines.push_back(j["line"]);
      EXPECT_GT(j["t"].get<double>(), paused_at) << l;
    }
    if (j["to"] == "sim") ++sim_lines;
  }
  EXPECT_EQ(walk_lines, (std::vector<std::string>{"velocity 0.2 0 0", "stop", "velocity 0.20 0 0", "stop"}));
  EXPECT_EQ(sim_lines, 4);  // pause, step, push, resume
  const std::string walk_out = ReadFile(dir / "walk.txt");
  EXPECT_NE(walk_out.find("live: 4 received, 0 refused"), std::string::npos) << walk_out;
  shm::testing::RemoveSegment(segment);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ohrp::view::testing
