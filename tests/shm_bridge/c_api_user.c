/* A controller and an observer written in C against ohrp_shm.h (compiled as C, so the header
 * is proved to be C). Called by c_api_test.cc. Each returns 0 on success, else the number of
 * the check that failed. */
#include "c_api_user.h"

#include <string.h>

#include "ohrp_shm.h"

int c_controller(const char* segment, int cycles) {
  char err[512];
  ohrp_robot* r = ohrp_open(segment, 2.0, err, sizeof err);
  if (!r) return 1;
  if (!ohrp_is_controller(r) || ohrp_njoint(r) != 3 || ohrp_nforce(r) != 1 || ohrp_nimu(r) != 1)
    return 2;
  if (strcmp(ohrp_joint_name(r, 1), "knee") != 0 || ohrp_joint_name(r, 3) != NULL) return 3;
  if (ohrp_joint_index(r, "ankle") != 2 || ohrp_joint_index(r, "elbow") != -1) return 4;
  double q[3], kp[3], q_min[3];
  ohrp_default_gains(r, kp, NULL);
  ohrp_joint_limits(r, q_min, NULL, NULL);
  if (kp[0] != 300.0 || q_min[1] != -2.0) return 5;
  for (int k = 0; k < cycles; ++k) {
    if (ohrp_read(r) != OHRP_OK) return 6;
    if (ohrp_cycle(r) != (uint64_t)k) return 7;
    ohrp_get_q(r, q);
    double ft[6];
    ohrp_get_force(r, ft);
    if (q[2] != 100.0 * k + 2 || ft[2] != 10.0 * k) return 8;
    double q_ref[3] = {-q[0], -q[1], -q[2]};
    if (ohrp_write(r, NULL, q_ref, NULL, NULL, NULL, NULL) != OHRP_OK) return 9;
  }
  const int last = ohrp_read(r);
  ohrp_close(r);
  return last == OHRP_PRODUCER_STOPPED ? 0 : 10;
}

int c_refusals(const char* missing_segment, char* err, size_t errlen) {
  if (ohrp_open(missing_segment, 1.0, err, errlen) != NULL) return 1;
  if (ohrp_observe(missing_segment, 1.0, NULL, 0) != NULL) return 2;
  if (ohrp_read(NULL) != OHRP_NOT_OPEN || ohrp_njoint(NULL) != 0) return 3;
  if (strcmp(ohrp_result_name(OHRP_DROPPED), "dropped") != 0) return 4;
  ohrp_close(NULL);
  return 0;
}

int c_observer(const char* segment, uint64_t* last_cycle) {
  char err[512];
  ohrp_robot* r = ohrp_observe(segment, 2.0, err, sizeof err);
  if (!r) return 1;
  if (ohrp_is_controller(r)) return 2;
  if (ohrp_write(r, NULL, NULL, NULL, NULL, NULL, NULL) != OHRP_NOT_CONTROLLER) return 3;
  int result;
  while ((result = ohrp_read(r)) == OHRP_OK) {
    double q[3];
    ohrp_get_q(r, q);
    if (q[0] != 100.0 * (double)ohrp_cycle(r)) return 4;
    *last_cycle = ohrp_cycle(r);
  }
  double q_ref[3];
  const int have = ohrp_last_commands(r, NULL, q_ref, NULL, NULL, NULL, NULL);
  ohrp_close(r);
  if (result != OHRP_PRODUCER_STOPPED) return 5;
  if (!have || q_ref[2] != -(100.0 * (double)*last_cycle + 2)) return 6;
  return 0;
}
