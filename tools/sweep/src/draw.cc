// A parameter's values drawn at random (domain randomisation as a sweep, issue 35):
//   draw: {distribution: uniform, from: A, to: B, n: N, seed: S}
//   draw: {distribution: normal, mean: M, std: S, clip: [LO, HI], n: N, seed: S}
// uniform on [A, B); normal truncated to [LO, HI] by redrawing (not clamped: no pile-up at the
// ends; default clip mean +- 3 std), each rounded to 6 significant digits. The draws become the parameter's values (in the order drawn,
// recorded in sweep.json with the distribution and seed), so the rest of the sweep (grid, zip,
// folders, report, plots) is as for listed values. Same seed, same draws (std::mt19937_64).
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "draw.h"
#include "spec_parameters.h"  // At
#include "yaml_read.h"

namespace ohrp::sweep {
namespace {

const std::set<std::string> kDrawKeys = {"distribution", "from", "to", "mean", "std", "clip", "n", "seed"};
constexpr long long kMaxDraws = 10000;

bool Number(const YAML::Node& d, const char* key, const std::string& path, const std::string& where,
            double* out, std::string* error) {
  std::string why;
  if (!d[key]) return *error = At(path, d) + where + "'" + key + "' is required", false;
  if (!runner::ReadNumber(d[key], out, &why))
    return *error = At(path, d[key]) + where + key + ": " + why, false;
  return true;
}

}  // namespace

bool ReadDraw(const YAML::Node& d, const std::string& path, const std::string& where,
              Parameter* p, std::string* error) {
  const std::string w = where + p->key + ": draw: ";
  if (!d.IsMap())
    return *error = At(path, d) + w + "must be a mapping, e.g. {distribution: "
                    "normal, mean: 1.5, std: 0.2, clip: [1, 2], n: 8, seed: 1}", false;
  if (!runner::KnownKeysOnly(d, kDrawKeys, path, w, error, "sweep")) return false;
  std::string kind, why;
  if (!d["distribution"] || !runner::ReadChoice(d["distribution"], {"uniform", "normal"}, &kind, &why))
    return *error = At(path, d) + w + "distribution: uniform or normal " + why, false;
  long long n = 0, seed = 0;
  if (!d["n"] || !runner::ReadInteger(d["n"], &n, &why) || n < 1 || n > kMaxDraws)
    return *error = At(path, d) + w + "n: the number of draws, a whole number in [1, " +
                    std::to_string(kMaxDraws) + "]", false;
  if (!d["seed"] || !runner::ReadInteger(d["seed"], &seed, &why) || seed < 0)
    return *error = At(path, d) + w + "seed: a non-negative whole number is required "
                    "(the draws are recorded with it)", false;
  double a = 0, b = 0, lo = 0, hi = 0;
  char text[200];
  if (kind == "uniform") {
    if (!Number(d, "from", path, w, &a, error) || !Number(d, "to", path, w, &b, error)) return false;
    if (!(a < b)) return *error = At(path, d) + w + "from must be below to", false;
    if (d["mean"] || d["std"] || d["clip"])
      return *error = At(path, d) + w + "uniform takes from and to (mean, std, clip are normal's)", false;
    std::snprintf(text, sizeof(text), "uniform [%g, %g), %lld draws, seed %lld", a, b, n, seed);
  } else {
    if (!Number(d, "mean", path, w, &a, error) || !Number(d, "std", path, w, &b, error)) return false;
    if (!(b > 0)) return *error = At(path, d["std"]) + w + "std must be above 0", false;
    if (d["from"] || d["to"])
      return *error = At(path, d) + w + "normal takes mean, std and clip (from, to are uniform's)", false;
    lo = a - 3 * b, hi = a + 3 * b;
    if (d["clip"]) {
      const YAML::Node c = d["clip"];
      if (!c.IsSequence() || c.size() != 2 || !runner::ReadNumber(c[0], &lo, &why) ||
          !runner::ReadNumber(c[1], &hi, &why) || !(lo < hi) || !(hi > a - 3 * b && lo < a + 3 * b))
        return *error = At(path, c) + w + "clip: [LO, HI] with LO < HI overlapping "
                        "mean +- 3 std", false;
    }
    std::snprintf(text, sizeof(text), "normal mean %g std %g clipped to [%g, %g] (redrawn), %lld draws, "
                  "seed %lld", a, b, lo, hi, n, seed);
  }
  std::mt19937_64 rng(static_cast<uint64_t>(seed));
  std::uniform_real_distribution<double> uniform(a, b);
  std::normal_distribution<double> normal(a, b);
  p->values.clear();
  for (long long i = 0; i < n; ++i) {
    double x = 0;
    if (kind == "uniform") {
      x = uniform(rng);
    } else {
      long tries = 0;
      do x = normal(rng);
      while ((x < lo || x > hi) && ++tries < 1000000);
      if (x < lo || x > hi)
        return *error = At(path, d) + w + "clip: no draw within it in a million "
                        "tries (widen it)", false;
    }
    char six[32];  // 6 significant digits: readable in the table, far below any spread drawn
    std::snprintf(six, sizeof(six), "%.6g", x);
    Value v;
    v.numeric = true;
    v.number = std::strtod(six, nullptr);  // the value the scenario gets
    v.text = NumberText(v.number);
    p->values.push_back(v);
  }
  p->draw = text;
  return true;
}

}  // namespace ohrp::sweep
