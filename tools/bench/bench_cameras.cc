// bench_cameras: what sim_host's cameras cost (sim_host/cameras.h, docs/effects.md).
//
// The standing HRP-1S (scene_flat, half-sitting, servos holding, soft feet) is stepped as
// sim_host steps it: a control cycle is 5 physics steps of 1 ms and the cameras' Tick, which
// publishes into a real segment. Measured, in turn, `--repeats` rounds, medians:
//   cycle           the control cycle without cameras (the baseline)
//   nobody asks     the same with the cameras' Tick and no request (what every run pays)
//   WxH rgb[+depth] one frame of the left camera: the camera poses, MuJoCo's renderer on OSMesa
//                   (llvmpipe), the read-back, the flip and the copy into the segment
// The frames are timed on the wall clock and on the process's CPU clock: OSMesa's llvmpipe
// renders with worker threads (the CPU time may exceed the wall time; on a loaded machine the
// wall time waits for them). The ratio is the 640x480 frame with depth over the control cycle,
// both in process CPU time.
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "quantile.h"
#include "shm_bridge/bridge.h"
#include "shm_bridge/observer.h"
#include "sim_host/cameras.h"
#include "sim_host/feet.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "sim_host/step.h"

namespace {

using namespace ohrp::sim;

constexpr int kStepsPerCycle = 5;

double Clock(clockid_t id) {
  timespec ts;
  clock_gettime(id, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

using ohrp::bench::Median;

[[noreturn]] void Fail(const std::string& what) {
  std::fprintf(stderr, "bench_cameras: %s\n", what.c_str());
  std::exit(2);
}

struct Row {
  std::string label;
  int width = 0, height = 0;  // 0: no frame (a plain cycle)
  bool depth = false;
  bool ticks = false;         // the cameras' Tick runs (with or without a request)
  std::vector<double> wall = {}, cpu = {};  // per round [s per cycle or per frame]
};

}  // namespace

int main(int argc, char** argv) {
  std::string scene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  int cycles = 60, repeats = 5;
  CLI::App app{
      "bench_cameras: the cost of sim_host's cameras on the standing HRP-1S: a control cycle\n"
      "(5 physics steps) without cameras, the same with the cameras' check and nobody asking, and\n"
      "one left-camera frame (offscreen, OSMesa) at 320x240 and 640x480, RGB and RGB + depth.\n"
      "Medians over the rounds; ends with the ratio of a 640x480 frame to a control cycle."};
  app.add_option("--scene", scene, "MJCF scene with a camera")->capture_default_str();
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  app.add_option("--cycles", cycles, "control cycles (and frames) per measurement")
      ->capture_default_str()->check(ohrp::cli::Plausible("cycles"));
  app.add_option("--repeats", repeats, "rounds over all rows")
      ->capture_default_str()->check(ohrp::cli::Plausible("repeats"));
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  ohrp::model::InstallMujocoHandlers(nullptr);

  std::string error;
  auto loaded = ohrp::model::Scene::Load(scene, &error);
  ohrp::model::RobotMap robot;
  if (!loaded || !ohrp::model::MapRobot(loaded->m(), &robot, &error)) Fail(error);
  if (robot.cameras.empty()) Fail(scene + " declares no camera");
  mjModel* m = loaded->m();
  mjData* d = loaded->d();
  m->opt.timestep = 0.001;
  std::unique_ptr<ohrp::contact::SoftFootContact> soft;
  if (!SetUpFeet(m, FeetOptions{}, robot.total_mass, &soft, &error)) Fail(error);

  // a segment to publish into, and a request for camera 0 (an observer of this process)
  const std::string segment = "bench_cameras_" + std::to_string(getpid());
  ohrp::shm::ProducerConfig pc = ohrp::model::MakeProducerConfig(robot, m, segment, 0.001, 0.005);
  ohrp::shm::Status status;
  auto producer = ohrp::shm::Producer::Create(pc, &status);
  if (!producer) Fail(status.message);
  ohrp::shm::Observer asking;
  if (!asking.open(segment).ok()) Fail("cannot observe the bench's own segment");

  std::vector<Row> rows = {{"cycle (5 x 1 ms steps)", 0, 0, false, false},
                           {"cycle + cameras, nobody asks", 0, 0, false, true},
                           {"frame 320x240 rgb", 320, 240, false, true},
                           {"frame 320x240 rgb+depth", 320, 240, true, true},
                           {"frame 640x480 rgb", 640, 480, false, true},
                           {"frame 640x480 rgb+depth", 640, 480, true, true}};
  // the cameras of a row: a frame every control cycle while asked
  auto make_cameras = [&](const Row& row) {
    CameraOptions co;
    co.rate = 1.0 / (kStepsPerCycle * 0.001);
    co.width = row.width > 0 ? row.width : 640;
    co.height = row.height > 0 ? row.height : 480;
    co.depth = row.depth;
    return std::make_unique<Cameras>(robot, co, true);
  };

  for (int round = 0; round < repeats; ++round) {
    for (std::size_t r = 0; r < rows.size(); ++r) {
      Row& row = rows[r];
      if (!loaded->Reset("halfsit", &error)) Fail(error);
      ohrp::model::Servo servo(robot);
      servo.HoldCurrent(d);
      PhysicsStep step(m, d, {&servo, soft.get()});
      const bool frames = row.width > 0;
      // fresh per round (its frame clock starts at t = 0); set up during the warm-up cycle
      const std::unique_ptr<Cameras> cams = row.ticks ? make_cameras(row) : nullptr;
      asking.request_images(frames ? 1u : 0u);
      double wall = 0, cpu = 0;
      for (int c = -1; c < cycles; ++c) {  // cycle -1: warm-up (and the renderer's set-up)
        const double w0 = Clock(CLOCK_MONOTONIC), c0 = Clock(CLOCK_PROCESS_CPUTIME_ID);
        for (int k = 0; k < kStepsPerCycle; ++k) step.Step(k == kStepsPerCycle - 1);
        const double w1 = Clock(CLOCK_MONOTONIC), c1 = Clock(CLOCK_PROCESS_CPUTIME_ID);
        if (row.ticks && !cams->Tick(m, d, producer.get(), &error)) Fail(error);
        const double w2 = Clock(CLOCK_MONOTONIC), c2 = Clock(CLOCK_PROCESS_CPUTIME_ID);
        if (c < 0) continue;
        // a plain cycle: steps (+ the check); a frame row: the frame alone
        wall += frames ? w2 - w1 : w2 - w0;
        cpu += frames ? c2 - c1 : c2 - c0;
      }
      if (frames && cams->frames() < static_cast<uint64_t>(cycles)) {
        Fail(row.label + ": " + std::to_string(cams->frames()) + " frames rendered for " +
             std::to_string(cycles) + " cycles");
      }
      row.wall.push_back(wall / cycles);
      row.cpu.push_back(cpu / cycles);
    }
  }
  asking.request_images(0);

  std::printf("bench_cameras: %s, left camera '%s', %d cycles x %d rounds, medians\n",
              scene.c_str(), robot.cameras[0].name.c_str(), cycles, repeats);
  std::printf("%-32s %12s %14s\n", "", "wall [ms]", "process CPU [ms]");
  for (const Row& row : rows) {
    std::printf("%-32s %12.3f %14.3f\n", row.label.c_str(), 1e3 * Median(row.wall),
                1e3 * Median(row.cpu));
  }
  // CPU time: on a shared machine the wall time of a sub-millisecond cycle is mostly the others
  const double cycle = Median(rows[0].cpu), frame = Median(rows[5].cpu);
  std::printf("nobody asks: %+.1f %% of a control cycle's CPU time\n",
              100.0 * (Median(rows[1].cpu) / cycle - 1.0));
  std::printf("ratio: %.2f (640x480 rgb+depth frame / control cycle, process CPU)\n", frame / cycle);
  return 0;
}
