// Loading and sampling OpenHRP-format trajectories and gain files.
#include "controllers/trajectory.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string_view>

namespace ohrp::controllers {
namespace {

//---------------- tokenising ----------------

bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits `line` into whitespace-separated tokens (views into `line`).
void Tokenise(std::string_view line, std::vector<std::string_view>* tokens) {
  tokens->clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsBlank(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !IsBlank(line[j])) ++j;
    if (j > i) tokens->push_back(line.substr(i, j - i));
    i = j;
  }
}

bool SkipLine(const std::vector<std::string_view>& tokens) {
  return tokens.empty() || tokens.front().front() == '#';
}

// Parses a whole token as a double ("nan" and "inf" parse, the caller rejects them).
bool ParseNumber(std::string_view token, double* value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, *value);
  return ec == std::errc() && ptr == end;
}

std::string Where(const std::string& source, int line) {
  return source + ":" + std::to_string(line) + ": ";
}

std::string ColumnName(std::size_t column) {
  return column == 0 ? std::string("time column") : "column " + std::to_string(column + 1) +
                                                        " (joint " + std::to_string(column - 1) +
                                                        ")";
}

// Parses the numbers of one row into `values`; reports malformed or non-finite tokens.
ConfigStatus ParseRow(const std::vector<std::string_view>& tokens, const std::string& source,
                      int line, std::vector<double>* values) {
  values->clear();
  for (std::size_t c = 0; c < tokens.size(); ++c) {
    double v = 0.0;
    if (!ParseNumber(tokens[c], &v)) {
      return ConfigStatus::Fail(ConfigError::kSyntax, Where(source, line) + "'" +
                                                          std::string(tokens[c]) +
                                                          "' in " + ColumnName(c) +
                                                          " is not a number");
    }
    if (!std::isfinite(v)) {
      return ConfigStatus::Fail(ConfigError::kNonFinite,
                                Where(source, line) + ColumnName(c) + " is " +
                                    std::string(tokens[c]) + ": values must be finite");
    }
    values->push_back(v);
  }
  return ConfigStatus::Ok();
}

// index of the segment [time[i], time[i+1]) holding t, for t within the trajectory
std::size_t SegmentIndex(const Trajectory& tr, double t) {
  auto it = std::upper_bound(tr.time.begin(), tr.time.end(), t);
  std::size_t i = static_cast<std::size_t>(it - tr.time.begin());
  i = i == 0 ? 0 : i - 1;
  return std::min(i, tr.rows() - 2);
}

}  // namespace

//---------------- trajectories ----------------

ConfigStatus ParseTrajectory(std::istream& in, const std::string& source, Trajectory* out) {
  *out = Trajectory{};
  out->source = source;
  std::string text;
  std::vector<std::string_view> tokens;
  std::vector<double> row;
  int line = 0;
  int first_line = 0;
  while (std::getline(in, text)) {
    ++line;
    Tokenise(text, &tokens);
    if (SkipLine(tokens)) continue;
    if (ConfigStatus s = ParseRow(tokens, source, line, &row); !s.ok()) return s;
    if (out->rows() == 0) {
      if (row.size() < 2) {
        return ConfigStatus::Fail(ConfigError::kColumns,
                                  Where(source, line) + "a row needs the time and at least one "
                                                        "joint value, found " +
                                      std::to_string(row.size()) + " column(s)");
      }
      out->njoint = static_cast<int>(row.size()) - 1;
      first_line = line;
    } else if (row.size() != static_cast<std::size_t>(out->njoint) + 1) {
      return ConfigStatus::Fail(
          ConfigError::kColumns,
          Where(source, line) + std::to_string(row.size() - 1) +
              " joint values after the time, expected " + std::to_string(out->njoint) +
              " (as on line " + std::to_string(first_line) + ")");
    }
    if (out->rows() > 0 && !(row[0] > out->time.back())) {
      return ConfigStatus::Fail(ConfigError::kTime,
                                Where(source, line) + "time " + std::string(tokens[0]) +
                                    " does not increase (previous row, line " +
                                    std::to_string(out->line.back()) + ", has " +
                                    std::to_string(out->time.back()) + ")");
    }
    out->time.push_back(row[0]);
    out->values.insert(out->values.end(), row.begin() + 1, row.end());
    out->line.push_back(line);
  }
  if (in.bad()) {
    return ConfigStatus::Fail(ConfigError::kFile, source + ": read error");
  }
  if (out->rows() == 0) {
    return ConfigStatus::Fail(ConfigError::kEmpty, source + ": no data rows (expected 'time "
                                                            "q0 q1 ...' per line)");
  }
  return ConfigStatus::Ok();
}

ConfigStatus LoadTrajectory(const std::string& path, Trajectory* out) {
  std::ifstream in(path);
  if (!in) {
    return ConfigStatus::Fail(ConfigError::kFile, path + ": cannot open the trajectory file");
  }
  return ParseTrajectory(in, path, out);
}

ConfigStatus CheckCompanion(const Trajectory& angles, const Trajectory& companion) {
  if (companion.njoint != angles.njoint) {
    return ConfigStatus::Fail(ConfigError::kMismatch,
                              companion.source + " has " + std::to_string(companion.njoint) +
                                  " joint columns but " + angles.source + " has " +
                                  std::to_string(angles.njoint));
  }
  if (companion.rows() != angles.rows()) {
    return ConfigStatus::Fail(ConfigError::kMismatch,
                              companion.source + " has " + std::to_string(companion.rows()) +
                                  " rows but " + angles.source + " has " +
                                  std::to_string(angles.rows()) + ": they must be sampled alike");
  }
  for (std::size_t i = 0; i < angles.rows(); ++i) {
    if (std::abs(companion.time[i] - angles.time[i]) > 1e-9) {
      return ConfigStatus::Fail(
          ConfigError::kMismatch,
          Where(companion.source, companion.line[i]) + "time " +
              std::to_string(companion.time[i]) + " differs from " + angles.source + ":" +
              std::to_string(angles.line[i]) + " (" + std::to_string(angles.time[i]) + ")");
    }
  }
  return ConfigStatus::Ok();
}

void SampleTrajectory(const Trajectory& tr, double t, double* q) noexcept {
  const int n = tr.njoint;
  if (tr.rows() == 1 || !(t > tr.start_time())) {
    std::copy_n(tr.row(0), n, q);
    return;
  }
  if (t >= tr.end_time()) {
    std::copy_n(tr.row(tr.rows() - 1), n, q);
    return;
  }
  const std::size_t i = SegmentIndex(tr, t);
  const double a = (t - tr.time[i]) / (tr.time[i + 1] - tr.time[i]);
  const double* r0 = tr.row(i);
  const double* r1 = tr.row(i + 1);
  // weighted sum, not r0 + a (r1 - r0): the difference of two finite values may overflow, and
  // the weights give r0 and r1 exactly at the rows
  for (int j = 0; j < n; ++j) q[j] = (1.0 - a) * r0[j] + a * r1[j];
}

void SampleSlope(const Trajectory& tr, double t, double* dq) noexcept {
  const int n = tr.njoint;
  if (tr.rows() == 1 || !(t >= tr.start_time()) || t >= tr.end_time()) {
    std::fill_n(dq, n, 0.0);
    return;
  }
  const std::size_t i = SegmentIndex(tr, t);
  const double inv_dt = 1.0 / (tr.time[i + 1] - tr.time[i]);
  const double* r0 = tr.row(i);
  const double* r1 = tr.row(i + 1);
  for (int j = 0; j < n; ++j) dq[j] = (r1[j] - r0[j]) * inv_dt;
}

//---------------- gains ----------------

ConfigStatus ParseGains(std::istream& in, const std::string& source, Gains* out) {
  *out = Gains{};
  out->source = source;
  std::string text;
  std::vector<std::string_view> tokens;
  std::vector<double> row;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    Tokenise(text, &tokens);
    if (SkipLine(tokens)) continue;
    if (tokens.size() != 2) {
      return ConfigStatus::Fail(ConfigError::kColumns,
                                Where(source, line) + "expected 'P D' (2 numbers) for joint " +
                                    std::to_string(out->kp.size()) + ", found " +
                                    std::to_string(tokens.size()));
    }
    if (ConfigStatus s = ParseRow(tokens, source, line, &row); !s.ok()) return s;
    if (row[0] < 0.0 || row[1] < 0.0) {
      return ConfigStatus::Fail(ConfigError::kSyntax,
                                Where(source, line) + "gains must not be negative");
    }
    out->kp.push_back(row[0]);
    out->kd.push_back(row[1]);
  }
  if (in.bad()) return ConfigStatus::Fail(ConfigError::kFile, source + ": read error");
  if (out->kp.empty()) {
    return ConfigStatus::Fail(ConfigError::kEmpty, source + ": no gain rows (expected 'P D' "
                                                            "per joint)");
  }
  return ConfigStatus::Ok();
}

ConfigStatus LoadGains(const std::string& path, Gains* out) {
  std::ifstream in(path);
  if (!in) return ConfigStatus::Fail(ConfigError::kFile, path + ": cannot open the gain file");
  return ParseGains(in, path, out);
}

}  // namespace ohrp::controllers
