// ohrp_video: offscreen video of a run (OSMesa, no display needed). Replays the data log of a
// run (base pose and joint angles per row, see sim_host/recorder.h) through the scene's model and
// renders it with MuJoCo's renderer (render/offscreen.h) into an MP4 (through Debian's ffmpeg) or PNG frames.
//
// Rendering after the run, from the log, keeps the simulation free of any rendering cost (the
// effects it runs are the ones the scene calls for) and works on any run folder, including the
// ones CI leaves behind.
#include <mujoco/mujoco.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "render/offscreen.h"
#include "render/png.h"
#include "robot_model/load.h"
#include "datalog/table.h"  // the data log's reader
#include "tool_process/run_command.h"

namespace {

void OnMujocoError(const char* msg) {
  std::fprintf(stderr, "ohrp_video: MuJoCo error: %s\n", msg);
  std::exit(3);
}
void OnMujocoWarning(const char* msg) { std::fprintf(stderr, "ohrp_video: MuJoCo warning: %s\n", msg); }

bool IsDir(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

}  // namespace

int main(int argc, char** argv) {
  mju_user_error = OnMujocoError;
  mju_user_warning = OnMujocoWarning;

  std::string input, scene, out, frames_dir;
  double fps = 30, speed = 1, from = 0, until = -1, distance = 3.2, azimuth = 135,
         elevation = -12;
  int width = 640, height = 480;
  bool shadows = false;
  std::vector<double> stills;
  CLI::App app{
      "ohrp_video: renders a run offscreen (OSMesa, no display) from its data log: the base pose\n"
      "and joint angles of each logged row, replayed through the scene's model. Writes an MP4\n"
      "through ffmpeg, PNG frames, or single stills."};
  app.add_option("run", input, "a run folder (ohrp_run --out DIR: log.csv, sim_summary.json) or a log.csv")
      ->required();
  app.add_option("--scene", scene, "MJCF scene (default: the one recorded in the run's sim_summary.json)");
  app.add_option("--out,-o", out, "MP4 file (default: RUN/video.mp4; needs ffmpeg, './ohrp setup' installs it)");
  app.add_option("--frames", frames_dir, "write PNG frames frame_00000.png... into this folder instead of an MP4");
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  using ohrp::cli::Plausible;
  app.add_option("--still", stills, "write one PNG per listed time [s] (RUN/still_<t>.png) and no video")
      ->delimiter(',')->check(Plausible("time"));
  app.add_option("--fps", fps, "frames per second of the video")->capture_default_str()->check(Plausible("frame_rate"));
  app.add_option("--speed", speed, "simulated seconds per video second")->capture_default_str()->check(Plausible("speed_factor"));
  app.add_option("--from", from, "start time [s]")->capture_default_str()->check(Plausible("time"));
  app.add_option("--until", until, "end time [s] (default: the end of the log)")->check(Plausible("time"));
  app.add_option("--width", width, "frame width [px]")->capture_default_str()->check(Plausible("pixels"));
  app.add_option("--height", height, "frame height [px]")->capture_default_str()->check(Plausible("pixels"));
  app.add_flag("--shadows", shadows, "render shadows and reflections (slower in software)");
  app.add_option("--distance", distance, "camera distance from the robot's base [m]")->capture_default_str()
      ->check(Plausible("distance"));
  app.add_option("--azimuth", azimuth, "camera azimuth [deg]")->capture_default_str()->check(Plausible("angle_deg"));
  app.add_option("--elevation", elevation, "camera elevation [deg]")->capture_default_str()->check(Plausible("angle_deg"));
  app.footer("Example: ohrp_video runs/demo/stand            (runs/demo/stand/video.mp4)\n"
             "         ohrp_video runs/demo/stand --still 1,5 (two PNG stills)\n"
             "Every number is checked against its plausible range (cli/plausible.h), and so are\n"
             "the log's times and the video's frame count, before anything is rendered.\n"
             "Exit codes: 0 written, 2 bad option, run folder, log, scene, time window or frame\n"
             "count, or no ffmpeg, 3 MuJoCo, OSMesa or ffmpeg failed.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;

  // ---- inputs: the log and the scene
  std::string run_dir, log_path = input;
  if (IsDir(input)) {
    run_dir = input;
    log_path = input + "/log.csv";
  } else {
    const size_t slash = input.rfind('/');
    run_dir = slash == std::string::npos ? "." : input.substr(0, slash);
  }
  if (scene.empty()) {
    std::ifstream s(run_dir + "/sim_summary.json");
    if (s) {
      try {
        scene = nlohmann::json::parse(s).value("scene", "");
      } catch (const std::exception& e) {
        std::fprintf(stderr, "ohrp_video: %s/sim_summary.json: %s\n", run_dir.c_str(), e.what());
      }
    }
    if (scene.empty()) {
      std::fprintf(stderr, "ohrp_video: no scene recorded beside '%s': pass --scene FILE.xml\n",
                   log_path.c_str());
      return 2;
    }
  }
  ohrp::datalog::Table log;
  std::string error;
  if (!log.Load(log_path, &error)) {
    std::fprintf(stderr, "ohrp_video: %s\n", error.c_str());
    return 2;
  }
  if (log.rows() < 2) {
    std::fprintf(stderr, "ohrp_video: '%s' has fewer than two rows: nothing to replay\n", log_path.c_str());
    return 2;
  }
  std::string load_error;
  mjModel* m = ohrp::model::LoadMujocoModel(scene, &load_error);  // a profile, VRML, MJCF, URDF
  if (!m) {
    std::fprintf(stderr, "ohrp_video: %s\n", load_error.c_str());
    return 2;
  }
  mjData* d = mj_makeData(m);
  // the model and its data are freed on every return (the sanitizer build fails on leaks)
  const std::unique_ptr<mjModel, decltype(&mj_deleteModel)> model_owner(m, mj_deleteModel);
  const std::unique_ptr<mjData, decltype(&mj_deleteData)> data_owner(d, mj_deleteData);

  // ---- which log column drives which qpos
  struct Drive {
    int column, qpos;
  };
  std::vector<Drive> drives;
  const int time_col = log.Column("time");
  int base_body = -1;
  for (int j = 0; j < m->njnt && base_body < 0; ++j) {
    if (m->jnt_type[j] != mjJNT_FREE) continue;
    base_body = m->jnt_bodyid[j];
    const char* names[7] = {"base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy", "base_qz"};
    for (int k = 0; k < 7; ++k) {
      const int c = log.Column(names[k]);
      if (c >= 0) drives.push_back({c, m->jnt_qposadr[j] + k});
    }
  }
  int joints = 0;
  std::string missing;
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) continue;
    const char* name = mj_id2name(m, mjOBJ_JOINT, j);
    const int c = name ? log.Column(std::string("q_") + name) : -1;
    if (c >= 0) {
      drives.push_back({c, m->jnt_qposadr[j]});
      ++joints;
    } else if (name) {
      missing += std::string(missing.empty() ? "" : ", ") + name;
    }
  }
  if (time_col < 0 || joints == 0) {
    std::fprintf(stderr,
                 "ohrp_video: '%s' does not match '%s': %s (the log's columns are time, base_*, "
                 "q_<joint>...)\n",
                 log_path.c_str(), scene.c_str(),
                 time_col < 0 ? "no 'time' column" : "no q_<joint> column names a joint of the scene");
    return 2;
  }
  if (!missing.empty())
    std::fprintf(stderr, "ohrp_video: joints not in the log keep their initial angle: %s\n", missing.c_str());

  const std::vector<double>& times = log.col(time_col);
  // the log's times are numbers of the file: a time of 1e300 would make the frame count absurd
  if (const std::string e = ohrp::cli::CheckPlausibleEach("time", times, log_path + ": time"); !e.empty()) {
    std::fprintf(stderr, "ohrp_video: %s\n", e.c_str());
    return 2;
  }
  const double t_first = times.front(), t_last = times.back();
  const bool to_end = app.count("--until") == 0;
  const double t0 = std::max(from, t_first), t1 = to_end ? t_last : std::min(until, t_last);
  if (t1 <= t0 && stills.empty()) {
    std::fprintf(stderr, "ohrp_video: nothing to render between %g and %g s (the log covers %g to %g s)\n",
                 from, to_end ? t_last : until, t_first, t_last);
    return 2;
  }
  // the frame count, checked as a number before it is one: every time is within the plausible
  // range, so the quotient is finite, and a count within "frames" fits an int
  const double frame_count = std::floor((t1 - t0) / speed * fps) + 1;
  if (stills.empty()) {
    const std::string e = ohrp::cli::CheckPlausible(
        "frames", frame_count, "the video's frame count ((--until - --from) / --speed x --fps)");
    if (!e.empty()) {
      std::fprintf(stderr, "ohrp_video: %s\n", e.c_str());
      return 2;
    }
  }

  // ---- the offscreen context (render/offscreen.h: OSMesa, then MuJoCo's)
  ohrp::render::OffscreenOptions render_options;
  render_options.width = width;
  render_options.height = height;
  render_options.shadows = shadows;
  const std::unique_ptr<ohrp::render::Offscreen> renderer =
      ohrp::render::Offscreen::Create(m, render_options, &error);
  if (!renderer) {
    std::fprintf(stderr, "ohrp_video: %s\n", error.c_str());
    return 3;
  }
  mjvCamera cam;
  mjv_defaultCamera(&cam);
  // a free camera following the base horizontally, looking at the base's height
  cam.type = mjCAMERA_FREE;
  cam.distance = distance;
  cam.azimuth = azimuth;
  cam.elevation = elevation;
  const mjrRect viewport{0, 0, width, height};
  std::vector<unsigned char> flipped(static_cast<size_t>(width) * height * 3);

  // renders the state at time t (linear interpolation between rows) into `flipped` (top row first)
  size_t row = 0;
  const std::string title = run_dir.substr(run_dir.rfind('/') == std::string::npos ? 0 : run_dir.rfind('/') + 1);
  auto render = [&](double t) {
    while (row + 2 < times.size() && times[row + 1] <= t) ++row;
    while (row > 0 && times[row] > t) --row;
    const size_t next = std::min(row + 1, times.size() - 1);
    const double span = times[next] - times[row];
    const double s = span > 0 ? std::clamp((t - times[row]) / span, 0.0, 1.0) : 0.0;
    for (const Drive& dr : drives) {
      const std::vector<double>& v = log.col(dr.column);
      d->qpos[dr.qpos] = v[row] + s * (v[next] - v[row]);
    }
    for (int j = 0; j < m->njnt; ++j)
      if (m->jnt_type[j] == mjJNT_FREE || m->jnt_type[j] == mjJNT_BALL) {
        const int q = m->jnt_qposadr[j] + (m->jnt_type[j] == mjJNT_FREE ? 3 : 0);
        mju_normalize4(d->qpos + q);
      }
    d->time = t;
    if (base_body >= 0) {
      const int q = m->jnt_qposadr[m->body_jntadr[base_body]];
      for (int k = 0; k < 3; ++k) cam.lookat[k] = d->qpos[q + k];
      cam.lookat[2] = std::max(0.3, d->qpos[q + 2] - 0.05);
    }
    mj_kinematics(m, d);
    mj_comPos(m, d);
    mj_camlight(m, d);
    renderer->Draw(m, d, &cam, width, height);
    char text[64];
    std::snprintf(text, sizeof(text), "t = %.2f s", t);
    mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, viewport, title.c_str(), text, renderer->context());
    renderer->Read(width, height, flipped.data(), nullptr);
  };

  int status = 0;
  if (!stills.empty()) {
    for (double t : stills) {
      if (t < t_first || t > t_last) {
        std::fprintf(stderr, "ohrp_video: still at %g s is outside the log (%g to %g s)\n", t, t_first, t_last);
        status = 2;
        continue;
      }
      char name[64];
      std::snprintf(name, sizeof(name), "/still_%.2f.png", t);
      render(t);
      if (!ohrp::render::WritePngRgb(run_dir + name, flipped.data(), width, height, false, &error)) {
        std::fprintf(stderr, "ohrp_video: %s\n", error.c_str());
        status = 1;
      } else {
        std::printf("%s%s\n", run_dir.c_str(), name);
      }
    }
  } else {
    const int frames = static_cast<int>(frame_count);  // within "frames": fits
    FILE* pipe = nullptr;
    std::unique_ptr<ohrp::tool::PipeTo> ffmpeg;
    if (frames_dir.empty()) {
      if (out.empty()) out = run_dir + "/video.mp4";
      // an argument vector, no shell (tool_process/run_command.h): the output path is one argument
      ffmpeg = ohrp::tool::PipeTo::Start(
          {"ffmpeg", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s",
           std::to_string(width) + "x" + std::to_string(height), "-r", std::to_string(fps), "-i",
           "-", "-pix_fmt", "yuv420p", "-vcodec", "libx264", out},
          "", &error);
      if (!ffmpeg) {
        std::fprintf(stderr, "ohrp_video: %s ('./ohrp setup' installs ffmpeg, or use --frames DIR "
                             "for PNG frames)\n", error.c_str());
        return 2;
      }
      pipe = ffmpeg->file();
    } else if (!IsDir(frames_dir) && mkdir(frames_dir.c_str(), 0755) != 0) {
      std::fprintf(stderr, "ohrp_video: cannot create '%s'\n", frames_dir.c_str());
      return 2;
    }
    std::fprintf(stderr, "ohrp_video: %d frames (%g to %g s at %gx, %d x %d, %g fps) of %s\n", frames,
                 t0, t1, speed, width, height, fps, scene.c_str());
    for (int k = 0; k < frames && status == 0; ++k) {
      render(t0 + k * speed / fps);
      if (pipe) {
        if (std::fwrite(flipped.data(), 1, flipped.size(), pipe) != flipped.size()) status = 1;
      } else {
        char name[64];
        std::snprintf(name, sizeof(name), "/frame_%05d.png", k);
        if (!ohrp::render::WritePngRgb(frames_dir + name, flipped.data(), width, height, false, &error)) {
          std::fprintf(stderr, "ohrp_video: %s\n", error.c_str());
          status = 1;
        }
      }
      if (k > 0 && k % 100 == 0) std::fprintf(stderr, "ohrp_video: frame %d of %d\n", k, frames);
    }
    if (ffmpeg && ffmpeg->Close() != 0) {
      std::fprintf(stderr, "ohrp_video: ffmpeg failed writing '%s'\n", out.c_str());
      status = 1;
    }
    if (status == 0) std::printf("%s\n", pipe ? out.c_str() : frames_dir.c_str());
  }

  return status;
}
