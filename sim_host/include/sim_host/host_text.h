// What sim_host prints before a run: the --explain answer on stdout, and the start lines on
// stderr (the robot, the segment, the step, the contact, the effects, notes).
#pragma once

#include <mujoco/mujoco.h>

#include "contact/soft_contact.h"
#include "sim_host/effects.h"
#include "sim_host/feet.h"
#include "sim_host/host.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "sim_host/self_collision_watch.h"

namespace ohrp::sim {

// the run as set up (control period resolved); pointers may be null (effect off, no soft soles)
struct HostText {
  const HostOptions& o;
  const model::RobotMap& robot;
  const EffectsPlan& effects;
  const SelfCollisionWatch* self_collision;
  const contact::SoftFootContact* soft;
  const mjModel* m;
  int steps_per_cycle;
  bool period_defaulted;  // the control period was not given: sim_host chose it
  ContactModel contact;
};

// sim_host --explain: every effect and why, the self-collision pairs, the control period, the
// actuation, the soft soles' impact note, the cameras (stdout)
void PrintExplain(const HostText& t);
// the start lines of a run (stderr)
void PrintStart(const HostText& t);

}  // namespace ohrp::sim
