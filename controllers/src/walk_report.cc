// The walk controller's log (written when it closes) and its report after the run (see walk.h).
#include <cstdio>
#include <ostream>

#include "controllers/walk.h"

namespace ohrp::controllers {

//---------------- log and report ----------------

void WalkController::on_close() {
  if (walk_options_.log_file.empty()) return;
  FILE* f = std::fopen(walk_options_.log_file.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "walk: cannot write the log %s\n", walk_options_.log_file.c_str());
    return;
  }
  std::fprintf(f, "t,com_ref_x,com_ref_y,com_ref_z,com_x,com_y,com_z,zmp_ref_x,zmp_ref_y,zmp_des_x,"
                  "zmp_des_y,zmp_x,zmp_y,dcm_x,dcm_y,left_x,left_y,left_z,left_yaw,right_x,right_y,"
                  "right_z,right_yaw,support_left,support_right,frame_x,frame_y,frame_yaw,"
                  "foot_roll_left,foot_pitch_left,foot_roll_right,foot_pitch_right\n");
  for (const auto& row : log_) {
    for (size_t c = 0; c < row.size(); ++c) std::fprintf(f, c ? ",%.6g" : "%.6f", row[c]);
    std::fputc('\n', f);
  }
  std::fclose(f);
}

void WalkController::report(std::ostream& out) const {
  BalanceController::report(out);
  char buf[640];
  const WalkStats& w = walk_stats_;
  std::snprintf(buf, sizeof buf,
                "walk: %s; %d of %d commands, %d of %d steps landed%s; walked %.2f s; max |CoM "
                "estimated - planned| %.1f mm, max |ZMP measured - desired| %.1f mm, plan frame "
                "corrections up to %.1f mm; %llu cycles whose leg IK did not converge\n",
                !started_ ? "never started walking (still standing up)"
                          : done() ? "done, standing on both feet" : "still walking at the end",
                w.commands_done, static_cast<int>(chunks_.size()), w.steps_done, w.steps_planned,
                w.stopped ? " (stopped by SIGUSR1)" : "", w.walk_cycles * header().control_period,
                w.max_com_error * 1e3, w.max_zmp_error * 1e3, w.max_frame_drift * 1e3,
                static_cast<unsigned long long>(w.ik_failures));
  out << buf;
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
