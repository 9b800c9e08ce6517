// sim_host: simulate a robot and serve its segment (see sim_host/host.h and README.md).
#include "cli/command_line.h"
#include "command_line.h"
#include "sim_host/host.h"

int main(int argc, char** argv) {
  ohrp::sim::HostOptions o;
  ohrp::sim::RawHostOptions raw;
  CLI::App app{
      "sim_host: simulates a robot in MuJoCo and serves its sensors and commands through the\n"
      "shared-memory segment NAME, to which a controller attaches (e.g. 'posture --segment NAME').\n"
      "Lock-step by default: simulated time advances only when the controller has answered."};
  ohrp::sim::AddHostOptions(&app, &o, &raw);
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  if (const int code = ohrp::sim::ResolveHostOptions(app, raw, &o); code >= 0) return code;
  return ohrp::sim::RunHost(o);
}
