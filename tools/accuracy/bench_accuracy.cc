// bench_accuracy: what accuracy costs in time. A speed-accuracy report in the manner of Erez,
// Tassa and Todorov (ICRA 2015) over time step, integrator, contact model, solver iterations and
// tolerance, and collision geometry detail, on six scenes; CSV, log-log charts and (with
// --write-docs) docs/accuracy.md, every number in it measured by this run.
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli/command_line.h"
#include "accuracy.h"
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

constexpr double kG = 9.81;
constexpr double kWindow = 0.016;  // comparison window = the largest step swept [s]

struct Options {
  bool quick = false;
  std::string out;
  std::string docs;  // write docs here when not empty
  std::vector<std::string> scenes;
  bool plot = true;
  int restarts = 10;
  int piece_windows = 8;
  double ref_dt = 1.0 / 16000;
};

bool HasDamping(const SceneSpec& scene) {
  Setting s;
  s.contact = scene.contacts.front();
  std::string error;
  auto sim = Sim::Create(scene, s, &error);
  if (!sim) return false;
  const mjModel* m = sim->m();
  for (int i = 0; i < m->nv; ++i)
    if (m->dof_damping[i] > 0) return true;
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
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
  ohrp::sim::InstallMujocoHandlers(OnFatal);
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
  auto wanted = [&](const std::string& n) {
    return o.scenes.empty() || std::find(o.scenes.begin(), o.scenes.end(), n) != o.scenes.end();
  };
  const std::string src = OHRP_SOURCE_DIR;
  const std::string ext = src + "/../shared/external";

  // ---- scenes ----
  std::vector<SceneSpec> scenes;
  Walk walk;
  const double dur = o.quick ? 0.25 : 0.0;  // quick: every reference 0.25 s
  if (wanted("pendulum")) {
    SceneSpec s;
    s.name = "pendulum";
    s.description = "chain of 4 hinged links released from a bent pose (no contact)";
    s.path = src + "/mjcf/bench/pendulum_chain.xml";
    s.keyframe = "release";
    s.contacts = {Contact::kNone};
    s.duration = o.quick ? dur : 2.0;
    scenes.push_back(s);
  }
  if (wanted("box")) {
    SceneSpec s;
    s.name = "box";
    s.description = "60 kg sole-sized block dropped from 6 cm at 1 m/s, lands and slides";
    s.path = src + "/mjcf/bench/box_slide.xml";
    s.keyframe = "drop";
    s.contacts = {Contact::kSoft, Contact::kNative, Contact::kRigid};
    s.geometries = {"box", "mesh8"};
    s.soles = {"box"};
    s.soft_mass = 60;
    s.duration = o.quick ? dur : 0.5;
    scenes.push_back(s);
  }
  if (wanted("ball")) {
    SceneSpec s;
    s.name = "ball";
    s.description = "1 kg ball (r 0.1 m) set down sliding at 2 m/s without spin: slides, rolls";
    s.xml = BallXml();
    s.keyframe = "slide";
    s.contacts = {Contact::kNative, Contact::kRigid};
    s.geometries = {"sphere", "ico0", "ico1", "ico2", "ico3"};
    s.soles = {"sphere"};
    s.duration = o.quick ? dur : 0.5;
    scenes.push_back(s);
  }
  const std::string hrp1s = src + "/mjcf/hrp1s/scene_flat.xml";
  if (wanted("hrp1s_stand")) {
    SceneSpec s;
    s.name = "hrp1s_stand";
    s.description = "HRP-1S (mjcf/hrp1s/scene_flat.xml) from key halfsit, joints held by the Servo";
    s.path = hrp1s;
    s.keyframe = "halfsit";
    s.contacts = {Contact::kSoft, Contact::kNative, Contact::kRigid};
    s.servo = true;
    s.duration = o.quick ? dur : 2.0;
    scenes.push_back(s);
  }
  if (wanted("hrp1s_walk")) {
    std::string error;
    if (!LoadWalk(ext + "/openhrp3-sample/SamplePD", &walk, &error)) {
      std::fprintf(stderr, "bench_accuracy: %s\n(the hrp1s_walk scene needs OpenHRP's SamplePD "
                           "data beside the repository; leave it out with --scenes)\n",
                   error.c_str());
      return 2;
    }
    SceneSpec s;
    s.name = "hrp1s_walk";
    s.description = "HRP-1S playing SamplePD's angle.dat/vel.dat/PDgain.dat (references a "
                    "function of simulated time), from 4.2 s: the first steps";
    s.path = hrp1s;
    s.keyframe = "init";
    s.contacts = {Contact::kSoft, Contact::kNative, Contact::kRigid};
    s.walk = &walk;
    s.preroll = o.quick ? 4.4 : 4.2;
    s.duration = o.quick ? dur : 2.0;
    scenes.push_back(s);
  }
  if (wanted("humanoid")) {
    const std::string path = ext + "/mujoco-2.2.2-models/humanoid/humanoid.xml";
    if (!fs::exists(path)) {
      std::fprintf(stderr, "bench_accuracy: MuJoCo's humanoid.xml is not at %s (it comes with "
                           "the shared external data beside the repository); leave the scene "
                           "out with --scenes\n", path.c_str());
      return 2;
    }
    SceneSpec s;
    s.name = "humanoid";
    s.description = "MuJoCo 2.2.2's humanoid.xml, controls zero: it collapses onto the floor";
    s.path = path;
    s.contacts = {Contact::kNative, Contact::kRigid};
    s.duration = o.quick ? dur : 1.5;
    // rigid: every body geom made near-rigid
    char err[1000] = "";
    mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof err);
    if (!m) {
      std::fprintf(stderr, "bench_accuracy: cannot load %s: %s\n", path.c_str(), err);
      return 2;
    }
    for (int g = 0; g < m->ngeom; ++g)
      if (m->geom_bodyid[g] != 0) s.soles.push_back(mj_id2name(m, mjOBJ_GEOM, g));
    mj_deleteModel(m);
    scenes.push_back(s);
  }
  for (auto& s : scenes) {
    if (s.name == "hrp1s_stand" || s.name == "hrp1s_walk") {
      std::string error;
      auto sc = ohrp::sim::Scene::Load(s.path, &error);
      ohrp::sim::RobotMap robot;
      if (!sc || !ohrp::sim::MapRobot(sc->m(), &robot, &error)) {
        std::fprintf(stderr, "bench_accuracy: %s\n", error.c_str());
        return 2;
      }
      s.soft_mass = 0.5 * robot.total_mass;
    }
  }

  // ---- settings ----
  std::vector<double> dts;
  if (o.quick) {
    dts = {0.25e-3, 1e-3, 4e-3, 16e-3};
  } else {
    for (int k = 0; k <= 8; ++k) dts.push_back(std::ldexp(1.0 / 16000, k));
  }
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) {
    std::fprintf(stderr, "bench_accuracy: cannot create %s: %s\n", o.out.c_str(),
                 ec.message().c_str());
    return 2;
  }

  std::vector<Row> rows;
  std::vector<ClosedRow> closed;
  std::vector<std::string> skipped, no_damping;
  std::map<std::string, std::map<Contact, Reference>> refs;
  const double t_start = ohrp::ThreadCpuSeconds();
  for (const SceneSpec& scene : scenes) {
    const std::string gdef = scene.geometries.empty() ? "" : scene.geometries[0];
    const bool damping = HasDamping(scene);
    std::vector<Integrator> integrators = {Integrator::kEuler, Integrator::kRK4};
    if (damping) integrators.push_back(Integrator::kImplicit);
    else no_damping.push_back(scene.name);
    for (Contact c : scene.contacts) {
      Setting rs;
      rs.integrator = Integrator::kRK4;
      rs.dt = o.ref_dt;
      rs.contact = c;
      rs.iterations = 200;
      rs.tolerance = 1e-12;
      rs.geometry = gdef;
      std::fprintf(stderr, "[%s] reference %s contact: %s, %.2f s ...\n", scene.name.c_str(),
                   ContactName(c), SettingName(rs, gdef).c_str(), scene.duration);
      std::string error;
      Reference& ref = refs[scene.name][c];
      if (!MakeReference(scene, rs, kWindow, &ref, &error)) {
        std::fprintf(stderr, "bench_accuracy: %s\n", error.c_str());
        return 1;
      }
      std::fprintf(stderr, "[%s] reference done: %.3g x real time\n", scene.name.c_str(),
                   ref.sim_time / ref.cpu);
      // the settings against this reference
      std::vector<std::pair<std::string, Setting>> settings;
      for (double dt : dts) {
        for (Integrator in : integrators) {
          if (o.quick && in == Integrator::kImplicit && dt != 1e-3) continue;
          Setting s;
          s.integrator = in;
          s.dt = dt;
          s.contact = c;
          s.geometry = gdef;
          settings.push_back({"dt", s});
        }
      }
      if (!o.quick) {
        // the reference's own error: its setting at half its step, compared with it
        Setting s = rs;
        s.dt = rs.dt / 2;
        settings.push_back({"refcheck", s});
      }
      if (c == Contact::kNative || c == Contact::kRigid) {
        std::vector<std::pair<int, double>> solver =
            o.quick ? std::vector<std::pair<int, double>>{{2, 1e-3}}
                    : std::vector<std::pair<int, double>>{{1, 1e-3}, {3, 1e-3}, {10, 1e-3},
                                                           {1, 1e-8}, {3, 1e-8}, {10, 1e-8}};
        for (auto [it, tol] : solver) {
          Setting s;
          s.dt = 1e-3;
          s.contact = c;
          s.iterations = it;
          s.tolerance = tol;
          s.geometry = gdef;
          settings.push_back({"solver", s});
        }
        for (size_t g = 1; g < scene.geometries.size(); ++g) {
          for (double dt : o.quick ? std::vector<double>{1e-3}
                                   : std::vector<double>{0.25e-3, 1e-3, 4e-3}) {
            Setting s;
            s.dt = dt;
            s.contact = c;
            s.geometry = scene.geometries[g];
            settings.push_back({"geometry", s});
          }
        }
      }
      for (size_t i = 0; i < settings.size(); ++i) {
        Row row;
        row.scene = scene.name;
        row.sweep = settings[i].first;
        row.s = settings[i].second;
        row.geometry = row.s.geometry.empty() ? "-" : row.s.geometry;
        row.reference = row.s.integrator == rs.integrator && row.s.dt == rs.dt &&
                        row.sweep == "dt";
        row.r = RunPieces(scene, row.s, ref, o.restarts, o.piece_windows);
        row.iterations = row.r.iterations;
        row.tolerance = row.r.tolerance;
        if (row.r.refsafe) {
          row.r.note += std::string(row.r.note.empty() ? "" : "; ") +
                        "refsafe: contact time constant raised to 2 dt";
        }
        if (row.reference) row.r.note += std::string(row.r.note.empty() ? "" : "; ") +
                                         "the reference's integrator and step";
        // closed forms
        double value = std::nan(""), exact = std::nan("");
        std::string note;
        auto add_closed = [&](const std::string& q, const std::string& unit, double err) {
          ClosedRow cr;
          cr.scene = scene.name;
          cr.s = row.s;
          cr.quantity = q;
          cr.unit = unit;
          cr.value = value;
          cr.exact = exact;
          cr.error = err;
          cr.note = note;
          closed.push_back(cr);
          value = exact = std::nan("");
          note.clear();
        };
        if (scene.name == "pendulum" && row.sweep == "dt") {
          exact = PendulumPeriod(0.26, 1.0, kG, 0.5, 0.1);
          value = MeasurePendulumPeriod(src + "/mjcf/bench/pendulum_single.xml", row.s, 3);
          row.closed_form = "period_rel";
          row.closed_form_error = std::fabs(value - exact) / exact;
          add_closed("pendulum period (exact, elliptic K; small-angle 2 pi sqrt(I/mgd) = " +
                         Num(2 * M_PI * std::sqrt(0.26 / (kG * 0.5)), "%.6f") + " s)",
                     "s", row.closed_form_error);
        }
        if (scene.name == "box" && (row.sweep == "dt" || row.sweep == "geometry")) {
          row.closed_form = "freefall_m";
          row.closed_form_error = FreeFallError(scene, row.s, &value, &exact);
          add_closed("free fall z(0.096 s) = z0 - g t^2/2", "m", row.closed_form_error);
          if (c == Contact::kSoft) {
            const double e1 = StaticSink(scene, row.s, &value, &exact, &note);
            add_closed("soft-foot static sink (m g / k)^(1/n)", "m", e1);
            const double e2 = Restitution(scene, row.s, &value, &exact, &note);
            add_closed("soft-foot restitution at 0.1 m/s (Hunt-Crossley law)", "-", e2);
          }
        }
        if (scene.name == "ball" && (row.sweep == "dt" || row.sweep == "geometry")) {
          row.closed_form = "rolling_mps";
          row.closed_form_error = RollingError(scene, row.s, &value, &exact);
          add_closed("rolling speed after sliding 5/7 v0", "m/s", row.closed_form_error);
        }
        std::fprintf(stderr, "[%s] %s %zu/%zu %-40s pos %-10s m force %-10s N rtf %-8s %s\n",
                     scene.name.c_str(), ContactName(c), i + 1, settings.size(),
                     SettingName(row.s, gdef).c_str(), Num(row.r.pos_error, "%.3g").c_str(),
                     Num(row.r.force_error, "%.3g").c_str(), Num(row.r.rtf(), "%.3g").c_str(),
                     row.r.note.c_str());
        rows.push_back(row);
      }
    }
  }

  if (!no_damping.empty()) {
    std::string names;
    for (const auto& n : no_damping) names += (names.empty() ? "" : ", ") + n;
    skipped.push_back("implicit on " + names + ": skipped, these models have no joint damping "
                      "(MuJoCo's implicit integrator then steps exactly as Euler)");
  }

  // ---- CSV ----
  const std::string csv = o.out + "/accuracy.csv";
  if (!WriteCsv(csv, rows) || !WriteClosedCsv(o.out + "/closed_forms.csv", closed)) {
    std::fprintf(stderr, "bench_accuracy: cannot write the CSV files in %s\n", o.out.c_str());
    return 2;
  }
  std::fprintf(stderr, "wrote %s and %s/closed_forms.csv\n", csv.c_str(), o.out.c_str());

  // ---- charts ----
  int plot_status = 0;
  if (o.plot) {
    const char* env = std::getenv("OHRP_PYTHON");
    const std::string python = env && *env ? env
                               : fs::exists("/usr/bin/python3") ? "/usr/bin/python3"
                                                                : "python3";
    std::string why;  // an argument vector, no shell (tool_process/run_command.h)
    plot_status = ohrp::tool::RunCommand({python, src + "/tools/scripts/plot_accuracy.py", csv, o.out}, "", &why);
    if (plot_status != 0)
      std::fprintf(stderr, "bench_accuracy: plotting failed (%s)\n",
                   plot_status < 0 ? why.c_str() : "plot_accuracy.py returned non-zero");
  }

  // ---- what to choose, the orders and the headline, from the rows ----
  const std::string choices = ChoiceTable(scenes, rows);
  const std::string orders = OrderTable(scenes, rows);
  double stand_ref_rtf = std::nan("");
  if (refs.count("hrp1s_stand") && refs["hrp1s_stand"].count(Contact::kSoft)) {
    const Reference& ref = refs["hrp1s_stand"][Contact::kSoft];
    stand_ref_rtf = ref.sim_time / ref.cpu;
  }
  const Headline head = StandingHeadline(rows, stand_ref_rtf);
  if (!head.text.empty()) std::printf("\n%s\n", head.text.c_str());

  // ---- docs ----
  if (write_docs) {
    DocsInput in;
    in.quick = o.quick;
    in.restarts = o.restarts;
    in.piece_windows = o.piece_windows;
    in.cpu = ohrp::ThreadCpuSeconds() - t_start;
    in.scenes = &scenes;
    in.skipped = &skipped;
    in.rows = &rows;
    in.closed = &closed;
    in.choices = choices;
    in.orders = orders;
    in.refcheck = ReferenceCheckTable(rows);
    in.soft_steps = SoftStepTable(scenes, rows);
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
