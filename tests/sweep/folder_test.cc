// Sweep folders read back (tools/sweep/src/gather.cc, folder.cc; issue 28 item 4): a variant whose
// summary holds a non-finite value (nlohmann writes inf and NaN as null) or whose robot fell or
// whose process crashed is gathered as such, never aborts the sweep; a folder is read back
// without its sweep file (--gather, --resume) with its unfinished variants; Slurm arrays are
// chunked below the site's MaxArraySize.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/scratch.h"
#include "sweep/sweep.h"

namespace ohrp::sweep {
namespace {

const std::string kSource = OHRP_SOURCE_DIR;
const std::string kPath = kSource + "/tests/sweep/in_memory.yaml";

SweepSpec ThreeVariants() {
  SweepSpec s;
  std::string error;
  EXPECT_TRUE(ParseSweep("scenario: stand_short.yaml\n"
                         "parameters:\n"
                         "  - {key: contact_params.damping, values: [20, 30, 40, 50, 60]}\n"
                         "plots:\n"
                         "  - {check: base_height, against: contact_params.damping}\n",
                         kPath, kSource, &s, &error))
      << error;
  return s;
}

void Write(const std::string& path, const nlohmann::json& j) { std::ofstream(path) << j.dump(2); }

nlohmann::json Status(int exit_code) {
  return {{"exit_code", exit_code}, {"wall_time", 1.5}, {"time_limit", 60}, {"killed_at_time_limit", false},
          {"cancelled", false}, {"host", "h"}};
}

// a summary.json as ohrp_run writes it; `settles` the value of a settles check (null: non-finite)
nlohmann::json Summary(const std::string& verdict, const nlohmann::json& settles, bool fell,
                       int controller_exit = 0) {
  return {{"verdict", verdict},
          {"real_time_factor", 3.0},
          {"sim_time", 1.5},
          {"checks",
           {{{"name", "settles"}, {"passed", settles.is_number()}, {"value", settles}, {"detail", "d"}},
            {{"name", "not_fallen"}, {"passed", !fell}, {"value", 0.2}, {"detail", "tilted 90 deg"}}}},
          {"processes", {{{"name", "sim_host"}, {"exit_code", 0}}, {{"name", "posture"}, {"exit_code", controller_exit}}}}};
}

TEST(SweepGather, NonFiniteFallenAndCrashedVariantsAreReportedNotFatal) {
  const SweepSpec spec = ThreeVariants();
  const std::string out = ohrp::testing::ScratchFolder("gather");
  std::string error;
  ASSERT_TRUE(Prepare(spec, out, &error)) << error;
  // v000 passes; v001 fell: settles is inf, written as null (the abort, exit 134)
  Write(VariantDir(out, 0) + "/status.json", Status(0));
  Write(VariantDir(out, 1) + "/status.json", Status(1));
  Write(VariantDir(out, 2) + "/status.json", Status(1));
  Write(VariantDir(out, 3) + "/status.json", Status(1));
  for (int v : {0, 1, 2, 3}) std::filesystem::create_directories(VariantDir(out, v) + "/run");
  Write(VariantDir(out, 0) + "/run/summary.json", Summary("pass", 0.4, false));
  Write(VariantDir(out, 1) + "/run/summary.json", Summary("fail", nullptr, true));
  // v002: the controller died of SIGSEGV; its settles value as the string "inf"
  Write(VariantDir(out, 2) + "/run/summary.json", Summary("fail", "inf", false, 139));
  // v003: sim_host's own fall verdict (its summary) with everything else numbers of the wrong type
  Write(VariantDir(out, 3) + "/run/summary.json",
        nlohmann::json{{"verdict", 7}, {"real_time_factor", "fast"}, {"checks", "none"}});
  Write(VariantDir(out, 3) + "/run/sim_summary.json",
        nlohmann::json{{"outcome", "fell"}, {"detail", "base tilt 95 deg at t=0.81 s"}});
  // v004: no status at all (not run)

  std::vector<VariantResult> r;
  ASSERT_NO_THROW(r = Gather(spec, out));
  ASSERT_EQ(r.size(), 5u);
  EXPECT_EQ(r[0].status, "pass");
  EXPECT_EQ(r[1].status, "fell");
  EXPECT_NE(r[1].detail.find("not_fallen: tilted 90 deg"), std::string::npos) << r[1].detail;
  EXPECT_NE(r[1].detail.find("not finite: settles = nan"), std::string::npos) << r[1].detail;
  ASSERT_EQ(r[1].checks.size(), 2u);
  EXPECT_TRUE(std::isnan(r[1].checks[0].value));
  EXPECT_EQ(r[2].status, "crashed");
  EXPECT_NE(r[2].detail.find("posture ended by signal 11"), std::string::npos) << r[2].detail;
  EXPECT_TRUE(std::isinf(r[2].checks[0].value));
  EXPECT_EQ(r[3].status, "fell");
  EXPECT_NE(r[3].detail.find("base tilt 95 deg"), std::string::npos) << r[3].detail;
  EXPECT_EQ(r[4].status, "not run");

  // the report: every variant in sweep.csv, the values as such
  std::string markdown;
  RunContext ctx{kSource, "", false};
  SweepSpec no_plots = spec;
  no_plots.plots.clear();
  ASSERT_TRUE(WriteReport(no_plots, r, out, ctx, &markdown, &error)) << error;
  const std::string csv = ohrp::testing::ReadFile(out + "/sweep.csv");
  EXPECT_NE(csv.find(",fell,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",crashed,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",nan,false,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",inf,false,"), std::string::npos) << csv;
}

TEST(SweepFolder, AFolderIsReadBackWithoutItsSweepFileWithItsUnfinishedVariants) {
  const SweepSpec spec = ThreeVariants();
  const std::string out = ohrp::testing::ScratchFolder("folder");
  std::string error;
  ASSERT_TRUE(Prepare(spec, out, &error)) << error;
  SweepSpec back;
  ASSERT_TRUE(LoadSweepFolder(out, &back, &error)) << error;
  EXPECT_EQ(back.name, spec.name);
  EXPECT_EQ(back.scenario_file, spec.scenario_file);
  EXPECT_EQ(back.time_limit, spec.time_limit);
  ASSERT_EQ(back.parameters.size(), 1u);
  EXPECT_EQ(back.parameters[0].key, "contact_params.damping");
  ASSERT_EQ(back.variants.size(), 5u);
  for (int v = 0; v < 5; ++v) EXPECT_EQ(back.variants[v].value_index, spec.variants[v].value_index);
  ASSERT_EQ(back.plots.size(), 1u);
  EXPECT_EQ(back.plots[0].against, "contact_params.damping");

  // finished: passed, failed, timed out; unfinished: cancelled, no status, half a status
  Write(VariantDir(out, 0) + "/status.json", Status(0));
  Write(VariantDir(out, 1) + "/status.json", Status(1));
  nlohmann::json cancelled = Status(130);
  cancelled["cancelled"] = true;
  Write(VariantDir(out, 2) + "/status.json", cancelled);
  std::ofstream(VariantDir(out, 4) + "/status.json") << "{\"exit_co";
  EXPECT_EQ(UnfinishedVariants(back, out), (std::vector<int>{2, 3, 4}));

  EXPECT_FALSE(LoadSweepFolder(ohrp::testing::ScratchFolder("empty"), &back, &error));
  EXPECT_NE(error.find("sweep.json"), std::string::npos) << error;
}

TEST(SweepSlurm, ArraysAreChunkedBelowMaxArraySize) {
  // 2500 variants, MaxArraySize 1001 (Slurm's default): indices 0..1000 per job
  std::vector<int> all;
  for (int i = 0; i < 2500; ++i) all.push_back(i);
  auto c = ChunkArray(all, 1001);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].offset, 0);
  EXPECT_EQ(c[0].indices, "0-1000");
  EXPECT_EQ(c[0].count, 1001);
  EXPECT_EQ(c[1].offset, 1001);
  EXPECT_EQ(c[1].indices, "0-1000");
  EXPECT_EQ(c[2].offset, 2002);
  EXPECT_EQ(c[2].indices, "0-497");
  EXPECT_EQ(c[0].count + c[1].count + c[2].count, 2500);
  // a resumed subset, unordered: ranges and single indices, every index below the limit
  c = ChunkArray({12, 3, 4, 5, 9, 10, 11, 1}, 5);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].offset, 0);
  EXPECT_EQ(c[0].indices, "1,3-4");
  EXPECT_EQ(c[1].offset, 5);
  EXPECT_EQ(c[1].indices, "0,4");
  EXPECT_EQ(c[2].offset, 10);
  EXPECT_EQ(c[2].indices, "0-2");
  EXPECT_TRUE(ChunkArray({}, 10).empty());
  // small sweeps: one job as before
  c = ChunkArray({0, 1, 2, 3, 4, 5, 6, 7, 8}, 1001);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].indices, "0-8");

  EXPECT_EQ(ParseMaxArraySize("Configuration data as of 2026-01-01\nMaxArraySize            = 1001\n"
                              "MaxJobCount             = 10000\n"),
            1001);
  EXPECT_EQ(ParseMaxArraySize("MaxArraySize = 40001"), 40001);
  EXPECT_EQ(ParseMaxArraySize("MaxJobCount = 10000\n"), 0);
}

}  // namespace
}  // namespace ohrp::sweep
