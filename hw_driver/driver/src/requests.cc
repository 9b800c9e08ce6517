// Stop and emergency-stop requests: async-signal-safe flags set by the signal handlers (or a
// caller) and read by the loop (see driver.h, requests.h).
#include "requests.h"

#include <signal.h>

#include <atomic>

#include "hw_driver/driver.h"

namespace ohrp::hw {
namespace {

std::atomic<int> g_stop_requests{0};
std::atomic<bool> g_emergency_stop{false};

void OnStopSignal(int) { RequestStop(); }
void OnEmergencySignal(int) { RequestEmergencyStop(); }

}  // namespace

int StopRequests() noexcept { return g_stop_requests.load(std::memory_order_relaxed); }
bool EmergencyStopRequested() noexcept { return g_emergency_stop.load(std::memory_order_relaxed); }

void RequestStop() noexcept { g_stop_requests.fetch_add(1); }
void RequestEmergencyStop() noexcept { g_emergency_stop.store(true); }
void ClearRequests() noexcept {
  g_stop_requests.store(0);
  g_emergency_stop.store(false);
}

void InstallSignalHandlers() {
  struct sigaction sa {};
  sa.sa_handler = OnStopSignal;  // no SA_RESTART: blocking waits return and see the request
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sa.sa_handler = OnEmergencySignal;
  sigaction(SIGUSR2, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

}  // namespace ohrp::hw
