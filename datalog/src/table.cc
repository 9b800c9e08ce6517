// The data log's reader (table.h).
#include "datalog/table.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ohrp::datalog {

bool Table::Load(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read the data log '" + path + "'";
    return false;
  }
  std::string line;
  if (!std::getline(in, line)) {
    *error = "the data log '" + path + "' is empty";
    return false;
  }
  names_.clear();
  std::stringstream hs(line);
  for (std::string n; std::getline(hs, n, ',');) names_.push_back(n);
  cols_.assign(names_.size(), {});
  size_t lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty()) continue;
    const char* p = line.c_str();
    for (size_t c = 0; c < names_.size(); ++c) {
      char* end = nullptr;
      const double v = std::strtod(p, &end);
      if (end == p) {
        *error = path + ":" + std::to_string(lineno) + ": expected " +
                 std::to_string(names_.size()) + " numbers";
        return false;
      }
      cols_[c].push_back(v);
      p = (*end == ',') ? end + 1 : end;
    }
  }
  return true;
}

int Table::Column(const std::string& name) const {
  auto it = std::find(names_.begin(), names_.end(), name);
  return it == names_.end() ? -1 : static_cast<int>(it - names_.begin());
}

}  // namespace ohrp::datalog
