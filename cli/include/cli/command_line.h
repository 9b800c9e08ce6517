// The command-line convention of every ohrp program: `--help` prints the help and exits 0; a
// bad option (unknown, missing, not a number, out of range, a file that does not exist) prints
// one line "PROGRAM: what was wrong" and exits 2 (kExitUsage), before anything runs. CLI11's own
// exit codes (105, 106, 109, ...) never leave a program.
//
// Use:
//   CLI::App app{"..."};
//   app.add_option("--period", period, "...")->check(ohrp::cli::Positive());
//   if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
//
// Header-only: CLI11 is a header library, and the programs' libraries do not depend on it.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "cli/plausible.h"

namespace ohrp::cli {

inline constexpr int kExitHelp = 0;   // --help (or --help-all) printed
inline constexpr int kExitUsage = 2;  // bad command line: every program's "2 bad option"

namespace detail {

// `text` as a finite number, or false (trailing characters, nan and inf are not numbers here)
inline bool ParseFinite(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(*value);
}

// a number in [lo, hi] (either bound may be open), with a message that says what would work
inline CLI::Validator NumberIn(double lo, bool lo_open, double hi, bool hi_open,
                               const std::string& what, const std::string& label) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0;
        if (!ParseFinite(text, &v)) return "'" + text + "' is not a number (want " + what + ")";
        const bool below = lo_open ? !(v > lo) : v < lo;
        const bool above = hi_open ? !(v < hi) : v > hi;
        if (below || above) return text + " is out of range (want " + what + ")";
        return std::string();
      },
      label);
}

// `v` in a short text for messages (%.15g: "0.0001", "1", "65535", not "0.000100")
inline std::string Short(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.15g", v);
  return buf;
}

}  // namespace detail

// A finite number > 0.
inline CLI::Validator Positive() {
  return detail::NumberIn(0.0, true, HUGE_VAL, false, "a number > 0", "POSITIVE");
}

// A finite number >= 0.
inline CLI::Validator NonNegative() {
  return detail::NumberIn(0.0, false, HUGE_VAL, false, "a number >= 0", "NONNEGATIVE");
}

// A finite number in [lo, hi].
inline CLI::Validator InRange(double lo, double hi) {
  const std::string range = "[" + detail::Short(lo) + ", " + detail::Short(hi) + "]";
  return detail::NumberIn(lo, false, hi, false, "a number in " + range, "in " + range);
}

// A finite number within the plausible range of `quantity` (cli/plausible.h): the table's range,
// unit and reason in the message. An unknown quantity refuses every value (a programming error
// the programs' tests catch).
inline CLI::Validator Plausible(const std::string& quantity) {
  const PlausibleRange* r = FindPlausible(quantity);
  const std::string label = r ? "in [" + detail::Short(r->lo) + ", " + detail::Short(r->hi) + "]" +
                                    (r->unit[0] ? std::string(" ") + r->unit : std::string())
                              : "?";
  return CLI::Validator(
      [quantity](std::string& text) -> std::string {
        double v = 0;
        if (!detail::ParseFinite(text, &v)) return "'" + text + "' is not a number";
        // "X is outside the plausible range ..." (CLI11 prefixes the option's name)
        const PlausibleRange* r = FindPlausible(quantity);
        if (r == nullptr) return CheckPlausible(quantity, v, text);
        return IsPlausible(*r, v) ? std::string() : text + " is outside " + PlausibleRangeText(*r);
      },
      label);
}

// Parses the command line of `app`. Returns -1 to go on, else the exit code to return at once:
// kExitHelp after printing the help on stdout, kExitUsage after printing the error (prefixed by
// the program's name, argv[0] without its folder) and a pointer to --help on stderr.
inline int ParseCommandLine(CLI::App* app, int argc, char** argv) {
  try {
    app->parse(argc, argv);
  } catch (const CLI::Success& e) {
    // --help, --help-all: CLI11 prints the help
    app->exit(e);
    return kExitHelp;
  } catch (const CLI::ParseError& e) {
    std::string program = argc > 0 ? argv[0] : "";
    program = program.substr(program.rfind('/') + 1);
    std::fprintf(stderr, "%s: %s\nRun with --help for the options.\n", program.c_str(), e.what());
    return kExitUsage;
  }
  return -1;
}

}  // namespace ohrp::cli
