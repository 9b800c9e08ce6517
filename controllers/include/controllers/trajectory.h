// Joint trajectories and gains in OpenHRP's plain-text formats.
//
// Trajectory file (SamplePD's angle.dat / vel.dat, hrpsys's *.pos): one row per sample,
// whitespace-separated numbers; the first column is time [s], then one column per joint in
// joint-id order [rad or m] (velocity files: [rad/s or m/s]). Time must be strictly increasing
// and every value finite. Blank lines and lines whose first non-blank character is '#' are
// skipped. The first data row fixes the joint count; every other row must match it.
//
// Gain file (SamplePD's PDgain.dat): one row per joint in joint-id order, "P D"
// ([N m/rad] and [N m s/rad]); blank lines and '#' lines skipped.
//
// Errors name the file and line ("angle.dat:12: ...").
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

#include "controllers/config_status.h"

namespace ohrp::controllers {

struct Trajectory {
  std::string source;          // file name, for messages
  int njoint = 0;              // joint columns (columns after the time)
  std::vector<double> time;    // (rows) strictly increasing [s]
  std::vector<double> values;  // (rows x njoint) row-major
  std::vector<int> line;       // (rows) 1-based source line of each row

  std::size_t rows() const { return time.size(); }
  const double* row(std::size_t i) const { return values.data() + i * njoint; }
  double start_time() const { return time.front(); }
  double end_time() const { return time.back(); }
  double duration() const { return time.back() - time.front(); }
};

// Parses a trajectory from `in`; `source` names it in messages. On failure `*out` is
// unspecified and the status says what was wrong where.
ConfigStatus ParseTrajectory(std::istream& in, const std::string& source, Trajectory* out);
// Opens `path` and parses it.
ConfigStatus LoadTrajectory(const std::string& path, Trajectory* out);

// Checks that `companion` (a velocity file) has the rows, times and joint count of `angles`.
ConfigStatus CheckCompanion(const Trajectory& angles, const Trajectory& companion);

// Linear interpolation at time `t` [s] (trajectory time): q[0..njoint). Before the first row
// it returns the first row, after the last row it holds the last row. Never allocates.
void SampleTrajectory(const Trajectory& trajectory, double t, double* q) noexcept;

// The derivative of that interpolant at `t`: the slope of the segment holding `t`, 0 before
// the first and after the last row. Never allocates.
void SampleSlope(const Trajectory& trajectory, double t, double* dq) noexcept;

struct Gains {
  std::string source;
  std::vector<double> kp;  // (njoint) [N m/rad]
  std::vector<double> kd;  // (njoint) [N m s/rad]
};

// Parses a gain file: exactly two finite non-negative numbers per row.
ConfigStatus ParseGains(std::istream& in, const std::string& source, Gains* out);
ConfigStatus LoadGains(const std::string& path, Gains* out);

}  // namespace ohrp::controllers
