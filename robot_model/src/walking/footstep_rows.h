// The steps of a footstep file as written, before they are placed in W (internal to
// ohrp_walking): the YAML and CSV readers fill them, footstep_file.cc places and checks them.
#pragma once

#include <set>
#include <string>
#include <vector>

namespace ohrp::walking {

// one step as written, with the lines of its parts for messages
struct Written {
  int line = 0;                // the step's first line (1-based)
  int foot_line = 0;           // the line of its foot
  int foot = -1;               // kLeft or kRight
  double x = 0, y = 0, z = 0;  // [m]
  double yaw_deg = 0;          // [deg]
  double height = -1;          // [m]; <0: the file's default
  double duration = -1;        // [s]; <0: the file's default
  bool has_z = false;          // z given (else the start's height)
  bool same_foot = false;      // the step says the previous step was by this foot too
};

// what a file says besides its steps
struct Header {
  bool world = false;                 // frame: world (else relative to the start's mid frame)
  double height = -1, duration = -1;  // defaults [m, s]; <0: the generator's
};

// "foot, x, y, yaw_deg (required); z, height, duration, same_foot" for messages
extern const char* const kStepKeys;

// the keys a step may have
const std::set<std::string>& StepKeys();

// "NAME:LINE: "
std::string At(const std::string& name, int line);

// sets `*error` to at + why and returns false
bool Fail(std::string* error, const std::string& at, const std::string& why);

// a finite number from the whole of `text`, or false
bool Number(const std::string& text, double* out);

// range checks of a height [m] and a duration [s]: "" or why (the key first)
std::string CheckHeight(double h);
std::string CheckDuration(double d);

// sets one value of a step from its key and its text: "" or why (the key first)
std::string SetValue(const std::string& key, const std::string& text, Written* w);

// "" when every required key is in `seen`, else the first missing one
std::string Missing(const std::set<std::string>& seen);

// the readers: the steps of `text` in order and the header; false with `*error`
bool ParseYamlSteps(const std::string& text, const std::string& name, Header* h,
                    std::vector<Written>* rows, std::string* error);
bool ParseCsvSteps(const std::string& text, const std::string& name, std::vector<Written>* rows,
                   std::string* error);

}  // namespace ohrp::walking
