// bench_accuracy --quick end to end: it exits 0, writes a CSV with every scene and the stated
// columns whose numbers are sane (positive real-time factors, finite errors where not diverged,
// the pendulum's error shrinking with the step), a PNG per scene, the closed forms, and ends with
// the ratio line. Also: bad input is refused with a non-zero exit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
const std::string kBench = std::string(OHRP_BIN_DIR) + "/bench_accuracy";

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

std::string Shell(const std::string& cmd, int* status) {
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (p && fgets(buf, sizeof buf, p)) out += buf;
  *status = p ? pclose(p) : -1;
  return out;
}

TEST(BenchAccuracy, QuickRunWritesASaneReport) {
  const fs::path out = fs::path(OHRP_BIN_DIR) / ".." / "test-runs" / "accuracy_quick";
  fs::remove_all(out);
  fs::create_directories(out);
  const fs::path docs = out / "accuracy.md";
  int status = 0;
  const std::string text = Shell("OHRP_PYTHON='" + std::string(OHRP_PYTHON) + "' '" + kBench +
                                   "' --quick --out '" + out.string() + "' --write-docs --docs '" +
                                   docs.string() + "' 2>'" + (out.string() + ".log") + "'",
                               &status);
  ASSERT_EQ(status, 0) << text << "\n(stderr in " << out.string() << ".log)";
  // the last line is the ratio
  std::string last;
  std::stringstream ts(text);
  for (std::string l; std::getline(ts, l);)
    if (!l.empty()) last = l;
  ASSERT_EQ(last.rfind("ratio: ", 0), 0u) << last;
  const double ratio = std::stod(last.substr(7));
  EXPECT_GT(ratio, 1.0) << "the recommended setting should be faster than the reference";

  std::ifstream f(out / "accuracy.csv");
  ASSERT_TRUE(f) << "no accuracy.csv";
  std::string header;
  std::getline(f, header);
  const auto cols = Split(header);
  std::map<std::string, int> col;
  for (size_t i = 0; i < cols.size(); ++i) col[cols[i]] = static_cast<int>(i);
  for (const char* c : {"scene", "integrator", "dt", "contact", "iterations", "tolerance",
                        "geometry", "rtf", "pos_error_m", "force_error_N", "closed_form_error",
                        "diverged"})
    ASSERT_TRUE(col.count(c)) << "missing column " << c << " in " << header;
  std::set<std::string> scenes, contacts, integrators, sweeps;
  std::map<std::string, double> pendulum_euler;  // dt -> error
  int rows = 0, ok = 0;
  for (std::string line; std::getline(f, line);) {
    const auto c = Split(line);
    ASSERT_EQ(c.size(), cols.size()) << line;
    ++rows;
    scenes.insert(c[col["scene"]]);
    contacts.insert(c[col["contact"]]);
    integrators.insert(c[col["integrator"]]);
    sweeps.insert(c[col["sweep"]]);
    const std::string div = c[col["diverged"]];
    ASSERT_TRUE(div == "no" || div == "yes" || div == "refused") << line;
    if (div != "no") continue;
    ++ok;
    const double rtf = std::stod(c[col["rtf"]]);
    const double pos = std::stod(c[col["pos_error_m"]]);
    const double force = std::stod(c[col["force_error_N"]]);
    EXPECT_GT(rtf, 0) << line;
    EXPECT_TRUE(std::isfinite(pos) && pos >= 0 && pos < 10) << line;
    EXPECT_TRUE(std::isfinite(force) && force >= 0) << line;
    if (c[col["scene"]] == "pendulum" && c[col["integrator"]] == "euler")
      pendulum_euler[c[col["dt"]]] = pos;
  }
  EXPECT_GE(rows, 60);
  EXPECT_GE(ok, rows / 2);
  EXPECT_EQ(scenes, (std::set<std::string>{"pendulum", "box", "ball", "hrp1s_stand", "hrp1s_walk",
                                           "humanoid"}));
  EXPECT_EQ(contacts, (std::set<std::string>{"none", "soft", "native", "rigid"}));
  EXPECT_EQ(integrators, (std::set<std::string>{"euler", "rk4", "implicit"}));
  EXPECT_EQ(sweeps, (std::set<std::string>{"dt", "solver", "geometry"}));
  ASSERT_TRUE(pendulum_euler.count("0.00025") && pendulum_euler.count("0.004")) << "pendulum rows";
  EXPECT_LT(pendulum_euler["0.00025"], pendulum_euler["0.004"] / 4);

  // closed forms
  std::ifstream cf(out / "closed_forms.csv");
  ASSERT_TRUE(cf);
  int closed = 0;
  for (std::string l; std::getline(cf, l);) ++closed;
  EXPECT_GE(closed, 10);

  // one chart per scene, a real PNG
  for (const std::string& s : scenes) {
    const fs::path png = out / (s + ".png");
    ASSERT_TRUE(fs::exists(png)) << png;
    EXPECT_GT(fs::file_size(png), 10000u) << png;
    std::ifstream p(png, std::ios::binary);
    char sig[8] = {};
    p.read(sig, 8);
    EXPECT_EQ(std::string(sig + 1, 3), "PNG") << png;
  }
  // the report: machine, link to the stability report, recommendations
  std::ifstream d(docs);
  ASSERT_TRUE(d);
  std::stringstream ds;
  ds << d.rdbuf();
  EXPECT_NE(ds.str().find("(stability.md)"), std::string::npos);
  EXPECT_NE(ds.str().find("1 mm at 20x real time"), std::string::npos);
  EXPECT_NE(ds.str().find(" cores"), std::string::npos);
}

TEST(BenchAccuracy, BadInputIsRefused) {
  int status = 0;
  Shell("'" + kBench + "' --scenes nosuchscene >/dev/null 2>&1", &status);
  EXPECT_NE(status, 0);
  Shell("'" + kBench + "' --restarts 0 >/dev/null 2>&1", &status);
  EXPECT_NE(status, 0);
  const std::string help = Shell("'" + kBench + "' --help", &status);
  EXPECT_EQ(status, 0);
  EXPECT_NE(help.find("--quick"), std::string::npos);
}

}  // namespace
