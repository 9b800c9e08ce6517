// The SampleRobot profile (see robot_profile.h and mjcf/hrp1s/README.md): patterns match the
// whole joint name, the first match wins.
#include "vrml/robot_profile.h"

#include <cmath>
#include <regex>

namespace ohrp::vrml {
namespace {

template <typename T>
const T* Lookup(const std::vector<std::pair<const char*, T>>& table, const std::string& name) {
  for (const auto& [pattern, value] : table)
    if (std::regex_match(name, std::regex(pattern))) return &value;
  return nullptr;
}

// torque limits [N m]: assumptions for a 130 kg humanoid (README: "Torque limits")
const std::vector<std::pair<const char*, double>> kTorqueLimits = {
    {"[RL]LEG_HIP_R", 400.0},       {"[RL]LEG_HIP_P", 400.0},     {"[RL]LEG_HIP_Y", 300.0},
    {"[RL]LEG_KNEE", 500.0},        {"[RL]LEG_ANKLE_P", 400.0},   {"[RL]LEG_ANKLE_R", 300.0},
    {"[RL]ARM_SHOULDER_[PR]", 200.0}, {"[RL]ARM_SHOULDER_Y", 100.0}, {"[RL]ARM_ELBOW", 150.0},
    {"[RL]ARM_WRIST_[YPR]", 100.0}, {"WAIST_[PR]", 400.0},        {"CHEST", 300.0},
};

// ranges of the joints sample1.wrl gives none [rad] (README: "Limits")
const std::vector<std::pair<const char*, std::pair<double, double>>> kRanges = {
    {"[RL]LEG_HIP_R", {-0.6109, 0.6109}},   {"[RL]LEG_HIP_P", {-2.0944, 0.7854}},
    {"[RL]LEG_HIP_Y", {-0.7854, 0.7854}},   {"[RL]LEG_KNEE", {-0.0873, 2.6180}},
    {"[RL]LEG_ANKLE_P", {-1.3090, 0.7854}}, {"[RL]LEG_ANKLE_R", {-0.6109, 0.6109}},
    {"WAIST_P", {-0.5236, 1.0472}},         {"WAIST_R", {-0.5236, 0.5236}},
    {"CHEST", {-1.5708, 1.5708}},
};

// OpenHRP's half-sitting pose [rad]
const std::vector<std::pair<const char*, double>> kHalfSitting = {
    {"[RL]LEG_HIP_P", -0.35},       {"[RL]LEG_KNEE", 0.70},       {"[RL]LEG_ANKLE_P", -0.35},
    {"[RL]ARM_SHOULDER_P", 0.17},   {"RARM_SHOULDER_R", -0.17},   {"LARM_SHOULDER_R", 0.17},
    {"[RL]ARM_ELBOW", -0.52},
};

}  // namespace

double TorqueLimit(const std::string& joint) {
  const double* v = Lookup(kTorqueLimits, joint);
  return v ? *v : 0.0;
}

std::pair<double, double> AssumedRange(const std::string& joint) {
  const auto* v = Lookup(kRanges, joint);
  return v ? *v : std::pair<double, double>(-M_PI, M_PI);
}

double HalfSitting(const std::string& joint) {
  const double* v = Lookup(kHalfSitting, joint);
  return v ? *v : 0.0;
}

const std::vector<std::pair<std::string, std::string>>& Soles() {
  static const std::vector<std::pair<std::string, std::string>> kSoles = {
      {"RLEG_ANKLE_R", "RLEG_SOLE"}, {"LLEG_ANKLE_R", "LLEG_SOLE"}};
  return kSoles;
}

int ForceSensorRank(const std::string& sensor) {
  static const char* kOrder[] = {"rfsensor", "lfsensor", "rhsensor", "lhsensor"};
  for (int i = 0; i < 4; ++i)
    if (sensor == kOrder[i]) return i;
  return 4;
}

}  // namespace ohrp::vrml
