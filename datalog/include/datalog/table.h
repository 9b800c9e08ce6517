// The one reader of the data log (datalog/recorder.h's CSV, and any CSV of numbers with a header
// line): the whole file read into columns of doubles, looked up by name.
#pragma once

#include <string>
#include <vector>

namespace ohrp::datalog {

// A CSV file read column by column.
class Table {
 public:
  bool Load(const std::string& path, std::string* error);
  int Column(const std::string& name) const;  // -1 when absent
  const std::vector<double>& col(int c) const { return cols_[c]; }
  size_t rows() const { return cols_.empty() ? 0 : cols_[0].size(); }
  const std::vector<std::string>& names() const { return names_; }

 private:
  std::vector<std::string> names_;
  std::vector<std::vector<double>> cols_;
};

}  // namespace ohrp::datalog
