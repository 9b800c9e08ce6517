// Touchdown (issue 30 item 4; controllers/walk.h): the landing foot's own force/torque sensor
// tells when it meets the ground.
// - Early (ground higher than the plan's: an unseen step, a stone, a slope that rises sooner):
//   from then on its sole is held at that height instead of being pushed on down to where the
//   plan expected the ground (which would tip the robot over the higher foot), and it supports
//   the robot there.
// - Late (ground lower than the plan's: an unseen step down, a hole): at its planned landing the
//   foot has not met the ground. The landing is held (Gait::DelayLanding: the ZMP stays on the
//   stance sole, the later steps wait) while the foot goes on down at kLateSpeed, as far as the
//   leg reaches with the hip midway between the soles; when it meets the ground it is held there
//   and the landing happens at once (the weight's transfer begins).
// When that foot next lifts off, a higher ground's offset is blended back out over its swing, so
// it lands where the plan says unless it meets the ground early again; a lower ground's offset
// is kept (the floor stays lower; a foot that meets it higher again touches early). The CoM
// goes down with the lower of the feet's offsets (com_dz_), so the legs keep the plan's reach.
#include <algorithm>
#include <cmath>

#include "controllers/walk.h"

namespace ohrp::controllers {

namespace {
// a late foot's descent below its planned landing [m/s], and how long the landing is held beyond
// that descent [s]. Measured on walk_unseen_step_down (docs/walking.md): 0.2 m/s held the landing
// too long (the CoM ran on past the stance toe: fell); at 0.6 m/s the servo lags the target and
// the foot meets the floor after the hold
constexpr double kLateSpeed = 0.6;
constexpr double kLateSettle = 0.03;

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
    if (g.swing == i && g.step >= 0) {
      const walking::Footstep& step = gen_.gait().step(g.step);
      if (swing_step_[i] != g.step) {  // a new swing: what the last touchdown left blends out
        swing_step_[i] = g.step;
        lift_dz_[i] = foot_dz_[i];
        touched_[i] = late_[i] = false;
        late_dz_[i] = 0;
        air_sum_[i] = air_fz_[i] = 0;
        air_n_[i] = touch_cycles_[i] = 0;
      }
      const double fz = s.force[force_[i]].force[2];
      if (!touched_[i] && std::isfinite(fz)) {
        // a higher ground left behind blends out; a lower one is kept (the floor stays lower)
        const double carried = lift_dz_[i] < 0 ? lift_dz_[i] : lift_dz_[i] * (1.0 - g.swing_phase);
        foot_dz_[i] = carried + late_dz_[i];
        if (g.swing_phase >= 0.2 && g.swing_phase < 0.5) {
          air_sum_[i] += fz;
          air_fz_[i] = air_sum_[i] / ++air_n_[i];
        }
        const double above = z_plan + foot_dz_[i] - step.p.z();
        const bool touching = g.swing_phase >= 0.5 && air_n_[i] > 0 && above <= window &&
                              fz - air_fz_[i] >= touch_load_;
        touch_cycles_[i] = touching ? touch_cycles_[i] + 1 : 0;
        if (touch_cycles_[i] >= 2) {
          touched_[i] = true;
          touch_z_[i] = z_plan + foot_dz_[i];
          if (late_[i]) {  // met it below the plan: it lands now, the weight may move
            ++walk_stats_.late_touchdowns;
            walk_stats_.max_late_depth = std::max(walk_stats_.max_late_depth, -late_dz_[i]);
            gen_.AdjustStep(g.step, step.p.head<2>(), w.t + dt, false);
          } else {
            ++walk_stats_.early_touchdowns;
            walk_stats_.max_touch_height = std::max(walk_stats_.max_touch_height, above);
          }
        } else if (late_[i]) {  // on down, within the leg's reach
          const double before = late_dz_[i];
          late_dz_[i] = std::max(late_dz_[i] - kLateSpeed * dt, -late_depth_[i]);
          if (before > -late_depth_[i] && late_dz_[i] <= -late_depth_[i]) ++walk_stats_.late_missed;
        } else if (w.t + dt >= gen_.gait().step_land(g.step) - 1e-9) {
          // the planned landing without contact: hold it while the foot goes on down
          late_depth_[i] = LateReach(walk_options_.gait.leg_reach, walk_options_.gait.hip_height,
                                     g.zmp.z(), step.p, g.feet.p[1 - i]);
          const double hold = late_depth_[i] / kLateSpeed + kLateSettle;
          if (late_depth_[i] > 0 && gen_.DelayLanding(g.step, hold)) late_[i] = true;
        }
      }
    }
    if (touched_[i]) foot_dz_[i] = touch_z_[i] - z_plan;  // held where it touched
  }
  // the CoM goes down with the lower of the feet (a late foot going on down, a floor found
  // lower): the legs keep the plan's reach; at most as fast as a late foot goes down
  const double target = std::min({0.0, foot_dz_[0], foot_dz_[1]});
  com_dz_ += std::clamp(target - com_dz_, -kLateSpeed * dt, kLateSpeed * dt);
}

}  // namespace ohrp::controllers
