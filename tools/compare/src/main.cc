// ohrp_compare_logs: two data logs of the same experiment held against each other (see
// compare/compare.h): aligned in time, per-channel differences, oscillation frequency and decay,
// a table on stdout, compare.json and overlaid plots (tools/scripts/plot_compare.py).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/command_line.h"
#include "cli/data_dir.h"
#include "compare/compare.h"
#include "tool_process/run_command.h"

namespace {

std::vector<std::string> SplitList(const std::vector<std::string>& items) {
  std::vector<std::string> out;
  for (const auto& item : items) {
    std::stringstream s(item);
    for (std::string n; std::getline(s, n, ',');)
      if (!n.empty()) out.push_back(n);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  ohrp::compare::CompareOptions o;
  std::vector<std::string> channels, oscillating, plot_channels;
  std::string out_dir = "compare-logs", labels;
  bool no_plot = false;
  CLI::App app{
      "ohrp_compare_logs: holds two data logs of the same experiment against each other (the\n"
      "paper's figures 12-14: simulation and robot on the same axes). A and B are CSV data logs\n"
      "as sim_host --log, ohrp_run (RUN_DIR/log.csv) and hw_driver --log write them. B is\n"
      "shifted in time to match A (the lag: B's time minus A's for the same instant), then per\n"
      "channel over the common window: RMS and peak of B - A, the mean difference, the channel's\n"
      "own lag; for --oscillation channels the damped frequency, log decrement (decay ratio per\n"
      "period) and damping ratio of each log. Prints a table, writes DIR/compare.json and\n"
      "DIR/compare.png.",
      "ohrp_compare_logs"};
  app.add_option("a", o.a, "log A (e.g. the simulation's log.csv)")->required()->check(CLI::ExistingFile);
  app.add_option("b", o.b, "log B (e.g. the robot's hw_driver --log file)")->required()->check(CLI::ExistingFile);
  app.add_option("--align", o.align,
                 "xcorr:CHANNEL (cross-correlation, the default on the first --channels or "
                 "--oscillation channel), event:NAME (first event NAME in each log's summary JSON, "
                 "e.g. push_start), event:CHANNEL>VALUE or event:CHANNEL<VALUE (first crossing), "
                 "none");
  app.add_option("--channels", channels, "channels compared (comma-separated or repeated); default: every channel both logs have");
  app.add_option("--oscillation", oscillating,
                 "channels whose damped oscillation is measured in each log (frequency, decay)");
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  app.add_option("--from", o.from, "[s] start of the compared window, A's time")
      ->check(ohrp::cli::Plausible("time"));
  app.add_option("--to", o.to, "[s] end of the compared window, A's time")
      ->check(ohrp::cli::Plausible("time"));
  app.add_option("--max-lag", o.max_lag, "[s] cross-correlation searches lags within +- this")
      ->capture_default_str()->check(ohrp::cli::Plausible("duration"));
  app.add_option("--min-coherence", o.min_coherence,
                 "the median correlation (A against the aligned B) of the channels that move in "
                 "both logs below which they are not the same experiment (exit 1); 0 compares anyway")
      ->capture_default_str()->check(ohrp::cli::Plausible("fraction"));
  app.add_option("--summary-a", o.summary_a, "summary JSON of A for event:NAME (default: sim_summary.json or summary.json beside A)")
      ->check(CLI::ExistingFile);
  app.add_option("--summary-b", o.summary_b, "summary JSON of B for event:NAME (e.g. hw_driver --summary)")
      ->check(CLI::ExistingFile);
  app.add_option("--labels", labels, "A,B: names in the table and the plot")->capture_default_str()
      ->default_str("simulation,robot");
  app.add_option("--plot", plot_channels,
                 "channels plotted (default: --channels if given, else the aligned and the "
                 "oscillating channels)");
  app.add_option("--out", out_dir, "folder for compare.json and compare.png")->capture_default_str();
  app.add_flag("--no-plot", no_plot, "no compare.png");
  app.footer(
      "Every number, of the options and of the logs' times, is checked against its plausible\n"
      "range (cli/plausible.h) before anything is compared.\n"
      "Exit codes: 0 compared, 1 the logs do not hold the same experiment (the figures are still\n"
      "printed and written), 2 bad option or input (a missing or malformed log, a time outside\n"
      "its plausible range, no common channel, an unknown channel, an alignment that cannot be\n"
      "done, an empty window), 3 the output cannot be written. docs/identify.md has the method.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  o.channels = SplitList(channels);
  o.oscillating = SplitList(oscillating);
  if (!labels.empty()) {
    const auto l = SplitList({labels});
    if (l.size() != 2) {
      std::fprintf(stderr, "ohrp_compare_logs: --labels wants two names, A,B (got '%s')\n", labels.c_str());
      return 2;
    }
    o.label_a = l[0];
    o.label_b = l[1];
  }
  if (!(o.from < o.to)) {
    std::fprintf(stderr, "ohrp_compare_logs: --from %g is not before --to %g\n", o.from, o.to);
    return 2;
  }

  ohrp::compare::Comparison c;
  std::string error;
  const int verdict = ohrp::compare::Compare(o, &c, &error);
  if (verdict != 0 && verdict != ohrp::compare::kExitDifferent) {
    std::fprintf(stderr, "ohrp_compare_logs: %s\n", error.c_str());
    return verdict;
  }
  std::printf("A: %s (%s)\nB: %s (%s)\n%s", o.a.c_str(), o.label_a.c_str(), o.b.c_str(),
              o.label_b.c_str(), ohrp::compare::Table(c).c_str());

  std::error_code ec;
  fs::create_directories(out_dir, ec);
  const std::string json_path = (fs::path(out_dir) / "compare.json").string();
  nlohmann::json j = ohrp::compare::ToJson(o, c);
  std::vector<std::string> plot = SplitList(plot_channels);
  if (plot.empty()) plot = o.channels;
  if (plot.empty()) {
    if (o.align.rfind("xcorr:", 0) == 0) plot.push_back(o.align.substr(6));
    for (const auto& n : o.oscillating)
      if (std::find(plot.begin(), plot.end(), n) == plot.end()) plot.push_back(n);
  }
  if (plot.size() > 12) plot.resize(12);
  j["plot"] = plot;
  {
    std::ofstream f(json_path);
    f << j.dump(2) << "\n";
    if (!f) {
      std::fprintf(stderr, "ohrp_compare_logs: cannot write %s\n", json_path.c_str());
      return 3;
    }
  }
  std::printf("\nwrote %s\n", json_path.c_str());
  if (!no_plot && !plot.empty()) {
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const std::string png = (fs::path(out_dir) / "compare.png").string();
    std::string why;  // an argument vector, no shell (tool_process/run_command.h)
    if (ohrp::tool::RunCommand({python, ohrp::cli::DataPath("tools/scripts/plot_compare.py"),
                          json_path, png},
                         (fs::path(out_dir) / "plot.stderr").string(), &why) != 0) {
      std::fprintf(stderr, "ohrp_compare_logs: the plot could not be made (see %s/plot.stderr)\n",
                   out_dir.c_str());
    } else {
      std::printf("wrote %s\n", png.c_str());
    }
  }
  if (verdict == ohrp::compare::kExitDifferent) {
    std::fprintf(stderr, "ohrp_compare_logs: FAILED: %s\n", error.c_str());
    return verdict;
  }
  return 0;
}
