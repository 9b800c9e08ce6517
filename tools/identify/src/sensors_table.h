// ohrp identify --sensors, inside: the log's columns as sensors.cc reads them, and the stages
// that sensors.cc and sensors_noise.cc share (not part of the library's interface).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "identify/sensors.h"

namespace ohrp::identify::detail {

// the log's columns by name, the rows within [from, to]
struct Table {
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> col;
  bool Has(const std::string& n) const { return col.count(n) != 0; }
};

// the centred moving average of `width` samples at rows [h, n - h), h = width / 2 (empty when x
// is shorter than width); a high-pass is x[h + i] less its i-th value
std::vector<double> MovingAverage(const std::vector<double>& x, int width);

// refused (false, `*error` naming the channel) when x's slow part (its moving average) spans more
// than max(tolerance, 8 noise / sqrt(width))
bool Still(const std::string& name, const std::vector<double>& x, const Stat& noise, int width,
           double tolerance, std::string* error);
// joint j's velocity noise (against the encoder's central difference) and torque noise (against
// its angle and velocity), beyond the motion those explain (sensors_noise.cc)
void MotionNoise(Table& t, const std::string& j, const SensorOptions& o, SensorEstimates* out);
// the IMU's orientation noise per axis beyond the turn its gyro's integral explains; false when
// the orientation turns slowly by more than tolerated (sensors_noise.cc)
bool OrientationNoise(Table& t, const SensorOptions& o, ImuEstimate* u,
                      std::vector<std::string>* warnings, std::string* error);

}  // namespace ohrp::identify::detail
