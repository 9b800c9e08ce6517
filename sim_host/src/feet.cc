// Contact model of the soles (see feet.h).
#include "sim_host/feet.h"

namespace ohrp::sim {

bool ParseContactModel(const std::string& name, ContactModel* model) {
  if (name == "auto") *model = ContactModel::kAuto;
  else if (name == "soft") *model = ContactModel::kSoft;
  else if (name == "native") *model = ContactModel::kNative;
  else if (name == "rigid") *model = ContactModel::kRigid;
  else return false;
  return true;
}

const char* ContactModelName(ContactModel model) {
  switch (model) {
    case ContactModel::kAuto: return "auto";
    case ContactModel::kSoft: return "soft";
    case ContactModel::kNative: return "native";
    case ContactModel::kRigid: return "rigid";
  }
  return "?";
}

ContactModel ResolveContactModel(const mjModel* m, const FeetOptions& o, const std::vector<int>& soles) {
  if (o.model != ContactModel::kAuto) return o.model;
  if (!o.soles.empty()) return ContactModel::kSoft;  // soles listed: they are the contact
  // soles that MuJoCo's contact would not touch (contype = conaffinity = 0, as a robot profile's
  // `contact: native` makes them) mark the support polygon: the author's own foot geoms are the
  // contact, natively
  bool markers = !soles.empty();
  for (int g : soles) markers = markers && m->geom_contype[g] == 0 && m->geom_conaffinity[g] == 0;
  return soles.empty() || markers ? ContactModel::kNative : ContactModel::kSoft;
}

bool SetUpFeet(mjModel* m, const FeetOptions& o, double mass,
               std::unique_ptr<contact::SoftFootContact>* soft, std::string* error,
               ContactModel* resolved) {
  soft->reset();
  // the soles: named, or every "*_SOLE" geom
  std::vector<std::string> soles = o.soles;
  if (soles.empty()) {
    for (int g = 0; g < m->ngeom; ++g) {
      const char* name = mj_id2name(m, mjOBJ_GEOM, g);
      const std::string n = name ? name : "";
      if (n.size() > 5 && n.compare(n.size() - 5, 5, "_SOLE") == 0) soles.push_back(n);
    }
  }
  std::vector<int> found;
  for (const auto& s : soles)
    if (const int g = mj_name2id(m, mjOBJ_GEOM, s.c_str()); g >= 0) found.push_back(g);
  const ContactModel model = ResolveContactModel(m, o, found);
  if (resolved) *resolved = model;
  if (model == ContactModel::kNative) return true;
  if (soles.empty()) {
    *error = std::string("the ") + ContactModelName(model) +
             " contact needs the robot's soles: name them *_SOLE in the model or list them "
             "with --soles, or use --contact native";
    return false;
  }
  std::vector<int> ids;
  for (const auto& s : soles) {
    const int g = mj_name2id(m, mjOBJ_GEOM, s.c_str());
    if (g < 0) {
      *error = "no sole geom '" + s + "' in the model";
      return false;
    }
    ids.push_back(g);
  }

  if (model == ContactModel::kRigid) {
    // near-rigid: the stiffest constraint MuJoCo keeps stable at this step (time constant of
    // two steps, critically damped), impedance close to 1 from the first tenth of a millimetre
    for (int g : ids) {
      m->geom_solref[mjNREF * g] = 2 * m->opt.timestep;
      m->geom_solref[mjNREF * g + 1] = 1.0;
      m->geom_solimp[mjNIMP * g] = 0.99;
      m->geom_solimp[mjNIMP * g + 1] = 0.999;
      m->geom_solimp[mjNIMP * g + 2] = 1e-4;
    }
    return true;
  }

  // soft: MuJoCo's contact off for the soles, the soft-foot model on
  for (int g : ids) {
    if (m->geom_type[g] != mjGEOM_BOX) {
      *error = "sole '" + std::string(mj_id2name(m, mjOBJ_GEOM, g)) +
               "' is not a box: the soft-foot contact samples a box's bottom face";
      return false;
    }
    m->geom_contype[g] = 0;
    m->geom_conaffinity[g] = 0;
  }
  std::string why;
  *soft = contact::SoftFootContact::Create(m, soles, {}, o.params, 0.5 * mass, &why);
  if (!*soft) {
    *error = "soft-foot contact: " + why;
    return false;
  }
  // RK4: the force follows the state through the step's four stages. Held over the step it
  // would make the contact an explicit Euler step that gains energy (tests/contact/stage_test).
  if (m->opt.integrator == mjINT_RK4 && !(*soft)->EvaluateAtEveryStage(true, &why)) {
    soft->reset();
    *error = "soft-foot contact with RK4: " + why;
    return false;
  }
  return true;
}

}  // namespace ohrp::sim
