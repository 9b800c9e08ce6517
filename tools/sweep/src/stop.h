// Stopping a sweep (internal): SIGINT or SIGTERM sets one flag that the executors and
// RunVariant poll; each ends what it started (its variants' process groups, a Slurm job).
#pragma once

namespace ohrp::sweep {

// SIGINT and SIGTERM set the flag (the handler does nothing else).
void InstallStopHandlers();
// The signal that asked to stop, 0 when none.
int StopSignal();
inline bool StopRequested() { return StopSignal() != 0; }

}  // namespace ohrp::sweep
