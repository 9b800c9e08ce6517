// ohrp view --control: the page's control requests, forwarded to sim_host's control channel
// (sim_host --control-socket) and walk's live command channel (walk --socket), one line each.
//
//   GET /control?token=T                    {"sim": bool, "walk": bool}: what can be controlled
//   GET /control?token=T&to=sim&line=L      L to sim_host, its one reply line back (text)
//   GET /control?token=T&to=walk&line=L     L to walk, its reply back
// A request without the run's token (or with another) is refused with 403; with --control off
// every /control request is answered 404. The token is random per run (MakeToken) and printed in
// the page's URL, so only who can read the viewer's output can control the run.
#pragma once

#include <string>

namespace ohrp::view {

struct ControlOptions {
  bool on = false;
  std::string token;        // a random hex token (MakeToken)
  std::string sim_socket;   // sim_host --control-socket PATH ("": none)
  std::string walk_socket;  // walk --socket PATH ("": none)
  std::string record;       // --control-record FILE: every line forwarded, as JSON lines
                            // ("": none)
};

// The record of the lines forwarded (--control-record): one JSON line each, {"wall": unix time,
// "t": the simulated time of the newest frame, "to", "line", "status", "reply"}; walk's commands
// are recorded only here (sim_host records what it applied in its own actions.jsonl).
void RecordControl(const std::string& path, double sim_time, const std::string& to,
                   const std::string& line, int status, const std::string& reply);

// 32 hex digits from the system's random source
std::string MakeToken();

// "?a=1&b=x%20y": the value of `key` decoded ("" when absent)
std::string QueryValue(const std::string& target, const std::string& key);

// answers a /control request (`target` with its query): the HTTP status (200, 400, 403, 404,
// 502) and the body
// (recorded when `options.record` is set, with `sim_time` the newest frame's time)
int AnswerControl(const std::string& target, const ControlOptions& options, std::string* body,
                  double sim_time = -1);

// sends `line` to the local stream socket at `path` and returns its one reply line; false with
// `*reply` saying why (no such socket, no answer within `timeout` [s])
bool SendLine(const std::string& path, const std::string& line, double timeout, std::string* reply);

}  // namespace ohrp::view
