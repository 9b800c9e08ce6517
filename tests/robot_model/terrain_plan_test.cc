// Tests walking/terrain's goal across the terrain (TerrainMap::PlanGoalAcross) against the
// scenes' closed-form geometry: up the three 0.1 m stairs of scene_stairs.xml (0.3 m treads,
// risers at x = 0.5, 0.8, 1.1 m of the world, the start frame 0.055 m behind the world's origin
// ... measured from the map) and down the two 0.15 m stairs of scene_stairs15_down.xml: every
// sole wholly on one tread with its margin, one stair at a time (a step onto a new level is
// followed by the other foot beside it), the goal reached; a slope is walked with strides, not
// one level at a time; a tread the limits cannot reach is refused naming max_forward; up and
// down scene_stairs15_updown.xml with every toe kShinLean x its height from a riser ahead; a goal across a
// nose moved onto one level; a footstep file's step too near a riser moved back or refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "walking/terrain.h"

namespace ohrp::walking {
namespace {

const std::string kSource = OHRP_SOURCE_DIR;

StepLimits Hrp1sStairLimits() {
  StepLimits lim;
  lim.sole_half_size = Eigen::Vector2d(0.125, 0.07);  // HRP-1S's sole
  lim.width = 0.18;
  lim.min_width = 0.12;
  lim.max_forward = 0.32;  // scenarios/steps/stairs_params.yaml
  return lim;
}

FeetPose Start(const StepLimits& lim) {
  FeetPose f;
  f.p[kLeft] = Eigen::Vector3d(0, 0.5 * lim.width, 0);
  f.p[kRight] = Eigen::Vector3d(0, -0.5 * lim.width, 0);
  f.yaw[kLeft] = f.yaw[kRight] = 0;
  return f;
}

std::unique_ptr<TerrainMap> Load(const std::string& scene) {
  std::string error;
  auto t = TerrainMap::Load(kSource + "/mjcf/hrp1s/" + scene, "halfsit", &error);
  EXPECT_TRUE(t) << error;
  return t;
}

// every step's sole on one tread of height z = k |rise| (rise < 0: stairs down; a step onto a
// new level and the other foot's closing beside it: with the margin around the sole too), after
// a step onto a new level the other foot beside it; returns the levels visited in order
std::vector<int> CheckOneStairAtATime(const TerrainMap& t, const FeetPose& start,
                                      const std::vector<Footstep>& steps, const StepLimits& lim,
                                      double rise) {
  std::vector<int> levels;
  FeetPose feet = start;
  bool closing = false;  // this step closes beside a step onto a new level
  for (size_t k = 0; k < steps.size(); ++k) {
    const Footstep& s = steps[k];
    EXPECT_EQ(CheckStep(feet, s, lim), "") << "step " << k + 1;
    const double level = s.p.z() / std::fabs(rise);
    EXPECT_NEAR(level, std::round(level), 1e-3 / std::fabs(rise)) << "step " << k + 1 << " at z " << s.p.z();
    const bool onto = std::fabs(s.p.z() - feet.p[1 - s.foot].z()) > 0.5 * std::fabs(rise);
    // going up kLevelMargin all round; going down behind the heel only (the toes may come to
    // the next nose: a drop)
    const bool down = rise < 0;
    const double m = onto || closing ? TerrainMap::kLevelMargin : 0.0;
    const double back = m, front = down ? 0.0 : m;
    const Eigen::Vector2d half = lim.sole_half_size + Eigen::Vector2d(0.5 * (back + front), m);
    const Eigen::Vector2d centre = s.p.head<2>() + Eigen::Vector2d(0.5 * (front - back), 0);
    SurfaceSample under;
    std::string why;
    EXPECT_TRUE(t.SurfaceUnder(centre, s.yaw, half, &under, &why)) << why;
    EXPECT_TRUE(under.planar) << "step " << k + 1 << " at x " << s.p.x() << " rests across an edge";
    closing = false;
    if (onto) {
      // onto a new level: the next step is the other foot, beside it, on the same level
      levels.push_back(static_cast<int>(std::round(level)));
      EXPECT_LT(k + 1, steps.size()) << "the walk ends on one foot on a new level";
      if (k + 1 >= steps.size()) break;
      EXPECT_EQ(steps[k + 1].foot, 1 - s.foot);
      EXPECT_NEAR(steps[k + 1].p.z(), s.p.z(), 1e-3);
      EXPECT_NEAR(steps[k + 1].p.x(), s.p.x(), 1e-9);
      closing = true;
    }
    feet = After(feet, s);
  }
  return levels;
}

void Print(const std::vector<Footstep>& steps) {
  for (const Footstep& s : steps)
    std::printf("[ plan     ] %-5s x %.3f y %.3f z %.3f\n", SideName(s.foot), s.p.x(), s.p.y(), s.p.z());
}

// A goal `x` m straight ahead across a scene, planned from the standing start with HRP-1S's
// stair limits (lim_, which a test may change first) and printed.
class TerrainPlan : public ::testing::Test {
 protected:
  // false when the scene does not load or the planner refuses (its reason in error_)
  bool PlanAcross(const std::string& scene, double x) {
    terrain_ = Load(scene);
    if (!terrain_) return false;
    start_ = Start(lim_);
    steps_.clear();
    if (!terrain_->PlanGoalAcross(start_, x, 0, 0, lim_, 0.05, &steps_, &error_)) return false;
    Print(steps_);
    return true;
  }

  StepLimits lim_ = Hrp1sStairLimits();
  std::unique_ptr<TerrainMap> terrain_;
  FeetPose start_;
  std::vector<Footstep> steps_;
  std::string error_;
};

TEST_F(TerrainPlan, UpTheStairsOneStairAtATime) {
  ASSERT_TRUE(PlanAcross("scene_stairs.xml", 1.3)) << error_;
  const std::vector<int> levels = CheckOneStairAtATime(*terrain_, start_, steps_, lim_, 0.1);
  EXPECT_EQ(levels, (std::vector<int>{1, 2, 3}));
  // at the goal, the feet side by side on the top
  FeetPose feet = start_;
  for (const Footstep& s : steps_) feet = After(feet, s);
  const Frame2 end = MidFrame(feet);
  EXPECT_NEAR(end.p.x(), 1.3, 1e-6);
  EXPECT_NEAR(end.p.y(), 0, 1e-6);
  EXPECT_NEAR(end.p.z(), 0.3, 1e-3);
}

TEST_F(TerrainPlan, DownTheStairsOneStairAtATime) {
  ASSERT_TRUE(PlanAcross("scene_stairs15_down.xml", 1.2)) << error_;
  const std::vector<int> levels = CheckOneStairAtATime(*terrain_, start_, steps_, lim_, -0.15);
  EXPECT_EQ(levels, (std::vector<int>{-1, -2}));
}

// scene_stairs15_updown.xml: risers at x = 0.5 and 0.8 m of the world (up to 0.15 and 0.3 m),
// noses at 1.7 and 2.0 m (down to 0.15 m and the floor); in the start frame less origin().x()
constexpr double kUpDownRisers[] = {0.5, 0.8}, kUpDownNoses[] = {1.7, 2.0};

// up two stairs, across the landing and down two: one stair at a time, each level z = 0.15 k,
// every sole's toes kShinLean x 0.15 m or more from the riser ahead (the closed form from the scene)
TEST_F(TerrainPlan, UpAndDownTheStairsOneStairAtATime) {
  ASSERT_TRUE(PlanAcross("scene_stairs15_updown.xml", 2.2)) << error_;
  const double x0 = terrain_->origin().x();
  std::vector<int> levels;
  FeetPose feet = start_;
  for (size_t k = 0; k < steps_.size(); ++k) {
    const Footstep& s = steps_[k];
    EXPECT_EQ(CheckStep(feet, s, lim_), "") << "step " << k + 1;
    const int level = static_cast<int>(std::lround(s.p.z() / 0.15));
    EXPECT_NEAR(s.p.z(), 0.15 * level, 1e-3) << "step " << k + 1;
    if (std::fabs(s.p.z() - feet.p[1 - s.foot].z()) > 0.075) {
      levels.push_back(level);
      ASSERT_LT(k + 1, steps_.size());
      EXPECT_EQ(steps_[k + 1].foot, 1 - s.foot);  // the other foot closes beside it
      EXPECT_NEAR(steps_[k + 1].p.z(), s.p.z(), 1e-3);
    }
    const double toe = s.p.x() + lim_.sole_half_size.x();
    for (double riser : kUpDownRisers)
      if (toe < riser - x0) {
        EXPECT_GE(riser - x0 - toe, TerrainMap::kShinLean * 0.15 - 1e-4) << "step " << k + 1;
      }
    feet = After(feet, s);
  }
  EXPECT_EQ(levels, (std::vector<int>{1, 2, 1, 0}));
  EXPECT_NEAR(MidFrame(feet).p.x(), 2.2, 1e-6);
  EXPECT_NEAR(MidFrame(feet).p.z(), 0, 1e-3);
}

// a goal whose heels would rest across the bottom nose (at 2.0 - x0): moved forward to the
// nearest spot (1 cm grid) with the heels kLevelMargin past it, and the note says so
TEST_F(TerrainPlan, AGoalAcrossANoseIsMovedOntoOneLevel) {
  terrain_ = Load("scene_stairs15_updown.xml");
  ASSERT_TRUE(terrain_);
  start_ = Start(lim_);
  std::string note;
  const double nose = kUpDownNoses[1] - terrain_->origin().x();
  const double goal = nose + 0.05;  // the heels 7.5 cm behind the nose
  ASSERT_TRUE(terrain_->PlanGoalAcross(start_, goal, 0, 0, lim_, 0.05, &steps_, &error_, &note)) << error_;
  FeetPose feet = start_;
  for (const Footstep& s : steps_) feet = After(feet, s);
  const double end = MidFrame(feet).p.x();
  const double heel_spot = nose + lim_.sole_half_size.x() + TerrainMap::kLevelMargin;
  EXPECT_GE(end, heel_spot - 1e-9);
  EXPECT_LT(end, heel_spot + 0.01);
  EXPECT_NE(note.find("the goal moved"), std::string::npos) << note;
  EXPECT_NE(note.find("forward"), std::string::npos) << note;
}

// a goal off the terrain (the floor ends 20 m from the world's origin) is not moved: the plan
// names the step with no surface under it
TEST_F(TerrainPlan, AGoalOffTheTerrainIsRefusedNamingTheStep) {
  EXPECT_FALSE(PlanAcross("scene_stairs15_updown.xml", 21.0));
  EXPECT_EQ(error_.find("rest across a rise"), std::string::npos) << error_;
  EXPECT_EQ(error_.rfind("step ", 0), 0u) << error_;
}

// every goal along the scene, 10 cm apart, plans (none refused for "changes of level": the goals
// whose soles rest across a nose went back and forth across it)
TEST_F(TerrainPlan, EveryGoalAcrossTheUpAndDownStairsPlans) {
  for (double g = 1.0; g < 2.85; g += 0.1) EXPECT_TRUE(PlanAcross("scene_stairs15_updown.xml", g)) << g << ": " << error_;
}

// a footstep 2 mm before a 0.15 m riser (a file's, not the planner's) is moved back until its toes
// are kShinLean x 0.15 m from the riser; with no search room it is refused naming the clearance
TEST_F(TerrainPlan, AFootstepTooNearARiserIsMovedOrRefused) {
  terrain_ = Load("scene_stairs15_updown.xml");
  ASSERT_TRUE(terrain_);
  start_ = Start(lim_);
  const double riser = kUpDownRisers[0] - terrain_->origin().x();
  const double x = riser - 0.002 - lim_.sole_half_size.x();
  std::vector<Footstep> steps(2);
  steps[0].foot = kRight;
  steps[0].p = Eigen::Vector3d(x, -0.5 * lim_.width, 0);
  steps[1].foot = kLeft;
  steps[1].p = Eigen::Vector3d(x, 0.5 * lim_.width, 0);
  std::vector<Footstep> placed = steps;
  ASSERT_TRUE(terrain_->PlaceSteps(&placed, start_, lim_, 0.05, &error_)) << error_;
  for (const Footstep& s : placed) {
    const double clearance = riser - (s.p.x() + lim_.sole_half_size.x());
    const double need = TerrainMap::kShinLean * 0.15;  // the riser 0.15 m above the floor
    EXPECT_GE(clearance, need - 1e-4);
    EXPECT_LT(clearance, need + 0.01);  // the nearest spot on the 1 cm grid
    double measured_need = 0;
    EXPECT_NEAR(terrain_->ToeClearance(s, lim_, &measured_need), clearance, 2e-4);
    EXPECT_NEAR(measured_need, need, 1e-9);
  }
  placed = steps;
  EXPECT_FALSE(terrain_->PlaceSteps(&placed, start_, lim_, 0.02, &error_));
  EXPECT_NE(error_.find("its toes 2 mm from a riser 150 mm high ahead; a sole keeps 0.20 of a "
                        "riser's height from it (30 mm"),
            std::string::npos)
      << error_;
}

// a step over a 0.1 m bar between its ends (floor to floor) swings above the bar: clear_z is the
// bar's top (the highest terrain under the sole's way, the ends' own surfaces left out); one
// backwards, away from it: the floor
TEST_F(TerrainPlan, TheSwingClearsTheHighestTerrainOnItsWay) {
  const std::string dir = ::testing::TempDir();
  const std::string scene = dir + "/terrain_plan_bar.xml";
  // MuJoCo includes relative to the scene's folder
  const std::string robot =
      std::filesystem::relative(kSource + "/mjcf/hrp1s/hrp1s.xml", dir).string();
  {
    FILE* f = std::fopen(scene.c_str(), "w");
    ASSERT_TRUE(f);
    std::fprintf(f,
                 "<mujoco><include file=\"%s\"/><worldbody>"
                 "<geom name=\"floor\" type=\"plane\" size=\"5 5 0.1\"/>"
                 "<geom name=\"bar\" type=\"box\" size=\"0.025 0.6 0.05\" pos=\"0.4 0 0.05\"/>"
                 "</worldbody></mujoco>\n",
                 robot.c_str());
    std::fclose(f);
  }
  std::string error;
  auto t = TerrainMap::Load(scene, "halfsit", &error);
  ASSERT_TRUE(t != nullptr) << error;
  start_ = Start(lim_);
  std::vector<Footstep> steps(1);
  steps[0].foot = kRight;
  steps[0].p = Eigen::Vector3d(0.7, -0.5 * lim_.width, 0);  // the bar at 0.375-0.425 - x0: between
  t->SetSwingClearance(&steps, start_, lim_);
  EXPECT_NEAR(steps[0].clear_z, 0.1, 1e-6);
  steps[0].p.x() = -0.35;  // backwards, away from the bar: the floor
  t->SetSwingClearance(&steps, start_, lim_);
  EXPECT_NEAR(steps[0].clear_z, 0.0, 1e-6);
}

// one foot per stair (scene_stairs15_up.xml: risers 0.427, 0.727 m ahead of the start frame): the
// left foot from the floor onto the second stair passes over the first; lift_z, the highest
// terrain under the first half of its way, is that stair's 0.15 m, clear_z at least that.
// Down scene_stairs15_down.xml (the platform's nose 0.445 m ahead): the left foot from the
// platform onto the floor past the stair; land_z, over the second half, is the stair's -0.15 m
TEST_F(TerrainPlan, AStrideOverAStairLiftsAboveItAndComesDownAboveIt) {
  start_ = Start(lim_);
  // the feet closed before the first riser (the platform's nose), then one foot per stair
  const auto stairs = [&](double x0, double x1, double x2, double dz) {
    std::vector<Footstep> s(4);
    const double x[4] = {x0, x0, x1, x2}, z[4] = {0, 0, dz, 2 * dz};
    for (int k = 0; k < 4; ++k) {
      s[k].foot = k % 2 == 0 ? kRight : kLeft;
      s[k].p = Eigen::Vector3d(x[k], (k % 2 == 0 ? -0.5 : 0.5) * lim_.width, z[k]);
    }
    return s;
  };
  auto up = Load("scene_stairs15_up.xml");
  ASSERT_TRUE(up);
  std::vector<Footstep> steps = stairs(0.27, 0.555, 0.855, 0.15);
  up->SetSwingClearance(&steps, start_, lim_);
  EXPECT_NEAR(steps[3].lift_z, 0.15, 1e-6);
  EXPECT_GE(steps[3].clear_z, 0.15 - 1e-6);
  auto down = Load("scene_stairs15_down.xml");
  ASSERT_TRUE(down);
  steps = stairs(0.28, 0.60, 0.90, -0.15);
  down->SetSwingClearance(&steps, start_, lim_);
  EXPECT_NEAR(steps[3].land_z, -0.15, 1e-6);
  EXPECT_NEAR(steps[3].lift_z, 0.0, 1e-6);  // the first half over the platform
}

TEST_F(TerrainPlan, ATreadBeyondTheStrideIsRefusedNamingTheLimit) {
  lim_.max_forward = 0.25;  // from the edge of one tread to the middle of the next is 0.3 m
  EXPECT_FALSE(PlanAcross("scene_stairs.xml", 1.3));
  EXPECT_NE(error_.find("max_forward 0.25"), std::string::npos) << error_;
}

// a slope has no rise: strides as PlaceSteps places them, not a step-to gait
TEST_F(TerrainPlan, ASlopeIsWalkedWithStrides) {
  lim_.max_forward = 0.25;
  ASSERT_TRUE(PlanAcross("scene_ramp_updown.xml", 2.0)) << error_;
  std::vector<Footstep> placed = PlanToGoal(start_, 2.0, 0, 0, lim_);
  ASSERT_TRUE(terrain_->PlaceSteps(&placed, start_, lim_, 0.05, &error_)) << error_;
  ASSERT_EQ(steps_.size(), placed.size());
  for (size_t k = 0; k < steps_.size(); ++k) {
    EXPECT_NEAR((steps_[k].p - placed[k].p).norm(), 0, 1e-9) << "step " << k + 1;
    EXPECT_NEAR(steps_[k].pitch, placed[k].pitch, 1e-9);
  }
}

}  // namespace
}  // namespace ohrp::walking
