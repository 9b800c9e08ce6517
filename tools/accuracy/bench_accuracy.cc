// bench_accuracy: what accuracy costs in time. A speed-accuracy report in the manner of Erez,
// Tassa and Todorov (ICRA 2015) over time step, integrator, contact model, solver iterations and
// tolerance, and collision geometry detail, on six scenes; CSV, log-log charts and (with
// --write-docs) docs/accuracy.md, every number in it measured by this run.
#include <sys/utsname.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
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

#include "accuracy.h"

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

struct Row {
  std::string scene, sweep;
  Setting s;
  int iterations = 0;
  double tolerance = 0;
  std::string geometry;
  PieceResult r;
  std::string closed_form;
  double closed_form_error = std::nan("");
  bool reference = false;
};

struct ClosedRow {
  std::string scene;
  Setting s;
  std::string quantity, unit;
  double value = std::nan(""), exact = std::nan(""), error = std::nan("");
  std::string note;
};

std::string Num(double v, const char* fmt = "%.4g") {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return "inf";
  char b[64];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}

std::string DtName(double dt) {
  const double ms = dt * 1e3;
  if (ms >= 1) return Num(ms, "%.0f") + " ms";
  return "1/" + Num(1.0 / ms, "%.0f") + " ms";
}

std::string SettingName(const Setting& s, const std::string& geometry_default) {
  std::string r = std::string(IntegratorName(s.integrator)) + " " + DtName(s.dt);
  if (s.contact != Contact::kNone) r += " " + std::string(ContactName(s.contact));
  if (s.iterations >= 0) r += " iter " + std::to_string(s.iterations);
  if (s.tolerance >= 0) r += " tol " + Num(s.tolerance, "%.0e");
  if (!s.geometry.empty() && s.geometry != geometry_default) r += " " + s.geometry;
  return r;
}

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

std::string CpuModel() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto p = line.find(':');
      if (p != std::string::npos) return line.substr(p + 2);
    }
  }
  return "unknown CPU";
}

std::string UtcNow() {
  std::time_t t = std::time(nullptr);
  char b[64];
  std::strftime(b, sizeof b, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
  return b;
}

// ---- recommendations, derived from the rows ----

const Row* Fastest(const std::vector<const Row*>& rows, double max_err, double min_rtf = 0) {
  const Row* best = nullptr;
  for (const Row* r : rows) {
    if (r->r.diverged || !(r->r.pos_error <= max_err) || r->r.rtf() < min_rtf) continue;
    if (!best || r->r.rtf() > best->r.rtf()) best = r;
  }
  return best;
}

const Row* MostAccurate(const std::vector<const Row*>& rows, double min_rtf) {
  const Row* best = nullptr;
  for (const Row* r : rows) {
    if (r->r.diverged || r->r.rtf() < min_rtf || r->reference) continue;
    if (!best || r->r.pos_error < best->r.pos_error) best = r;
  }
  return best;
}

std::string Brief(const Row* r, const std::string& gdef) {
  if (!r) return "none measured";
  return SettingName(r->s, gdef) + " (" + Num(r->r.pos_error * 1e3, "%.3g") + " mm, " +
         Num(r->r.force_error, "%.3g") + " N, " + Num(r->r.rtf(), "%.3g") + "x)";
}

std::string Need(const std::vector<const Row*>& rows, double err, double rtf,
                 const std::string& gdef) {
  const Row* both = Fastest(rows, err, rtf);
  if (both) return Brief(both, gdef);
  const Row* a = Fastest(rows, err);
  const Row* b = MostAccurate(rows, rtf);
  return "not reached; fastest within " + Num(err * 1e3, "%g") + " mm: " + Brief(a, gdef) +
         "; most accurate at " + Num(rtf, "%g") + "x: " + Brief(b, gdef);
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
  app.add_option("--restarts", o.restarts, "restart points per setting (default 10, quick 2)");
  app.add_option("--piece-windows", o.piece_windows,
                 "16 ms windows per piece (default 8, quick 4)");
  CLI11_PARSE(app, argc, argv);
  ohrp::sim::InstallMujocoHandlers(OnFatal);
  if (o.quick) {
    if (app.count("--restarts") == 0) o.restarts = 2;
    if (app.count("--piece-windows") == 0) o.piece_windows = 4;
  }
  if (o.restarts < 1 || o.piece_windows < 1) {
    std::fprintf(stderr, "bench_accuracy: --restarts and --piece-windows must be >= 1\n");
    return 2;
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
  std::vector<std::string> skipped;
  std::map<std::string, std::map<Contact, Reference>> refs;
  const double t_start = ThreadCpu();
  for (const SceneSpec& scene : scenes) {
    const std::string gdef = scene.geometries.empty() ? "" : scene.geometries[0];
    const bool damping = HasDamping(scene);
    std::vector<Integrator> integrators = {Integrator::kEuler, Integrator::kRK4};
    if (damping) integrators.push_back(Integrator::kImplicit);
    else
      skipped.push_back(scene.name + ": implicit skipped, the model has no joint damping (MuJoCo's "
                        "implicit integrator then steps exactly as Euler)");
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
        if (scene.name == "box" && row.sweep != "solver") {
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
        if (scene.name == "ball" && row.sweep != "solver") {
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

  // ---- CSV ----
  const std::string csv = o.out + "/accuracy.csv";
  {
    std::ofstream f(csv);
    f << "scene,sweep,integrator,dt,contact,iterations,tolerance,geometry,rtf,pos_error_m,"
         "force_error_N,closed_form,closed_form_error,diverged,note\n";
    for (const Row& r : rows) {
      std::string note = r.r.note;
      std::replace(note.begin(), note.end(), ',', ';');
      std::replace(note.begin(), note.end(), '\n', ' ');
      f << r.scene << "," << r.sweep << "," << IntegratorName(r.s.integrator) << ","
        << Num(r.s.dt, "%.9g") << "," << ContactName(r.s.contact) << "," << (r.iterations > 0 ? std::to_string(r.iterations) : "") << ","
        << (r.iterations > 0 ? Num(r.tolerance, "%.0e") : "") << "," << r.geometry << "," << Num(r.r.rtf(), "%.6g") << ","
        << Num(r.r.pos_error, "%.6g") << "," << Num(r.r.force_error, "%.6g") << ","
        << r.closed_form << "," << Num(r.closed_form_error, "%.6g") << ","
        << (note.rfind("refused", 0) == 0 ? "refused" : r.r.diverged ? "yes" : "no") << ","
        << note << "\n";
    }
    if (!f) {
      std::fprintf(stderr, "bench_accuracy: cannot write %s\n", csv.c_str());
      return 2;
    }
  }
  {
    std::ofstream f(o.out + "/closed_forms.csv");
    f << "scene,integrator,dt,contact,geometry,quantity,unit,value,exact,error,note\n";
    for (const ClosedRow& c : closed) {
      std::string note = c.note;
      std::replace(note.begin(), note.end(), ',', ';');
      std::replace(note.begin(), note.end(), '\n', ' ');
      std::string q = c.quantity;
      std::replace(q.begin(), q.end(), ',', ';');
      f << c.scene << "," << IntegratorName(c.s.integrator) << "," << Num(c.s.dt, "%.9g") << ","
        << ContactName(c.s.contact) << "," << (c.s.geometry.empty() ? "-" : c.s.geometry) << ","
        << q << "," << c.unit << "," << Num(c.value, "%.10g") << "," << Num(c.exact, "%.10g")
        << "," << Num(c.error, "%.6g") << "," << note << "\n";
    }
  }
  std::fprintf(stderr, "wrote %s and %s/closed_forms.csv\n", csv.c_str(), o.out.c_str());

  // ---- charts ----
  int plot_status = 0;
  if (o.plot) {
    const char* env = std::getenv("OHRP_PYTHON");
    const std::string python = env && *env ? env
                               : fs::exists("/usr/bin/python3") ? "/usr/bin/python3"
                                                                : "python3";
    const std::string cmd = "'" + python + "' '" + src + "/tools/scripts/plot_accuracy.py' '" +
                            csv + "' '" + o.out + "'";
    plot_status = std::system(cmd.c_str());
    if (plot_status != 0) std::fprintf(stderr, "bench_accuracy: plotting failed (%s)\n", cmd.c_str());
  }

  // ---- what to choose, from the rows ----
  std::ostringstream rec;  // markdown
  std::printf("\n%-12s %-8s %-58s %-58s %-58s\n", "scene", "contact", "1 mm at 20x real time",
              "fastest within 1 cm", "most accurate at real time");
  rec << "| scene | contact | 1 mm at 20x real time | 0.1 mm, fastest | 1 cm, fastest | most "
         "accurate at >= 1x real time |\n|---|---|---|---|---|---|\n";
  for (const SceneSpec& scene : scenes) {
    const std::string gdef = scene.geometries.empty() ? "" : scene.geometries[0];
    for (Contact c : scene.contacts) {
      std::vector<const Row*> sel;
      for (const Row& r : rows)
        if (r.scene == scene.name && r.s.contact == c) sel.push_back(&r);
      const std::string a = Need(sel, 1e-3, 20, gdef);
      const std::string b = Brief(Fastest(sel, 1e-4), gdef);
      const std::string d = Brief(Fastest(sel, 1e-2), gdef);
      const std::string e = Brief(MostAccurate(sel, 1.0), gdef);
      std::printf("%-12s %-8s %-58s %-58s %-58s\n", scene.name.c_str(), ContactName(c), a.c_str(),
                  d.c_str(), e.c_str());
      rec << "| " << scene.name << " | " << ContactName(c) << " | " << a << " | " << b << " | "
          << d << " | " << e << " |\n";
    }
  }

  // ---- the headline ratio: the standing robot, soft soles ----
  double ratio = std::nan("");
  std::string ratio_text = "(no hrp1s_stand scene in this run)";
  std::string headline;
  if (refs.count("hrp1s_stand") && refs["hrp1s_stand"].count(Contact::kSoft)) {
    const Reference& ref = refs["hrp1s_stand"][Contact::kSoft];
    std::vector<const Row*> sel;
    for (const Row& r : rows)
      if (r.scene == "hrp1s_stand" && r.s.contact == Contact::kSoft && !r.reference)
        sel.push_back(&r);
    const Row* best = Fastest(sel, 1e-3);
    const double ref_rtf = ref.sim_time / ref.cpu;
    if (best) {
      ratio = best->r.rtf() / ref_rtf;
      headline = "recommended default for the standing robot on soft soles (fastest within 1 mm): " +
                 SettingName(best->s, "") + ", " + Num(best->r.pos_error * 1e3, "%.3g") +
                 " mm at " + Num(best->r.rtf(), "%.3g") + "x real time; the reference (RK4 1/16 ms) " +
                 Num(ref_rtf, "%.3g") + "x";
      ratio_text = "(" + Num(best->r.rtf(), "%.3g") + "x / " + Num(ref_rtf, "%.3g") + "x)";
    }
  }
  if (!headline.empty()) std::printf("\n%s\n", headline.c_str());

  // ---- docs ----
  if (write_docs) {
    std::ofstream f(docs_path);
    utsname u{};
    uname(&u);
    f << "# What accuracy costs in time\n\n"
      << "<!-- GENERATED by `build/bin/bench_accuracy" << (o.quick ? " --quick" : "")
      << " --write-docs` (tools/accuracy/bench_accuracy.cc): do not edit by hand, rerun it. -->\n\n"
      << "Made on " << UtcNow() << " on " << CpuModel() << ", "
      << std::thread::hardware_concurrency() << " cores (" << u.sysname << " " << u.release
      << "), MuJoCo " << mj_versionString() << ", " << (o.quick ? "`--quick` run" : "full run")
      << " in " << Num(ThreadCpu() - t_start, "%.0f") << " s of CPU. "
      << "Regenerate with `./ohrp bench accuracy --write-docs` (charts and CSV land in "
         "`build/accuracy/`).\n\n"
      << "Hard cases that stay (or do not stay) numerically stable, and the settings they need: "
         "[docs/stability.md](stability.md).\n\n"
      << "## Method\n\n"
      << "After Erez, Tassa and Todorov, \"Simulation tools for model-based robotics\" (ICRA "
         "2015). For each scene and contact model, a reference trajectory is integrated with "
         "RK4 at 1/16 ms, solver iterations 200 and tolerance 1e-12. Each setting then restarts "
         "from " << o.restarts << " reference states spread along it (qpos, qvel, act, time, "
         "qacc_warmstart, xfrc_applied and the soft-foot contact's friction anchors are restored), "
         "integrates " << o.piece_windows << " windows of 16 ms and is compared with the reference "
         "at each window's end: **pos error** is the mean distance of the bodies' positions "
         "(after mj_kinematics) [m], **force error** the mean error of the 16 ms average of the "
         "total contact normal force [N]. **rtf** is simulated time over the thread's CPU time "
         "(CLOCK_THREAD_CPUTIME_ID) spent stepping. Controls are functions of simulated time. "
         "Errors are against the same contact model's own reference: they say how far a "
         "setting is from that model's converged solution, not which contact model is right. "
         "`rigid` sets the contact's time constant to 2 dt (sim_host/src/feet.cc), so its "
         "physics changes with dt by design. The soft-foot force and the Servo are held over a "
         "step (zero-order hold, as sim_host does), so RK4 is first order on the robot scenes; "
         "MuJoCo's own contact forces are re-evaluated in every RK4 stage.\n\n"
      << "Scenes:\n\n";
    for (const SceneSpec& s : scenes) {
      f << "- `" << s.name << "`: " << s.description << "; reference over " << s.duration
        << " s";
      if (s.preroll > 0) f << " after a " << s.preroll << " s pre-roll at 1 ms Euler";
      f << ".\n";
    }
    f << "\nSkipped combinations: ";
    for (const auto& s : skipped) f << s << ". ";
    f << "Soft-foot contact on the ball, the mesh variants and MuJoCo's humanoid: not "
         "applicable (it samples a box sole). Solver rows: Euler at 1 ms with MuJoCo contact "
         "only (the soft soles need no constraint solver). Geometry rows: Euler at 0.25, 1 and "
         "4 ms. Soft-foot rows at steps where the contact's own parameter check "
         "(contact::Validate) refuses the default parameters are marked `refused`.\n\n";
    f << "## What to choose\n\n"
      << "Derived from the table below by the tool (fastest setting meeting the error bound; "
         "the error is the mean body position error).\n\n"
      << rec.str() << "\n";
    if (!headline.empty()) f << "Headline: " << headline << ".\n\n";
    f << "## Refsafe\n\nAt large steps MuJoCo's `refsafe` raises a contact's time constant "
         "to 2 dt when the model asks for less: the contact itself becomes softer, so the "
         "error at those steps includes a change of the physics, not only of the integration. "
         "Rows where this happens are marked in the table's notes.\n\n";
    f << "## Closed forms\n\n| scene | setting | quantity | value | exact | error |\n"
         "|---|---|---|---|---|---|\n";
    for (const ClosedRow& c : closed) {
      const std::string gdef =
          c.scene == "box" ? "box" : c.scene == "ball" ? "sphere" : "";
      f << "| " << c.scene << " | " << SettingName(c.s, gdef) << " | " << c.quantity << " ["
        << c.unit << "] | " << Num(c.value, "%.8g") << " | " << Num(c.exact, "%.8g") << " | "
        << (c.note.empty() ? Num(c.error, "%.3g") : Num(c.error, "%.3g") + " " + c.note)
        << " |\n";
    }
    f << "\nErrors: relative for the period, the sink and the restitution, absolute (m, m/s) for "
         "the free fall and the rolling speed.\n\n";
    f << "## Table\n\n| scene | setting | rtf | pos error [m] | force error [N] | closed form | "
         "diverged | note |\n|---|---|---|---|---|---|---|---|\n";
    for (const Row& r : rows) {
      const std::string gdef = r.scene == "box" ? "box" : r.scene == "ball" ? "sphere" : "";
      std::string note = r.r.note;
      std::replace(note.begin(), note.end(), '\n', ' ');
      std::replace(note.begin(), note.end(), '|', '/');
      f << "| " << r.scene << " | " << SettingName(r.s, gdef) << " | " << Num(r.r.rtf(), "%.3g")
        << " | " << Num(r.r.pos_error, "%.3g") << " | " << Num(r.r.force_error, "%.3g") << " | "
        << (r.closed_form.empty() ? "" : r.closed_form + " " + Num(r.closed_form_error, "%.3g"))
        << " | " << (note.rfind("refused", 0) == 0 ? "refused" : r.r.diverged ? "yes" : "no")
        << " | " << note << " |\n";
    }
    f << "\n## Charts\n\n`build/accuracy/<scene>.png`: position error (left) and force error "
         "(right) against the real-time factor, log-log, one curve per integrator and contact "
         "model over the time step (the step is written at each point), solver and geometry "
         "rows as separate markers.\n";
    if (!f) {
      std::fprintf(stderr, "bench_accuracy: cannot write %s\n", docs_path.c_str());
      return 2;
    }
    std::fprintf(stderr, "wrote %s\n", docs_path.c_str());
  }

  std::printf("ratio = real-time factor of the recommended standing setting (hrp1s_stand, soft "
              "soles, fastest within 1 mm) / that of its reference (RK4 1/16 ms)\n");
  std::printf("ratio: %s %s\n", std::isnan(ratio) ? "nan" : Num(ratio, "%.2f").c_str(),
              ratio_text.c_str());
  return plot_status == 0 ? 0 : 1;
}
