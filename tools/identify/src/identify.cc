// ohrp identify: the soles' K and D from a recording of the damped rocking (see identify.h).
#include "identify/identify.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli/plausible.h"
#include "compare/oscillation.h"
#include "compare/signal.h"
#include "contact/params.h"
#include "identify/rocking.h"
#include "robot_model/model.h"
#include "datalog/table.h"
#include "runner/scenario.h"
#include "measure.h"
#include "noise_spread.h"
#include "recording_checks.h"
#include "simulate.h"

namespace ohrp::identify {
namespace {

constexpr int kOk = 0, kFailed = 1, kUsage = 2;

// the end of the scenario's last push [s]: its `pushes` or a --push in its sim_args
bool PushEnd(const runner::Scenario& s, double* end) {
  bool found = false;
  for (const auto& p : s.pushes) {
    *end = found ? std::max(*end, p.at + p.duration) : p.at + p.duration;
    found = true;
  }
  for (size_t i = 0; i + 1 < s.sim_args.size(); ++i) {
    if (s.sim_args[i] != "--push") continue;
    double t0 = 0, t1 = 0;
    if (std::sscanf(s.sim_args[i + 1].c_str(), "%lf,%lf", &t0, &t1) == 2) {
      *end = found ? std::max(*end, t1) : t1;
      found = true;
    }
  }
  return found;
}

std::string Fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[200];
  std::snprintf(buf, sizeof(buf), f, a, b, c, d);
  return buf;
}

// the slopes of (b)'s lines and where they put K and D
struct Refinement {
  double kb = 0, db = 0;        // the refined K [N/m], D [s/m]
  double df2dk = 0, dzdd = 0;   // d(f^2)/dK, d zeta/dD
  double dzeta_ddelta = 0;      // at the recording's log decrement
};

// one identification: its inputs loaded once, then the stages of identify.h in turn
class Identification {
 public:
  Identification(const IdentifyOptions& o, IdentifyResult* r, std::string* error)
      : o(o), r(r), error(error) {}
  int Run();

 private:
  bool LoadRecording();
  bool LoadExperiment(double* push_end);
  void Say(const std::string& s) const;
  bool Simulate(const std::string& stage, const std::vector<std::pair<double, double>>& kd,
                std::vector<Measured>* ms);
  bool Align(const Measured& sim, const std::string& on);
  bool ClosedForm(Estimate* e, RockingGeometry* geo);
  int RefineK(RockingGeometry* geo, Refinement* f);
  int RefineD(Refinement* f);
  int CompareFinalRun(const Measured& nominal, const Refinement& f);
  double RmsAgainstRecording(const Measured& m) const;

  const IdentifyOptions& o;
  IdentifyResult* r;
  std::string* error;
  datalog::Table rec;
  std::vector<double> rx;                       // the recording's channel
  const std::vector<double>* rt = nullptr;      // the recording's times
  std::unique_ptr<model::Scene> model;
  contact::SoftContactParams p;  // the soles' other parameters: sim_host's defaults
  std::string err;
};

}  // namespace

int Identify(const IdentifyOptions& o, IdentifyResult* r, std::string* error) {
  return Identification(o, r, error).Run();
}

int Identification::Run() {
  double push_end = 0;
  if (!LoadRecording() || !LoadExperiment(&push_end)) return kUsage;
  r->noise = compare::NoiseSigma(rx);
  r->from = push_end + o.settle;
  r->to = r->from + o.window;
  std::vector<Measured> nominal_run;
  if (!Simulate("nominal", {{p.stiffness, p.damping}}, &nominal_run)) return kFailed;
  // rows across the experiment (the push, the window, the lags searched): no gap as long as a
  // tenth of the simulated experiment's period (a few skipped 2 ms cycles are no gap)
  if (!CheckTimeBase(*rt, push_end - 1.0, r->to + 2.0, 0.1 / nominal_run[0].osc.frequency,
                     o.recording, error))
    return kUsage;
  // first on the nominal run, whose frequency may be far from the recording's (3.0 Hz against
  // 2.45): the lag found then can be off by a fraction of a period, which puts the recording's
  // window on other swings than the simulations' and biases its decay (20 % in D seen). The
  // first estimate centres the K stage; the recording is then aligned again on that stage's
  // middle run, whose frequency is the recording's to a few per cent.
  if (!Align(nominal_run[0], "nominal run")) return kUsage;
  RockingGeometry geo;
  if (!ClosedForm(&r->first, &geo)) return kUsage;
  r->first_lag = r->lag;
  Say(Fmt("first estimate: K %.4g N/m, D %.4g s/m", r->first.k, r->first.d));
  Refinement f;
  if (const int code = RefineK(&geo, &f); code != kOk) return code;
  if (const int code = RefineD(&f); code != kOk) return code;
  return CompareFinalRun(nominal_run[0], f);
}

void Identification::Say(const std::string& s) const {
  if (!o.quiet) std::fprintf(stderr, "ohrp identify: %s\n", s.c_str());
}

// the recording: a data log of plausible times holding the channel
bool Identification::LoadRecording() {
  if (!rec.Load(o.recording, error)) return false;
  if (rec.Column("time") < 0 || rec.rows() < 3) {
    *error = o.recording + ": not a data log (no 'time' column, or fewer than 3 rows)";
    return false;
  }
  // the recording's times are numbers of the file: a plausible run's
  *error = cli::CheckPlausibleEach("time", rec.col(rec.Column("time")), o.recording + ": time");
  if (!error->empty()) return false;
  if (!Channel(rec, o.recording, o.channel, &rx, error)) return false;
  rt = &rec.col(rec.Column("time"));
  return true;
}

// the experiment: a scenario with a push, whose sim_args leave the soles to the simulations,
// and its scene
bool Identification::LoadExperiment(double* push_end) {
  runner::Scenario sc;
  if (!runner::LoadScenario(o.scenario, &sc, error)) return false;
  if (!PushEnd(sc, push_end)) {
    *error = o.scenario + ": no push (pushes, or --push in sim_args): the experiment is a push "
             "and the free rocking after it (scenarios/rocking_fig12.yaml)";
    return false;
  }
  // the simulations set the soles through contact_params; the scenario's own sim_args come
  // after them on sim_host's command line and would win
  for (const auto& a : sc.sim_args)
    if (a == "--contact-stiffness" || a == "--contact-damping") {
      *error = o.scenario + ": sim_args has " + a + ", which would override the K and D the "
               "simulations set (contact_params.stiffness, .damping): give the soles in "
               "contact_params instead";
      return false;
    }
  const std::string scene = sc.scene.empty() || sc.scene[0] == '/' ? sc.scene : o.source_dir + "/" + sc.scene;
  model = model::Scene::Load(scene, &err);
  if (!model) {
    *error = err;
    return false;
  }
  return true;
}

//---- the simulated experiment at sim_host's default soles: where the recording's window is
// each stage's runs are one sweep (simulate.h), measured as the recording is
bool Identification::Simulate(const std::string& stage,
                              const std::vector<std::pair<double, double>>& kd,
                              std::vector<Measured>* ms) {
  std::vector<std::string> dirs;
  nlohmann::json record;
  const bool ran = SimulateStage(o, stage, kd, &dirs, &record, error);
  if (!record.is_null()) r->sweeps.push_back(record);
  if (!ran) return false;
  Say("stage " + stage + Fmt(": %g simulations in %.1f s wall", static_cast<double>(kd.size()),
                             record["wall_time"].get<double>()));
  ms->assign(kd.size(), Measured{});
  for (size_t i = 0; i < kd.size(); ++i) {
    const auto [k, d] = kd[i];
    Measured& m = (*ms)[i];
    const std::string log = dirs[i] + "/run/log.csv";
    datalog::Table t;
    if (!t.Load(log, error) || !Measure(t, log, o.channel, r->from, r->to, &m, error, r->noise))
      return false;
    r->runs.push_back({{"k", k}, {"d", d}, {"frequency", m.osc.frequency},
                       {"log_decrement", m.osc.log_decrement}, {"stage", stage}, {"dir", dirs[i]}});
    Say(Fmt("simulated K %.4g N/m, D %.4g s/m: f %.4f Hz, log decrement %.4f", k, d,
            m.osc.frequency, m.osc.log_decrement));
  }
  return true;
}

// the recording aligned on a simulation (the lag of its channel behind the simulation's) and
// its oscillation measured over the simulations' window shifted by that lag
bool Identification::Align(const Measured& sim, const std::string& on) {
  const auto& rt = *this->rt;
  if (!compare::CrossCorrelationLag(sim.t, sim.x, rt, rx, 0.0, 2.0, &r->lag, &err)) {
    *error = "aligning the recording on the simulation (" + o.channel + "): " + err;
    return false;
  }
  Measured recorded;
  if (!Measure(rec, o.recording, o.channel, r->from + r->lag, r->to + r->lag, &recorded, error) ||
      !CheckSwing(recorded.osc.amplitude, sim.osc.amplitude, r->from + r->lag, r->to + r->lag,
                  o.recording, error))
    return false;
  r->f = recorded.osc.frequency;
  r->f_se = recorded.osc.frequency_se;
  r->delta = recorded.osc.log_decrement;
  r->delta_se = recorded.osc.log_decrement_se;
  Say("recording aligned on the " + on + Fmt(": lag %.4f s; f %.4f +- %.4f Hz", r->lag, r->f, r->f_se) +
      Fmt(", log decrement %.4f +- %.4f (%g extrema)", r->delta, r->delta_se, recorded.osc.extrema));
  return true;
}

//---- (a) the closed form in the recorded posture (mean joint positions over the window)
bool Identification::ClosedForm(Estimate* e, RockingGeometry* geo) {
  const auto& rt = *this->rt;
  std::vector<std::pair<std::string, double>> q;
  for (const auto& name : rec.names()) {
    if (name.rfind("q_", 0) != 0) continue;
    const auto& v = rec.col(rec.Column(name));
    double s = 0;
    int cnt = 0;
    for (size_t i = 0; i < rt.size(); ++i)
      if (rt[i] >= r->from + r->lag && rt[i] <= r->to + r->lag) {
        s += v[i];
        ++cnt;
      }
    if (cnt > 0) q.emplace_back(name.substr(2), s / cnt);
  }
  if (!GeometryAt(model->m(), q, p, geo, error)) return false;
  if (!InvertRocking(*geo, p, 2 * M_PI * r->f, ZetaOf(r->delta), &e->k, &e->d, error)) return false;
  // standard errors: the measurement's, through the inversion (one-sided differences)
  double k1 = 0, d1 = 0, k2 = 0, d2 = 0;
  std::string ignore;
  InvertRocking(*geo, p, 2 * M_PI * (r->f + r->f_se), ZetaOf(r->delta), &k1, &d1, &ignore);
  InvertRocking(*geo, p, 2 * M_PI * r->f, ZetaOf(r->delta + r->delta_se), &k2, &d2, &ignore);
  e->k_se = std::hypot(k1 - e->k, k2 - e->k);
  e->d_se = std::hypot(d1 - e->d, d2 - e->d);
  return true;
}

//---- (b) simulations around it: f against K at D_a, then the log decrement against D
int Identification::RefineK(RockingGeometry* geo, Refinement* f) {
  std::vector<std::pair<double, double>> kd;
  for (double s : {1 - o.step, 1.0, 1 + o.step}) kd.emplace_back(r->first.k * s, r->first.d);
  std::vector<Measured> k_runs;
  if (!Simulate("k", kd, &k_runs)) return kFailed;
  if (!Align(k_runs[1], "K stage's middle run")) return kUsage;
  if (!ClosedForm(&r->closed_form, geo)) return kUsage;
  const double ka = r->closed_form.k, da = r->closed_form.d;
  Say(Fmt("(a) closed form (mass %.2f kg, Iyy %.2f kg m^2, CoM %.3f m above the soles): ", geo->mass,
          geo->Iyy, geo->com_height) +
      Fmt("K %.4g +- %.2g N/m, D %.4g +- %.2g s/m", ka, r->closed_form.k_se, da, r->closed_form.d_se));
  // the squared frequency against K: the rocking mode's omega^2 is affine in the soles'
  // stiffness (the rotational spring K w l^2 less gravity's m g h, over the inertia), so a line
  // through three runs is exact up to the damping's small share; f itself is concave in K, and
  // a line of f put K_b 0.2-0.9 % high (issue 35)
  std::vector<double> ks, f2s;
  for (size_t i = 0; i < kd.size(); ++i) {
    ks.push_back(kd[i].first);
    f2s.push_back(k_runs[i].osc.frequency * k_runs[i].osc.frequency);
  }
  double f2a = 0;
  f->df2dk = Line(ks, f2s, &f2a);
  if (!(f->df2dk > 0)) {
    *error = "the simulated frequency does not grow with K around the estimate: cannot refine";
    return kFailed;
  }
  f->kb = (r->f * r->f - f2a) / f->df2dk;
  return kOk;
}

int Identification::RefineD(Refinement* f) {
  const double da = r->closed_form.d;
  std::vector<std::pair<double, double>> kd;
  for (double s : {1 - 2 * o.step, 1.0, 1 + 2 * o.step}) kd.emplace_back(f->kb, da * s);
  std::vector<Measured> d_runs;
  if (!Simulate("d", kd, &d_runs)) return kFailed;
  // the damping ratio against D: zeta is proportional to the damping of the linearised soles
  // (b = D k w delta), which the log decrement is not (delta = 2 pi zeta / sqrt(1 - zeta^2))
  std::vector<double> ds, zetas;
  for (size_t i = 0; i < kd.size(); ++i) {
    ds.push_back(kd[i].second);
    zetas.push_back(ZetaOf(d_runs[i].osc.log_decrement));
  }
  double zeta_a = 0;
  f->dzdd = Line(ds, zetas, &zeta_a);
  if (!(f->dzdd > 0)) {
    *error = "the simulated decay does not grow with D around the estimate: cannot refine";
    return kFailed;
  }
  f->db = (ZetaOf(r->delta) - zeta_a) / f->dzdd;
  // standard errors through the lines: d(f^2) = 2 f df, d zeta / d delta = 4 pi^2 / (4 pi^2 + delta^2)^1.5
  f->dzeta_ddelta = 4 * M_PI * M_PI / std::pow(4 * M_PI * M_PI + r->delta * r->delta, 1.5);
  r->refined = {f->kb, 2 * r->f * r->f_se / f->df2dk, f->db, f->dzeta_ddelta * r->delta_se / f->dzdd};
  return kOk;
}

//---- (c) the run at the refined K, D against the recording
int Identification::CompareFinalRun(const Measured& nominal, const Refinement& f) {
  std::vector<Measured> final_run;
  if (!Simulate("final", {{f.kb, f.db}}, &final_run)) return kFailed;
  const Measured& fin = final_run[0];
  r->final_f = fin.osc.frequency;
  r->final_delta = fin.osc.log_decrement;
  r->final_rms = RmsAgainstRecording(fin);
  r->nominal_rms = RmsAgainstRecording(nominal);
  // (d) the uncertainty one recording leaves: the final run's channel (which matches the
  // recording) under 40 draws of the recording's noise, measured as the recording is; its spread
  // of f and delta through the same lines, beside the measurement's standard errors (the larger
  // is stated)
  const Spread spread = NoiseSpread(fin.t, fin.x, r->from, r->to, r->noise);
  if (spread.measured >= 2) {
    const double f_sd = std::max(r->f_se, spread.f_sd), delta_sd = std::max(r->delta_se, spread.delta_sd);
    r->refined.k_se = 2 * r->f * f_sd / f.df2dk;
    r->refined.d_se = f.dzeta_ddelta * delta_sd / f.dzdd;
    r->spread_f = spread.f_sd;
    r->spread_delta = spread.delta_sd;
    Say(Fmt("(d) the recording's noise alone moves f by %.4f Hz and delta by %.4f (1 sigma, %g draws)",
            spread.f_sd, spread.delta_sd, spread.measured));
  }
  Say(Fmt("(b) refined: K %.4g +- %.2g N/m, D %.4g +- %.2g s/m", f.kb, r->refined.k_se, f.db, r->refined.d_se));
  Say(Fmt("(c) at the refined K, D: f %.4f Hz (recording %.4f), log decrement %.4f (%.4f)", r->final_f,
          r->f, r->final_delta, r->delta) +
      Fmt("; RMS of recording - simulation over the window %.4g (at sim_host's default soles %.4g)",
          r->final_rms, r->nominal_rms));
  return kOk;
}

// the recording against a simulation over the window, aligned by the lag found
double Identification::RmsAgainstRecording(const Measured& m) const {
  double s2 = 0;
  int cnt = 0;
  size_t cursor = 0;
  for (size_t i = 0; i < m.t.size(); ++i) {
    if (m.t[i] < r->from || m.t[i] > r->to) continue;
    const double dlt = compare::Interpolate(*rt, rx, m.t[i] + r->lag, &cursor) - m.x[i];
    s2 += dlt * dlt;
    ++cnt;
  }
  return cnt ? std::sqrt(s2 / cnt) : NAN;
}

}  // namespace ohrp::identify
