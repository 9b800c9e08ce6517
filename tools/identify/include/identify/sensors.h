// ohrp identify --sensors LOG: the sensors' bias and noise from a data log of the robot standing
// still (hw_driver --log or sim_host --log while `posture` holds), and the actuators' bandwidth
// from an excite chirp (ohrp identify --joints). See docs/identify.md.
//
// Noise: the std of a channel less its centred moving average of `width` samples; for white
// noise of std s that residual has std s sqrt(1 - 1/width), which is divided out. Its standard
// error s / sqrt(2 (n - 1)) (white Gaussian noise). Bias: a mean, its standard error from batch
// means (kBatches blocks: covers slowly correlated noise). Still: the moving average's range on
// each joint and IMU channel below max(the tolerance, 8 noise / sqrt(width)), else refused.
//
// What a still log observes: the gyro's bias (the rate is zero); the accelerometer's along
// gravity (|mean| - g) and, with the IMU's orientation logged (IMU_qw..qz), across it too (the
// bias is then relative to that orientation: the estimator's or the board's, whatever its own
// error); the noise of every channel. Not the encoders' bias: a held joint reads q + bias and
// nothing in one still log tells q.
#pragma once

#include <string>
#include <vector>

#include "identify/joints.h"
#include "robot_model/sensor_params.h"

namespace ohrp::identify {

inline constexpr int kBatches = 20;

struct Stat {
  double value = 0, se = 0;
};

// the mean, its standard error from kBatches batch means
Stat MeanOf(const std::vector<double>& x);
// the white noise's std after the centred moving average of `width` (odd) samples is taken out
Stat NoiseStd(const std::vector<double>& x, int width);
// the range (max - min) of the centred moving average of `width` samples: the slow motion
double SlowRange(const std::vector<double>& x, int width);

// The noise of a channel that the robot's own motion moves too (a joint's velocity or torque, the
// IMU's orientation): x and each of `motion` (the signals that measure that motion, as long as
// x) high-passed by the centred moving average of `width` samples; x's part fitted away by least
// squares on them (with a constant); the noise the std of the remainder over its degrees of
// freedom (n - the fit's rank), divided by sqrt(1 - 1/width) as NoiseStd; standard error
// s / sqrt(2 dof). `*explained`: the share of x's high-passed variance the fit took (0..1).
// No regressors: NoiseStd's estimate (less the constant's degree of freedom).
Stat NoiseBeyondMotion(const std::vector<double>& x, const std::vector<std::vector<double>>& motion,
                       int width, double* explained = nullptr);
// The rotation vector [rad] of each logged orientation (w x y z, world from IMU) relative to the
// first, in the first's frame (for small motion, the IMU's): the orientation's error per axis
// as the sensor model makes it (robot_model/sensor_params.h SensorModel::Orientation).
void OrientationErrors(const std::vector<double>& w, const std::vector<double>& x,
                       const std::vector<double>& y, const std::vector<double>& z,
                       std::vector<double> out[3]);

struct SensorOptions {
  double from = 0, to = 1e300;  // [s] the still window in the log's time
  int width = 51;               // moving average [samples]
  double gravity = 9.81;        // [m/s^2]
  double joint_still = 2e-3;    // [rad] tolerated slow motion of a joint
  double gyro_still = 5e-3;     // [rad/s]
  double accel_still = 0.05;    // [m/s^2]
  double min_gravity_stiffness = 2.0;  // [N m/rad] --model: below it an encoder bias is not observable
  double orientation_still = 2e-3;  // [rad] tolerated slow turn of the IMU's orientation
  double max_explained = 0.5;  // a warning when the motion explains more of a channel's variance
};

struct ImuEstimate {
  std::string name;
  Stat gyro_bias[3], gyro_noise[3], accel_noise[3], accel_mean[3];
  Stat accel_bias_along_g;     // |mean| - g
  bool oriented = false;           // the log has the IMU's orientation
  Stat accel_bias[3];          // with it: mean - R^T (0, 0, g) per axis
  // with it: the orientation's noise per axis of its error's rotation vector [rad], beyond what
  // the gyro's integral explains, and all three pooled (the sensor file's one value)
  Stat orientation_noise[3], orientation_noise_pooled;
  double orientation_explained[3] = {};
};

struct SensorEstimates {
  size_t samples = 0;
  double period = 0;
  std::vector<std::string> joints, forces;
  std::vector<Stat> encoder_noise;  // per joint [rad]
  std::vector<Stat> ft_noise;       // per F/T sensor, 6 axes [N, N m]
  std::vector<double> joint_mean;   // per joint, its mean position [rad]
  std::vector<Stat> joint_tau;      // per joint, its mean torque (tau_J; value NaN without it)
  // with a model (EstimateEncoderBias): per joint the bias, its gravity stiffness, observable
  std::vector<Stat> encoder_bias;
  std::vector<double> gravity_stiffness;  // [N m/rad] -dG_j/dq_j at the posture
  std::vector<bool> encoder_observable;
  std::vector<Stat> ft_mean;        // per F/T sensor, 6 axes: the mean reading
  // with a model (EstimateForceBias): the static load of each sensor's subtree and the offset
  std::vector<double> ft_expected;
  std::vector<Stat> ft_bias;
  std::vector<ImuEstimate> imus;
  // per joint, beyond the motion (NoiseBeyondMotion): the velocity's noise (dq_J columns:
  // sim_host/hw_driver --log-dq; empty without) against the encoder's central difference, the
  // torque's (tau_J; value NaN without) against the joint's angle and velocity
  std::vector<Stat> velocity_noise, torque_noise;
  std::vector<double> velocity_explained, torque_explained;
  std::vector<std::string> warnings;  // the motion explains more than max_explained of a channel
};

// Reads a data log's columns (time, then q_J/qref_J, F_fx.., IMU_gx..) within the window and
// estimates; false with `*error` when the log is unreadable, too short or not still.
bool EstimateSensors(const std::string& path, const SensorOptions& o, SensorEstimates* out,
                     std::string* error);

// ohrp identify --sensors: the table on stdout, OUT_DIR/sensors.json. Exit code 0 or 2.
// The estimates as the simulator's sensor file (robot_model/sensor_params.h): the noise of every
// channel, the gyro bias, the accelerometer bias when the orientation was logged (else 0), the
// encoder and F/T bias 0 (not identified); each entry's standard errors as its note.
model::SensorParams SensorFileOf(const SensorEstimates& s);
bool WriteSensorFile(const SensorEstimates& s, const std::string& log, const std::string& path,
                     std::string* error);

// The F/T offsets (`ft_bias`) of a log whose F/T sensors' subtrees hang free (the rig), against
// the model's static load at the logged joints' means (the rest of the posture the keyframe's):
// sensors_ft_bias.cc has the closed form. False with `*error` when the model lacks a joint or
// sensor site, or when a subtree touches something at that posture (a foot on the floor).
bool EstimateForceBias(const JointModel& model, double gravity, SensorEstimates* s,
                       std::string* error);

// The encoder biases of a still log of the robot on the rig (its base fixed, nothing touching),
// from the servos' steady torques against the model's gravity torques (sensors_encoder_bias.cc
// has the closed form). Joints whose gravity stiffness is below `min_stiffness` [N m/rad] are not
// observable (left out, said). False with `*error` without torque columns or model joints.
bool EstimateEncoderBias(const JointModel& model, double min_stiffness, SensorEstimates* s,
                         std::string* error);

// `model`: when given (--model), the F/T offsets too (EstimateForceBias)
int IdentifySensors(const std::string& log, const std::string& out_dir, const SensorOptions& o,
                    const JointModel& model = {});

// The actuator's bandwidth from a chirp on the reference: per window of two of the reference's
// periods (between its upward crossings of its mean), a sinusoid fitted to ref and to q; the
// magnitude |q| / |ref| against the window's frequency (the reference's phase interpolated
// between its crossings of its mean, so that the chirp's rising frequency fits); the -3 dB
// frequency where the magnitude first falls below 1 / sqrt(2) (0 dB: q follows ref), from a
// straight line through the windows around it, its standard error from that line's (its
// residual's scatter or the magnitudes' own standard errors, the larger) and the window's span of
// the chirp's frequencies (span / sqrt(12), in quadrature). gain0 (the mean of the
// three lowest windows) is reported: a joint whose gravity load takes some of the servo's
// stiffness has gain0 < 1.
struct Bandwidth {
  bool found = false;       // false: the magnitude stays above -3 dB up to f_max
  double f = 0, f_se = 0;   // [Hz]; f_se: the fit's and the window's frequency span's
  double f_fit_se = 0;      // [Hz] the line's alone
  double gain0 = 0, f_max = 0;
  std::vector<double> freq, mag, mag_se;  // per window
};
bool EstimateBandwidth(const JointLog& log, Bandwidth* b, std::string* error);

}  // namespace ohrp::identify
