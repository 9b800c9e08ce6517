// Tests walking/terrain's goal across the terrain (TerrainMap::PlanGoalAcross) against the
// scenes' closed-form geometry: up the three 0.1 m stairs of scene_stairs.xml (0.3 m treads,
// risers at x = 0.5, 0.8, 1.1 m of the world, the start frame 0.055 m behind the world's origin
// ... measured from the map) and down the two 0.15 m stairs of scene_stairs15_down.xml: every
// sole wholly on one tread with its margin, one stair at a time (a step onto a new level is
// followed by the other foot beside it), the goal reached; a slope is walked with strides, not
// one level at a time; a tread the limits cannot reach is refused naming max_forward.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

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

TEST(TerrainPlan, UpTheStairsOneStairAtATime) {
  auto t = Load("scene_stairs.xml");
  ASSERT_TRUE(t);
  const StepLimits lim = Hrp1sStairLimits();
  const FeetPose start = Start(lim);
  std::vector<Footstep> steps;
  std::string error;
  ASSERT_TRUE(t->PlanGoalAcross(start, 1.3, 0, 0, lim, 0.05, &steps, &error)) << error;
  Print(steps);
  const std::vector<int> levels = CheckOneStairAtATime(*t, start, steps, lim, 0.1);
  EXPECT_EQ(levels, (std::vector<int>{1, 2, 3}));
  // at the goal, the feet side by side on the top
  FeetPose feet = start;
  for (const Footstep& s : steps) feet = After(feet, s);
  const Frame2 end = MidFrame(feet);
  EXPECT_NEAR(end.p.x(), 1.3, 1e-6);
  EXPECT_NEAR(end.p.y(), 0, 1e-6);
  EXPECT_NEAR(end.p.z(), 0.3, 1e-3);
}

TEST(TerrainPlan, DownTheStairsOneStairAtATime) {
  auto t = Load("scene_stairs15_down.xml");
  ASSERT_TRUE(t);
  const StepLimits lim = Hrp1sStairLimits();
  const FeetPose start = Start(lim);
  std::vector<Footstep> steps;
  std::string error;
  ASSERT_TRUE(t->PlanGoalAcross(start, 1.2, 0, 0, lim, 0.05, &steps, &error)) << error;
  Print(steps);
  const std::vector<int> levels = CheckOneStairAtATime(*t, start, steps, lim, -0.15);
  EXPECT_EQ(levels, (std::vector<int>{-1, -2}));
}

TEST(TerrainPlan, ATreadBeyondTheStrideIsRefusedNamingTheLimit) {
  auto t = Load("scene_stairs.xml");
  ASSERT_TRUE(t);
  StepLimits lim = Hrp1sStairLimits();
  lim.max_forward = 0.25;  // from the edge of one tread to the middle of the next is 0.3 m
  std::vector<Footstep> steps;
  std::string error;
  EXPECT_FALSE(t->PlanGoalAcross(Start(lim), 1.3, 0, 0, lim, 0.05, &steps, &error));
  EXPECT_NE(error.find("max_forward 0.25"), std::string::npos) << error;
}

// a slope has no rise: strides as PlaceSteps places them, not a step-to gait
TEST(TerrainPlan, ASlopeIsWalkedWithStrides) {
  auto t = Load("scene_ramp_updown.xml");
  ASSERT_TRUE(t);
  StepLimits lim = Hrp1sStairLimits();
  lim.max_forward = 0.25;
  const FeetPose start = Start(lim);
  std::vector<Footstep> across, placed = PlanToGoal(start, 2.0, 0, 0, lim);
  std::string error;
  ASSERT_TRUE(t->PlanGoalAcross(start, 2.0, 0, 0, lim, 0.05, &across, &error)) << error;
  ASSERT_TRUE(t->PlaceSteps(&placed, start, lim, 0.05, &error)) << error;
  ASSERT_EQ(across.size(), placed.size());
  for (size_t k = 0; k < across.size(); ++k) {
    EXPECT_NEAR((across[k].p - placed[k].p).norm(), 0, 1e-9) << "step " << k + 1;
    EXPECT_NEAR(across[k].pitch, placed[k].pitch, 1e-9);
  }
}

}  // namespace
}  // namespace ohrp::walking
