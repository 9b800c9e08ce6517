// The report of bench_accuracy (see report.h): CSV files, the choice and order tables derived
// from the rows, the headline ratio, and docs/accuracy.md.
#include "report.h"

#include <sys/utsname.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <thread>

namespace ohrp::accuracy {

std::string Num(double v, const char* fmt) {
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
  std::ostringstream r;
  r << IntegratorName(s.integrator) << " " << DtName(s.dt);
  if (s.contact != Contact::kNone) r << " " << ContactName(s.contact);
  if (s.iterations >= 0) r << " iter " << s.iterations;
  if (s.tolerance >= 0) r << " tol " << Num(s.tolerance, "%.0e");
  if (!s.geometry.empty() && s.geometry != geometry_default) r << " " << s.geometry;
  return r.str();
}

namespace {

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

//---------------- CSV ----------------

bool WriteCsv(const std::string& path, const std::vector<Row>& rows) {
  {
    std::ofstream f(path);
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
    return static_cast<bool>(f);
  }
}

bool WriteClosedCsv(const std::string& path, const std::vector<ClosedRow>& closed) {
  {
    std::ofstream f(path);
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
    return static_cast<bool>(f);
  }
}

//---------------- derived from the rows ----------------

std::string ChoiceTable(const std::vector<SceneSpec>& scenes, const std::vector<Row>& rows) {
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
        if (r.scene == scene.name && r.s.contact == c && r.sweep != "refcheck") sel.push_back(&r);
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

  return rec.str();
}

std::string SoftStepTable(const std::vector<SceneSpec>& scenes, const std::vector<Row>& rows) {
  std::ostringstream t;  // markdown
  t << "| scene | step | soft: pos error [m] | force error [N] | rtf | native: pos error [m] | "
       "rtf | soft step / native step |\n|---|---|---|---|---|---|---|---|\n";
  bool any = false;
  const auto find = [&](const std::string& scene, Contact c, double dt) -> const Row* {
    for (const Row& r : rows)
      if (r.scene == scene && r.s.contact == c && r.s.integrator == Integrator::kEuler &&
          r.sweep == "dt" && std::fabs(r.s.dt - dt) < 1e-12)
        return &r;
    return nullptr;
  };
  for (const SceneSpec& scene : scenes) {
    std::vector<double> steps;
    for (const Row& r : rows)
      if (r.scene == scene.name && r.s.contact == Contact::kSoft &&
          r.s.integrator == Integrator::kEuler && r.sweep == "dt" && r.s.dt >= 1e-3 - 1e-12)
        steps.push_back(r.s.dt);
    std::sort(steps.begin(), steps.end());
    for (double dt : steps) {
      const Row* soft = find(scene.name, Contact::kSoft, dt);
      const Row* native = find(scene.name, Contact::kNative, dt);
      const double cost = native && soft && soft->r.rtf() > 0 ? native->r.rtf() / soft->r.rtf()
                                                               : std::nan("");
      t << "| " << scene.name << " | " << DtName(dt) << " | " << Num(soft->r.pos_error, "%.3g")
        << " | " << Num(soft->r.force_error, "%.3g") << " | " << Num(soft->r.rtf(), "%.3g")
        << " | " << (native ? Num(native->r.pos_error, "%.3g") : "") << " | "
        << (native ? Num(native->r.rtf(), "%.3g") : "") << " | " << Num(cost, "%.2f") << " |\n";
      any = true;
    }
  }
  return any ? t.str() : "";
}

std::string OrderTable(const std::vector<SceneSpec>& scenes, const std::vector<Row>& rows) {
  std::ostringstream orders;  // markdown
  orders << "| scene | contact | integrator | steps | median order | range |\n"
            "|---|---|---|---|---|---|\n";
  for (const SceneSpec& scene : scenes) {
    for (Contact c : scene.contacts) {
      for (Integrator in : {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
        std::vector<const Row*> sel;
        for (const Row& r : rows)
          if (r.scene == scene.name && r.s.contact == c && r.s.integrator == in &&
              r.sweep == "dt" && !r.reference && !r.r.diverged && r.r.pos_error > 0)
            sel.push_back(&r);
        std::sort(sel.begin(), sel.end(),
                  [](const Row* a, const Row* b) { return a->s.dt < b->s.dt; });
        std::vector<double> p;
        for (size_t i = 0; i + 1 < sel.size(); ++i) {
          if (std::fabs(sel[i + 1]->s.dt - 2 * sel[i]->s.dt) > 1e-12) continue;
          p.push_back(std::log2(sel[i + 1]->r.pos_error / sel[i]->r.pos_error));
        }
        if (p.empty()) continue;
        std::vector<double> sorted = p;
        std::sort(sorted.begin(), sorted.end());
        const double med = sorted[sorted.size() / 2];
        orders << "| " << scene.name << " | " << ContactName(c) << " | " << IntegratorName(in)
               << " | " << DtName(sel.front()->s.dt) << " .. " << DtName(sel.back()->s.dt)
               << " | " << Num(med, "%.2f") << " | " << Num(sorted.front(), "%.2f") << " .. "
               << Num(sorted.back(), "%.2f") << " |\n";
      }
    }
  }

  return orders.str();
}

std::string ReferenceCheckTable(const std::vector<Row>& rows) {
  std::ostringstream t;
  int n = 0;
  t << "| scene | contact | reference's setting at half its step | pos error [m] | force error "
       "[N] |\n|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    if (r.sweep != "refcheck") continue;
    ++n;
    t << "| " << r.scene << " | " << ContactName(r.s.contact) << " | "
      << SettingName(r.s, r.s.geometry) << " | " << Num(r.r.pos_error, "%.3g") << " | "
      << Num(r.r.force_error, "%.3g") << " |\n";
  }
  return n ? t.str() : std::string();
}

Headline StandingHeadline(const std::vector<Row>& rows, double ref_rtf) {
  Headline h;
  if (std::isfinite(ref_rtf)) {
    std::vector<const Row*> sel;
    for (const Row& r : rows)
      if (r.scene == "hrp1s_stand" && r.s.contact == Contact::kSoft && !r.reference &&
          r.sweep != "refcheck")
        sel.push_back(&r);
    const Row* best = Fastest(sel, 1e-3);
    if (best) {
      h.ratio = best->r.rtf() / ref_rtf;
      std::ostringstream t, r;
      t << "recommended default for the standing robot on soft soles (fastest within 1 mm): "
        << SettingName(best->s, "") << ", " << Num(best->r.pos_error * 1e3, "%.3g") << " mm, "
        << Num(best->r.force_error, "%.3g") << " N at " << Num(best->r.rtf(), "%.3g")
        << "x real time; the reference (RK4 1/16 ms) " << Num(ref_rtf, "%.3g") << "x";
      r << "(" << Num(best->r.rtf(), "%.3g") << "x / " << Num(ref_rtf, "%.3g") << "x)";
      h.text = t.str();
      h.ratio_text = r.str();
    }
  }
  return h;
}

//---------------- docs/accuracy.md ----------------

bool WriteDocs(const std::string& path, const DocsInput& in) {
  std::ofstream f(path);
  utsname u{};
  uname(&u);
  f << "# What accuracy costs in time\n\n"
    << "<!-- GENERATED by `build/bin/bench_accuracy" << (in.quick ? " --quick" : "")
    << " --write-docs` (tools/accuracy/bench_accuracy.cc): do not edit by hand, rerun it. -->\n\n"
    << "Made on " << UtcNow() << " on " << CpuModel() << ", "
    << std::thread::hardware_concurrency() << " cores (" << u.sysname << " " << u.release
    << "), MuJoCo " << mj_versionString() << ", " << (in.quick ? "`--quick` run" : "full run")
    << " in " << Num(in.cpu, "%.0f") << " s of CPU. "
    << "Regenerate with `./ohrp bench accuracy --write-docs` (charts and CSV land in "
       "`build/accuracy/`).\n\n"
    << "Hard cases that stay (or do not stay) numerically stable, and the settings they need: "
       "[docs/stability.md](stability.md).\n\n"
    << "## Method\n\n"
    << "After Erez, Tassa and Todorov, \"Simulation tools for model-based robotics\" (ICRA "
       "2015). For each scene and contact model, a reference trajectory is integrated with "
       "RK4 at 1/16 ms, solver iterations 200 and tolerance 1e-12. Each setting then restarts "
       "from " << in.restarts << " reference states spread along it (qpos, qvel, act, time, "
       "qacc_warmstart, xfrc_applied and the soft-foot contact's friction anchors are restored), "
       "integrates " << in.piece_windows << " windows of 16 ms and is compared with the reference "
       "at each window's end: **pos error** is the mean distance of the bodies' positions "
       "(after mj_kinematics) [m], **force error** the mean error of the 16 ms average of the "
       "total contact normal force [N]. **rtf** is simulated time over the thread's CPU time "
       "(CLOCK_THREAD_CPUTIME_ID) spent stepping. Controls are functions of simulated time. "
       "Errors are against the same contact model's own reference: they say how far a "
       "setting is from that model's converged solution, not which contact model is right. "
       "`rigid` sets the contact's time constant to 2 dt (sim_host/src/feet.cc), so its "
       "physics changes with dt by design. The soft-foot force and the Servo are held over a "
       "step (zero-order hold, as sim_host does), so RK4 is first order on the robot scenes; "
       "MuJoCo's own contact forces are re-evaluated in every RK4 stage; the force recorded for "
       "an RK4 step with MuJoCo's contact is the one of the step's last stage (MuJoCo keeps "
       "no RK4-weighted force), so RK4 force errors include that sampling.\n\n"
    << "Scenes:\n\n";
  for (const SceneSpec& s : *in.scenes) {
    f << "- `" << s.name << "`: " << s.description << "; reference over " << s.duration
      << " s";
    if (s.preroll > 0) f << " after a " << s.preroll << " s pre-roll at 1 ms Euler";
    f << ".\n";
  }
  f << "\nSkipped combinations: ";
  for (const auto& s : *in.skipped) f << s << ". ";
  f << "Soft-foot contact on the ball, the mesh variants and MuJoCo's humanoid: not "
       "applicable (it samples a box sole). Solver rows: Euler at 1 ms with MuJoCo contact "
       "only (the soft soles need no constraint solver). Geometry rows: Euler at 0.25, 1 and "
       "4 ms. Soft-foot rows at steps where the contact's own parameter check "
       "(contact::Validate) refuses the default parameters are marked `refused`.\n\n";
  f << "## What to choose\n\n"
    << "Derived from the table below by the tool (fastest setting meeting the error bound; "
       "the error is the mean body position error).\n\n"
    << in.choices << "\n";
  if (!in.headline.empty()) f << "Headline: " << in.headline << ".\n\n";
  if (!in.soft_steps.empty())
    f << "## The soft soles at each step\n\nThe paper's spring-damper soles (their force "
         "linearly implicit and averaged along the step's path, sim_host/contact/src/implicit.cc) "
         "with Euler from 1 ms up, beside MuJoCo's native contact at the same step: the errors "
         "against each model's own converged reference, the real-time factors (thread CPU), and "
         "what a step with the soft soles costs over one with the native contact (native rtf / "
         "soft rtf, above 1 when the soft step is dearer). Steps the explicit soles were refused "
         "at (above 1 ms) now run.\n\n"
      << in.soft_steps << "\n";
  f << "## Observed order\n\nlog2 of the ratio of the position errors at steps 2h and h, over "
       "the step sweep (the reference's own setting left out): about 1 for a first-order "
       "method, 4 for RK4 where the dynamics are smooth and every force is re-evaluated in "
       "its stages. Orders near 0 over a range of steps mean the error does not shrink "
       "there: the setting lands on another branch of the motion (an impact, a stick-slip "
       "transition) than the reference.\n\n"
    << in.orders << "\n";
  if (!in.refcheck.empty()) {
    f << "## How good the reference is\n\nThe reference's own setting at half its step "
         "(1/32 ms), restarted and compared like any other setting: an estimate of the "
         "reference's own error, below which the errors in the table say nothing. For "
         "`rigid` it includes the change of the contact itself (time constant 2 dt).\n\n"
      << in.refcheck << "\n";
  }
  f << "## Refsafe\n\nAt large steps MuJoCo's `refsafe` raises a contact's time constant "
       "to 2 dt when the model asks for less: the contact itself becomes softer, so the "
       "error at those steps includes a change of the physics, not only of the integration. "
       "Rows where this happens are marked in the table's notes.\n\n";
  f << "## Closed forms\n\n| scene | setting | quantity | value | exact | error |\n"
       "|---|---|---|---|---|---|\n";
  for (const ClosedRow& c : *in.closed) {
    std::string cnote = c.note;
    std::replace(cnote.begin(), cnote.end(), '\n', ' ');
    std::replace(cnote.begin(), cnote.end(), '|', '/');
    const std::string gdef =
        c.scene == "box" ? "box" : c.scene == "ball" ? "sphere" : "";
    f << "| " << c.scene << " | " << SettingName(c.s, gdef) << " | " << c.quantity << " ["
      << c.unit << "] | " << Num(c.value, "%.10g") << " | " << Num(c.exact, "%.10g") << " | "
      << (cnote.empty() ? Num(c.error, "%.3g") : Num(c.error, "%.3g") + " " + cnote)
      << " |\n";
  }
  f << "\nErrors: relative for the period, the sink and the restitution, absolute (m, m/s) for "
       "the free fall and the rolling speed.\n\n";
  f << "## Table\n\n| scene | setting | rtf | pos error [m] | force error [N] | closed form | "
       "diverged | note |\n|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : *in.rows) {
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
  return static_cast<bool>(f);
}

}  // namespace ohrp::accuracy
