// The CSV reader of footstep files (see walking/footstep_file.h and footstep_rows.h).
#include <sstream>

#include "footstep_rows.h"

namespace ohrp::walking {
namespace {

// the comma-separated cells of a line, trimmed of blanks
std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string c;
  while (std::getline(in, c, ',')) {
    const size_t a = c.find_first_not_of(" \t"), b = c.find_last_not_of(" \t");
    out.push_back(a == std::string::npos ? "" : c.substr(a, b - a + 1));
  }
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

// a blank line or a comment
bool Skipped(const std::string& line) {
  const size_t a = line.find_first_not_of(" \t");
  return a == std::string::npos || line[a] == '#';
}

// the header: known columns, none twice, the required ones there
bool ReadHeader(const std::vector<std::string>& cells, const std::string& at, std::string* error) {
  std::set<std::string> seen;
  for (const auto& c : cells) {
    if (!StepKeys().count(c))
      return Fail(error, at, "unknown column '" + c + "' (known: " + kStepKeys + ")");
    if (!seen.insert(c).second) return Fail(error, at, c + ": column given twice");
  }
  const std::string why = Missing(seen);
  return why.empty() || Fail(error, at, "header: " + why);
}

// a row; an empty cell of an optional column keeps the default
bool ReadRow(const std::vector<std::string>& cells, const std::vector<std::string>& columns,
             const std::string& at, Written* w, std::string* error) {
  if (cells.size() != columns.size())
    return Fail(error, at,
                "row: " + std::to_string(cells.size()) + " cells, the header has " +
                    std::to_string(columns.size()));
  for (size_t i = 0; i < cells.size(); ++i) {
    const std::string& key = columns[i];
    if (cells[i].empty()) {
      if (key == "foot" || key == "x" || key == "y" || key == "yaw_deg")
        return Fail(error, at, key + ": empty (every step has " + kStepKeys + ")");
      continue;
    }
    const std::string why = SetValue(key, cells[i], w);
    if (!why.empty()) return Fail(error, at, why);
  }
  return true;
}

}  // namespace

bool ParseCsvSteps(const std::string& text, const std::string& name, std::vector<Written>* rows,
                   std::string* error) {
  std::stringstream in(text);
  std::string line;
  std::vector<std::string> columns;
  for (int n = 1; std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (Skipped(line)) continue;
    const std::vector<std::string> cells = Cells(line);
    // the first line names the columns, the others are steps
    if (columns.empty()) {
      if (!ReadHeader(cells, At(name, n), error)) return false;
      columns = cells;
      continue;
    }
    Written w;
    w.line = w.foot_line = n;
    if (!ReadRow(cells, columns, At(name, n), &w, error)) return false;
    rows->push_back(w);
  }
  if (columns.empty())
    return Fail(error, At(name, 1),
                "header: missing: the first line names the columns, e.g. foot,x,y,yaw_deg");
  return true;
}

}  // namespace ohrp::walking
