// The contact under the soles, as sim_host and hw_emulator choose it (see contact_choice.h).
#include "sim_host/contact_choice.h"


#include "contact/params_file.h"
#include "robot_model/profile.h"

namespace ohrp::sim {

std::vector<std::pair<std::string, std::string>> ContactParamFlags() {
  std::vector<std::pair<std::string, std::string>> flags;
  for (const char* k : {"stiffness", "exponent", "damping", "friction", "tangential_stiffness",
                        "tangential_damping"}) {
    std::string flag = std::string("--contact-") + k;
    for (char& ch : flag) ch = ch == '_' ? '-' : ch;
    flags.emplace_back(k, flag);
  }
  return flags;
}

bool ChooseContact(const std::string& scene, const ContactChoice& c, FeetOptions* feet,
                   std::string* contact_file, std::string* error) {
  if (!ParseContactModel(c.contact, &feet->model)) {
    *error = "--contact '" + c.contact + "': want auto, soft, native or rigid";
    return false;
  }
  std::string file = c.contact_file;
  if (file.empty() && model::IsProfilePath(scene)) {
    model::RobotProfile profile;
    if (!model::ReadProfile(scene, &profile, error)) return false;
    file = profile.contact_file;
  }
  if (contact_file) *contact_file = file;
  if (file.empty()) return true;
  std::vector<std::string> keys;
  if (!contact::ReadContactFile(file, &feet->params, &keys, error, c.given)) {
    *error = "--contact-file: " + *error;
    return false;
  }
  return true;
}

}  // namespace ohrp::sim
