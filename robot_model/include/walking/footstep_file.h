// Footstep files: a list of steps written by hand, in YAML (.yaml, .yml) or CSV (.csv). The
// format is documented with a worked example in docs/footsteps.md; scenarios/steps/ holds
// examples.
//
// YAML:
//   frame: start            # optional: start (default; x, y, z, yaw relative to the start's
//                           #   mid frame) or world
//   defaults: {height: 0.04, duration: 0.8}   # optional: for steps that give none
//   steps:
//     - {foot: left, x: 0.20, y: 0.09, yaw_deg: 0}
//     - {foot: right, x: 0.40, y: -0.09, z: 0.0, yaw_deg: 0, height: 0.05, duration: 1.0}
// CSV (always relative to the start's mid frame; `#` starts a comment line; the header names the
// columns, in any order; an empty cell of an optional column takes the default):
//   foot,x,y,z,yaw_deg,height,duration
//   left,0.20,0.09,,0,,
//
// Per step: foot (left or right), x, y [m], yaw_deg [deg] required; z (the surface height under
// the sole [m], default: the start's), height (swing apex [m], 0 .. 0.5), duration (the step's
// time [s], above 0 .. 10) and same_foot (true: this foot stepped last too; without it the same
// foot twice in a row is refused) optional.
#pragma once

#include <string>
#include <vector>

#include "walking/footsteps.h"

namespace ohrp::walking {

enum class FootstepFormat { kYaml, kCsv };

// The format of a file by its extension (.yaml, .yml, .csv); false for any other.
bool FootstepFormatOf(const std::string& path, FootstepFormat* format);

// Reads the footstep file at `path` and fills `*steps` with the steps in W from `start` (both
// soles before the first step). Every step is checked against `limits` (CheckStep) from the
// stance the previous steps leave. False with `*error` naming the file, the line, the key and
// what would work ("PATH:LINE: KEY: why (what would work)"): a file that cannot be read, an
// unknown extension, YAML that does not parse, unknown or repeated keys, wrong types, a missing
// required key, values out of range, the same foot twice without `same_foot: true`, feet that
// cross and steps beyond the limits (the limit named). `*steps` is left empty on failure.
bool ReadFootstepFile(const std::string& path, const FeetPose& start, const StepLimits& limits,
                      std::vector<Footstep>* steps, std::string* error);

// The same for text in `format`; `name` stands for the file in messages.
bool ParseFootstepText(const std::string& text, FootstepFormat format, const std::string& name,
                       const FeetPose& start, const StepLimits& limits,
                       std::vector<Footstep>* steps, std::string* error);

}  // namespace ohrp::walking
