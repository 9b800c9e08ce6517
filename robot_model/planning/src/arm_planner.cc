// RRTConnect in the group's joint box, OMPL's simplification, a final check at resolution.
#include "planning/arm_planner.h"

#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace ohrp::planning {
namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// OMPL's generators draw their seeds from one global sequence: restarting it before each plan
// makes the plan's generators (sampler, nearest neighbours, simplifier) the same every time.
// OMPL logs an error when the sequence restarts after use; it is expected here.
void Reseed(unsigned seed) {
  const ompl::msg::LogLevel level = ompl::msg::getLogLevel();
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
  ompl::RNG::setSeed(std::max(1u, seed));
  ompl::msg::setLogLevel(level);
}

std::vector<double> Values(const ob::State* s, int n) {
  const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
  return std::vector<double>(v->values, v->values + n);
}

// refuses a start or goal that is outside the limits or too close to something; "" when fine
std::string Refusal(PostureCheck& check, const std::string& which, std::span<const double> values,
                    std::vector<double>& posture) {
  const std::string outside = OutsideLimits(check.group(), values);
  if (!outside.empty()) return which + ": " + outside;
  SetGroupValues(check.group(), values, posture);
  const Verdict v = check.Evaluate(posture);
  if (!v.valid) return which + " in collision: " + check.Describe(v);
  return "";
}

}  // namespace

double PathLength(const std::vector<std::vector<double>>& w) {
  double length = 0;
  for (size_t k = 0; k + 1 < w.size(); ++k) {
    double d2 = 0;
    for (size_t j = 0; j < w[k].size(); ++j) d2 += (w[k + 1][j] - w[k][j]) * (w[k + 1][j] - w[k][j]);
    length += std::sqrt(d2);
  }
  return length;
}

Verdict ClosestAlong(PostureCheck& check, std::span<const double> posture,
                     const std::vector<std::vector<double>>& w, double resolution) {
  std::vector<double> q(posture.begin(), posture.end());
  const int n = check.group().size();
  std::vector<double> v(n);
  Verdict closest;
  closest.valid = true;
  closest.distance = INFINITY;
  auto visit = [&](std::span<const double> values) {
    SetGroupValues(check.group(), values, q);
    const Verdict here = check.Evaluate(q);
    if (here.distance < closest.distance) closest = here;
    closest.valid = closest.valid && here.valid;
  };
  if (w.size() == 1) visit(w[0]);
  for (size_t k = 0; k + 1 < w.size(); ++k) {
    const double length = PathLength({w[k], w[k + 1]});
    const int steps = std::max(1, static_cast<int>(std::ceil(length / resolution)));
    for (int i = k == 0 ? 0 : 1; i <= steps; ++i) {
      const double s = static_cast<double>(i) / steps;
      for (int j = 0; j < n; ++j) v[j] = w[k][j] + s * (w[k + 1][j] - w[k][j]);
      visit(v);
    }
  }
  return closest;
}

PlanResult PlanJoints(PostureCheck& check, std::span<const double> posture,
                      std::span<const double> goal, const PlanOptions& options) {
  PlanResult result;
  const JointGroup& group = check.group();
  const int n = group.size();
  const long evaluations0 = check.evaluations();
  std::vector<double> q(posture.begin(), posture.end());
  std::vector<double> start(n);
  GroupValues(group, posture, start);
  if (static_cast<int>(goal.size()) != n) {
    result.reason = "the goal has " + std::to_string(goal.size()) + " values, the group " +
                    std::to_string(n) + " joints";
    return result;
  }
  result.reason = Refusal(check, "start", start, q);
  if (result.reason.empty()) result.reason = Refusal(check, "goal", goal, q);
  if (!result.reason.empty()) return result;

  if (ompl::msg::getLogLevel() < ompl::msg::LOG_WARN) ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  Reseed(options.seed);
  auto space = std::make_shared<ob::RealVectorStateSpace>(n);
  ob::RealVectorBounds bounds(n);
  for (int j = 0; j < n; ++j) {
    bounds.setLow(j, group.lo[j]);
    bounds.setHigh(j, group.hi[j]);
  }
  space->setBounds(bounds);
  og::SimpleSetup setup(space);
  const ob::SpaceInformationPtr si = setup.getSpaceInformation();
  std::vector<double> scratch = q;
  setup.setStateValidityChecker([&check, &scratch, n](const ob::State* s) {
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
    SetGroupValues(check.group(), std::span<const double>(v->values, n), scratch);
    return check.Valid(scratch);
  });
  si->setStateValidityCheckingResolution(
      std::min(1.0, options.resolution / std::max(1e-9, space->getMaximumExtent())));
  ob::ScopedState<> s0(space), s1(space);
  for (int j = 0; j < n; ++j) {
    s0[j] = start[j];
    s1[j] = goal[j];
  }
  setup.setStartAndGoalStates(s0, s1);
  auto planner = std::make_shared<og::RRTConnect>(si);
  if (options.range > 0) planner->setRange(options.range);
  setup.setPlanner(planner);
  setup.setup();

  auto t0 = std::chrono::steady_clock::now();
  const ob::PlannerStatus status = setup.solve(options.time_limit);
  result.plan_time = Seconds(t0);
  if (status != ob::PlannerStatus::EXACT_SOLUTION) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g", options.time_limit);
    result.reason = std::string("no collision-free path found in ") + limit + " s (OMPL: " +
                    status.asString() + ")";
    result.evaluations = check.evaluations() - evaluations0;
    return result;
  }
  og::PathGeometric& path = setup.getSolutionPath();
  result.raw_length = path.length();
  if (options.simplify) {
    t0 = std::chrono::steady_clock::now();
    // vertex reduction and shortcuts (each change re-checked), no B-spline: the timing stops at
    // each waypoint, so the fewer the better; fixed rounds, no clock (the same seed, the same path)
    og::PathSimplifier simplifier(si);
    bool more = true;
    for (int i = 0; i < 5 && more; ++i) more = simplifier.reduceVertices(path);
    simplifier.collapseCloseVertices(path);
    more = true;
    for (int i = 0; i < 5 && more; ++i) more = simplifier.shortcutPath(path);
    simplifier.reduceVertices(path);
    result.simplify_time = Seconds(t0);
  }
  for (size_t k = 0; k < path.getStateCount(); ++k) result.waypoints.push_back(Values(path.getState(k), n));
  result.length = PathLength(result.waypoints);
  // the whole path again, at the resolution: what will be executed
  result.closest = ClosestAlong(check, posture, result.waypoints, options.resolution);
  result.evaluations = check.evaluations() - evaluations0;
  if (!result.closest.valid) {
    result.reason = "the simplified path fails the final check: " + check.Describe(result.closest);
    return result;
  }
  result.solved = true;
  return result;
}

}  // namespace ohrp::planning
