// The contact under the robot's soles, chosen per scene or scenario, for the same robot:
//   soft    the paper's spring-damper contact (ohrp::contact, section 3.3): MuJoCo's own
//           contact is switched off for the soles, the soft-foot model computes their forces
//           (the default: HRP-1S has a mechanical spring-damper in its feet);
//   native  MuJoCo's soft-constraint contact as the scene defines it;
//   rigid   MuJoCo's contact made near-rigid for the soles (constraint time constant of two
//           physics steps, critically damped, impedance close to 1);
//   auto    soft when the model has soles, native when it has none (a model without feet) or
//           when its *_SOLE geoms do not collide (contype = conaffinity = 0: markers of the
//           support polygon, as a robot profile's `contact: native` makes them).
// The soles are the box geoms named "*_SOLE" unless listed explicitly.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "contact/soft_contact.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::sim {

enum class ContactModel { kAuto, kSoft, kNative, kRigid };

struct FeetOptions {
  ContactModel model = ContactModel::kAuto;
  std::vector<std::string> soles;          // empty: every geom whose name ends with "_SOLE"
  contact::SoftContactParams params;       // soft model only
};

// Parses "auto", "soft", "native" or "rigid"; false for anything else.
bool ParseContactModel(const std::string& name, ContactModel* model);
const char* ContactModelName(ContactModel model);

// The contact `o.model` resolves to on `m` whose soles are the geoms `soles` (kAuto as above).
ContactModel ResolveContactModel(const mjModel* m, const FeetOptions& o, const std::vector<int>& soles);

// Sets the model up for the chosen contact (must run before the first mj_forward/mj_step),
// resolving kAuto into `*resolved` (which may be null), and,
// for the soft model, creates the soft-foot contact of the soles against every static geom.
// `mass` is the robot's mass [kg] (half of it rides on one sole when standing: the stability
// check of the parameters uses it). With RK4 (m->opt.integrator, so set it first) the soft
// contact is evaluated at every stage (SoftFootContact::EvaluateAtEveryStage; mjcb_control,
// so one such contact per process at a time). Returns false with `*error` naming what is wrong (no soles,
// a sole that is not a box, parameters refused and why). `*soft` stays null unless soft.
bool SetUpFeet(mjModel* m, const FeetOptions& options, double mass,
               std::unique_ptr<contact::SoftFootContact>* soft, std::string* error,
               ContactModel* resolved = nullptr);

}  // namespace ohrp::sim
