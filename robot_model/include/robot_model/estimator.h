// State estimation of the floating base from the robot's own sensors (never sim_truth, which
// the robot does not have): what a controller needs to know where its body is.
//
//   orientation  the IMU frame I is estimated (the IMU may sit above torso joints: on HRP-1S it
//                is on the CHEST, WAIST_P, WAIST_R and CHEST lie between it and the base) and
//                the base follows from the measured joints: R_WB = R_WI R_BI^T. The gyro is
//                integrated (trapezoid over the cycle), its drift in roll and pitch corrected
//                towards the gravity direction (a complementary filter whose crossover is
//                `tilt_gain`): the accelerometer's specific force rotated to W, minus the
//                IMU's own acceleration from the leg kinematics (the differentiated velocity
//                below), is gravity; that measurement is low-passed at 5 Hz (both terms alike,
//                against the noise of the differentiated velocity). Right after Reset the
//                correction is the running mean of those gravity directions, the Reset's
//                sample weighing 20 (gain 1/(20 + n) for the n-th), until that falls below
//                tilt_gain dt (after 2 s at the defaults and a 5 ms cycle), so that a Reset on
//                one noisy sample converges like an average. The correction is off while
//                that gravity differs from the model's g by more than `accel_trust` (shocks)
//                and while no sole is in contact. Yaw is the gyro's integral (unobservable
//                from gravity). The IMU's orientation output (quat_WI) is not used.
//   contact      a sole is in contact when its normal force exceeds `contact_force` (with a
//                hysteresis of half that): the F/T force rotated to W with the estimated
//                orientation, its z component.
//   position     leg kinematics: each sole in contact is anchored in the world where the
//                estimate puts it at touchdown and stays there while in contact; the base
//                position follows from the anchor, the estimated base orientation and the
//                joint angles (p_WB = p_WS - R_WB p_BS), averaged over the soles in contact
//                weighted by their normal forces. A sole that rolls on an edge or slides breaks
//                the assumption (its frame S moves: rolling by 1 deg about an edge 0.125 m
//                away raises it by 2 mm); the soft soles of the simulation sink about 0.2 mm
//                under the robot's weight, which the estimate does not see either.
//   velocity     the same leg kinematics differentiated (0 = v_WB + w_WB x R_WB p_BS +
//                R_WB v_BS with v_BS from the joint velocities, w_WB from the gyro and the
//                torso joints' velocities), low-passed at `velocity_cutoff`.
//   in the air   with no sole in contact the accelerometer is integrated (velocity, then
//                position): dead reckoning that drifts, usable for short flights only.
// At Reset the robot is assumed at rest with yaw 0, roll and pitch from the accelerometer
// (upright when it reads less than 1 m/s^2, e.g. in free fall), standing on the soles in
// contact with their bottoms on the plane z = 0 of the world (with no sole in contact, the
// robot is taken as held just above the ground: the lower sole's bottom on z = 0), and the
// base above the midpoint of the two soles at x = y = 0 when `origin_at_feet` is set
// (otherwise the base itself at x = y = 0). Update before any Reset resets.
//
// The constructor throws std::invalid_argument also when the model has no gravity.
// Update allocates nothing and never throws; it returns false (and keeps the last estimate and
// the state of `kin`) when the sensors it needs (q, dq, the IMU's gyro and accelerometer, the
// soles' F/T forces) are not finite or dt is not positive.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>

#include "robot_model/kinematics.h"
#include "shm_bridge/layout.h"

namespace ohrp::model {

struct EstimatorOptions {
  int imu = 0;                  // index of the IMU in the segment
  double tilt_gain = 0.5;       // complementary filter crossover [1/s] (roll and pitch)
  double accel_trust = 2.0;     // use the accelerometer only when | |a| - g | < this [m/s^2]
  double contact_force = 50.0;  // normal force above which a sole is in contact [N]
  double velocity_cutoff = 20.0;  // low-pass of the base velocity [Hz]
  bool origin_at_feet = true;   // Reset: x = y = 0 between the soles (else at the base)
};

struct BaseEstimate {
  Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();    // base position [m]
  Eigen::Quaterniond quat_WB = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_WB = Eigen::Vector3d::Zero();    // base linear velocity in W [m/s]
  Eigen::Vector3d w_WB = Eigen::Vector3d::Zero();    // base angular velocity in W [rad/s]
  Eigen::Vector3d p_WCoM = Eigen::Vector3d::Zero();  // centre of mass [m]
  Eigen::Vector3d v_WCoM = Eigen::Vector3d::Zero();  // its velocity [m/s]
  bool contact[2] = {false, false};                  // left, right sole in contact
  double fz[2] = {0, 0};                             // their normal forces [N]
};

class BaseEstimator {
 public:
  // Uses (and updates the state of) `kin`, which must outlive the estimator. Throws
  // std::invalid_argument when the robot has no IMU, no two soles, or no F/T sensor on each
  // sole (what is missing is in the message).
  BaseEstimator(Kinematics* kin, EstimatorOptions options = {});

  // Starts from a sensor block (see the assumptions above). Returns false on non-finite input.
  bool Reset(const shm::SensorBlock& s);
  // One cycle `dt` [s] after the previous one. On return `kin` holds the estimated state.
  bool Update(const shm::SensorBlock& s, double dt);

  const BaseEstimate& estimate() const { return est_; }
  // the anchors of the soles in contact (valid while contact[i])
  const Eigen::Vector3d& anchor(int side) const { return anchor_[side]; }

 private:
  bool Finite(const shm::SensorBlock& s) const;
  void Measure(const shm::SensorBlock& s);
  void ContactForces(const shm::SensorBlock& s, const Eigen::Matrix3d& R_WB, bool hysteresis);
  bool LegVelocity(const Eigen::Matrix3d& R_WB, const Eigen::Vector3d& w_WB,
                   Eigen::Vector3d* v_WB) const;
  void Anchor(int i, const Eigen::Vector3d& p_WB, const Eigen::Matrix3d& R_WB);
  void Publish(const shm::SensorBlock& s, const Eigen::Matrix3d& R_WB);

  Kinematics* kin_;
  EstimatorOptions options_;
  BaseEstimate est_;
  Eigen::Vector3d anchor_[2];
  int sole_[2] = {-1, -1};    // left, right sole index in kin->soles()
  int force_[2] = {-1, -1};   // their F/T sensors
  int force_site_[2] = {-1, -1};  // MuJoCo site ids of those sensors
  int imu_site_ = -1;
  double gravity_ = 9.81;  // the model's |g|: what the accelerometer reads at rest [m/s^2]

  // filter state
  bool started_ = false;                 // Reset has run
  bool anchored_[2] = {false, false};    // anchor_[i] holds a touchdown position
  Eigen::Quaterniond quat_WI_ = Eigen::Quaterniond::Identity();  // IMU orientation
  Eigen::Vector3d gyro_prev_ = Eigen::Vector3d::Zero();  // last gyro sample [rad/s]
  long samples_ = 0;                     // weight of the running mean of gravity directions
  Eigen::Vector3d f_W_prev_ = Eigen::Vector3d::Zero();   // last specific force in W [m/s^2]
  Eigen::Vector3d up_W_ = Eigen::Vector3d::Zero();       // gravity measured, low-passed [m/s^2]
  Eigen::Vector3d v_WI_ = Eigen::Vector3d::Zero();       // IMU point velocity [m/s]
  bool v_WI_from_legs_ = false;          // v_WI_ came from leg kinematics (not inertial)
  Eigen::Vector3d v_raw_ = Eigen::Vector3d::Zero();      // unfiltered base velocity [m/s]

  // the robot relative to its base, from the measured joints (Measure)
  Eigen::MatrixXd J_;                    // 6 x nv scratch
  Eigen::Vector3d p_BS_[2], v_BS_[2];    // sole position and velocity in B
  Eigen::Matrix3d R_BF_[2];              // F/T sensor frames
  Eigen::Matrix3d R_BI_;                 // IMU frame
  Eigen::Vector3d p_BI_, v_BI_, w_BI_;   // IMU position, velocity and angular velocity in B
};

}  // namespace ohrp::model
