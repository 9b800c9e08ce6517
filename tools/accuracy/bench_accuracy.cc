// bench_accuracy: what accuracy costs in time. A speed-accuracy report in the manner of Erez,
// Tassa and Todorov (ICRA 2015) over time step, integrator, contact model, solver iterations and
// tolerance, and collision geometry detail, on six scenes; CSV, log-log charts and (with
// --write-docs) docs/accuracy.md, every number in it measured by this run. What is measured is
// bench_plan.cc; the charts and the report report.cc.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "accuracy.h"
#include "bench_plan.h"
#include "cli/command_line.h"
#include "report.h"
#include "shm_bridge/clock.h"
#include "tool_process/run_command.h"

namespace fs = std::filesystem;
using namespace ohrp::accuracy;

namespace {

[[noreturn]] void OnFatal(const char* msg) {
  std::fprintf(stderr, "bench_accuracy: MuJoCo error: %s\n", msg);
  std::exit(3);
}

// what one run measured
struct Measured {
  std::vector<Row> rows;
  std::vector<ClosedRow> closed;
  std::vector<std::string> skipped, no_damping;
  std::map<std::string, std::map<Contact, Reference>> refs;
};

// the time steps swept: 1/16 ms to 16 ms in octaves (quick: four of them)
std::vector<double> TimeSteps(bool quick) {
  if (quick) return {0.25e-3, 1e-3, 4e-3, 16e-3};
  std::vector<double> dts;
  for (int k = 0; k <= 8; ++k) dts.push_back(std::ldexp(1.0 / 16000, k));
  return dts;
}

// one setting against its reference, with the scene's closed forms
Row MeasureSetting(const BenchOptions& o, const SceneSpec& scene, const std::string& src,
                   const Reference& ref, const Setting& rs,
                   const std::pair<std::string, Setting>& setting, std::vector<ClosedRow>* closed) {
  Row row;
  row.scene = scene.name;
  row.sweep = setting.first;
  row.s = setting.second;
  row.geometry = row.s.geometry.empty() ? "-" : row.s.geometry;
  row.reference = row.s.integrator == rs.integrator && row.s.dt == rs.dt && row.sweep == "dt";
  row.r = RunPieces(scene, row.s, ref, o.restarts, o.piece_windows);
  row.iterations = row.r.iterations;
  row.tolerance = row.r.tolerance;
  auto note = [&](const char* text) {
    row.r.note += std::string(row.r.note.empty() ? "" : "; ") + text;
  };
  if (row.r.refsafe) note("refsafe: contact time constant raised to 2 dt");
  if (row.reference) note("the reference's integrator and step");
  MeasureClosedForms(scene, src, &row, closed);
  return row;
}

// every setting of every scene and contact model against its reference; false on an error
bool Sweep(const BenchOptions& o, const std::vector<SceneSpec>& scenes, const std::string& src,
           Measured* out) {
  const std::vector<double> dts = TimeSteps(o.quick);
  for (const SceneSpec& scene : scenes) {
    const std::string gdef = scene.geometries.empty() ? "" : scene.geometries[0];
    const bool damping = HasDamping(scene);
    if (!damping) out->no_damping.push_back(scene.name);
    for (Contact c : scene.contacts) {
      const Setting rs = ReferenceSetting(o, scene, c);
      std::fprintf(stderr, "[%s] reference %s contact: %s, %.2f s ...\n", scene.name.c_str(),
                   ContactName(c), SettingName(rs, gdef).c_str(), scene.duration);
      std::string error;
      Reference& ref = out->refs[scene.name][c];
      if (!MakeReference(scene, rs, kWindow, &ref, &error)) {
        std::fprintf(stderr, "bench_accuracy: %s\n", error.c_str());
        return false;
      }
      std::fprintf(stderr, "[%s] reference done: %.3g x real time\n", scene.name.c_str(),
                   ref.sim_time / ref.cpu);
      const auto settings = SettingsFor(o, scene, rs, dts, damping);
      for (size_t i = 0; i < settings.size(); ++i) {
        const Row row = MeasureSetting(o, scene, src, ref, rs, settings[i], &out->closed);
        std::fprintf(stderr, "[%s] %s %zu/%zu %-40s pos %-10s m force %-10s N rtf %-8s %s\n",
                     scene.name.c_str(), ContactName(c), i + 1, settings.size(),
                     SettingName(row.s, gdef).c_str(), Num(row.r.pos_error, "%.3g").c_str(),
                     Num(row.r.force_error, "%.3g").c_str(), Num(row.r.rtf(), "%.3g").c_str(),
                     row.r.note.c_str());
        out->rows.push_back(row);
      }
    }
  }
  if (!out->no_damping.empty()) {
    std::string names;
    for (const auto& n : out->no_damping) names += (names.empty() ? "" : ", ") + n;
    out->skipped.push_back("implicit on " + names + ": skipped, these models have no joint "
                           "damping (MuJoCo's implicit integrator then steps exactly as Euler)");
  }
  return true;
}

// the log-log charts (tools/scripts/plot_accuracy.py): 0, or the plotter's failure
int Plot(const std::string& src, const std::string& csv, const std::string& out) {
  const char* env = std::getenv("OHRP_PYTHON");
  const std::string python = env && *env ? env
                             : fs::exists("/usr/bin/python3") ? "/usr/bin/python3"
                                                              : "python3";
  std::string why;  // an argument vector, no shell (tool_process/run_command.h)
  const int status =
      ohrp::tool::RunCommand({python, src + "/tools/scripts/plot_accuracy.py", csv, out}, "", &why);
  if (status != 0)
    std::fprintf(stderr, "bench_accuracy: plotting failed (%s)\n",
                 status < 0 ? why.c_str() : "plot_accuracy.py returned non-zero");
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  BenchOptions o;
  o.out = std::string(OHRP_BUILD_DIR) + "/accuracy";
  bool write_docs = false;
  std::string docs_path = std::string(OHRP_SOURCE_DIR) + "/docs/accuracy.md";
  CLI::App app{
      "bench_accuracy: what accuracy costs in time (Erez, Tassa & Todorov, ICRA 2015).\n"
      "Per scene, a reference trajectory (RK4 at 1/16 ms, solver iterations 200, tolerance\n"
      "1e-12); per setting (time step 1/16..16 ms, integrator, contact model, solver iterations\n"
      "and tolerance, collision geometry), pieces restarted from reference states and compared\n"
      "with it every 16 ms: mean body position error [m] and mean error of the 16 ms-average\n"
      "total contact normal force [N], against the real-time factor (simulated time / thread\n"
      "CPU time). Closed forms where they exist (pendulum period, free fall, soft-foot static\n"
      "sink and restitution, rolling at 5/7 v0). Writes accuracy.csv, closed_forms.csv and one\n"
      "PNG per scene into --out; --write-docs also writes docs/accuracy.md. Ends with\n"
      "'ratio: X (rtf of the recommended standing setting / rtf of its reference)'."};
  app.add_flag("--quick", o.quick, "few settings, short pieces (< 60 s; what the test runs)");
  app.add_option("--out", o.out, "output directory")->capture_default_str();
  app.add_flag("--write-docs", write_docs, "write the report (markdown) to --docs");
  app.add_option("--docs", docs_path, "where --write-docs writes")->capture_default_str();
  app.add_option("--scenes", o.scenes,
                 "only these scenes: pendulum box ball hrp1s_stand hrp1s_walk humanoid");
  app.add_flag("!--no-plot", o.plot, "no PNG charts");
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  app.add_option("--restarts", o.restarts, "restart points per setting (default 10, quick 2)")
      ->check(ohrp::cli::Plausible("repeats"));
  app.add_option("--piece-windows", o.piece_windows,
                 "16 ms windows per piece (default 8, quick 4)")
      ->check(ohrp::cli::Plausible("repeats"));
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  ohrp::model::InstallMujocoHandlers(OnFatal);
  if (o.quick) {
    if (app.count("--restarts") == 0) o.restarts = 2;
    if (app.count("--piece-windows") == 0) o.piece_windows = 4;
  }
  const std::set<std::string> known = {"pendulum", "box", "ball", "hrp1s_stand", "hrp1s_walk",
                                       "humanoid"};
  for (const auto& s : o.scenes) {
    if (!known.count(s)) {
      std::fprintf(stderr, "bench_accuracy: unknown scene '%s' (pendulum box ball hrp1s_stand "
                           "hrp1s_walk humanoid)\n", s.c_str());
      return 2;
    }
  }
  const std::string src = OHRP_SOURCE_DIR;

  // ---- scenes ----
  std::vector<SceneSpec> scenes;
  Walk walk;
  std::string error;
  if (!MakeScenes(o, src, &walk, &scenes, &error)) {
    std::fprintf(stderr, "bench_accuracy: %s\n", error.c_str());
    return 2;
  }
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) {
    std::fprintf(stderr, "bench_accuracy: cannot create %s: %s\n", o.out.c_str(),
                 ec.message().c_str());
    return 2;
  }

  // ---- the settings against their references ----
  const double t_start = ohrp::ThreadCpuSeconds();
  Measured m;
  if (!Sweep(o, scenes, src, &m)) return 1;

  // ---- CSV ----
  const std::string csv = o.out + "/accuracy.csv";
  if (!WriteCsv(csv, m.rows) || !WriteClosedCsv(o.out + "/closed_forms.csv", m.closed)) {
    std::fprintf(stderr, "bench_accuracy: cannot write the CSV files in %s\n", o.out.c_str());
    return 2;
  }
  std::fprintf(stderr, "wrote %s and %s/closed_forms.csv\n", csv.c_str(), o.out.c_str());

  // ---- charts ----
  const int plot_status = o.plot ? Plot(src, csv, o.out) : 0;

  // ---- what to choose, the orders and the headline, from the rows ----
  const std::string choices = ChoiceTable(scenes, m.rows);
  const std::string orders = OrderTable(scenes, m.rows);
  double stand_ref_rtf = std::nan("");
  if (m.refs.count("hrp1s_stand") && m.refs["hrp1s_stand"].count(Contact::kSoft)) {
    const Reference& ref = m.refs["hrp1s_stand"][Contact::kSoft];
    stand_ref_rtf = ref.sim_time / ref.cpu;
  }
  const Headline head = StandingHeadline(m.rows, stand_ref_rtf);
  if (!head.text.empty()) std::printf("\n%s\n", head.text.c_str());

  // ---- docs ----
  if (write_docs) {
    DocsInput in;
    in.quick = o.quick;
    in.restarts = o.restarts;
    in.piece_windows = o.piece_windows;
    in.cpu = ohrp::ThreadCpuSeconds() - t_start;
    in.scenes = &scenes;
    in.skipped = &m.skipped;
    in.rows = &m.rows;
    in.closed = &m.closed;
    in.choices = choices;
    in.orders = orders;
    in.refcheck = ReferenceCheckTable(m.rows);
    in.soft_steps = SoftStepTable(scenes, m.rows);
    in.headline = head.text;
    if (!WriteDocs(docs_path, in)) {
      std::fprintf(stderr, "bench_accuracy: cannot write %s\n", docs_path.c_str());
      return 2;
    }
    std::fprintf(stderr, "wrote %s\n", docs_path.c_str());
  }

  std::printf("ratio = real-time factor of the recommended standing setting (hrp1s_stand, soft "
              "soles, fastest within 1 mm) / that of its reference (RK4 1/16 ms)\n");
  std::printf("ratio: %s %s\n", std::isnan(head.ratio) ? "nan" : Num(head.ratio, "%.2f").c_str(),
              head.ratio_text.c_str());
  return plot_status == 0 ? 0 : 1;
}
