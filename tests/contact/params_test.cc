// Parameter validation: each refusal names the parameter, says why, and what would work; the
// suggested value is accepted.
#include "contact/params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace ohrp::contact {
namespace {

constexpr double kDt = 0.001;
constexpr double kMass = 60.0;

TEST(ContactParams, DefaultsAreValidForTheRobot) {
  std::string error;
  EXPECT_TRUE(Validate(SoftContactParams{}, kDt, kMass, &error)) << error;
  // A foot touching down carries far less than half the robot, but never less than 15 kg:
  // the leg's joints each have 12 kg m^2 of rotor inertia (armature), which a sole 0.3-0.6 m
  // away feels as tens of kilograms. The defaults stay stable at 1 ms for 15 kg; for a foot
  // alone (5 kg) the 30 s/m damper is past the margin and Validate says so.
  EXPECT_TRUE(Validate(SoftContactParams{}, kDt, 15.0, &error)) << error;
  EXPECT_FALSE(Validate(SoftContactParams{}, kDt, 5.0, &error));
  EXPECT_NE(error.find("use damping <= "), std::string::npos) << error;
}

// an impact lasts half a period of the linearised law at the static load: pi sqrt(m / k) for
// the linear default sole; below 4 steps per impact the note says so and what would resolve it
TEST(ContactParams, ImpactDurationAndItsNote) {
  SoftContactParams p;
  EXPECT_NEAR(ImpactDuration(p, 60.0), M_PI * std::sqrt(60.0 / p.stiffness), 1e-15);
  p.exponent = 1.5;  // K = 1.5 k delta^0.5, delta = (m g / k)^(2/3)
  const double delta = std::pow(60.0 * 9.81 / p.stiffness, 1 / 1.5);
  EXPECT_NEAR(ImpactDuration(p, 60.0), M_PI / std::sqrt(1.5 * p.stiffness * std::sqrt(delta) / 60.0), 1e-15);
  p = SoftContactParams{};
  const double t = ImpactDuration(p, 60.0);  // 14.05 ms
  EXPECT_EQ(ImpactNote(p, 0.001, 60.0), "");
  EXPECT_EQ(ImpactNote(p, 0.999 * t / kImpactSteps, 60.0), "");
  const std::string note = ImpactNote(p, 0.004, 60.0);
  EXPECT_NE(note.find("14 ms"), std::string::npos) << note;
  EXPECT_NE(note.find("dt <= 3.51 ms"), std::string::npos) << note;
}

TEST(ContactParams, NegativeStiffnessIsRefusedWithName) {
  SoftContactParams p;
  p.stiffness = -1e5;
  std::string error;
  ASSERT_FALSE(Validate(p, kDt, kMass, &error));
  EXPECT_NE(error.find("stiffness = -100000"), std::string::npos) << error;
  EXPECT_NE(error.find("> 0"), std::string::npos) << error;
  EXPECT_NE(error.find("3e6"), std::string::npos) << error;  // what would work
}

TEST(ContactParams, ExponentBelowOneIsRefused) {
  SoftContactParams p;
  p.exponent = 0.5;
  std::string error;
  ASSERT_FALSE(Validate(p, kDt, kMass, &error));
  EXPECT_NE(error.find("exponent = 0.5"), std::string::npos) << error;
  EXPECT_NE(error.find("infinite"), std::string::npos) << error;
}

TEST(ContactParams, EveryProblemIsReported) {
  SoftContactParams p;
  p.friction = -0.2;
  p.damping = -1;
  p.grid_x = 1;
  std::string error;
  ASSERT_FALSE(Validate(p, kDt, kMass, &error));
  EXPECT_NE(error.find("friction = -0.2"), std::string::npos) << error;
  EXPECT_NE(error.find("damping = -1"), std::string::npos) << error;
  EXPECT_NE(error.find("grid = 1 x 3"), std::string::npos) << error;
  EXPECT_FALSE(Validate(SoftContactParams{}, 0.0, kMass, &error));
  EXPECT_NE(error.find("dt = 0"), std::string::npos) << error;
  EXPECT_FALSE(Validate(SoftContactParams{}, kDt, -3, &error));
  EXPECT_NE(error.find("mass_scale = -3"), std::string::npos) << error;
}

// Pulls the number that follows `key` out of a message.
double NumberAfter(const std::string& text, const std::string& key) {
  const size_t at = text.find(key);
  if (at == std::string::npos) return -1;
  return std::stod(text.substr(at + key.size()));
}

TEST(ContactParams, UnstableDampingIsRefusedAndTheSuggestionWorks) {
  SoftContactParams p;
  p.damping = 200;  // 2*dt*c*3g = 11.8: far beyond the explicit limit at 1 ms
  std::string error;
  ASSERT_FALSE(Validate(p, kDt, kMass, &error));
  EXPECT_NE(error.find("damping = 200 s/m makes the explicit step unstable"), std::string::npos)
      << error;
  const double c_max = NumberAfter(error, "use damping <= ");
  // (2 - dt^2 k/m) / (2 dt 3 g) = (2 - 0.05) / 0.05886 = 33.1 s/m
  EXPECT_NEAR(c_max, 33.1, 0.1) << error;
  p.damping = 0.99 * c_max;
  EXPECT_TRUE(Validate(p, kDt, kMass, &error)) << error;
  p.damping = 1.02 * c_max;
  EXPECT_FALSE(Validate(p, kDt, kMass, &error));
  // A smaller step makes the same damping acceptable.
  p.damping = 200;
  EXPECT_TRUE(Validate(p, kDt / 10, kMass, &error)) << error;
}

TEST(ContactParams, TooStiffForTheStepIsRefused) {
  SoftContactParams p;
  p.stiffness = 1e9;
  std::string error;
  ASSERT_FALSE(Validate(p, kDt, kMass, &error));
  EXPECT_NE(error.find("stiffness = 1e+09 N/m^n is too stiff for dt = 0.001"), std::string::npos)
      << error;
  const double dt_max = NumberAfter(error, "or dt <= ");
  ASSERT_GT(dt_max, 0) << error;
  EXPECT_TRUE(Validate(p, 0.99 * dt_max, kMass, &error)) << error;
}

TEST(ContactParams, UnstableTangentialDampingIsRefused) {
  SoftContactParams p;
  p.tangential_damping = 1e5;
  std::string error;
  ASSERT_FALSE(Validate(p, kDt, kMass, &error));
  EXPECT_NE(error.find("tangential_damping = 1e+05"), std::string::npos) << error;
  const double b_max = NumberAfter(error, "use tangential_damping <= ");
  p.tangential_damping = 0.99 * b_max;
  EXPECT_TRUE(Validate(p, kDt, kMass, &error)) << error;
}

}  // namespace
}  // namespace ohrp::contact

namespace ohrp::contact {
namespace {

// The implicit step (SoftFootContact's default) is stable at any step for the linearised law:
// the defaults are accepted at 2, 4 and 8 ms and for a 5 kg foot; out-of-range values are
// still refused whatever the scheme.
TEST(ContactParams, ImplicitStepAcceptsLargerStepsButNotBadValues) {
  std::string error;
  for (double dt : {0.002, 0.004, 0.008}) {
    EXPECT_FALSE(Validate(SoftContactParams{}, dt, kMass, &error, StepScheme::kExplicit)) << dt;
    EXPECT_TRUE(Validate(SoftContactParams{}, dt, kMass, &error, StepScheme::kImplicit)) << error;
  }
  EXPECT_TRUE(Validate(SoftContactParams{}, kDt, 5.0, &error, StepScheme::kImplicit)) << error;
  SoftContactParams p;
  p.stiffness = -1;
  EXPECT_FALSE(Validate(p, kDt, kMass, &error, StepScheme::kImplicit));
  EXPECT_NE(error.find("stiffness"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::contact
