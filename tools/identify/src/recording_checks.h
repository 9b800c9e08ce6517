// Does the recording hold the experiment? Checked before its oscillation is trusted (issue 35):
// its time base has no gap across the experiment, and its swing in the window is of the size the
// simulated experiment's is (a push that came seconds early leaves only the decayed tail there).
#pragma once

#include <string>
#include <vector>

namespace ohrp::identify {

// The recording's times within [from, to]: no step longer than `max_gap` [s] (the identification
// asks for a tenth of the oscillation's period: an emulator that resynchronised to the wall
// clock leaves a longer gap; a driver that skipped a few cycles does not). False with `*error`
// naming the gap and where.
bool CheckTimeBase(const std::vector<double>& t, double from, double to, double max_gap,
                   const std::string& path, std::string* error);

// The recording's first swing in its window against the simulated experiment's at the nominal
// soles: within a factor kSwingFactor either way (other soles change it by far less). False with
// `*error` saying both and what it suggests.
inline constexpr double kSwingFactor = 5.0;
bool CheckSwing(double recorded, double simulated, double from, double to, const std::string& path,
                std::string* error);

}  // namespace ohrp::identify
