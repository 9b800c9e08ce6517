// The data log's end and the provisional summary (see report.h): what reached the disk, and a
// failed write as an event, the run's outcome and its exit code.
#include <unistd.h>

#include <cstdio>
#include <nlohmann/json.hpp>

#include "sim_host/report.h"

namespace ohrp::sim {
namespace {

// an event at a given time and cycle (RunStats::Record stamps the current cycle)
void RecordAt(RunStats* st, double time, uint64_t cycle, const char* kind, int64_t value) {
  if (st->events.size() < kMaxHostEvents) {
    st->events.push_back(HostEvent{time, cycle, kind, value});
  } else {
    ++st->events_dropped;
  }
}

}  // namespace

void EndLog(datalog::Recorder* log, RunStats* st, int* exit_code) {
  log->Close();
  st->log_rows = log->rows_on_disk();
  st->log_dropped = log->dropped();
  st->log_lost = log->lost();
  st->log_over_limit = log->over_limit();
  st->log_bytes = log->bytes_on_disk();
  if (log->limit_reached()) {
    RecordAt(st, log->limit_time(), log->limit_cycle(), "log_limit_reached",
             static_cast<int64_t>(log->over_limit()));
  }
  if (log->failed()) {
    st->log_error = log->error();
    RecordAt(st, log->failure_time(), log->failure_cycle(), "log_write_failed",
             static_cast<int64_t>(log->rows_on_disk()));
    if (*exit_code == kExitOk) {
      st->outcome = "log_failed";
      st->detail = "the data log '" + log->path() + "' is incomplete: " + log->error();
      *exit_code = kExitOutputFailed;
    }
  }
  if (log->failed() || log->limit_reached() || log->dropped() > 0)
    std::fprintf(stderr, "sim_host: %s\n", log->Describe().c_str());
}

std::string ProvisionalSummary(const HostOptions& o) {
  nlohmann::json j;
  j["outcome"] = "running";
  j["detail"] = "sim_host (pid " + std::to_string(getpid()) +
                ") has not written its summary: still running, or killed before its end";
  j["exit_code"] = nullptr;
  j["scene"] = o.scene;
  return j.dump(2) + "\n";
}

}  // namespace ohrp::sim
