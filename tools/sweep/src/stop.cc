// Stopping a sweep (see stop.h).
#include "stop.h"

#include <signal.h>

#include <atomic>

namespace ohrp::sweep {
namespace {

std::atomic<int> g_signal{0};
void OnSignal(int sig) { g_signal.store(sig); }

}  // namespace

void InstallStopHandlers() {
  struct sigaction sa {};
  sa.sa_handler = OnSignal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int StopSignal() { return g_signal.load(); }

}  // namespace ohrp::sweep
