// The data log's reader (table.h).
#include "datalog/table.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace ohrp::datalog {

namespace {

// the fields of one line, split at commas, each without trailing blanks or '\r'
std::vector<std::string> Fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) {
    while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' ')) cell.pop_back();
    out.push_back(cell);
  }
  return out;
}

}  // namespace

bool Table::Load(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read the data log '" + path + "'";
    return false;
  }
  std::string line;
  if (!std::getline(in, line)) {
    *error = "the data log '" + path + "' is empty (expected a header line of column names)";
    return false;
  }
  names_ = Fields(line);
  cols_.assign(names_.size(), {});
  lines_.clear();
  size_t lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> cells = Fields(line);
    if (cells.size() != names_.size()) {
      *error = path + ":" + std::to_string(lineno) + ": " + std::to_string(cells.size()) +
               " fields, the header has " + std::to_string(names_.size());
      return false;
    }
    for (size_t c = 0; c < cells.size(); ++c) {
      char* end = nullptr;
      const double v = std::strtod(cells[c].c_str(), &end);
      if (end == cells[c].c_str() || *end != '\0') {
        *error = path + ":" + std::to_string(lineno) + ": '" + cells[c] + "' in column '" +
                 names_[c] + "' is not a number";
        return false;
      }
      cols_[c].push_back(v);
    }
    lines_.push_back(lineno);
  }
  return true;
}

int Table::Column(const std::string& name) const {
  auto it = std::find(names_.begin(), names_.end(), name);
  return it == names_.end() ? -1 : static_cast<int>(it - names_.begin());
}

}  // namespace ohrp::datalog
