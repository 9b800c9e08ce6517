// The identification tested honestly: a "robot" recording made with hw_driver + hw_emulator whose
// soles have parameters the identification is not told (2e6 N/m and 45 s/m; sim_host's default
// soles are 3e6 N/m and 30 s/m), the experiment of scenarios/rocking_fig12.yaml (its posture and
// gains, its push), sensor noise added to every channel of the driver's log afterwards; then
// ohrp_identify on the noisy log must recover both within 10 %. The same on a recording that
// sim_host makes of the scenario with those soles (no real time: this one runs on a busy
// machine too; it does not recover D, see there). Both check that the refinement's simulations ran as sweeps (one sweep folder per
// stage, its sweep.csv listing the runs identify.json reports).
#include <gtest/gtest.h>

#include <signal.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <chrono>
#include <vector>

#include "contact/params.h"  // sim_host's default soles: the first simulation's
#include "contact/params_file.h"
#include "../controllers/fake_robot.h"  // Spawn, WaitExit, Program, TempPath, ReadFile

namespace ohrp::identify {
namespace {

namespace fs = std::filesystem;
using controllers::testing::Program;
using ohrp::testing::ReadFile;
using controllers::testing::RemoveSegment;
using controllers::testing::Spawn;
using controllers::testing::TempPath;
using controllers::testing::UniqueSegment;
using controllers::testing::WaitExit;

const std::string kSource = OHRP_SOURCE_DIR;
constexpr double kStiffness = 2e6;  // [N/m] the robot's soles, not told to the identification
constexpr double kDamping = 45;     // [s/m]

// the sensor noise added to the log, per kind of column (1 sigma)
double NoiseOf(const std::string& c) {
  auto ends = [&](const char* s) { return c.size() > 3 && c.compare(c.size() - 3, 3, s) == 0; };
  if (c.rfind("q_", 0) == 0) return 1e-4;     // [rad] encoders
  if (c.rfind("tau_", 0) == 0) return 0.5;    // [N m]
  if (ends("_fx") || ends("_fy") || ends("_fz")) return 2.0;  // [N]
  if (ends("_tx") || ends("_ty") || ends("_tz")) return 0.5;  // [N m]
  if (ends("_gx") || ends("_gy") || ends("_gz")) return 5e-3;  // [rad/s]
  if (ends("_ax") || ends("_ay") || ends("_az")) return 0.05;  // [m/s^2]
  return 0;  // time, status, rejected, qref_, quaternions
}

// Records the experiment on the emulated robot into dir/robot.csv. Returns "" for a faithful
// real-time recording, else why not: the emulator resynchronised its robot time to the wall
// clock (it fell far behind: the robot's time then runs slower than the driver's, and every
// frequency in the log with it) or the driver skipped cycles at more than 50 places after the
// push (a loaded machine).
std::string Record(const std::string& dir, const std::string& segment) {
  const std::string scene = kSource + "/mjcf/hrp1s/scene_flat.xml";
  fs::remove(dir + "/port");
  fs::remove(dir + "/emulator.out");
  fs::remove(dir + "/driver.out");
  // the robot: the emulated boards with soft soles of their own, the scenario's push
  const pid_t emu = Spawn({Program("hw_emulator"), "--model", scene, "--keyframe", "halfsit",
                           "--port", "0", "--port-file", dir + "/port", "--wait-driver", "60",
                           "--timestep", "0.0005", "--period", "0.002", "--contact", "soft",
                           "--contact-stiffness", "2e6", "--contact-damping", "45", "--push",
                           "9.0,9.5,0,0,0,0,40,0"},
                          dir + "/emulator.out");
  int port = 0;
  for (int i = 0; i < 600 && port == 0; ++i) {
    std::ifstream in(dir + "/port");
    if (!(in >> port)) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (port == 0) {
    kill(emu, SIGKILL);
    WaitExit(emu, 10);
    return "hw_emulator did not start: " + ReadFile(dir + "/emulator.out");
  }
  const pid_t drv = Spawn({Program("hw_driver"), "--model", scene, "--io",
                           Program("../lib/libohrp_io_udp.so"), "--io-arg",
                           "port=" + std::to_string(port), "--io-arg", "timeout_ms=100",
                           "--segment", segment, "--period", "0.002", "--watchdog-cycles", "100",
                           "--board-timeout-cycles", "100", "--rt-priority", "0", "--no-mlock",
                           "--duration", "13.5", "--log", dir + "/robot.csv", "--summary",
                           dir + "/driver.json", "--quiet"},
                          dir + "/driver.out");
  for (int i = 0; i < 600 && !fs::exists("/dev/shm/ohrp_" + segment); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  // the scenario's controller (scenarios/rocking_fig12.yaml)
  const pid_t ctl = Spawn({Program("posture"), "--segment", segment, "--pose",
                           kSource + "/controllers/poses/hrp1s_halfsit_lean.yaml", "--ramp", "4.0",
                           "--kp-scale", "100", "--kd-scale", "10"},
                          dir + "/posture.out");
  const int drv_code = WaitExit(drv, 120);
  WaitExit(ctl, 30);
  kill(emu, SIGINT);
  WaitExit(emu, 30);
  RemoveSegment(segment);
  if (drv_code != 0)
    return "hw_driver exited " + std::to_string(drv_code) + ": " + ReadFile(dir + "/driver.out");
  const std::string emu_out = ReadFile(dir + "/emulator.out");
  unsigned long resyncs = 0;
  const size_t at = emu_out.find(" overruns, ");
  if (at != std::string::npos) resyncs = std::stoul(emu_out.substr(at + 11));
  // the driver's rows from the push on (8.5 .. 13.5 s): a few skipped cycles only lose rows
  // (measured here: 12 places, the identification unchanged to 0.1 %), many mean a stalled loop
  int gaps = 0;
  {
    std::ifstream in(dir + "/robot.csv");
    std::string line;
    std::getline(in, line);
    double prev = -1;
    while (std::getline(in, line)) {
      const double t = std::stod(line);
      if (prev >= 8.5 && t - prev > 1.5 * 0.002) ++gaps;
      prev = t;
    }
  }
  if (resyncs > 0 || gaps > 50)
    return "not real time (a loaded machine): hw_emulator resynchronised " +
           std::to_string(resyncs) + " times, hw_driver skipped cycles at " + std::to_string(gaps) +
           " places after 8.5 s";
  return "";
}

// The refinement's simulations went through ohrp sweep's library: `id` holds one sweep folder
// per stage (nominal, k, d, final) whose sweep.csv lists exactly the runs identify.json reports
// for that stage, at the K and D the method prescribes from the estimates it reports (K stage:
// K_a x (1 -+ step) at D_a; D stage: D_a x (1 -+ 2 step) at K_b; final: (K_b, D_b)), each run
// in that sweep's variants/vNNN folder with its data log.
void ExpectStagesRanAsSweeps(const std::string& id, const nlohmann::json& j, double step) {
  // the K stage is centred on the first estimate (the recording aligned on the nominal run), the
  // D stage on the closed form after the recording is aligned again on the K stage's middle run
  const double k1 = j["first"]["k"], d1 = j["first"]["d"];
  const double da = j["closed_form"]["d"];
  const double kb = j["refined"]["k"], db = j["refined"]["d"];
  const std::vector<std::pair<std::string, std::vector<std::pair<double, double>>>> stages = {
      {"nominal", {{contact::SoftContactParams{}.stiffness, contact::SoftContactParams{}.damping}}},
      {"k", {{k1 * (1 - step), d1}, {k1, d1}, {k1 * (1 + step), d1}}},
      {"d", {{kb, da * (1 - 2 * step)}, {kb, da}, {kb, da * (1 + 2 * step)}}},
      {"final", {{kb, db}}}};
  size_t total = 0;
  ASSERT_TRUE(j.contains("sweeps"));
  ASSERT_EQ(j["sweeps"].size(), stages.size());
  for (size_t s = 0; s < stages.size(); ++s) {
    const auto& [stage, kd] = stages[s];
    SCOPED_TRACE("stage " + stage);
    EXPECT_EQ(j["sweeps"][s]["stage"], stage);
    EXPECT_EQ(j["sweeps"][s]["variants"], kd.size());
    EXPECT_GT(j["sweeps"][s]["wall_time"].get<double>(), 0);
    // sweep.csv: variant, contact_params.stiffness, contact_params.damping, status, ...
    std::ifstream csv(id + "/" + stage + "/sweep.csv");
    ASSERT_TRUE(csv.good()) << id << "/" << stage << "/sweep.csv is missing";
    std::string line;
    ASSERT_TRUE(std::getline(csv, line));
    EXPECT_EQ(line.rfind("variant,contact_params.stiffness,contact_params.damping,status,", 0), 0u) << line;
    std::vector<std::vector<std::string>> rows;
    while (std::getline(csv, line)) {
      std::vector<std::string> cells;
      std::stringstream ls(line);
      for (std::string c; cells.size() < 4 && std::getline(ls, c, ',');) cells.push_back(c);
      rows.push_back(cells);
    }
    ASSERT_EQ(rows.size(), kd.size());
    for (size_t i = 0; i < kd.size(); ++i) {
      ASSERT_EQ(rows[i].size(), 4u);
      EXPECT_EQ(std::stoi(rows[i][0]), static_cast<int>(i));
      EXPECT_NEAR(std::stod(rows[i][1]), kd[i].first, 1e-9 * kd[i].first);
      EXPECT_NEAR(std::stod(rows[i][2]), kd[i].second, 1e-9 * kd[i].second);
      EXPECT_TRUE(rows[i][3] == "pass" || rows[i][3] == "fail") << rows[i][3];
      // identify.json's run of this variant: the same K, D, measured from that folder's log
      const nlohmann::json& run = j["runs"][total + i];
      EXPECT_EQ(run["stage"], stage);
      EXPECT_NEAR(run["k"].get<double>(), kd[i].first, 1e-9 * kd[i].first);
      EXPECT_NEAR(run["d"].get<double>(), kd[i].second, 1e-9 * kd[i].second);
      char v[32];
      std::snprintf(v, sizeof(v), "/v%03zu", i);
      EXPECT_EQ(run["dir"], id + "/" + stage + "/variants" + v);
      EXPECT_TRUE(fs::exists(id + "/" + stage + "/variants" + v + "/run/log.csv"));
    }
    total += kd.size();
  }
  EXPECT_EQ(j["runs"].size(), total);
}

// Sensor noise on every measured channel of the log `in_path` (NoiseOf, seeded) into `out_path`.
void AddNoise(const std::string& in_path, const std::string& out_path, int min_rows) {
  std::ifstream in(in_path);
  std::ofstream out(out_path);
  std::string header, line;
  ASSERT_TRUE(std::getline(in, header));
  out << header << "\n";
  std::vector<double> sd;
  std::stringstream hs(header);
  for (std::string c; std::getline(hs, c, ',');) sd.push_back(NoiseOf(c));
  std::mt19937 rng(16);
  std::normal_distribution<double> n(0.0, 1.0);
  int rows = 0;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    size_t c = 0;
    for (std::string v; std::getline(ls, v, ','); ++c) {
      const double x = std::stod(v) + (c < sd.size() ? sd[c] * n(rng) : 0.0);
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%.9g", x);
      out << (c ? "," : "") << buf;
    }
    out << "\n";
    ++rows;
  }
  ASSERT_GT(rows, min_rows);
}

// ohrp_identify on `recording` (told nothing of the soles), its results in dir/id: the stages
// run as sweeps; the refinement brought the final run onto the recording (its frequency within
// 1 %, its log decrement within 5 %: the lines of (b) are straight to that); with
// `expect_recovery` both estimates within 10 % of kStiffness and kDamping.
void IdentifyAndCheck(const std::string& dir, const std::string& recording, const char* what,
                      bool expect_recovery) {
  // identify, told nothing of the soles
  const int code = WaitExit(Spawn({Program("ohrp_identify"), recording, "--scenario",
                                   kSource + "/scenarios/rocking_fig12.yaml", "--out", dir + "/id",
                                   "--jobs", "2"},
                                  dir + "/identify.out"),
                            300);
  ASSERT_EQ(code, 0) << ReadFile(dir + "/identify.out");
  std::ifstream in(dir + "/id/identify.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << ReadFile(dir + "/identify.out");
  const double k = j["refined"]["k"], d = j["refined"]["d"];
  const double ka = j["closed_form"]["k"], da = j["closed_form"]["d"];
  if (expect_recovery) {
    EXPECT_NEAR(k, kStiffness, 0.10 * kStiffness);
    EXPECT_NEAR(d, kDamping, 0.10 * kDamping);
    // the linearised model alone, to the paper's 10 % as well
    EXPECT_NEAR(ka, kStiffness, 0.10 * kStiffness);
    EXPECT_NEAR(da, kDamping, 0.10 * kDamping);
  }
  const double f = j["recorded"]["frequency"], delta = j["recorded"]["log_decrement"];
  EXPECT_NEAR(j["final"]["frequency"].get<double>(), f, 0.01 * f);
  EXPECT_NEAR(j["final"]["log_decrement"].get<double>(), delta, 0.05 * delta);
  EXPECT_GT(j["refined"]["k_se"].get<double>(), 0);
  EXPECT_GT(j["refined"]["d_se"].get<double>(), 0);
  ExpectStagesRanAsSweeps(dir + "/id", j, 0.15);  // --step's default
  std::printf("[ figures  ] %s: soles 2e6 N/m, 45 s/m; recording f %.4f +- %.4f Hz, delta %.4f +- %.4f; "
              "closed form K %.4g (%+.2f %%), D %.4g (%+.2f %%); refined K %.4g +- %.2g (%+.2f %%), "
              "D %.4g +- %.2g (%+.2f %%); %zu simulations\n",
              what, j["recorded"]["frequency"].get<double>(), j["recorded"]["frequency_se"].get<double>(),
              j["recorded"]["log_decrement"].get<double>(), j["recorded"]["log_decrement_se"].get<double>(),
              ka, 100 * (ka / kStiffness - 1), da, 100 * (da / kDamping - 1), k,
              j["refined"]["k_se"].get<double>(), 100 * (k / kStiffness - 1), d,
              j["refined"]["d_se"].get<double>(), 100 * (d / kDamping - 1), j["runs"].size());
}

TEST(IdentifyRobot, RecoversTheSolesOfAnEmulatedRobotFromANoisyDriverLog) {
  for (const char* p : {"hw_emulator", "hw_driver", "posture", "ohrp_identify", "ohrp_run", "sim_host"})
    if (!fs::exists(Program(p))) GTEST_SKIP() << Program(p) << " is not built";
  const std::string tmp = TempPath("identify_robot");
  const std::string dir = tmp + ".d";
  fs::remove(tmp);
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string segment = UniqueSegment("idrobot");

  // a faithful recording: up to three tries on a loaded machine, each saying why it was not
  std::string why;
  for (int attempt = 0; attempt < 3; ++attempt) {
    why = Record(dir, segment);
    if (why.empty()) break;
    std::printf("[ note     ] recording %d not used: %s\n", attempt + 1, why.c_str());
  }
#ifdef OHRP_SANITIZE
  // the sanitizers slow the emulated robot's real-time loop: a recording that could not be made
  // in real time there says so instead of failing (the normal build fails on it)
  if (!why.empty()) GTEST_SKIP() << "under the sanitizers: " << why;
#endif
  ASSERT_TRUE(why.empty()) << why;

  // sensor noise on every measured channel, seeded
  AddNoise(dir + "/robot.csv", dir + "/robot_noisy.csv", 6000);  // 13.5 s at 2 ms
  if (HasFatalFailure()) return;

  IdentifyAndCheck(dir, dir + "/robot_noisy.csv", "emulated robot", true);
  if (!HasFailure()) fs::remove_all(dir);  // kept for a look otherwise
}

// The same identification on a recording sim_host makes itself: the scenario with the soles
// 2e6 N/m and 45 s/m (contact_params), run by ohrp_run (not in real time: it does not depend on
// a quiet machine, unlike the test above), the same sensor noise added: the stages' sweeps, the
// refinement's convergence on the recording, the recovery within 10 % and the true lag.
TEST(IdentifySimulated, RecoversTheSolesOfANoisySimulatedRecordingThroughSweeps) {
  for (const char* p : {"ohrp_identify", "ohrp_run", "sim_host", "posture"})
    if (!fs::exists(Program(p))) GTEST_SKIP() << Program(p) << " is not built";
  const std::string tmp = TempPath("identify_sim");
  const std::string dir = tmp + ".d";
  fs::remove(tmp);
  fs::remove_all(dir);
  fs::create_directories(dir);
  char params[96];
  std::snprintf(params, sizeof(params), "contact_params: {stiffness: %.9g, damping: %.9g}\n",
                kStiffness, kDamping);
  std::ofstream(dir + "/robot.yaml") << ReadFile(kSource + "/scenarios/rocking_fig12.yaml") << params;
  const int run = WaitExit(Spawn({Program("ohrp_run"), dir + "/robot.yaml", "--out", dir + "/robot",
                                  "--no-plot", "-q"},
                                 dir + "/robot.out"),
                           300);
  ASSERT_EQ(run, 0) << ReadFile(dir + "/robot.out");
  AddNoise(dir + "/robot/log.csv", dir + "/robot_noisy.csv", 1000);
  if (HasFatalFailure()) return;
  // this recording once came out at K -2.7 %, D -20.5 %: aligned on the nominal run (3.0 Hz
  // against its 2.45 Hz) it was 0.059 s off, and its decay was read over the last swings, a few
  // noise sigma high, that this draw of noise kept (docs/identify.md, "Alignment and noise")
  IdentifyAndCheck(dir, dir + "/robot_noisy.csv", "simulated robot", true);
  std::ifstream in(dir + "/id/identify.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(j.is_discarded());
  // aligned again on a run at the recording's frequency: the true lag, 0, to a tenth of the
  // 2 ms sample (the first alignment may be a fraction of a period off)
  EXPECT_NEAR(j["lag"].get<double>(), 0.0, 0.002) << "first alignment: " << j["first"]["lag"];
  // the stated uncertainty covers the error (issue 35: it was the measurement's standard error,
  // 5-40 times smaller than the errors): within 3 stated sigma of the truth
  EXPECT_LT(std::fabs(j["refined"]["k"].get<double>() - kStiffness), 3 * j["refined"]["k_se"].get<double>());
  EXPECT_LT(std::fabs(j["refined"]["d"].get<double>() - kDamping), 3 * j["refined"]["d_se"].get<double>());
  EXPECT_GT(j["noise_spread"]["frequency"].get<double>(), 0);
  // the soles as sim_host --contact-file takes them, and the rocking closer to the recording at
  // them than at sim_host's default soles (issue 35, item 4)
  contact::SoftContactParams soles;
  std::vector<std::string> keys;
  std::string error;
  ASSERT_TRUE(contact::ReadContactFile(dir + "/id/soles.yaml", &soles, &keys, &error)) << error;
  EXPECT_NEAR(soles.stiffness, j["refined"]["k"].get<double>(), 1e-8 * kStiffness);
  EXPECT_NEAR(soles.damping, j["refined"]["d"].get<double>(), 1e-8 * kDamping);
  EXPECT_LT(j["final"]["rms"].get<double>(), 0.5 * j["final"]["rms_nominal"].get<double>());
  std::printf("[ figures  ] RMS of recording - simulation over the window: %.4g at the default soles, "
              "%.4g at the identified ones\n", j["final"]["rms_nominal"].get<double>(), j["final"]["rms"].get<double>());
  if (!HasFailure()) fs::remove_all(dir);  // kept for a look otherwise
}

}  // namespace
}  // namespace ohrp::identify
