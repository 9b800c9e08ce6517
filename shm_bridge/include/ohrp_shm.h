/* The robot segment from C (and from any language that can call C: Python's ctypes, Rust,
 * Julia...). One handle is either the CONTROLLER of a segment (the paper's robot adaptor: it
 * reads the sensors of each cycle and writes the commands answering it, in lock-step with
 * sim_host or hw_driver) or an OBSERVER (read-only: it sees the sensors and the last commands,
 * never slows the lock-step, and many may watch at once).
 *
 *   char err[512];
 *   ohrp_robot* r = ohrp_open("hrp1s", 2.0, err, sizeof err);      // or ohrp_observe(...)
 *   if (!r) { fprintf(stderr, "%s\n", err); exit(2); }
 *   int n = ohrp_njoint(r);
 *   while (ohrp_read(r) == OHRP_OK) {
 *     ohrp_get_q(r, q);                        // n values, joint-id order
 *     ... compute q_ref ...
 *     ohrp_write(r, NULL, q_ref, NULL, NULL, kp, kd);   // NULL: mode position, 0, defaults
 *   }
 *   ohrp_close(r);
 *
 * Units and conventions are the segment's (shm_bridge/include/shm_bridge/layout.h): SI, joint
 * angles in rad, quaternions (w, x, y, z), forces of the child side on the parent side in the
 * sensor frame. Arrays are filled in the segment's order (ohrp_joint_name gives the names).
 * The per-cycle calls (ohrp_read, ohrp_get_*, ohrp_write) do not allocate. A handle is used by
 * one thread at a time. Link with -lohrp_shm_c. */
#ifndef OHRP_SHM_H_
#define OHRP_SHM_H_

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ohrp_robot ohrp_robot;

/* results of ohrp_read and ohrp_write */
enum {
  OHRP_OK = 0,               /* fresh sensors read / commands written */
  OHRP_TIMEOUT = 1,          /* nothing arrived in time; the producer is still alive */
  OHRP_PRODUCER_GONE = 2,    /* the producer's process is gone */
  OHRP_PRODUCER_STOPPED = 3, /* the producer ended its run (see ohrp_producer_failed) */
  OHRP_NOT_OPEN = 4,         /* a NULL or closed handle */
  OHRP_DROPPED = 5,          /* the producer let this controller go (it missed a deadline) */
  OHRP_NOT_CONTROLLER = 6,   /* ohrp_write on an observer */
  OHRP_SYNC_CORRUPTED = 7,   /* the segment's wake-up words were scribbled on: restart the producer */
  OHRP_SEGMENT_CORRUPTED = 8 /* the segment's file was truncated or its header overwritten by
                                another process: restart the producer */
};

/* joint modes of ohrp_write (as the segment's JointMode) */
enum { OHRP_NAME_LEN = 32 }; /* bytes of a name field in the segment (ohrp::shm::kNameLen) */
enum { OHRP_MODE_OFF = 0, OHRP_MODE_POSITION = 1, OHRP_MODE_VELOCITY = 2, OHRP_MODE_TORQUE = 3 };

/* producer kinds (ohrp_producer_kind) */
enum { OHRP_PRODUCER_UNKNOWN = 0, OHRP_PRODUCER_SIMULATION = 1, OHRP_PRODUCER_HARDWARE = 2,
       OHRP_PRODUCER_REPLAY = 3 };

/* the segment's capacities: arrays of these sizes always suffice */
int ohrp_max_joints(void);
int ohrp_max_force_sensors(void);
int ohrp_max_imus(void);

/* ---- attach / detach ---- */

/* Attaches as the segment's controller; read_timeout [s] is how long ohrp_read waits for a
 * cycle. NULL on failure, with a sentence saying what failed and what to do in err (when err
 * is not NULL; truncated to errlen). */
ohrp_robot* ohrp_open(const char* segment, double read_timeout, char* err, size_t errlen);
/* Attaches as an observer (read-only); ohrp_read then waits up to read_timeout [s] for a
 * cycle newer than the last it returned. */
ohrp_robot* ohrp_observe(const char* segment, double read_timeout, char* err, size_t errlen);
/* Detaches (a controller frees its slot) and frees the handle. NULL is fine. */
void ohrp_close(ohrp_robot* r);

/* ---- the header (fixed while attached) ---- */

int ohrp_is_controller(const ohrp_robot* r);
const char* ohrp_robot_name(const ohrp_robot* r);
int ohrp_producer_kind(const ohrp_robot* r);
int ohrp_njoint(const ohrp_robot* r);
int ohrp_nforce(const ohrp_robot* r);
int ohrp_nimu(const ohrp_robot* r);
/* passive joints: joints no actuator drives (e.g. Cassie's shin and tarsus), read-only */
int ohrp_npassive(const ohrp_robot* r);
const char* ohrp_joint_name(const ohrp_robot* r, int i); /* NULL when i is out of range */
const char* ohrp_force_name(const ohrp_robot* r, int i);
const char* ohrp_imu_name(const ohrp_robot* r, int i);
const char* ohrp_passive_name(const ohrp_robot* r, int i);
/* index of a joint / force sensor / IMU by name, -1 when there is none */
int ohrp_joint_index(const ohrp_robot* r, const char* name);
int ohrp_force_index(const ohrp_robot* r, const char* name);
int ohrp_imu_index(const ohrp_robot* r, const char* name);
double ohrp_control_period(const ohrp_robot* r); /* [s] */
double ohrp_physics_period(const ohrp_robot* r); /* [s], 0 for hardware */
/* njoint values each; any pointer may be NULL */
void ohrp_joint_limits(const ohrp_robot* r, double* q_min, double* q_max, double* tau_max);
void ohrp_default_gains(const ohrp_robot* r, double* kp, double* kd);

/* ---- the cycle ---- */

/* Waits for the next cycle's sensors and keeps them in the handle (ohrp_get_*). */
int ohrp_read(ohrp_robot* r);
/* of the last block read */
uint64_t ohrp_cycle(const ohrp_robot* r);
double ohrp_time(const ohrp_robot* r);      /* [s] */
uint32_t ohrp_status(const ohrp_robot* r);  /* the segment's status bits */
void ohrp_get_q(const ohrp_robot* r, double* q);      /* njoint [rad or m] */
void ohrp_get_dq(const ohrp_robot* r, double* dq);    /* njoint [rad/s or m/s] */
void ohrp_get_tau(const ohrp_robot* r, double* tau);  /* njoint [N m or N] */
void ohrp_get_passive_q(const ohrp_robot* r, double* q);    /* npassive [rad or m] */
void ohrp_get_passive_dq(const ohrp_robot* r, double* dq);  /* npassive [rad/s or m/s] */
/* nforce x 6: fx fy fz tx ty tz [N, N m] */
void ohrp_get_force(const ohrp_robot* r, double* ft);
/* nimu x 10: gyro xyz [rad/s], accel xyz [m/s^2], quaternion wxyz */
void ohrp_get_imu(const ohrp_robot* r, double* imu);
/* simulation ground truth, 13 values: base position xyz, quaternion wxyz, linear velocity,
 * angular velocity (world). Returns 1 when valid (a simulating producer), 0 otherwise. */
int ohrp_get_sim_truth(const ohrp_robot* r, double* truth);

/* Writes the commands answering the last cycle read (controller only). njoint values each;
 * NULL arrays mean: mode OHRP_MODE_POSITION, q_ref = the q just read, dq_ref 0, tau_ff 0,
 * kp / kd the producer's default gains. */
int ohrp_write(ohrp_robot* r, const int32_t* mode, const double* q_ref, const double* dq_ref,
               const double* tau_ff, const double* kp, const double* kd);
/* Observer: the last commands the controller wrote (NULL arrays skipped); 1 when there were
 * any, 0 otherwise. */
int ohrp_last_commands(const ohrp_robot* r, int32_t* mode, double* q_ref, double* dq_ref,
                       double* tau_ff, double* kp, double* kd);
/* Observer: the controller's self-collision guard in its last commands (the command block's
 * guard record, ohrp::shm::GuardRecord): *holding 1 when it held the motion that cycle, *holds
 * the hold episodes begun, *distance the held pair's predicted distance [m]; link_a / link_b
 * (each OHRP_NAME_LEN bytes, NUL-terminated; NULL skipped) the pair. 1 when there were
 * commands, 0 otherwise (a controller without the guard writes zeros). */
int ohrp_last_guard(const ohrp_robot* r, int32_t* holding, uint64_t* holds, double* distance,
                    char* link_a, char* link_b);

/* ---- camera images (shm_bridge/images.h) ---- */

/* results of ohrp_read_image */
enum {
  OHRP_IMAGE_OK = 0,          /* a frame was copied */
  OHRP_IMAGE_NO_FRAME = 1,    /* no frame newer than after_frame (none asked for, or not yet) */
  OHRP_IMAGE_BUSY = 2,        /* the producer kept rewriting the slot: retry */
  OHRP_IMAGE_BAD_CAMERA = 3,  /* no such camera */
  OHRP_IMAGE_TOO_SMALL = 4,   /* rgb_len or depth_len is smaller than the frame */
  OHRP_IMAGE_NOT_OPEN = 5
};

int ohrp_ncamera(const ohrp_robot* r);
const char* ohrp_camera_name(const ohrp_robot* r, int i); /* NULL when i is out of range */
int ohrp_camera_index(const ohrp_robot* r, const char* name);
/* camera i's size [pixel] and vertical field of view [deg] (pointers may be NULL); 0 when i
 * is out of range */
int ohrp_camera_info(const ohrp_robot* r, int i, int* width, int* height, double* fovy);
/* Asks the producer for the images of the cameras in `mask` (bit i: camera i; 0 withdraws;
 * ohrp_close withdraws too). The producer renders (sim_host) or delivers (hw_driver) only
 * what somebody asks for. 1 when accepted, 0 otherwise (a bit names no camera, or 16
 * programs ask already). A set-up call: it may allocate. */
int ohrp_request_images(ohrp_robot* r, uint32_t mask);
/* Copies the latest frame of camera `camera` whose counter is greater than `after_frame` (0:
 * any): RGB8 width x height x 3, top row first, into `rgb` (rgb_len bytes); the depth [m],
 * width x height floats, into `depth` when not NULL and the frame has one (depth_len floats);
 * its counter, capture time [s], size and whether it has depth into the pointers that are not
 * NULL. Does not wait for a new frame and does not allocate once ohrp_request_images ran. */
int ohrp_read_image(ohrp_robot* r, int camera, uint64_t after_frame, uint64_t* frame,
                    double* time, int* width, int* height, int* has_depth, uint8_t* rgb,
                    size_t rgb_len, float* depth, size_t depth_len);

/* 1 when the producer has ended its run after failing (e.g. a diverged simulation) */
int ohrp_producer_failed(const ohrp_robot* r);
/* a name for a result code ("ok", "timeout", ...) */
const char* ohrp_result_name(int result);

#ifdef __cplusplus
}
#endif

#endif /* OHRP_SHM_H_ */
