// FormatG9 against printf's "%.9g" itself: every value must give the same text.
#include "datalog/format_g9.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace ohrp::datalog {
namespace {

std::string Printf(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

std::string Fast(double v) {
  char b[kFormatG9Max + 8];
  std::memset(b, 'X', sizeof b);
  char* end = FormatG9(b, v);
  EXPECT_LE(end - b, kFormatG9Max);
  return std::string(b, end);
}

// counts and shows the first few values whose text differs
void ExpectSame(const std::vector<double>& values, const char* what) {
  int bad = 0;
  for (double v : values) {
    const std::string want = Printf(v), got = Fast(v);
    if (want != got && ++bad <= 5) {
      ADD_FAILURE() << what << ": " << std::hexfloat << v << " printf " << want << " FormatG9 "
                    << got;
    }
  }
  EXPECT_EQ(bad, 0) << what << ": " << bad << " of " << values.size() << " differ";
}

TEST(FormatG9, SpecialValues) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ExpectSame({0.0, -0.0, 1.0, -1.0, 0.5, 1e-4, 1e-5, 9.9999999995e-5, 0.0001, 123456789.0,
              1234567890.0, 999999999.5, 999999999.4999, 1e9, 1e8, 100000000.5, 1e-300, 1e300,
              std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
              std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(), inf, -inf,
              nan, -nan},
             "special values");
  EXPECT_EQ(Fast(0.25), "0.25");
  EXPECT_EQ(Fast(-1.5e-7), "-1.5e-07");
  EXPECT_EQ(Fast(15000000.0), "15000000");
  EXPECT_EQ(Fast(1.0 / 3.0), "0.333333333");
}

TEST(FormatG9, RandomBitPatterns) {  // every exponent, subnormals, NaN payloads
  std::mt19937_64 rng(11);
  std::vector<double> v(1000000);
  for (double& x : v) {
    const uint64_t bits = rng();
    std::memcpy(&x, &bits, sizeof x);
  }
  ExpectSame(v, "random bit patterns");
}

TEST(FormatG9, SensorLikeValues) {  // what a log holds: moderate values over a few decades
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> v;
  for (int i = 0; i < 1000000; ++i) v.push_back(u(rng) * std::pow(10.0, int(rng() % 12) - 6));
  for (int i = 0; i < 200000; ++i) v.push_back(std::round(u(rng) * 1e6) / 1e3);  // short decimals
  for (int i = 0; i < 200000; ++i) v.push_back(double(float(u(rng) * 100)));
  ExpectSame(v, "sensor-like values");
}

TEST(FormatG9, RoundingTiesAndTheirNeighbours) {
  // ten significant digits ending in 5 are (to within a rounding) halfway between two
  // nine-digit results: the exact path must decide, and the doubles either side of them too
  std::mt19937_64 rng(13);
  std::vector<double> v;
  for (int i = 0; i < 200000; ++i) {
    char b[64];
    std::snprintf(b, sizeof b, "%d.%08d5e%d", 1 + int(rng() % 9), int(rng() % 100000000),
                  int(rng() % 80) - 40);
    const double t = std::strtod(b, nullptr);
    v.push_back(t);
    v.push_back(std::nextafter(t, 0.0));
    v.push_back(std::nextafter(t, 1e300));
  }
  ExpectSame(v, "ties");
}

// powers of ten and 9.99999999x: where the exponent and the notation change
TEST(FormatG9, DecadeBoundaries) {
  std::mt19937_64 rng(14);
  std::vector<double> v;
  for (int k = -320; k <= 308; ++k) {
    const double p = std::strtod(("1e" + std::to_string(k)).c_str(), nullptr);
    for (double q : {p, std::nextafter(p, 0.0), std::nextafter(p, 1e308), -p}) v.push_back(q);
  }
  for (int i = 0; i < 100000; ++i) {
    char b[64];
    std::snprintf(b, sizeof b, "9.99999999%de%d", int(rng() % 10), int(rng() % 80) - 40);
    v.push_back(std::strtod(b, nullptr));
  }
  ExpectSame(v, "decade boundaries");
}

}  // namespace
}  // namespace ohrp::datalog
