// --joints --model --draws-for (identify/joints.h WriteDrawSweep): the identified joint
// parameters written as a sweep of normal draws about each estimate with its standard error;
// the file read back as ohrp sweep reads it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "common/scratch.h"
#include "identify/joints.h"
#include "sweep/sweep.h"

namespace ohrp::identify {
namespace {

TEST(JointDraws, EachParameterDrawnWithinItsStandardErrorAsASweep) {
  std::vector<model::JointParams> params(2);
  std::vector<JointEstimate> estimates(2);
  params[0].joint = "RLEG_KNEE", params[0].armature = 2.5, params[0].damping = 4.0, params[0].frictionloss = 1.5;
  estimates[0].inertia_se = 0.1, estimates[0].viscous_se = 0.2, estimates[0].coulomb_se = 0.6;
  // the left knee's friction was negative (left out: NaN) and its damping has no error
  params[1].joint = "LLEG_KNEE", params[1].armature = 2.4, params[1].damping = 3.0;
  estimates[1].inertia_se = 0.05, estimates[1].viscous_se = 0.0, estimates[1].coulomb_se = 0.3;
  JointModel model;
  model.draws_for = "walk_push";
  model.draws = 400;
  const std::string path = ohrp::testing::ScratchPath("joints_draws", ".yaml");
  ASSERT_EQ(WriteDrawSweep("excite.csv", params, estimates, model, path), 0);
  sweep::SweepSpec spec;
  std::string error;
  ASSERT_TRUE(sweep::LoadSweep(path, OHRP_SOURCE_DIR, &spec, &error)) << error;
  ASSERT_EQ(spec.parameters.size(), 4u);  // 3 + the left armature, zipped into one axis
  EXPECT_EQ(spec.variants.size(), 400u);
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  EXPECT_NE(text.str().find("# Not drawn (no value, or no positive standard error): "
                            "joint_params.LLEG_KNEE.damping, joint_params.LLEG_KNEE.frictionloss"),
            std::string::npos) << text.str();
  // each parameter's draws: mean within 4 standard errors of the estimate, spread about its
  // standard error (clipped at 3: the truncated normal's std is 0.9866 of it), within the clip
  const struct {
    const char* key;
    double mean, se;
  } expected[] = {{"joint_params.RLEG_KNEE.armature", 2.5, 0.1},
                  {"joint_params.RLEG_KNEE.damping", 4.0, 0.2},
                  {"joint_params.RLEG_KNEE.frictionloss", 1.5, 0.6},
                  {"joint_params.LLEG_KNEE.armature", 2.4, 0.05}};
  for (size_t p = 0; p < 4; ++p) {
    const sweep::Parameter& par = spec.parameters[p];
    EXPECT_EQ(par.key, expected[p].key);
    double sum = 0, sq = 0, lo = 1e9, hi = -1e9;
    for (const sweep::Value& v : par.values) {
      sum += v.number;
      sq += v.number * v.number;
      lo = std::fmin(lo, v.number), hi = std::fmax(hi, v.number);
    }
    const double n = par.values.size(), mean = sum / n, std = std::sqrt(sq / n - mean * mean);
    const double se = expected[p].se;
    EXPECT_NEAR(mean, expected[p].mean, 4 * se / std::sqrt(n)) << par.key;
    EXPECT_NEAR(std, 0.9866 * se, 4 * se / std::sqrt(2 * n)) << par.key;
    EXPECT_GE(lo, std::fmax(0.0, expected[p].mean - 3 * se) - 1e-9) << par.key;
    EXPECT_LE(hi, expected[p].mean + 3 * se + 1e-9) << par.key;
  }
}

TEST(JointDraws, NothingToDrawOrAnUnknownScenarioExitsTwo) {
  std::vector<model::JointParams> params(1);
  std::vector<JointEstimate> estimates(1);
  params[0].joint = "RLEG_KNEE";  // every value left out
  JointModel model;
  model.draws_for = "walk_push";
  EXPECT_EQ(WriteDrawSweep("excite.csv", params, estimates, model, ohrp::testing::ScratchPath("d", ".yaml")), 2);
  params[0].armature = 1, estimates[0].inertia_se = 0.1;
  model.draws_for = "no_such_scenario";
  const std::string path = ohrp::testing::ScratchPath("d", ".yaml");
  EXPECT_EQ(WriteDrawSweep("excite.csv", params, estimates, model, path), 2);
  EXPECT_FALSE(std::ifstream(path).good());  // nothing written
}

}  // namespace
}  // namespace ohrp::identify
