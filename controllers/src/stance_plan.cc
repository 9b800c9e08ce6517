// The stance plan (see stance_plan.h).
#include "controllers/stance_plan.h"

#include "controllers/ramp.h"

namespace ohrp::controllers {
namespace {

StanceShift Lerp(const StanceShift& a, const StanceShift& b, double s) {
  return {a.hips + s * (b.hips - a.hips), a.com + s * (b.com - a.com)};
}

}  // namespace

void StancePlan::Configure(const StanceShift& centre, double centre_time,
                           const StanceShift side[2], const OneLegOptions& o) {
  segments_.clear();
  lift_ = o.lift;
  double t = 0;
  auto add = [&](Kind kind, double duration, const StanceShift& from, const StanceShift& to,
                 int s) {
    segments_.push_back({kind, t, t + duration, from, to, s});
    t += duration;
  };
  add(Kind::kMove, centre_time, StanceShift{}, centre, -1);
  for (int s : o.sides) {
    add(Kind::kMove, o.pause, centre, centre, -1);
    add(Kind::kMove, o.shift_time, centre, side[s], -1);
    add(Kind::kLift, o.lift_time, side[s], side[s], s);
    add(Kind::kHold, o.hold, side[s], side[s], s);
    add(Kind::kLower, o.lift_time, side[s], side[s], s);
    add(Kind::kMove, o.shift_time, side[s], centre, -1);
  }
  rest_ = centre;
}

double StancePlan::duration() const { return segments_.empty() ? 0 : segments_.back().t1; }

StanceTargets StancePlan::At(double t) const noexcept {
  StanceTargets out;
  out.shift = rest_;
  for (const Segment& g : segments_) {
    if (t >= g.t1) continue;
    const double u = g.t1 > g.t0 ? (t - g.t0) / (g.t1 - g.t0) : 1.0;
    const double s = MinimumJerk(u);
    out.shift = Lerp(g.from, g.to, s);
    if (g.side >= 0) {
      const int swing = 1 - g.side;
      out.standing_on = g.side;
      out.supporting[swing] = false;
      out.lift[swing] = g.kind == Kind::kLift ? lift_ * s : g.kind == Kind::kHold ? lift_ : lift_ * (1 - s);
    }
    return out;
  }
  return out;
}

}  // namespace ohrp::controllers
