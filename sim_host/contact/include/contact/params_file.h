// The soles' parameters from a file (sim_host --contact-file): what `ohrp identify` writes
// (DIR/soles.yaml), or one written by hand:
//   contact_params:            # any of the keys of SoftContactParams' law, SI units
//     stiffness: 2.0e6         # [N/m^n]
//     damping: 45              # [s/m]
//     exponent: 1              # friction, tangential_stiffness, tangential_damping likewise
//   identified: {...}          # provenance (ohrp identify): read past, not applied
// Every value a positive number (exponent within [1, 3]); anything else is refused with the
// file, the line and the key.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "contact/params.h"

namespace ohrp::contact {

// Sets the keys the file gives in *p, except those in `keep` (given otherwise, e.g. on the
// command line: checked, not applied), and lists the keys it set in *keys ("stiffness", ...).
// False with `*error` ("FILE:LINE: contact_params: KEY: why") on any problem; *p is then
// unchanged.
bool ReadContactFile(const std::string& path, SoftContactParams* p, std::vector<std::string>* keys,
                     std::string* error, const std::set<std::string>& keep = {});

}  // namespace ohrp::contact
