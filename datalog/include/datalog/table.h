// The one reader of the data log (datalog/recorder.h's CSV, and any CSV of numbers with a header
// line): the whole file read into columns of doubles, looked up by name.
#pragma once

#include <string>
#include <vector>

namespace ohrp::datalog {

// A CSV file read column by column.
class Table {
 public:
  // Reads the whole file: the first line names the columns, every other non-blank line has as
  // many fields, each a number (blanks and a '\r' at a field's end are ignored). False with
  // `*error` naming the file, and the line and column where a row is wrong.
  bool Load(const std::string& path, std::string* error);
  int Column(const std::string& name) const;  // -1 when absent
  const std::vector<double>& col(int c) const { return cols_[c]; }
  size_t rows() const { return cols_.empty() ? 0 : cols_[0].size(); }
  const std::vector<std::string>& names() const { return names_; }
  // the file's line number (1: the header) of row `r`, for messages about a row
  size_t line(size_t r) const { return lines_[r]; }

 private:
  std::vector<std::string> names_;
  std::vector<std::vector<double>> cols_;
  std::vector<size_t> lines_;
};

}  // namespace ohrp::datalog
