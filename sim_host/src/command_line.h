// sim_host's command line (main.cc): the options in groups, then the values that need more than
// a range check (a profile's files, the contact, sizes, effects, pushes) turned into HostOptions,
// each refused with exit 2 (kExitUsage) and a line naming the option before anything runs.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "sim_host/host.h"

namespace ohrp::sim {

// the options as typed, before they are resolved into HostOptions
struct RawHostOptions {
  std::string contact = "auto", loss = "end", on_fall = "end", camera_size = "640x480", log_max;
  std::vector<std::string> pushes, effects;
};

// every option of sim_host, bound to `o` and `r`
void AddHostOptions(CLI::App* app, HostOptions* o, RawHostOptions* r);

// after parsing: -1 to go on, else the exit code (the error printed)
int ResolveHostOptions(const CLI::App& app, const RawHostOptions& r, HostOptions* o);

}  // namespace ohrp::sim
