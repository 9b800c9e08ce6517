// Touchdown on ground higher than the plan's (issue 30 item 4; controllers/walk.h): an unseen
// step, a stone, a slope that rises sooner than the plan thinks. The landing foot's own
// force/torque sensor tells when it meets the ground; from then on its sole is held at that
// height instead of being pushed on down to where the plan expected the ground (which would
// tip the robot over the higher foot), and it supports the robot there. When that foot next
// lifts off, the offset is blended back out over its swing, so it lands where the plan says
// unless it meets the ground early again (the next stone, the rest of a platform).
#include <cmath>

#include "controllers/walk.h"

namespace ohrp::controllers {

void WalkController::Touchdown(const shm::SensorBlock& s, const walking::WalkSample& w) noexcept {
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
      if (swing_step_[i] != g.step) {  // a new swing: what the last touchdown left blends out
        swing_step_[i] = g.step;
        lift_dz_[i] = foot_dz_[i];
        touched_[i] = false;
        air_sum_[i] = air_fz_[i] = 0;
        air_n_[i] = touch_cycles_[i] = 0;
      }
      const double fz = s.force[force_[i]].force[2];
      if (!touched_[i] && std::isfinite(fz)) {
        foot_dz_[i] = lift_dz_[i] * (1.0 - g.swing_phase);
        if (g.swing_phase >= 0.2 && g.swing_phase < 0.5) {
          air_sum_[i] += fz;
          air_fz_[i] = air_sum_[i] / ++air_n_[i];
        }
        const double above = z_plan + foot_dz_[i] - gen_.gait().step(g.step).p.z();
        const bool touching = g.swing_phase >= 0.5 && air_n_[i] > 0 && above <= window &&
                              fz - air_fz_[i] >= touch_load_;
        touch_cycles_[i] = touching ? touch_cycles_[i] + 1 : 0;
        if (touch_cycles_[i] >= 2) {
          touched_[i] = true;
          touch_z_[i] = z_plan + foot_dz_[i];
          ++walk_stats_.early_touchdowns;
          walk_stats_.max_touch_height = std::max(walk_stats_.max_touch_height, above);
        }
      }
    }
    if (touched_[i]) foot_dz_[i] = touch_z_[i] - z_plan;  // held where it touched
  }
}

}  // namespace ohrp::controllers
