// ohrp_run: run one scenario headless (see runner/runner.h and docs/scenarios.md).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "cli/command_line.h"
#include "cli/data_dir.h"
#include "runner/runner.h"
#include "runner/scenario.h"

int main(int argc, char** argv) {
  std::string file;
  ohrp::runner::RunOptions o;
  bool no_plot = false, quiet = false;
  CLI::App app{
      "ohrp_run: one headless scripted run. Starts sim_host and the scenario's controllers side\n"
      "by side, runs for the scenario's duration, evaluates its checks and writes summary.json,\n"
      "log.csv and plot.png into the output folder; \"{out}\" in a controller's args names that\n"
      "folder (e.g. --log \"{out}/walk.csv\"). Scenario format: docs/scenarios.md."};
  app.add_option("scenario", file, "scenario file (YAML)")->required()->check(CLI::ExistingFile);
  app.add_option("--out", o.out_dir, "output folder (default: runs/<name>-<date>-<time>)");
  std::string contact;
  app.add_option("--contact", contact,
                 "run with this contact under the soles instead of the scenario's "
                 "(soft, native, rigid): to compare contact models on the same run")
      ->check(CLI::IsMember({"soft", "native", "rigid"}));
  app.add_option("--segment", o.segment,
                 "the run's segment name (default: run_<name>_<pid>); e.g. one per Slurm task, so "
                 "that runs sharing a machine never collide (ohrp_sweep)")
      ->check([](const std::string& v) {
        for (char c : v)
          if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.')
            return std::string("must be letters, digits, '_', '-' or '.'");
        return v.empty() || v.size() > 100 ? std::string("must be 1 to 100 characters") : std::string();
      });
  app.add_flag("--no-plot", no_plot, "do not draw plot.png");
  app.add_flag("--quiet,-q", quiet, "do not echo the processes' output while they run");
  bool realtime = false, view = false;
  int view_port = 0;
  app.add_flag("--realtime", realtime, "pace sim_host to the wall clock (sim_host --realtime)");
  app.add_flag("--view", view, "watch the run in a browser: starts ohrp_view on its segment and "
                               "prints the URL (docs/view.md); best with --realtime");
  app.add_option("--view-port", view_port, "--view: TCP port of the viewer (0 picks a free one)")
      ->check(ohrp::cli::InRange(0, 65535));
  app.footer(
      "Exit codes: 0 every check passed, 1 a check failed or a process ended badly, 2 bad option\n"
      "or scenario, 130 interrupted (SIGINT/SIGTERM).");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  o.plot = !no_plot;
  o.echo = !quiet;
  o.source_dir = ohrp::cli::DataDir();
  o.bin_dir = std::filesystem::canonical("/proc/self/exe").parent_path().string();

  ohrp::runner::Scenario s;
  std::string error;
  if (!ohrp::runner::LoadScenario(file, &s, &error)) {
    std::fprintf(stderr, "ohrp_run: %s\n", error.c_str());
    return ohrp::runner::kRunUsage;
  }
  if (!contact.empty()) {
    s.contact = contact;
    s.name += "_" + contact;
  }
  if (realtime) s.sim_args.push_back("--realtime");
  // the viewer: its own process on the run's segment, ended with the run
  pid_t viewer = -1;
  if (view) {
    if (o.segment.empty()) o.segment = "run_" + s.name + "_" + std::to_string(getpid());
    const std::string scene = s.scene.empty() || s.scene[0] == '/' ? s.scene : o.source_dir + "/" + s.scene;
    const std::string program = o.bin_dir + "/ohrp_view", port = std::to_string(view_port);
    viewer = fork();
    if (viewer == 0) {
      execl(program.c_str(), program.c_str(), o.segment.c_str(), "--scene", scene.c_str(),
            "--attach-timeout", "60", "--exit-when-ended", "--port", port.c_str(),
            static_cast<char*>(nullptr));
      std::fprintf(stderr, "ohrp_run: cannot start '%s' (build it: cmake --build build --target ohrp_view)\n",
                   program.c_str());
      _exit(2);
    }
  }
  const int code = ohrp::runner::RunScenario(s, o);
  if (viewer > 0) {
    kill(viewer, SIGTERM);
    waitpid(viewer, nullptr, 0);
  }
  return code;
}
