// --joints --model --draws-for SCENARIO: the identified joint parameters as a sweep of random
// draws within their uncertainty (DIR/joints_draws.yaml, ohrp sweep FILE; identify/joints.h).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "cli/data_dir.h"
#include "identify/joints.h"
#include "sweep/sweep.h"

namespace ohrp::identify {
namespace {

// one drawn parameter: its key in the scenario, the identified value and its standard error
struct Drawn {
  std::string key;
  double mean, std;
};

// the parameters that can be drawn: a value kept in the joint file (not left out as negative)
// with a positive, finite standard error; the others named in `skipped`
std::vector<Drawn> DrawnParameters(const std::vector<model::JointParams>& params,
                                   const std::vector<JointEstimate>& estimates,
                                   std::vector<std::string>* skipped) {
  std::vector<Drawn> out;
  for (size_t i = 0; i < params.size() && i < estimates.size(); ++i) {
    const model::JointParams& p = params[i];
    const JointEstimate& e = estimates[i];
    const struct {
      const char* key;
      double value, se;
    } each[] = {{"armature", p.armature, e.inertia_se},
                {"damping", p.damping, e.viscous_se},
                {"frictionloss", p.frictionloss, e.coulomb_se}};
    for (const auto& k : each) {
      const std::string key = "joint_params." + p.joint + "." + k.key;
      if (std::isfinite(k.value) && std::isfinite(k.se) && k.se > 0)
        out.push_back({key, k.value, k.se});
      else
        skipped->push_back(key);
    }
  }
  return out;
}

std::string SweepText(const std::vector<Drawn>& drawn, const std::vector<std::string>& skipped,
                      const std::string& log, const std::string& scenario, int n) {
  std::ostringstream s;
  s << "# The joints as identified by ohrp identify --joints from " << log << ", each parameter\n"
    << "# drawn from a normal distribution about its estimate with its standard error (clipped to\n"
    << "# 3 standard errors and to non-negative values, each its own seed), the draws zipped into\n"
    << "# one axis of " << n << " variants: how " << scenario << "'s checks depend on what identification\n"
    << "# leaves uncertain. Run: ohrp sweep THIS\n";
  if (!skipped.empty()) {
    s << "# Not drawn (no value, or no positive standard error): ";
    for (size_t i = 0; i < skipped.size(); ++i) s << (i ? ", " : "") << skipped[i];
    s << "\n";
  }
  s << "name: " << scenario << "_joint_draws\nscenario: " << scenario << "\nparameters:\n  - zip:\n";
  int seed = 1;
  for (const Drawn& d : drawn) {
    const double lo = std::fmax(0.0, d.mean - 3 * d.std), hi = d.mean + 3 * d.std;
    s << "      - {key: " << d.key << ", draw: {distribution: normal, mean: " << sweep::NumberText(d.mean)
      << ", std: " << sweep::NumberText(d.std) << ", clip: [" << sweep::NumberText(lo) << ", "
      << sweep::NumberText(hi) << "], n: " << n << ", seed: " << seed++ << "}}\n";
  }
  return s.str();
}

}  // namespace

int WriteDrawSweep(const std::string& log, const std::vector<model::JointParams>& params,
                   const std::vector<JointEstimate>& estimates, const JointModel& model,
                   const std::string& path) {
  std::vector<std::string> skipped;
  const std::vector<Drawn> drawn = DrawnParameters(params, estimates, &skipped);
  if (drawn.empty()) {
    std::fprintf(stderr, "ohrp_identify: --draws-for: no parameter has a value and a positive "
                 "standard error to draw about\n");
    return 2;
  }
  const std::string text = SweepText(drawn, skipped, log, model.draws_for, model.draws);
  // the file as ohrp sweep will read it: a scenario that does not exist, or a key the scenario's
  // parser refuses, is said now
  sweep::SweepSpec spec;
  std::string error;
  if (!sweep::ParseSweep(text, path, cli::DataDir(), &spec, &error)) {
    std::fprintf(stderr, "ohrp_identify: --draws-for %s: %s\n", model.draws_for.c_str(), error.c_str());
    return 2;
  }
  std::ofstream f(path);
  f << text;
  if (!f.flush()) {
    std::fprintf(stderr, "ohrp_identify: cannot write %s\n", path.c_str());
    return 2;
  }
  std::printf("%zu joint parameters drawn %d times about their estimates: %s (ohrp sweep)\n",
              drawn.size(), model.draws, path.c_str());
  return 0;
}

}  // namespace ohrp::identify
