// ohrp view --control by the mouse in the 3D view (docs/view.md "Control from the page", web/
// workbench.js), in headless Chromium on a live HRP-1S standing under walk (sim_host in real time
// with --control-socket, walk --socket): a drag from the base pushes it along the drag (the
// camera's right vector for a drag to the right), the push reaching sim_host's actions.jsonl;
// a Ctrl-drag on the floor sends walk a goal at the point pressed, heading along the drag, and
// the robot walks there; a Ctrl-click farther than walk takes a live goal is refused with the
// reason on the page.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <thread>
#include <vector>

#include "browser.h"
#include "common/scratch.h"
#include "view_process.h"

namespace ohrp::view::testing {
namespace {

TEST(ViewWorkbench, DragPushesAndCtrlClickSendsAGoal) {
  const std::string segment = shm::testing::UniqueSegment("vwb");
  shm::testing::RemoveSegment(segment);
  const fs::path dir = ohrp::testing::ScratchFolder("view_workbench");
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
                        sim_sock, "--walk-socket", walk_sock}, (dir / "viewer.txt").string());
  Browser page(viewer.url);
  ASSERT_TRUE(page.ok()) << page.error();
  const std::string state = "document.getElementById('state').dataset";
  ASSERT_TRUE(page.WaitTrue(state + ".control === 'ready' && Number(" + state + ".t) > 1.5", 40))
      << ReadFile(dir / "sim_host.txt") << ReadFile(dir / "walk.txt") << ReadFile(viewer.out_file);
  auto replies = [&] { return page.Eval("Number(" + state + ".controlReplies || 0)").get<int>(); };
  auto reply = [&] { return page.Eval(state + ".controlReply").get<std::string>(); };
  auto t = [&] { return page.Eval("Number(" + state + ".t)").get<double>(); };
  // the page's pixel of a world point (the camera as drawn)
  auto pixel = [&](double x, double y, double z) {
    return page.Eval("(() => { placeCamera(); camera.updateMatrixWorld(); const v = new THREE.Vector3(" +
                     std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
                     ").project(camera); const b = canvas.getBoundingClientRect(); return [b.x + (v.x + 1) / 2 * "
                     "b.width, b.y + (1 - v.y) / 2 * b.height]; })()");
  };
  page.Eval("document.getElementById('follow').checked = false");  // the camera stays put

  // a drag from the base 80 px to the right: a push along the camera's right vector. The press is
  // on a pixel where the base is the first thing under the mouse (the base's origin may lie behind
  // a hip link as the camera sees it): the nearest such pixel to the origin's, searched in rings.
  const nlohmann::json from = page.Eval(
      "(() => { placeCamera(); camera.updateMatrixWorld();"
      " const c = moving.find((o) => o && o.userData.body === 'WAIST').getWorldPosition(new THREE.Vector3()).project(camera);"
      " const b = canvas.getBoundingClientRect(); const ray = new THREE.Raycaster();"
      " for (let r = 0; r <= 60; r += 3) for (let a = 0; a < (r ? 24 : 1); ++a) {"
      "   const px = b.x + (c.x + 1) / 2 * b.width + r * Math.cos(a * Math.PI / 12);"
      "   const py = b.y + (1 - c.y) / 2 * b.height + r * Math.sin(a * Math.PI / 12);"
      "   ray.setFromCamera(new THREE.Vector2(2 * (px - b.x) / b.width - 1, 1 - 2 * (py - b.y) / b.height), camera);"
      "   const hit = ray.intersectObjects(moving.filter((o) => o), true)[0];"
      "   let o = hit && hit.object; while (o && moving.indexOf(o) < 0) o = o.parent;"
      "   if (o && o.userData.body === 'WAIST') return [px, py]; }"
      " return null; })()");
  ASSERT_TRUE(from.is_array()) << "no pixel within 60 px of the base's origin shows the base";
  const nlohmann::json right = page.Eval("(() => { const r = new THREE.Vector3().setFromMatrixColumn("
                                         "camera.matrixWorld, 0); return [r.x, r.y, r.z]; })()");
  int before = replies();
  page.Drag(from[0].get<double>(), from[1].get<double>(), from[0].get<double>() + 80, from[1].get<double>());
  ASSERT_TRUE(shm::testing::WaitFor([&] { return replies() > before; }, 15))
      << "the press started " << page.Eval(state + ".benchPress").dump() << " at " << from.dump();
  const std::string push = page.Eval(state + ".dragPush").get<std::string>();
  EXPECT_EQ(reply().rfind("ok: " + push, 0), 0u) << reply();
  std::printf("drag on the base: %s (camera right %s)\n", push.c_str(), right.dump().c_str());
  char body[32];
  double f[3], seconds;
  ASSERT_EQ(std::sscanf(push.c_str(), "push %31s %lf %lf %lf %lf", body, &f[0], &f[1], &f[2], &seconds), 5) << push;
  EXPECT_STREQ(body, "WAIST");
  const double n = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  const double cosine = (f[0] * right[0].get<double>() + f[1] * right[1].get<double>() +
                         f[2] * right[2].get<double>()) / n;
  EXPECT_GT(cosine, std::cos(2 * M_PI / 180)) << push;  // within 2 deg of the drag's direction
  EXPECT_GT(n * seconds, 1.0);
  EXPECT_LE(n * seconds, 150.0 + 1e-3);

  // a Ctrl-drag on the floor 0.6 m ahead and 0.2 m to the left of the feet, then 0.5 m along +y:
  // the goal there, facing +y (the robot starts facing +x)
  const nlohmann::json feet = page.Eval("feetNow()");
  ASSERT_TRUE(feet.is_object()) << feet.dump();
  const double gx = feet["x"].get<double>() + 0.6, gy = feet["y"].get<double>() + 0.2;
  const nlohmann::json g0 = pixel(gx, gy, 0), g1 = pixel(gx, gy + 0.5, 0);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  before = replies();
  page.Drag(g0[0].get<double>(), g0[1].get<double>(), g1[0].get<double>(), g1[1].get<double>(), 2);
  ASSERT_TRUE(shm::testing::WaitFor([&] { return replies() > before; }, 15));
  const std::string goal = page.Eval(state + ".goalLine").get<std::string>();
  EXPECT_EQ(reply().rfind("ok: \"" + goal + "\": ", 0), 0u) << reply();
  double x, y, yaw;
  ASSERT_EQ(std::sscanf(goal.c_str(), "goal_now %lf %lf %lf", &x, &y, &yaw), 3) << goal;
  const double feet_yaw = feet["yaw"].get<double>() * 180 / M_PI;
  std::printf("ctrl-drag on the floor: %s (feet at %s); walk: %s\n", goal.c_str(), feet.dump().c_str(),
              reply().c_str());
  // the point pressed, in the feet's frame, as far as a pixel is (about 3 mm here)
  EXPECT_NEAR(x, 0.6 * std::cos(feet["yaw"].get<double>()) + 0.2 * std::sin(feet["yaw"].get<double>()), 0.02);
  EXPECT_NEAR(y, -0.6 * std::sin(feet["yaw"].get<double>()) + 0.2 * std::cos(feet["yaw"].get<double>()), 0.02);
  EXPECT_NEAR(yaw, 90 - feet_yaw, 2.0);
  // walked there: the feet's middle at the point, facing +y (the simulation's truth, as drawn)
  const double sent_at = t();
  EXPECT_TRUE(page.WaitTrue("Number(" + state + ".t) > " + std::to_string(sent_at + 12), 60));
  const nlohmann::json end = page.Eval("feetNow()");
  std::printf("after 12 s: feet at %s, goal (%.3f, %.3f, 90 deg)\n", end.dump().c_str(), gx, gy);
  EXPECT_NEAR(end["x"].get<double>(), gx, 0.08);
  EXPECT_NEAR(end["y"].get<double>(), gy, 0.08);
  EXPECT_NEAR(end["yaw"].get<double>() * 180 / M_PI, 90, 5.0);

  // a Ctrl-click 6 m away from the camera's side of the robot: refused, the reason on the page
  const double az = page.Eval("orbit.azimuth").get<double>();
  const nlohmann::json now = page.Eval("feetNow()");
  const nlohmann::json far = pixel(now["x"].get<double>() - 6 * std::cos(az), now["y"].get<double>() - 6 * std::sin(az), 0);
  before = replies();
  page.Drag(far[0].get<double>(), far[1].get<double>(), far[0].get<double>(), far[1].get<double>(), 2, 1);
  ASSERT_TRUE(shm::testing::WaitFor([&] { return replies() > before; }, 15));
  const std::string shown = page.Eval("document.getElementById('control_reply').textContent").get<std::string>();
  EXPECT_NE(shown.find("m from the feet, farther than the 5 m a live goal may be"), std::string::npos) << shown;
  EXPECT_EQ(page.Eval("document.getElementById('control_reply').className").get<std::string>(), "warn");

  for (pid_t p : children) ohrp::testing::Terminate(p, 10.0);
  // the push in sim_host's actions, as the page sent it
  std::istringstream actions(ReadFile(dir / "actions.jsonl"));
  int pushes = 0;
  for (std::string l; std::getline(actions, l);) {
    const nlohmann::json j = nlohmann::json::parse(l);
    if (j["action"] != push) continue;
    ++pushes;
    EXPECT_EQ(j["body"], "WAIST");
    EXPECT_TRUE(j.contains("sim_host_push")) << l;
  }
  EXPECT_EQ(pushes, 1) << ReadFile(dir / "actions.jsonl");
  const std::string walk_out = ReadFile(dir / "walk.txt");
  EXPECT_NE(walk_out.find("live: 2 received, 1 refused"), std::string::npos) << walk_out;
  shm::testing::RemoveSegment(segment);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ohrp::view::testing
