// ohrp_video: offscreen video of a run (OSMesa, no display needed). Replays the data log of a
// run (base pose and joint angles per row, see datalog/recorder.h) through the scene's model and
// renders it with MuJoCo's renderer (render/offscreen.h) into an MP4 (through Debian's ffmpeg) or
// PNG frames (replay.h).
//
// Rendering after the run, from the log, keeps the simulation free of any rendering cost (the
// effects it runs are the ones the scene calls for) and works on any run folder, including the
// ones CI leaves behind.
//
// main reads as its stages: the options, the run's inputs, the model and the log's mapping onto
// it, the time window, the renderer, then stills or the video.
#include <mujoco/mujoco.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "render/png.h"
#include "replay.h"
#include "robot_model/load.h"
#include "tool_process/run_command.h"

namespace {

using ohrp::video::FrameRenderer;
using ohrp::video::LogReplay;
using ohrp::video::RunInputs;

void OnMujocoError(const char* msg) {
  std::fprintf(stderr, "ohrp_video: MuJoCo error: %s\n", msg);
  std::exit(3);
}
void OnMujocoWarning(const char* msg) { std::fprintf(stderr, "ohrp_video: MuJoCo warning: %s\n", msg); }

int Fail(int code, const std::string& what) {
  std::fprintf(stderr, "ohrp_video: %s\n", what.c_str());
  return code;
}

struct Options {
  std::string input, scene, out, frames_dir;
  double fps = 30, speed = 1, from = 0, until = -1;
  bool to_end = true;  // no --until
  std::vector<double> stills;
  ohrp::video::FrameOptions frame;
};

// -1 to go on, else the exit code (--help, a bad option)
int ParseOptions(int argc, char** argv, Options* o) {
  CLI::App app{
      "ohrp_video: renders a run offscreen (OSMesa, no display) from its data log: the base pose\n"
      "and joint angles of each logged row, replayed through the scene's model. Writes an MP4\n"
      "through ffmpeg, PNG frames, or single stills."};
  app.add_option("run", o->input, "a run folder (ohrp_run --out DIR: log.csv, sim_summary.json) or a log.csv")
      ->required();
  app.add_option("--scene", o->scene, "MJCF scene (default: the one recorded in the run's sim_summary.json)");
  app.add_option("--out,-o", o->out, "MP4 file (default: RUN/video.mp4; needs ffmpeg, './ohrp setup' installs it)");
  app.add_option("--frames", o->frames_dir, "write PNG frames frame_00000.png... into this folder instead of an MP4");
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  using ohrp::cli::Plausible;
  ohrp::video::FrameOptions& f = o->frame;
  app.add_option("--still", o->stills, "write one PNG per listed time [s] (RUN/still_<t>.png) and no video")
      ->delimiter(',')->check(Plausible("time"));
  app.add_option("--fps", o->fps, "frames per second of the video")->capture_default_str()->check(Plausible("frame_rate"));
  app.add_option("--speed", o->speed, "simulated seconds per video second")->capture_default_str()->check(Plausible("speed_factor"));
  app.add_option("--from", o->from, "start time [s]")->capture_default_str()->check(Plausible("time"));
  app.add_option("--until", o->until, "end time [s] (default: the end of the log)")->check(Plausible("time"));
  app.add_option("--width", f.width, "frame width [px]")->capture_default_str()->check(Plausible("pixels"));
  app.add_option("--height", f.height, "frame height [px]")->capture_default_str()->check(Plausible("pixels"));
  app.add_flag("--shadows", f.shadows, "render shadows and reflections (slower in software)");
  app.add_option("--distance", f.distance, "camera distance from the robot's base [m]")->capture_default_str()
      ->check(Plausible("distance"));
  app.add_option("--azimuth", f.azimuth, "camera azimuth [deg]")->capture_default_str()->check(Plausible("angle_deg"));
  app.add_option("--elevation", f.elevation, "camera elevation [deg]")->capture_default_str()->check(Plausible("angle_deg"));
  app.footer("Example: ohrp_video runs/demo/stand            (runs/demo/stand/video.mp4)\n"
             "         ohrp_video runs/demo/stand --still 1,5 (two PNG stills)\n"
             "Every number is checked against its plausible range (cli/plausible.h), and so are\n"
             "the log's times and the video's frame count, before anything is rendered.\n"
             "Exit codes: 0 written, 2 bad option, run folder, log, scene, time window or frame\n"
             "count, or no ffmpeg, 3 MuJoCo, OSMesa or ffmpeg failed.");
  const int code = ohrp::cli::ParseCommandLine(&app, argc, argv);
  o->to_end = app.count("--until") == 0;
  return code;
}

// The window [*t0, *t1] of the log to render and the video's frame count, checked: "" or why not.
std::string TimeWindow(const Options& o, const std::vector<double>& times, const std::string& log_path,
                       double* t0, double* t1, double* frame_count) {
  // the log's times are numbers of the file: a time of 1e300 would make the frame count absurd
  if (std::string e = ohrp::cli::CheckPlausibleEach("time", times, log_path + ": time"); !e.empty())
    return e;
  const double t_first = times.front(), t_last = times.back();
  *t0 = std::max(o.from, t_first);
  *t1 = o.to_end ? t_last : std::min(o.until, t_last);
  if (*t1 <= *t0 && o.stills.empty()) {
    char text[160];
    std::snprintf(text, sizeof(text), "nothing to render between %g and %g s (the log covers %g to %g s)",
                  o.from, o.to_end ? t_last : o.until, t_first, t_last);
    return text;
  }
  // the frame count, checked as a number before it is one: every time is within the plausible
  // range, so the quotient is finite, and a count within "frames" fits an int
  *frame_count = std::floor((*t1 - *t0) / o.speed * o.fps) + 1;
  if (!o.stills.empty()) return "";
  return ohrp::cli::CheckPlausible("frames", *frame_count,
                                   "the video's frame count ((--until - --from) / --speed x --fps)");
}

// The renderer and what it renders: the model posed from the log.
struct Replay {
  mjModel* m;
  mjData* d;
  LogReplay* log;
  FrameRenderer* frames;
  const std::vector<unsigned char>& At(double t) {
    log->Pose(m, t, d);
    frames->Render(m, d, log->base_body(), t);
    return frames->pixels();
  }
};

// one PNG per --still time beside the run: the exit code
int WriteStills(const Options& o, const RunInputs& in, Replay* r) {
  const std::vector<double>& times = r->log->times();
  int status = 0;
  std::string error;
  for (double t : o.stills) {
    if (t < times.front() || t > times.back()) {
      std::fprintf(stderr, "ohrp_video: still at %g s is outside the log (%g to %g s)\n", t,
                   times.front(), times.back());
      status = 2;
      continue;
    }
    char name[64];
    std::snprintf(name, sizeof(name), "/still_%.2f.png", t);
    if (!ohrp::render::WritePngRgb(in.run_dir + name, r->At(t).data(), o.frame.width,
                                   o.frame.height, false, &error)) {
      status = Fail(1, error);
    } else {
      std::printf("%s%s\n", in.run_dir.c_str(), name);
    }
  }
  return status;
}

// the frames into ffmpeg (an MP4) or PNG files: the exit code
int WriteVideo(Options o, const RunInputs& in, double t0, double t1, int frames, Replay* r) {
  std::string error;
  const int width = o.frame.width, height = o.frame.height;
  std::unique_ptr<ohrp::tool::PipeTo> ffmpeg;
  if (o.frames_dir.empty()) {
    if (o.out.empty()) o.out = in.run_dir + "/video.mp4";
    // an argument vector, no shell (tool_process/run_command.h): the output path is one argument
    ffmpeg = ohrp::tool::PipeTo::Start(
        {"ffmpeg", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s",
         std::to_string(width) + "x" + std::to_string(height), "-r", std::to_string(o.fps), "-i",
         "-", "-pix_fmt", "yuv420p", "-vcodec", "libx264", o.out},
        "", &error);
    if (!ffmpeg)
      return Fail(2, error + " ('./ohrp setup' installs ffmpeg, or use --frames DIR for PNG frames)");
  } else {
    struct stat st {};
    const bool is_dir = stat(o.frames_dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
    if (!is_dir && mkdir(o.frames_dir.c_str(), 0755) != 0)
      return Fail(2, "cannot create '" + o.frames_dir + "'");
  }
  FILE* pipe = ffmpeg ? ffmpeg->file() : nullptr;
  std::fprintf(stderr, "ohrp_video: %d frames (%g to %g s at %gx, %d x %d, %g fps) of %s\n", frames,
               t0, t1, o.speed, width, height, o.fps, in.scene.c_str());
  int status = 0;
  for (int k = 0; k < frames && status == 0; ++k) {
    const std::vector<unsigned char>& px = r->At(t0 + k * o.speed / o.fps);
    if (pipe) {
      if (std::fwrite(px.data(), 1, px.size(), pipe) != px.size()) status = 1;
    } else {
      char name[64];
      std::snprintf(name, sizeof(name), "/frame_%05d.png", k);
      if (!ohrp::render::WritePngRgb(o.frames_dir + name, px.data(), width, height, false, &error))
        status = Fail(1, error);
    }
    if (k > 0 && k % 100 == 0) std::fprintf(stderr, "ohrp_video: frame %d of %d\n", k, frames);
  }
  if (ffmpeg && ffmpeg->Close() != 0) status = Fail(1, "ffmpeg failed writing '" + o.out + "'");
  if (status == 0) std::printf("%s\n", pipe ? o.out.c_str() : o.frames_dir.c_str());
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  mju_user_error = OnMujocoError;
  mju_user_warning = OnMujocoWarning;
  Options o;
  if (const int code = ParseOptions(argc, argv, &o); code >= 0) return code;

  RunInputs in;
  std::string error;
  if (!ohrp::video::ReadRunInputs(o.input, o.scene, &in, &error)) return Fail(2, error);
  mjModel* m = ohrp::model::LoadMujocoModel(in.scene, &error);  // a profile, VRML, MJCF, URDF
  if (!m) return Fail(2, error);
  mjData* d = mj_makeData(m);
  // the model and its data are freed on every return (the sanitizer build fails on leaks)
  const std::unique_ptr<mjModel, decltype(&mj_deleteModel)> model_owner(m, mj_deleteModel);
  const std::unique_ptr<mjData, decltype(&mj_deleteData)> data_owner(d, mj_deleteData);

  LogReplay log;
  std::string missing;
  if (!log.Map(m, in.log, &missing, &error))
    return Fail(2, "'" + in.log_path + "' does not match '" + in.scene + "': " + error +
                       " (the log's columns are time, base_*, q_<joint>...)");
  if (!missing.empty())
    std::fprintf(stderr, "ohrp_video: joints not in the log keep their initial angle: %s\n", missing.c_str());
  double t0 = 0, t1 = 0, frame_count = 0;
  if (const std::string e = TimeWindow(o, log.times(), in.log_path, &t0, &t1, &frame_count); !e.empty())
    return Fail(2, e);

  const size_t slash = in.run_dir.rfind('/');
  o.frame.title = in.run_dir.substr(slash == std::string::npos ? 0 : slash + 1);
  const std::unique_ptr<FrameRenderer> frames = FrameRenderer::Create(m, o.frame, &error);
  if (!frames) return Fail(3, error);
  Replay replay{m, d, &log, frames.get()};
  if (!o.stills.empty()) return WriteStills(o, in, &replay);
  return WriteVideo(o, in, t0, t1, static_cast<int>(frame_count), &replay);
}
