// The figures walk and balance derive from the robot (controllers/derived_gait.h) against their
// closed forms.
#include "controllers/derived_gait.h"

#include <cmath>

#include <gtest/gtest.h>

#include "controllers/walk.h"

namespace ohrp::controllers {
namespace {

// dynamic similarity: lengths scale as L, times as sqrt(L / g)
TEST(DerivedGait, LengthsScaleWithTheLegTimesWithItsSquareRoot) {
  const DerivedGait d = ScaleGait(0.5, 2.0, 0.25, 0.04, 0.8);
  EXPECT_DOUBLE_EQ(d.ratio, 0.25);
  EXPECT_DOUBLE_EQ(d.max_forward, 0.0625);  // 0.25 x 0.25
  EXPECT_DOUBLE_EQ(d.step_height, 0.01);    // 0.04 x 0.25
  EXPECT_DOUBLE_EQ(d.step_time, 0.4);       // 0.8 x sqrt(0.25)
  // the Froude number v^2 / (g L) of the walk, v = stride / step time, is the anchor's
  const double v = d.max_forward / d.step_time, v0 = 0.25 / 0.8;
  EXPECT_NEAR(v * v / 0.5, v0 * v0 / 2.0, 1e-12);
}

// HRP-1S's leg (and one within kSameLeg of it) keeps walk's defaults exactly
TEST(DerivedGait, TheAnchorKeepsItsFigures) {
  const walking::StepLimits lim;
  const walking::GaitOptions gait;
  for (double leg : {kAnchorLegLength, kAnchorLegLength * (1 + 0.9 * kSameLeg),
                     kAnchorLegLength * (1 - 0.9 * kSameLeg)}) {
    const DerivedGait d =
        ScaleGait(leg, kAnchorLegLength, lim.max_forward, gait.step_height, gait.step_time);
    EXPECT_EQ(d.ratio, 1.0);
    EXPECT_EQ(d.max_forward, lim.max_forward);
    EXPECT_EQ(d.step_height, gait.step_height);
    EXPECT_EQ(d.step_time, gait.step_time);
  }
  const DerivedGait d = ScaleGait(kAnchorLegLength * (1 + 2 * kSameLeg), kAnchorLegLength, 0.25,
                                  0.04, 0.8);
  EXPECT_DOUBLE_EQ(d.ratio, 1 + 2 * kSameLeg);
}

// the sag is |tau| / kp at the joint where it is largest; joints without stiffness are skipped
TEST(DerivedGait, LargestSagOverTheLegsJoints) {
  const double tau[5] = {100, -30, 8, 50, 1000};
  const double kp[5] = {1e4, 1000, 0, 2000, 10};
  const int leg[4] = {0, 1, 2, 3};  // joint 4 is not the leg's
  const SagEstimate s = LargestSag(leg, 4, tau, kp);
  EXPECT_EQ(s.joint, 1);
  EXPECT_DOUBLE_EQ(s.sag, 0.03);  // 30 / 1000 beats 50 / 2000 and 100 / 1e4
  EXPECT_DOUBLE_EQ(s.tau, -30);
  EXPECT_DOUBLE_EQ(s.kp, 1000);
  const int none[1] = {2};
  EXPECT_EQ(LargestSag(none, 1, tau, kp).joint, -1);
}

// a leg that yields: the stride less leg x sag, at least half; none within kSagLimit
TEST(DerivedGait, AYieldingLegShortensTheStride) {
  EXPECT_DOUBLE_EQ(CompliantStride(0.3, 0.8, 0.1), 0.3 - 0.08);
  EXPECT_DOUBLE_EQ(CompliantStride(0.3, 0.8, 0.5), 0.15);         // at least half
  EXPECT_DOUBLE_EQ(CompliantStride(0.3, 0.8, kSagLimit), 0.3);    // a stiff leg: unchanged
  EXPECT_DOUBLE_EQ(CompliantStride(0.3, 0.8, 0.0), 0.3);
}

// D is the ankle's stiffness times the time constant, at most the default
TEST(DerivedGait, FootDampingFromTheAnklesStiffness) {
  EXPECT_DOUBLE_EQ(AnkleDamping(500, 300, 0.2), 100);      // 500 N m/rad x 0.2 s
  EXPECT_DOUBLE_EQ(AnkleDamping(17000, 300, 0.2), 300);    // a stiff ankle keeps the default
  EXPECT_DOUBLE_EQ(AnkleDamping(0, 300, 0.2), 300);        // no stiffness known
  EXPECT_DOUBLE_EQ(AnkleDamping(INFINITY, 300, 0.2), 300);
}

}  // namespace
}  // namespace ohrp::controllers

namespace ohrp::controllers {
namespace {

WalkOptions Options(const std::string& model, const std::string& keyframe) {
  WalkOptions o;
  o.balance.model = model;
  o.balance.keyframe = keyframe;
  o.commands.push_back({});
  o.commands.back().x = 0.5;
  o.commands.back().text = "goal 0.5 0 0";
  return o;
}

// HRP-1S (the default model): its leg is the anchor, walk's defaults stay; its servo is stiff
TEST(DerivedGait, HRP1SKeepsWalksDefaultsAndNoFeedforward) {
  ConfigStatus status;
  auto walk = WalkController::Create(Options("", ""), &status);
  ASSERT_TRUE(walk) << status.message;
  EXPECT_EQ(walk->walk_options().limits.max_forward, walking::StepLimits{}.max_forward);
  EXPECT_EQ(walk->walk_options().gait.step_height, walking::GaitOptions{}.step_height);
  EXPECT_EQ(walk->walk_options().gait.step_time, walking::GaitOptions{}.step_time);
  EXPECT_EQ(walk->walk_options().balance.load_feedforward, 0);
}

// a leg of another length: the three figures by the one ratio r (lengths r, times sqrt(r));
// a figure given (here the step time, as the command line or the profile gives it) stays
TEST(DerivedGait, AnotherLegScalesTheFiguresByOneRatio) {
  const std::string child = std::string(OHRP_SOURCE_DIR) + "/tests/robots/child_derived.yaml";
  WalkOptions o = Options(child, "stand");
  o.gait.step_time = 0.7;
  o.given.push_back("step_time");
  ConfigStatus status;
  auto walk = WalkController::Create(o, &status);
  ASSERT_TRUE(walk) << status.message;
  const WalkOptions& w = walk->walk_options();
  const double r = w.gait.step_height / walking::GaitOptions{}.step_height;
  EXPECT_GT(r, 0.3);
  EXPECT_LT(r, 0.9);  // the child's leg is shorter than HRP-1S's
  EXPECT_EQ(w.gait.step_time, 0.7);
  // its position servos sag beyond kSagLimit under its weight: the feed-forward is on, and the
  // stride is the scaled one less the leg (r HRP-1S's) times that sag
  EXPECT_EQ(w.balance.load_feedforward, 1);
  EXPECT_GT(w.balance.stance_sag, kSagLimit);
  EXPECT_NEAR(w.limits.max_forward,
              r * walking::StepLimits{}.max_forward - r * kAnchorLegLength * w.balance.stance_sag,
              1e-9);
  o = Options(child, "stand");
  walk = WalkController::Create(o, &status);
  ASSERT_TRUE(walk) << status.message;
  EXPECT_NEAR(walk->walk_options().gait.step_time,
              std::sqrt(r) * walking::GaitOptions{}.step_time, 1e-12);
}

}  // namespace
}  // namespace ohrp::controllers
