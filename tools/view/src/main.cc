// ohrp_view: the robot in a browser, live from a running segment or replayed from a run folder
// (docs/view.md). The work is in the view library; this file reads the command line.
#include <signal.h>
#include <sys/stat.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "cli/command_line.h"
#include "cli/data_dir.h"
#include "robot_model/model.h"
#include "view/server.h"

namespace {

bool IsDir(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

[[noreturn]] void OnMujocoError(const char* msg) {
  std::fprintf(stderr, "ohrp_view: MuJoCo error: %s\n", msg);
  std::exit(3);
}

}  // namespace

int main(int argc, char** argv) {
  std::string target, scene;
  ohrp::view::ServerOptions server;
  server.web_dir = ohrp::cli::DataPath("tools/view/web");
  server.three_js = "/usr/share/javascript/three/three.min.js";
  server.chart_js = "/usr/share/javascript/chart.js/chart.min.js";
  double rate = 30, image_rate = 10, attach_timeout = 0;
  bool exit_when_ended = false;
  CLI::App app{
      "ohrp_view: the robot in 3D in a browser, with time plots of joints, ankle forces, ZMP and any\n"
      "log column picked by name (a click on a plot seeks a replay; the camera is framed from the\n"
      "robot's size, with follow on/off and reset).\n"
      "TARGET is a segment name (a running sim_host or hw_driver: attach as a read-only observer,\n"
      "never slowing it) or a run folder (./ohrp run ... --out DIR: replay its log.csv with a\n"
      "timeline). Serves on 127.0.0.1 only and prints the URL to open."};
  app.add_option("target", target, "segment name (e.g. hrp1s) or run folder (e.g. runs/demo/stand)")->required();
  app.add_option("--scene", scene,
                 "MJCF scene (live default: mjcf/hrp1s/scene_flat.xml; replay default: the scene "
                 "recorded in the run's sim_summary.json)");
  // every number within its plausible range (cli/plausible.h), checked before anything runs;
  // camera images are narrower (a page shows at most 30 a second)
  app.add_option("--port", server.port, "TCP port on 127.0.0.1; 0 picks a free one")
      ->capture_default_str()->check(ohrp::cli::Plausible("port"));
  app.add_option("--rate", rate, "live frames per second sent to the page [Hz]")
      ->capture_default_str()->check(ohrp::cli::Plausible("frame_rate"));
  app.add_option("--image-rate", image_rate,
                 "live: camera images per second sent to a page, per camera, while it shows them [Hz]")
      ->capture_default_str()->check(ohrp::cli::Plausible("frame_rate"))->check(ohrp::cli::InRange(1, 30));
  app.add_option("--attach-timeout", attach_timeout, "[s] wait this long for the segment to appear")
      ->capture_default_str()->check(ohrp::cli::Plausible("wait"));
  app.add_flag("--exit-when-ended", exit_when_ended, "live: end when the producer ends its run");
  app.add_flag("--control", server.control.on,
               "live: control the run from the page (pause, resume, step, reset, push through "
               "--sim-socket; walk commands through --walk-socket); the URL printed carries a "
               "random token, requests without it are refused (403)");
  app.add_option("--sim-socket", server.control.sim_socket,
                 "with --control: sim_host's --control-socket PATH");
  app.add_option("--walk-socket", server.control.walk_socket,
                 "with --control: walk's --socket PATH (its live command channel)");
  app.add_option("--control-record", server.control.record,
                 "with --control: append every line forwarded (walk's commands included) with "
                 "its simulated time and reply, as JSON lines, to FILE (e.g. RUN/view_actions.jsonl)");
  app.footer("Examples: ohrp_view hrp1s                 (sim_host --segment hrp1s running)\n"
             "          ohrp_view runs/demo/stand --port 8080\n"
             "A real-time run that a page must not disturb (few cores): run sim_host under\n"
             "`chrt -f 70` and the controller with --rt-priority 70, and watch with --rate 10\n"
             "(docs/view.md \"The page's cost to a real-time run\").\n"
             "Exit codes: 0 ended, 2 bad option, no such segment or run folder, a run folder\n"
             "without log.csv, a scene that does not hold the segment's robot, port in use;\n"
             "3 MuJoCo error.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  if (!server.control.on && (!server.control.sim_socket.empty() || !server.control.walk_socket.empty() ||
                             !server.control.record.empty())) {
    std::fprintf(stderr, "ohrp_view: --sim-socket, --walk-socket and --control-record are for "
                         "--control: add --control\n");
    return 2;
  }
  if (server.control.on && server.control.sim_socket.empty() && server.control.walk_socket.empty()) {
    std::fprintf(stderr, "ohrp_view: --control needs --sim-socket PATH (sim_host --control-socket) "
                         "and/or --walk-socket PATH (walk --socket)\n");
    return 2;
  }
  if (server.control.on && IsDir(target)) {
    std::fprintf(stderr, "ohrp_view: --control is for a live run (a segment), not a run folder\n");
    return 2;
  }
  if (!server.control.record.empty() && !std::ofstream(server.control.record, std::ios::app)) {
    std::fprintf(stderr, "ohrp_view: --control-record %s: cannot write there\n",
                 server.control.record.c_str());
    return 2;
  }
  if (server.control.on) server.control.token = ohrp::view::MakeToken();
  ohrp::model::InstallMujocoHandlers(OnMujocoError);
  // a page that goes away mid-write is an error on its socket, not a signal that ends us
  signal(SIGPIPE, SIG_IGN);

  // a folder is a run to replay; a name without '/' is a segment; anything else is a mistake
  std::unique_ptr<ohrp::view::Source> source;
  std::string error;
  if (IsDir(target)) {
    source = ohrp::view::ReplaySource::Open(target, scene, &error);
  } else if (target.find('/') != std::string::npos) {
    error = "no run folder '" + target + "' (a folder written by './ohrp run SCENARIO --out DIR'; a "
            "segment name has no '/')";
  } else {
    if (scene.empty()) scene = ohrp::cli::DataPath("mjcf/hrp1s/scene_flat.xml");
    source = ohrp::view::LiveSource::Open(target, scene, rate, image_rate, attach_timeout, &error);
  }
  if (!source) {
    std::fprintf(stderr, "ohrp_view: %s\n", error.c_str());
    return 2;
  }
  return ohrp::view::Serve(source.get(), server, exit_when_ended);
}
