// printf's "%.9g" by one scaled product (format_g9.h).
//
// With a = |v| and x = floor(log10 a), s = a 10^(8 - x) lies in [1e8, 1e9), and the nine
// significant digits are s rounded to the nearest integer. 10^k is the correctly rounded double
// (strtod), so s carries a relative error of at most two roundings, 2.3e-16: under 2.3e-7 in
// absolute terms. Wherever the fraction of s is further than 1e-5 from 1/2 the rounding is
// therefore that of the exact value; nearer, the exact path decides.
#include "datalog/format_g9.h"

#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

namespace ohrp::datalog {
namespace {

constexpr int kMinPow = -320, kMaxPow = 320;
constexpr double kTieMargin = 1e-5;  // far above the product's error, 2.3e-7

struct Pow10 {
  double v[kMaxPow - kMinPow];
  Pow10() {
    for (int k = kMinPow; k < kMaxPow; ++k)
      v[k - kMinPow] = std::strtod(("1e" + std::to_string(k)).c_str(), nullptr);
  }
  double operator()(int k) const { return v[k - kMinPow]; }
};

const Pow10& Powers() {
  static const Pow10 table;
  return table;
}

constexpr char kPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

char* Exact(char* out, double v) {
  return std::to_chars(out, out + kFormatG9Max, v, std::chars_format::general, 9).ptr;
}

}  // namespace

char* FormatG9(char* out, double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  // 2^-959 .. 2^977 (about 1e-289 .. 1e294): the scale 10^(8 - x) stays in the table
  if (biased < 64 || biased > 2000) {
    if (v == 0) {
      if (bits >> 63) *out++ = '-';
      *out++ = '0';
      return out;
    }
    return Exact(out, v);
  }
  const double a = v < 0 ? -v : v;
  const Pow10& pow10 = Powers();
  // floor(log10 2^e) (78913 / 2^18 = log10 2 to 6e-8): x is floor(log10 a) or one less
  int x = ((biased - 1023) * 78913) >> 18;
  double s = a * pow10(8 - x);
  if (s >= 1e9 - 0.5 + kTieMargin) {
    ++x;
    s = a * pow10(8 - x);
  } else if (s < 1e8 - 0.5) {
    --x;
    s = a * pow10(8 - x);
  }
  if (!(s >= 1e8 - 0.5 && s < 1e9)) return Exact(out, v);
  const uint64_t whole = static_cast<uint64_t>(s);
  const double frac = s - static_cast<double>(whole);
  if (frac > 0.5 - kTieMargin && frac < 0.5 + kTieMargin) return Exact(out, v);
  uint32_t m = static_cast<uint32_t>(whole) + (frac > 0.5 ? 1 : 0);
  if (m >= 1000000000u) {  // rounded up to the next decade
    m = 100000000u;
    ++x;
  }
  if (m < 100000000u) return Exact(out, v);
  char digit[9];
  digit[0] = static_cast<char>('0' + m / 100000000u);
  uint32_t rest = m % 100000000u;
  for (int i = 7; i >= 1; i -= 2) {
    const uint32_t pair = rest % 100;
    rest /= 100;
    digit[i] = kPairs[2 * pair];
    digit[i + 1] = kPairs[2 * pair + 1];
  }
  int n = 9;
  while (n > 1 && digit[n - 1] == '0') --n;  // %g drops trailing zeros
  if (v < 0) *out++ = '-';
  if (x >= -4 && x < 9) {  // %g's fixed notation: exponent in [-4, precision)
    if (x < 0) {
      *out++ = '0';
      *out++ = '.';
      for (int i = -1; i > x; --i) *out++ = '0';
      for (int i = 0; i < n; ++i) *out++ = digit[i];
    } else {
      int i = 0;
      for (; i <= x; ++i) *out++ = i < n ? digit[i] : '0';
      if (n > x + 1) {
        *out++ = '.';
        for (; i < n; ++i) *out++ = digit[i];
      }
    }
    return out;
  }
  *out++ = digit[0];
  if (n > 1) {
    *out++ = '.';
    for (int i = 1; i < n; ++i) *out++ = digit[i];
  }
  *out++ = 'e';
  *out++ = x < 0 ? '-' : '+';
  int e = x < 0 ? -x : x;  // at least two digits, as printf
  if (e >= 100) {
    *out++ = static_cast<char>('0' + e / 100);
    e %= 100;
  }
  *out++ = kPairs[2 * e];
  *out++ = kPairs[2 * e + 1];
  return out;
}

}  // namespace ohrp::datalog
