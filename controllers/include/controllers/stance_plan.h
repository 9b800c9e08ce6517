// The stance plan of the balance controller: where the hips and the centre of mass should be,
// which soles carry the robot and how high a lifted foot is, as a function of the time since
// the robot stood. A timeline of segments, each a minimum-jerk move between two shifts:
//
//   centre      0 -> the shift that puts the CoM over the middle of the soles
//   per side s of `one_leg` in turn (s = 0 left, 1 right; the other foot is the swing foot):
//     pause     on both feet
//     shift     centre -> the shift that puts the CoM over sole s
//     lift      the swing foot rises by `lift` (it no longer supports from the segment's start)
//     hold      on one foot
//     lower     the swing foot comes down (it supports again at the segment's end)
//     back      shift of side s -> centre
//   then on both feet, centred, for good.
// Shifts are in the base frame (x forward, y left) [m]: `hips` moves the base relative to the
// soles, `com` is how far the CoM moves with it (less: the legs stay with the feet).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace ohrp::controllers {

struct StanceShift {
  Eigen::Vector2d hips = Eigen::Vector2d::Zero();  // [m]
  Eigen::Vector2d com = Eigen::Vector2d::Zero();   // [m]
};

struct OneLegOptions {
  std::vector<int> sides;   // soles to stand on in turn (0 left, 1 right); empty: none
  double pause = 1.0;       // [s] on both feet before each shift
  double shift_time = 1.5;  // [s] to move the CoM over the stance sole (and back)
  double lift_time = 1.0;   // [s] to lift the swing foot (and to lower it)
  double hold = 5.0;        // [s] on one foot
  double lift = 0.05;       // [m] swing foot height
};

struct StanceTargets {
  StanceShift shift;                  // hips and CoM shift now
  bool supporting[2] = {true, true};  // left, right sole carries the robot
  double lift[2] = {0, 0};            // left, right sole raised by [m]
  int standing_on = -1;               // the stance sole while on one foot, else -1
};

class StancePlan {
 public:
  // centre: the shift onto the middle of the soles (zero: stay); side[i]: onto sole i
  void Configure(const StanceShift& centre, double centre_time, const StanceShift side[2],
                 const OneLegOptions& one_leg);
  // the targets `t` [s] after the robot stood; no allocation
  StanceTargets At(double t) const noexcept;
  // [s] until the plan rests centred on both feet
  double duration() const;

 private:
  enum class Kind { kMove, kLift, kHold, kLower };
  struct Segment {
    Kind kind;
    double t0, t1;
    StanceShift from, to;
    int side;  // stance sole (kLift/kHold/kLower), -1 otherwise
  };
  std::vector<Segment> segments_;
  StanceShift rest_;
  double lift_ = 0;
};

}  // namespace ohrp::controllers
