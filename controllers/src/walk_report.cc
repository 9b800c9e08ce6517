// The walk controller's log (written when it closes) and its report after the run (see walk.h).
#include <cmath>
#include <cstdio>
#include <ostream>

#include "controllers/walk.h"
#include "robot_model/output_file.h"

namespace ohrp::controllers {

//---------------- log and report ----------------

void WalkController::on_close() {
  if (channel_) channel_->Close();  // no more commands; its counts stay for the report
  WriteLiveRecord();
  if (walk_options_.log_file.empty()) return;
  std::string text =
      "t,com_ref_x,com_ref_y,com_ref_z,com_x,com_y,com_z,zmp_ref_x,zmp_ref_y,zmp_des_x,"
      "zmp_des_y,zmp_x,zmp_y,dcm_x,dcm_y,left_x,left_y,left_z,left_yaw,right_x,right_y,"
      "right_z,right_yaw,support_left,support_right,frame_x,frame_y,frame_yaw,"
      "foot_roll_left,foot_pitch_left,foot_roll_right,foot_pitch_right,base_roll\n";
  char value[32];
  for (const auto& row : log_) {
    for (size_t c = 0; c < row.size(); ++c) {
      std::snprintf(value, sizeof value, c ? ",%.6g" : "%.6f", row[c]);
      text += value;
    }
    text += '\n';
  }
  model::WriteWholeFile(walk_options_.log_file, text, &log_error_);
}

std::string WalkController::Unverified() const {
  const WalkStats& w = walk_stats_;
  char buf[400];
  if (!started_) return "it never started walking (still standing up when the run ended)";
  if (w.steps_missed > 0) {
    std::snprintf(buf, sizeof buf,
                  "%d step(s) did not land: the first, step %d (%s foot, due at t = %.3f s), "
                  "carried at most %.0f N within a quarter of its duration of that time or "
                  "before the weight was to move onto it (a landed foot carries %.0f N, a tenth "
                  "of the weight)",
                  w.steps_missed, w.first_missed_step + 1, walking::SideName(w.first_missed_foot),
                  w.first_missed_due, w.first_missed_load, land_load_);
    return buf;
  }
  if (!done()) {
    std::snprintf(buf, sizeof buf, "still walking when the run ended (%d of %d commands begun)",
                  w.commands_done, static_cast<int>(chunks_.size()));
    return buf;
  }
  if (next_to_land_ < gen_.gait().step_count()) {
    std::snprintf(buf, sizeof buf, "the landing of %d planned step(s) was never measured",
                  gen_.gait().step_count() - next_to_land_);
    return buf;
  }
  // standing on both feet, upright: each foot carries a quarter of the weight, and the base is
  // within the tipping angle of the soles (fall_watch.h)
  const double quarter = 2.5 * land_load_;
  const double tipping = std::atan2(sole_reach_, std::max(com_height_, 1e-3));
  if (!(end_load_[0] >= quarter && end_load_[1] >= quarter)) {
    std::snprintf(buf, sizeof buf,
                  "at the end the feet carry %.0f N (left) and %.0f N (right): not standing on "
                  "both (each should carry a quarter of the weight, %.0f N)",
                  end_load_[0], end_load_[1], quarter);
    return buf;
  }
  if (!(end_tilt_ >= 0 && end_tilt_ <= tipping)) {
    std::snprintf(buf, sizeof buf,
                  "at the end the base is tilted %.1f deg from %s (the soles' tipping angle "
                  "is %.1f deg)",
                  end_tilt_ * 180 / M_PI, tilt_reference(), tipping * 180 / M_PI);
    return buf;
  }
  return std::string();
}

std::string WalkController::failure() const {
  const std::string balance = BalanceController::failure();
  if (!balance.empty()) return balance;
  if (!log_error_.empty()) return "--log: " + log_error_;  // the walk's log is not all there
  const std::string walk = Unverified();
  return walk.empty() ? walk : "the walk is not done: " + walk;
}

void WalkController::report(std::ostream& out) const {
  BalanceController::report(out);
  for (const std::string& note : notes_) out << "walk: note: " << note << "\n";
  char buf[640];
  const WalkStats& w = walk_stats_;
  const std::string unverified = Unverified();
  std::string what;
  if (fall().cause != FallCause::kNone) {
    what = "NOT done: the robot fell (" + std::string(FallCauseName(fall().cause)) + ")";
  } else if (unverified.empty()) {
    what = "done, standing on both feet";
  } else {
    what = "NOT done: " + unverified;
  }
  char commands[160];
  if (channel_) {
    std::snprintf(commands, sizeof commands, "%d commands (live: %d received, %d refused)",
                  w.commands_done, channel_->received(), channel_->refused());
  } else if (!replay_.empty()) {
    std::snprintf(commands, sizeof commands, "%d commands (--live-replay: %d recorded)", w.commands_done,
                  static_cast<int>(replay_.size()));
  } else {
    std::snprintf(commands, sizeof commands, "%d of %d commands", w.commands_done,
                  static_cast<int>(chunks_.size()));
  }
  std::snprintf(buf, sizeof buf,
                "walk: %s; %s, %d of %d steps landed (measured)%s; walked %.2f s; "
                "max |CoM estimated - planned| %.1f mm, max |ZMP measured - desired| %.1f mm, "
                "plan frame corrections up to %.1f mm; %llu cycles whose leg IK did not "
                "converge\n",
                what.c_str(), commands, w.steps_done,
                w.steps_planned, w.stopped ? (channel_ ? " (stopped)" : " (stopped by SIGUSR1)") : "",
                w.walk_cycles * header().control_period, w.max_com_error * 1e3,
                w.max_zmp_error * 1e3, w.max_frame_drift * 1e3,
                static_cast<unsigned long long>(w.ik_failures));
  out << buf;
  if (w.steps_fitted > 0) {
    std::snprintf(buf, sizeof buf,
                  "walk: the plan frame's correction moved %d step(s) out of the step limits "
                  "against the stance foot; each was set back within them before it began, by up "
                  "to %.1f mm and %.1f deg\n",
                  w.steps_fitted, w.max_fit * 1e3, w.max_fit_yaw * 180 / M_PI);
    out << buf;
  }
  if (w.steps_adjusted > 0) {
    std::snprintf(buf, sizeof buf,
                  "walk: stepping strategy: %d landing(s) moved where the measured DCM needed them "
                  "(beyond what the stance ankle takes back), by up to %.1f mm\n",
                  w.steps_adjusted, w.max_adjust * 1e3);
    out << buf;
  }
  if (w.steps_shortened > 0) {
    std::snprintf(buf, sizeof buf,
                  "walk: stepping strategy: %d swing(s) landed sooner (their landing out of reach "
                  "in time), by up to %.0f ms\n",
                  w.steps_shortened, w.max_shorten * 1e3);
    out << buf;
  }
  if (w.early_touchdowns > 0) {
    std::snprintf(buf, sizeof buf,
                  "walk: touchdown: %d swing foot/feet met the ground before their planned landing "
                  "(by their force/torque sensors) and were held there, up to %.1f mm above the "
                  "plan's ground\n",
                  w.early_touchdowns, w.max_touch_height * 1e3);
    out << buf;
    if (w.step_ups > 0) {
      std::snprintf(buf, sizeof buf,
                    "walk: touchdown: %d of them found a step up (more than 5 mm above the ground "
                    "looked for): the torso's pitch was limited to %.2f rad until the trailing foot "
                    "was in the air\n",
                    w.step_ups, WalkController::kStepUpTorsoPitch);
      out << buf;
    }
  }
  if (w.late_touchdowns > 0 || w.late_missed > 0) {
    std::snprintf(buf, sizeof buf,
                  "walk: touchdown: %d swing foot/feet had not met the ground at their planned "
                  "landing, went on down (the landing held) and met it, up to %.1f mm below the "
                  "plan's ground; %d reached the leg's reach without contact; %d landed before "
                  "contact (the DCM at the stance sole's edge) and searched on in support\n",
                  w.late_touchdowns, w.max_late_depth * 1e3, w.late_missed, w.late_dcm_cut);
    out << buf;
  }
  if (w.ik_failures > 0) {
    static const char* what[] = {"the left leg cannot reach its sole's target",
                                 "the right leg cannot reach its sole's target",
                                 "the CoM cannot be put where planned"};
    std::snprintf(buf, sizeof buf, "walk: the first IK failure at t = %.3f s: %s\n",
                  w.first_ik_failure, what[w.first_ik_failure_what]);
    out << buf;
  }
}

}  // namespace ohrp::controllers
