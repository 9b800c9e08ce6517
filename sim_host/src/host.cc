// The sim_host run (see host.h): the process's signal handling around one HostRun (host_run.h:
// set-up in host_setup.cc, the control cycle and the report in host_loop.cc).
#include "sim_host/host.h"

#include <signal.h>

#include <atomic>
#include <boost/interprocess/shared_memory_object.hpp>

#include "host_run.h"

namespace ohrp::sim {
namespace {

std::atomic<int> g_signal{0};
char g_segment_object[128] = "";  // removed by the fatal-error path

void OnSignal(int sig) { g_signal.store(sig); }

void OnFatal(const char*) {
  if (g_segment_object[0]) boost::interprocess::shared_memory_object::remove(g_segment_object);
}

}  // namespace

int RunHost(const HostOptions& options) {
  model::InstallMujocoHandlers(OnFatal);
  struct sigaction sa {};
  sa.sa_handler = OnSignal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
  signal(SIGXFSZ, SIG_IGN);  // a file size limit fails the log's write (reported), never kills

  HostRun run(options, &g_signal, g_segment_object, sizeof(g_segment_object));
  bool ran_enough = false;
  const int code = run.SetUp(&ran_enough);
  if (code != kExitOk || ran_enough) return code;
  return run.Run();
}

}  // namespace ohrp::sim
