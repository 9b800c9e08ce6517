// A logged row of the simulated state put back into a MuJoCo model (log_posture.h).
#include "log_posture.h"

namespace ohrp::runner {

bool PostureFromLogRow(const mjModel* m, mjData* d, const datalog::Table& log, size_t row,
                       bool all_joints, int* joints, std::string* error) {
  int set = 0;
  for (int j = 0; j < m->njnt; ++j) {
    const int adr = m->jnt_qposadr[j];
    if (m->jnt_type[j] == mjJNT_FREE) {
      const char* names[7] = {"base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy", "base_qz"};
      for (int k = 0; k < 7; ++k) {
        const int col = log.Column(names[k]);
        if (col < 0) return *error = std::string("the data log has no ") + names[k] + " column", false;
        d->qpos[adr + k] = log.col(col)[row];
      }
      mju_normalize4(d->qpos + adr + 3);
    } else if (m->jnt_type[j] == mjJNT_HINGE || m->jnt_type[j] == mjJNT_SLIDE) {
      const char* name = mj_id2name(m, mjOBJ_JOINT, j);
      const int col = name ? log.Column(std::string("q_") + name) : -1;
      if (col < 0 && all_joints)
        return *error = std::string("the data log has no q_") + (name ? name : "?") + " column", false;
      if (col < 0) continue;  // a passive joint not logged: as built
      d->qpos[adr] = log.col(col)[row];
      ++set;
    }
  }
  if (joints) *joints = set;
  return true;
}

}  // namespace ohrp::runner
