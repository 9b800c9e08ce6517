// Base state estimation from the IMU, the leg kinematics and the F/T contact (see estimator.h).
#include "robot_model/estimator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ohrp::model {
namespace {

constexpr double kMinSpecificForce = 1.0;  // below this the accelerometer shows no tilt [m/s^2]
// weight of the Reset's accelerometer sample, in samples, in the running mean that starts the
// tilt correction: the larger, the less one noisy gravity measurement right after Reset turns
// the estimate (by 1 / (N + 1) of its error) and the longer the Reset's own sample lingers
// (half of it after N cycles)
constexpr long kStartWeight = 20;
// low-pass of the gravity measurement (specific force minus the legs' acceleration) [Hz]: the
// differentiated leg velocity carries the gyro's noise times the lever from the soles to the
// IMU (at sim_host's default noise 5e-3 rad/s x 1.2 m / 5 ms = 1.7 m/s^2 per cycle, 10 deg of
// direction), about a tenth of it after this filter. Both terms pass the same filter, so a
// push's acceleration still cancels.
constexpr double kGravityCutoff = 5.0;

bool AllFinite(const double* x, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) return false;
  return true;
}

// the rotation by the rotation vector `w` [rad]
Eigen::Quaterniond Exp(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Eigen::Quaterniond(1, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle));
}

// the base rotation with yaw 0 whose up direction in the base frame is `up_B` (unit)
Eigen::Matrix3d TiltFromUp(const Eigen::Vector3d& up_B) {
  // R = Ry(pitch) Rx(roll) maps up_B to e_z: up_B = (-sin p, sin r cos p, cos r cos p)
  const double pitch = std::atan2(-up_B.x(), std::hypot(up_B.y(), up_B.z()));
  const double roll = std::atan2(up_B.y(), up_B.z());
  return (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace

BaseEstimator::BaseEstimator(Kinematics* kin, EstimatorOptions options)
    : kin_(kin), options_(options) {
  if (kin_ == nullptr) throw std::invalid_argument("BaseEstimator: no kinematics given");
  const RobotMap& robot = kin_->robot();
  if (!kin_->floating())
    throw std::invalid_argument("BaseEstimator: robot '" + robot.name +
                                "' has no free base to estimate");
  if (options_.imu < 0 || options_.imu >= static_cast<int>(robot.imus.size()))
    throw std::invalid_argument("BaseEstimator: robot '" + robot.name + "' has no IMU " +
                                std::to_string(options_.imu) + " (it has " +
                                std::to_string(robot.imus.size()) + ")");
  if (kin_->left_sole() < 0 || kin_->right_sole() < 0)
    throw std::invalid_argument("BaseEstimator: robot '" + robot.name +
                                "' does not have two soles (box geoms named *_SOLE)");
  imu_site_ = robot.imus[options_.imu].site_id;
  sole_[0] = kin_->left_sole();
  sole_[1] = kin_->right_sole();
  for (int i = 0; i < 2; ++i) {
    const SoleMap& sole = kin_->soles()[sole_[i]];
    if (sole.force_sensor < 0)
      throw std::invalid_argument("BaseEstimator: sole " + sole.name +
                                  " has no force/torque sensor between it and the leg");
    force_[i] = sole.force_sensor;
    force_site_[i] = robot.forces[sole.force_sensor].site_id;
  }
  J_.setZero(6, kin_->nv());
  gravity_ = Eigen::Vector3d(kin_->m()->opt.gravity).norm();
  if (gravity_ < kMinSpecificForce)
    throw std::invalid_argument("BaseEstimator: the model of robot '" + robot.name +
                                "' has no gravity, from which the IMU would tell the tilt");
}

//---------------- sensors ----------------

bool BaseEstimator::Finite(const shm::SensorBlock& s) const {
  const int n = kin_->njoint();
  const shm::Imu& imu = s.imu[options_.imu];
  if (!AllFinite(s.q, n) || !AllFinite(s.dq, n)) return false;
  if (!AllFinite(imu.gyro, 3) || !AllFinite(imu.accel, 3)) return false;
  for (int i = 0; i < 2; ++i)
    if (!AllFinite(s.force[force_[i]].force, 3)) return false;
  return true;
}

// the robot relative to its base: forward kinematics of the measured joints with the base at
// the origin (W = B), and the velocities the joint velocities give the soles and the IMU
void BaseEstimator::Measure(const shm::SensorBlock& s) {
  kin_->SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  kin_->SetJointPositions(s.q);
  kin_->UpdatePositions();  // no CoM velocity here: Publish computes it at the estimate
  const int nj = kin_->njoint();
  const int c0 = kin_->base_columns();
  const Eigen::Map<const Eigen::VectorXd> dq(s.dq, nj);
  for (int i = 0; i < 2; ++i) {
    p_BS_[i] = kin_->p_WSole(sole_[i]);
    R_BF_[i] = kin_->R_WSite(force_site_[i]);
    kin_->J_WSole(sole_[i], J_);
    v_BS_[i] = J_.block(0, c0, 3, nj).lazyProduct(dq);
  }
  R_BI_ = kin_->R_WSite(imu_site_);
  p_BI_ = kin_->p_WSite(imu_site_);
  kin_->J_WSite(imu_site_, J_);
  v_BI_ = J_.block(0, c0, 3, nj).lazyProduct(dq);
  w_BI_ = J_.block(3, c0, 3, nj).lazyProduct(dq);
}

// the normal force of each sole (its F/T force rotated to W) and whether it is in contact
void BaseEstimator::ContactForces(const shm::SensorBlock& s, const Eigen::Matrix3d& R_WB,
                                  bool hysteresis) {
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector3d f_F(s.force[force_[i]].force);
    est_.fz[i] = (R_WB * R_BF_[i] * f_F).z();
    const double on = options_.contact_force;
    const double off = hysteresis ? 0.5 * on : on;
    est_.contact[i] = (est_.contact[i] && hysteresis) ? est_.fz[i] > off : est_.fz[i] > on;
    if (!est_.contact[i]) anchored_[i] = false;
  }
}

// the base velocity from the soles in contact, taken as still (weighted by their normal
// forces): 0 = v_WB + w_WB x R_WB p_BS + R_WB v_BS. False (and `*v_WB` untouched) without one.
bool BaseEstimator::LegVelocity(const Eigen::Matrix3d& R_WB, const Eigen::Vector3d& w_WB,
                                Eigen::Vector3d* v_WB) const {
  Eigen::Vector3d v_sum = Eigen::Vector3d::Zero();
  double w_sum = 0;
  for (int i = 0; i < 2; ++i) {
    if (!est_.contact[i]) continue;
    v_sum += est_.fz[i] * (-w_WB.cross(R_WB * p_BS_[i]) - R_WB * v_BS_[i]);
    w_sum += est_.fz[i];
  }
  if (w_sum <= 0) return false;
  *v_WB = v_sum / w_sum;
  return true;
}

// anchors sole i where the estimate (base pose p_WB, R_WB) puts it
void BaseEstimator::Anchor(int i, const Eigen::Vector3d& p_WB, const Eigen::Matrix3d& R_WB) {
  anchor_[i] = p_WB + R_WB * p_BS_[i];
  anchored_[i] = true;
}

//---------------- reset ----------------

bool BaseEstimator::Reset(const shm::SensorBlock& s) {
  if (!Finite(s)) return false;
  Measure(s);
  const shm::Imu& imu = s.imu[options_.imu];
  const Eigen::Vector3d gyro(imu.gyro), accel(imu.accel);

  // orientation: roll and pitch from gravity, yaw 0 (upright when the accelerometer reads
  // too little to tell, e.g. in free fall)
  Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity();
  if (accel.norm() > kMinSpecificForce) R_WB = TiltFromUp(R_BI_ * accel.normalized());
  quat_WI_ = Eigen::Quaterniond(R_WB * R_BI_).normalized();
  gyro_prev_ = gyro;
  samples_ = kStartWeight;
  f_W_prev_ = quat_WI_ * accel;
  up_W_ = f_W_prev_;

  // contact without hysteresis; the base height puts the soles in contact on z = 0, or the
  // lower sole when none is (a robot held in the air is taken as just above the ground)
  est_.contact[0] = est_.contact[1] = false;
  ContactForces(s, R_WB, false);
  const Eigen::Vector3d r_L = R_WB * p_BS_[0], r_R = R_WB * p_BS_[1];
  Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();
  const double wL = est_.contact[0] ? est_.fz[0] : 0.0, wR = est_.contact[1] ? est_.fz[1] : 0.0;
  if (wL + wR > 0) {
    p_WB.z() = -(wL * r_L.z() + wR * r_R.z()) / (wL + wR);
  } else {
    p_WB.z() = -std::min(r_L.z(), r_R.z());
  }
  if (options_.origin_at_feet) p_WB.head<2>() = -0.5 * (r_L + r_R).head<2>();
  for (int i = 0; i < 2; ++i) {
    anchored_[i] = false;
    if (est_.contact[i]) Anchor(i, p_WB, R_WB);
  }

  // velocities: from the legs when a sole is in contact, else at rest
  est_.p_WB = p_WB;
  est_.w_WB = quat_WI_ * gyro - R_WB * w_BI_;
  v_raw_.setZero();
  v_WI_from_legs_ = LegVelocity(R_WB, est_.w_WB, &v_raw_);
  est_.v_WB = v_raw_;
  v_WI_ = v_raw_ + est_.w_WB.cross(R_WB * p_BI_) + R_WB * v_BI_;
  started_ = true;
  Publish(s, R_WB);
  return true;
}

//---------------- one cycle ----------------

bool BaseEstimator::Update(const shm::SensorBlock& s, double dt) {
  if (!(dt > 0) || !std::isfinite(dt) || !Finite(s)) return false;
  if (!started_) return Reset(s);
  Measure(s);
  const shm::Imu& imu = s.imu[options_.imu];
  const Eigen::Vector3d gyro(imu.gyro), accel(imu.accel);

  // orientation, predicted: the gyro integrated (trapezoid over the cycle)
  quat_WI_ = (quat_WI_ * Exp(0.5 * (gyro_prev_ + gyro) * dt)).normalized();
  gyro_prev_ = gyro;
  Eigen::Matrix3d R_WI = quat_WI_.toRotationMatrix();
  Eigen::Matrix3d R_WB = R_WI * R_BI_.transpose();

  // contact, and the base velocity from the soles in contact
  ContactForces(s, R_WB, true);
  const Eigen::Vector3d w_WB = R_WI * gyro - R_WB * w_BI_;
  const bool legs = LegVelocity(R_WB, w_WB, &v_raw_);
  const Eigen::Vector3d r_BI_W = R_WB * p_BI_;
  const Eigen::Vector3d g_W(0, 0, gravity_);
  Eigen::Vector3d v_WI, a_WI;
  if (legs) {
    v_WI = v_raw_ + w_WB.cross(r_BI_W) + R_WB * v_BI_;
    // the IMU's acceleration from the legs (differentiated velocity), none after a flight
    a_WI = v_WI_from_legs_ ? Eigen::Vector3d((v_WI - v_WI_) / dt) : Eigen::Vector3d::Zero();
  } else {
    // in the air: the accelerometer integrated (drifts: only for short flights)
    a_WI = R_WI * accel - g_W;
    v_WI = v_WI_ + a_WI * dt;
    v_raw_ = v_WI - w_WB.cross(r_BI_W) - R_WB * v_BI_;
  }
  v_WI_ = v_WI;
  v_WI_from_legs_ = legs;

  // tilt correction (complementary filter): the specific force (averaged over the cycle, as
  // the differentiated velocity is) minus the IMU's own acceleration is gravity; turn the
  // estimate towards it by the fraction tilt_gain dt, or more right after Reset: 1 / (N + n)
  // for the n-th sample, the running mean of the gravity directions in which the Reset's
  // sample weighs N = kStartWeight
  const Eigen::Vector3d f_W = R_WI * accel;
  const double tau_g = 1.0 / (2 * M_PI * kGravityCutoff);
  up_W_ += dt / (tau_g + dt) * (0.5 * (f_W + f_W_prev_) - a_WI - up_W_);
  f_W_prev_ = f_W;
  const Eigen::Vector3d& up_W = up_W_;
  const double up = up_W.norm();
  if (legs && std::abs(up - gravity_) < options_.accel_trust) {
    const double gain = std::max(options_.tilt_gain * dt, 1.0 / static_cast<double>(++samples_));
    const Eigen::Vector3d e_W = (up_W / up).cross(Eigen::Vector3d::UnitZ());
    quat_WI_ = (Exp(gain * e_W) * quat_WI_).normalized();
    R_WI = quat_WI_.toRotationMatrix();
    R_WB = R_WI * R_BI_.transpose();
  }

  // position: each anchored sole gives the base, weighted by its normal force; without
  // one, the velocity integrated
  Eigen::Vector3d p_sum = Eigen::Vector3d::Zero();
  double p_weight = 0;
  for (int i = 0; i < 2; ++i) {
    if (!anchored_[i]) continue;
    p_sum += est_.fz[i] * (anchor_[i] - R_WB * p_BS_[i]);
    p_weight += est_.fz[i];
  }
  const Eigen::Vector3d p_WB = p_weight > 0 ? Eigen::Vector3d(p_sum / p_weight)
                                            : Eigen::Vector3d(est_.p_WB + v_raw_ * dt);
  // soles that touched down this cycle are anchored where the estimate puts them
  for (int i = 0; i < 2; ++i) {
    if (est_.contact[i] && !anchored_[i]) Anchor(i, p_WB, R_WB);
  }

  // velocity low-passed (first order at velocity_cutoff)
  const double tau = 1.0 / (2 * M_PI * options_.velocity_cutoff);
  est_.v_WB += dt / (tau + dt) * (v_raw_ - est_.v_WB);
  est_.p_WB = p_WB;
  est_.w_WB = w_WB;
  Publish(s, R_WB);
  return true;
}

// the estimate into `est_` and `kin_` (pose, velocities, centre of mass)
void BaseEstimator::Publish(const shm::SensorBlock& s, const Eigen::Matrix3d& R_WB) {
  est_.quat_WB = Eigen::Quaterniond(R_WB).normalized();
  kin_->SetBasePose(est_.p_WB, est_.quat_WB);
  kin_->SetBaseVelocity(est_.v_WB, est_.w_WB);
  kin_->SetJointPositions(s.q);
  kin_->SetJointVelocities(s.dq);
  kin_->Update();
  est_.p_WCoM = kin_->p_WCoM();
  est_.v_WCoM = kin_->v_WCoM();
}

}  // namespace ohrp::model
