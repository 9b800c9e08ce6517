// How a producer chooses the contact under the soles from its command line and the scene: the
// one choice sim_host and hw_emulator make, so that the same robot stands on the same contact
// under both (docs/robots.md "Robot profiles", hw_driver/README.md).
//   --contact auto | soft | native | rigid   (auto: feet.h; it honours a robot profile's
//                                              `contact:` key, which marks the soles)
//   --contact-file FILE                      the soft soles' parameters (contact/params_file.h);
//                                              default: a robot profile's `contact_file:`
//   --contact-<key> VALUE                    a parameter given on the command line wins over
//                                              the file's
#pragma once

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "sim_host/feet.h"

namespace ohrp::sim {

struct ContactChoice {
  std::string contact = "auto";   // --contact
  std::string contact_file;       // --contact-file; empty: the profile's contact_file, if any
  std::set<std::string> given;    // SoftContactParams keys given on the command line
                                  // ("stiffness", "damping", ...): the file does not set them
};

// The soft soles' parameters a contact file may set, each with its command-line flag:
// {"stiffness", "--contact-stiffness"}, ..., {"tangential_damping", "--contact-tangential-damping"}.
std::vector<std::pair<std::string, std::string>> ContactParamFlags();

// Fills `feet->model` from c.contact and `feet->params` (already holding the command line's
// values) from the contact file: c.contact_file, else, when `scene` is a robot profile, its
// contact_file. `*contact_file` (may be null) receives the file used ("" when none). False with
// `*error` (the option or the profile's line named) on a bad contact name, profile or file.
bool ChooseContact(const std::string& scene, const ContactChoice& c, FeetOptions* feet,
                   std::string* contact_file, std::string* error);

}  // namespace ohrp::sim
