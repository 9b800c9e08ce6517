// Touchdown (issue 30 item 4; controllers/walk.h): the landing foot's own force/torque sensor
// tells when it meets the ground.
// - Early (ground higher than the plan's: an unseen step up, a stone, a slope that rises sooner):
//   from then on its sole is held at that height instead of being pushed on down to where the
//   plan expected the ground (which would tip the robot over the higher foot), it supports the
//   robot there, and the swing ends (the landing, the weight's transfer, comes at once).
// - Late (ground lower than the plan's: an unseen step down, a hole): at its planned landing the
//   foot has not met the ground. The landing is held (Gait::DelayLanding: the ZMP stays on the
//   stance sole, the later steps wait) while the foot goes on down, as far as the leg reaches
//   with the hip midway between the soles. The descent follows the measured sole (its target
//   leads the foot by at most kLead: the servo lags a falling target, and a target far below
//   the foot at the touch would push it into the ground). The hold ends at the touch, or when
//   the DCM (measured) leaves the stance sole (less the stabilizer's margin): the CoM cannot
//   wait longer there, so the landing is taken where the foot is, and the foot searches on
//   down in support until it touches.
// The plan is re-based on the touched ground: where a foot touched (early or late), measured
// (the soles' height difference from the estimate's kinematics, against the plan's, on top of
// the stance foot's own ground) is the ground's height for the later steps (floor_dz_): each
// swing blends its foot's offset from where it lifted off to that by its landing. The CoM goes with the lower of the feet's
// offsets (com_dz_), so the legs keep the plan's reach.
#include <algorithm>
#include <cmath>

#include "controllers/walk.h"

namespace ohrp::controllers {

namespace {
// a late foot's descent below its planned landing [m/s] at most, and how far its target may
// lead the measured sole [m] (the servo's lag: 6 Hz follows a ramp v about v / (2 pi 6) behind)
constexpr double kLateSpeed = 0.6;
constexpr double kLead = 0.01;
// the CoM rises onto a higher ground found at most this fast [m/s] (over about a step: a jump
// of the hips would push the soles into the ground)
constexpr double kComRise = 0.05;
// how long the landing is held beyond the descent to the leg's reach [s]
constexpr double kLateSettle = 0.03;
// an early touch lands the foot this soon [s] (the swing's rest: the sole's last travel)
// when the sole touched more than kEarlyRise [m] above the ground it looked for
constexpr double kEarlyLand = 0.04;
constexpr double kEarlyRise = 0.005;
// and its sole has come within kEarlyTravel [m] of its landing (over a rise, short of it, the
// sole is held at the touched height while it travels on: it would land across the rise's edge)
constexpr double kEarlyTravel = 0.01;

// how far below its planned landing `land` a foot may go on with the hip `hip_height` above the
// plan's ground `ground` and midway between the landing and the stance sole `stance`: the leg
// stretched to `reach` (the step down's rule, walking::StepDownDrop)
double LateReach(double reach, double hip_height, double ground, const Eigen::Vector3d& land,
                 const Eigen::Vector3d& stance) {
  const double d = 0.5 * (land - stance).head<2>().norm();
  if (!(reach > d) || !(hip_height > 0)) return 0;
  return std::max(std::sqrt(reach * reach - d * d) - hip_height - (ground - land.z()), 0.0);
}
}  // namespace

double WalkController::SoleLag(int i, const walking::GaitState& g) const noexcept {
  // the foot's measured height over the other's, less its target's (> 0: above its target)
  const model::Kinematics& k = *kin_est_;
  const double measured = k.p_WSole(sole_[i]).z() - k.p_WSole(sole_[1 - i]).z();
  // (the stabilizer's leg-length difference dz on the targets as SolveWalkJoints puts it)
  const double dz = (i == 0 ? 1.0 : -1.0) * stabilizer_.output().dz;
  const double target = g.feet.p[i].z() + foot_dz_[i] - g.feet.p[1 - i].z() - foot_dz_[1 - i] + dz;
  return measured - target;
}

double WalkController::MeasuredGround(int i, const walking::GaitState& g) noexcept {
  // the ground under foot i off the plan's: the other foot's ground and the soles' measured
  // height difference against the plan's (both on their grounds now)
  const model::Kinematics& k = *kin_est_;
  const double measured = k.p_WSole(sole_[i]).z() - k.p_WSole(sole_[1 - i]).z();
  const double planned = gen_.gait().step(g.step >= 0 ? g.step : 0).p.z() - g.feet.p[1 - i].z();
  ground_dz_[i] = ground_dz_[1 - i] + measured - planned;
  return ground_dz_[i];
}

void WalkController::LateDescent(int i, const walking::GaitState& g, double dt) noexcept {
  const double lag = SoleLag(i, g);
  const double step = std::min(kLateSpeed * dt, std::max(kLead - lag, 0.0));
  // the leg's reach below the plan, and as much more as the hips have gone down since the search
  // began (the CoM follows the foot), at most a swing height more (the stance knee bends)
  const double depth = late_depth_[i] + std::clamp(late_com0_[i] - com_dz_, 0.0,
                                                   gen_.gait().options().step_height);
  const double before = late_dz_[i];
  late_dz_[i] = std::max(late_dz_[i] - step, -depth);
  if (before > -depth && late_dz_[i] <= -depth) ++walk_stats_.late_missed;
}

bool WalkController::DcmPastStance(const walking::GaitState& g) const noexcept {
  const int st = 1 - g.swing;
  const Eigen::Rotation2Dd R(g.feet.yaw[st]);
  const Eigen::Vector2d e =
      R.inverse() * (stabilizer_.output().dcm - input_.support.centre[st]);
  const Eigen::Vector2d half =
      (input_.support.half_size[st].array() - stabilizer_.gains().support_margin).max(0.0);
  return std::abs(e.x()) > half.x() || std::abs(e.y()) > half.y();
}

void WalkController::Touchdown(const shm::SensorBlock& s, const walking::WalkSample& w,
                               double dt) noexcept {
  if (!walk_options_.touchdown) return;
  const walking::GaitState& g = w.gait;
  // only near the end of the descent: the sole within a swing height of its landing (a toe
  // scuffing a stair's nose higher up is not the ground), in the second half of the swing; a
  // touch is the sensor's vertical force risen by a twentieth of the weight over what it read in
  // the air (the foot's own weight and swing), two cycles in a row
  const double window = gen_.gait().options().step_height;
  for (int i = 0; i < 2; ++i) {
    const double z_plan = g.feet.p[i].z();
    const double fz = s.force[force_[i]].force[2];
    if (g.swing == i && g.step >= 0) {
      const walking::Footstep& step = gen_.gait().step(g.step);
      if (swing_step_[i] != g.step) {  // a new swing: from where the foot stands to the ground
        swing_step_[i] = g.step;
        lift_dz_[i] = foot_dz_[i];
        touched_[i] = late_[i] = late_landed_[i] = false;
        late_dz_[i] = 0;
        air_sum_[i] = air_fz_[i] = 0;
        air_n_[i] = touch_cycles_[i] = 0;
      }
      if (!touched_[i] && std::isfinite(fz)) {
        // the offset blends from where it lifted off to the ground last touched
        const double carried = lift_dz_[i] + (floor_dz_ - lift_dz_[i]) * std::min(g.swing_phase, 1.0);
        foot_dz_[i] = carried + late_dz_[i];
        if (g.swing_phase >= 0.2 && g.swing_phase < 0.5) {
          air_sum_[i] += fz;
          air_fz_[i] = air_sum_[i] / ++air_n_[i];
        }
        const double above = z_plan + foot_dz_[i] - step.p.z();
        const bool touching = g.swing_phase >= 0.5 && air_n_[i] > 0 && above <= window + floor_dz_ &&
                              fz - air_fz_[i] >= touch_load_;
        touch_cycles_[i] = touching ? touch_cycles_[i] + 1 : 0;
        if (touch_cycles_[i] >= 2) {
          touched_[i] = true;
          // held where the sole is (the servo lags: its target is below it while it descends)
          touch_z_[i] = z_plan + foot_dz_[i] + std::max(SoleLag(i, g), 0.0);
          const double rise = above - floor_dz_;  // over the ground it was looking for
          floor_dz_ = MeasuredGround(i, g);
          if (late_[i]) {  // met it below the plan: it lands now, the weight may move
            ++walk_stats_.late_touchdowns;
            walk_stats_.max_late_depth = std::max(walk_stats_.max_late_depth, -floor_dz_);
            gen_.AdjustStep(g.step, step.p.head<2>(), w.t + dt, false);
          } else {
            ++walk_stats_.early_touchdowns;
            // a step up found: the other foot trails on the lower ground until it is in the air
            if (rise > kEarlyRise) {
              rise_foot_ = i;
              ++walk_stats_.step_ups;
            }
            walk_stats_.max_touch_height = std::max(walk_stats_.max_touch_height, above);
            // the swing ends: the landing (the weight's transfer) comes now
            const double travel = (step.p - g.feet.p[i]).head<2>().norm();
            if (rise > kEarlyRise && travel < kEarlyTravel &&
                gen_.gait().step_land(g.step) - w.t > kEarlyLand)
              gen_.AdjustStep(g.step, step.p.head<2>(), w.t + kEarlyLand, false);
          }
        } else if (late_[i]) {  // on down, within the leg's reach, while the stance holds the DCM
          LateDescent(i, g, dt);
          if (!late_landed_[i] && DcmPastStance(g) &&
              gen_.AdjustStep(g.step, step.p.head<2>(), w.t + dt, false)) {
            late_landed_[i] = true;
            ++walk_stats_.late_dcm_cut;
          }
        } else if (w.t + dt >= gen_.gait().step_land(g.step) - 1e-9) {
          // the planned landing without contact: hold it while the foot goes on down
          late_depth_[i] = LateReach(walk_options_.gait.leg_reach, walk_options_.gait.hip_height,
                                     g.zmp.z(), step.p, g.feet.p[1 - i]);
          const double hold = late_depth_[i] / kLateSpeed + kLateSettle;
          if (late_depth_[i] > 0 && gen_.DelayLanding(g.step, hold)) late_[i] = true;
          late_com0_[i] = com_dz_;
        }
      }
    } else if (late_[i] && !touched_[i] && std::isfinite(fz)) {
      // landed in the plan before contact: it searches on down in support
      touch_cycles_[i] = fz - air_fz_[i] >= touch_load_ ? touch_cycles_[i] + 1 : 0;
      if (touch_cycles_[i] >= 2) {
        touched_[i] = true;
        touch_z_[i] = z_plan + foot_dz_[i];
        floor_dz_ = MeasuredGround(i, g);
        ++walk_stats_.late_touchdowns;
        walk_stats_.max_late_depth = std::max(walk_stats_.max_late_depth, -floor_dz_);
      } else {
        LateDescent(i, g, dt);
        foot_dz_[i] = floor_dz_ + late_dz_[i];  // carried down to the ground last touched
      }
    }
    if (touched_[i]) foot_dz_[i] = touch_z_[i] - z_plan;  // held where it touched
  }
  // the CoM goes with the lower of the feet (a late foot going on down, the ground found lower
  // or higher): the legs keep the plan's reach; at most as fast as a late foot goes down
  if (rise_foot_ >= 0 && g.swing == 1 - rise_foot_ && g.swing_phase >= 0.5) rise_foot_ = -1;  // it left
  const double target = std::min(foot_dz_[0], foot_dz_[1]);
  com_dz_ += std::clamp(target - com_dz_, -kLateSpeed * dt, kComRise * dt);
}

}  // namespace ohrp::controllers
