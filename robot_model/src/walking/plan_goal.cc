// Footstep plans to a relative goal (see walking/footsteps.h, PlanToGoal).
//
// For a walk of n steps the turn and the translation are shared among the steps by each foot's
// capacity (the foot turning out takes up to max_turn, the other max_turn_in; the foot moving
// outward up to max_side, the other what min_width and the soles leave), and the walk is kept when
// every step passes CheckStep. The turn is tried five ways: in the first steps (the last steps
// turn least: a turn on the spot), in the last steps (a long walk keeps its heading, then turns),
// spread evenly, and turning on the spot before or after the translation. n is tried upwards from a
// lower bound: one by one for the first counts, then by doubling and bisection.
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "plan_walk.h"
#include "step_geometry.h"

namespace ohrp::walking {
namespace {

constexpr int kLinearCounts = 64;  // step counts tried one by one before doubling

// when the turn is taken in a walk, and whether the turning steps also carry the translation
struct Turn {
  enum When { kFirst, kLast, kEven } when;
  bool apart;  // the translation only in the steps that do not turn
};
constexpr Turn kTurns[] = {{Turn::kFirst, false},
                           {Turn::kLast, false},
                           {Turn::kEven, false},
                           {Turn::kFirst, true},
                           {Turn::kLast, true}};

// each step's turn capacity towards `sign` (+1 left)
double TurnCap(int foot, double sign, const StepLimits& l) {
  return SideSign(foot) == sign ? l.max_turn : l.max_turn_in;
}

// the yaw increments of an n-step walk turning by `yaw`; false when the turn does not fit
bool YawIncrements(double yaw, int n, int first, Turn::When when, const StepLimits& l,
                   std::vector<Pose2>* inc) {
  const double sign = yaw >= 0 ? 1 : -1;
  std::vector<double> cap(n);
  double total = 0;
  for (int k = 0, foot = first; k < n; ++k, foot = 1 - foot)
    total += cap[k] = TurnCap(foot, sign, l);
  if (total < std::abs(yaw) - kZero) return false;
  // the even turn: each step the same fraction of its capacity
  if (when == Turn::kEven) {
    for (int k = 0; k < n; ++k) (*inc)[k].yaw = sign * cap[k] * std::abs(yaw) / total;
    return true;
  }
  // first or last: full capacity from the first turning step, the rest on the last of them
  int from = 0;
  if (when == Turn::kLast) {
    double tail = 0;
    for (from = n; from > 0 && tail < std::abs(yaw) - kZero;) tail += cap[--from];
  }
  double left = std::abs(yaw);
  for (int k = 0; k < n; ++k) {
    const double d = k < from ? 0 : std::min(left, cap[k]);
    (*inc)[k].yaw = sign * d;
    left -= d;
  }
  return true;
}

// the translation increments of an n-step walk to `goal` with the yaw increments set: step k
// moves (u.x w_k.x, u.y w_k.y) in the mid frame before it, w_k its foot's capacity towards the
// goal as seen from that frame, u solving the sum for the goal (the directions iterated until they
// agree with u's signs); false when there is no such u
bool TranslationIncrements(const Eigen::Vector2d& goal, int first, bool apart, const StepLimits& l,
                           std::vector<Pose2>* inc) {
  const int n = static_cast<int>(inc->size());
  std::vector<double> heading(n, 0.0);
  for (int k = 1; k < n; ++k) heading[k] = heading[k - 1] + (*inc)[k - 1].yaw;
  // the direction of each step's motion: the goal's as seen from its frame, to start with
  std::vector<Eigen::Vector2d> dir(n), w(n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d seen = Eigen::Rotation2Dd(-heading[k]) * goal;
    dir[k] = Eigen::Vector2d(seen.x() >= 0 ? 1 : -1, seen.y() >= 0 ? 1 : -1);
  }
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  for (int iteration = 0; iteration < 4; ++iteration) {
    // signed capacities and their sum in the start's mid frame
    Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
    for (int k = 0, foot = first; k < n; ++k, foot = 1 - foot) {
      const bool out = SideSign(foot) == dir[k].y();
      w[k] = dir[k].cwiseProduct(Eigen::Vector2d(dir[k].x() > 0 ? l.max_forward : l.max_backward,
                                                 out ? l.max_side : InwardSide(l)));
      if (apart && (*inc)[k].yaw != 0) w[k].setZero();
      a += Eigen::Rotation2Dd(heading[k]).toRotationMatrix() * w[k].asDiagonal();
    }
    // a column of zeros (no capacity in a direction the goal does not need) solves as 0
    const bool cx = a.col(0).norm() > kZero, cy = a.col(1).norm() > kZero;
    u.setZero();
    if (cx && cy && std::abs(a.determinant()) > 1e-12) {
      u = a.lu().solve(goal);
    } else if (cx && !cy) {
      u.x() = a.col(0).dot(goal) / a.col(0).squaredNorm();
    } else if (cy && !cx) {
      u.y() = a.col(1).dot(goal) / a.col(1).squaredNorm();
    }
    if ((a * u - goal).norm() > kZero) return false;
    if (u.x() >= 0 && u.y() >= 0) break;
    // a negative factor: those directions were the wrong way round
    for (auto& d : dir) d = d.cwiseProduct(Eigen::Vector2d(u.x() < 0 ? -1 : 1, u.y() < 0 ? -1 : 1));
  }
  for (int k = 0; k < n; ++k) (*inc)[k].p = u.cwiseProduct(w[k]);
  return true;
}

// an n-step walk to goal g from foot `first`, the turn tried each way; "" or why not
std::string TryCount(const FeetPose& start, const Pose2& g, int n, int first, const StepLimits& l,
                     std::vector<Footstep>* steps) {
  std::string why = "the limits cannot reach the goal in " + std::to_string(n) + " steps";
  std::vector<Pose2> inc(n);
  for (const Turn& turn : kTurns) {
    if (std::abs(g.yaw) < kZero && (turn.when != Turn::kFirst || turn.apart)) break;  // one way
    if (!YawIncrements(g.yaw, n, first, turn.when, l, &inc)) return why;
    if (!TranslationIncrements(g.p, first, turn.apart, l, &inc)) continue;
    why = Walk(start, inc, first, l, steps);
    if (why.empty()) return "";
  }
  return why;
}

// the fewest-step walk to goal g from foot `first`; "" or why not
std::string PlanFrom(const FeetPose& start, const Pose2& g, int first, const StepLimits& l,
                     std::vector<Footstep>* steps) {
  // a lower bound: a step moves the mid frame by at most the reach of a step and turns it by at
  // most the larger turn limit (less one for the closing step, and a margin)
  const double reach = std::hypot(std::max(l.max_forward, l.max_backward), l.width + l.max_side);
  const double turn = std::max(l.max_turn, l.max_turn_in);
  const double bound = std::max(g.p.norm() / std::max(reach, kZero), std::abs(g.yaw) / turn);
  if (bound > kMaxSteps) return "the goal needs more than " + std::to_string(kMaxSteps) + " steps";
  const int lo = std::max(1, static_cast<int>(0.9 * bound) - 1);
  // one by one
  std::string why;
  int n = lo;
  for (; n < lo + kLinearCounts; ++n) {
    why = TryCount(start, g, n, first, l, steps);
    if (why.empty()) return "";
  }
  // doubling, then bisection between the last count that failed and the first that walked
  int failed = n - 1;
  for (int span = kLinearCounts;; span *= 2) {
    n = std::min(kMaxSteps, failed + span);
    why = TryCount(start, g, n, first, l, steps);
    if (why.empty()) break;
    failed = n;
    if (n == kMaxSteps) return why;
  }
  int walked = n;
  while (walked - failed > 1) {
    const int mid = (failed + walked) / 2;
    (TryCount(start, g, mid, first, l, steps).empty() ? walked : failed) = mid;
  }
  return TryCount(start, g, walked, first, l, steps);
}

}  // namespace

std::vector<Footstep> PlanToGoal(const FeetPose& start, double x, double y, double yaw,
                                 const StepLimits& limits, std::string* error) {
  std::vector<Footstep> none;
  auto fail = [&](const std::string& why) {
    if (error) *error = "cannot plan the goal: " + why;
    return none;
  };
  if (error) error->clear();
  // the command and the start
  const std::string bad = CheckLimits(limits);
  if (!bad.empty()) return fail(bad);
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(yaw))
    return fail("x, y and yaw must be finite numbers");
  const std::string stance = StanceProblem(start, limits);
  if (!stance.empty()) return fail(stance);
  Pose2 g;
  g.p = Eigen::Vector2d(x, y);
  // the short way round, but a half turn keeps the direction asked
  g.yaw = std::abs(yaw) > M_PI ? WrapAngle(yaw) : yaw;
  if (g.p.norm() < kZero && std::abs(g.yaw) < kZero) return none;
  // the direction's first foot; the other only when it needs fewer steps
  const int first = FirstFoot(y, g.yaw, limits);
  std::vector<Footstep> a, b;
  const std::string why_a = PlanFrom(start, g, first, limits, &a);
  const std::string why_b = PlanFrom(start, g, 1 - first, limits, &b);
  if (why_a.empty() && (!why_b.empty() || a.size() <= b.size())) return a;
  if (why_b.empty()) return b;
  return fail(why_a);
}

}  // namespace ohrp::walking
