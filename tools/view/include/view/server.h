// The viewer's HTTP + WebSocket server (Boost.Beast), on 127.0.0.1 only.
//
//   GET /                      the page (web/index.html)
//   GET /view.js               its script (web/view.js)
//   GET /plots.js              its plots (web/plots.js)
//   GET /overlays.js           its balance overlays in 3D (web/overlays.js)
//   GET /plan.js               its walk-plan overlays in 3D (web/plan.js)
//   GET /lib/three.min.js      three.js from Debian's libjs-three (nothing from the internet)
//   GET /lib/chart.min.js      Chart.js from Debian's libjs-chart.js
//   GET /control?token=...     --control: pause, step, push, walk commands (view/control.h)
//   GET /ws                    the WebSocket: the server sends the source's Hello() first, then
//                              live: every new frame (text, JSON; a slow page gets the newest
//                              frame when it is ready again, never a queue of old ones);
//                              replay: answers each {"t": seconds} message with FrameAt(t).
//   GET /ws/images             live: the camera images (binary messages, source.h), asked from
//                              the producer only while at least one page holds this socket open;
//                              the page answers each image it has drawn (any message), and at
//                              most two per camera are unanswered (the newest sent, never a queue);
//                              replay: closed at once (a run folder has no images).
// One thread per connection, so a stalled page stalls only its own connection; the source's
// thread (the observer) never waits for a page.
#pragma once

#include <string>

#include "view/control.h"
#include "view/source.h"

namespace ohrp::view {

struct ServerOptions {
  int port = 0;             // 0: the system picks a free port
  std::string web_dir;      // folder of index.html and view.js
  std::string three_js;     // path of three.min.js
  std::string chart_js;     // path of chart.min.js
  ControlOptions control;   // --control: /control requests (view/control.h); the URL printed
                            // carries the token
};

// Binds 127.0.0.1:port and prints "ohrp_view: serving http://127.0.0.1:PORT/ ..." on stdout.
// Returns 2 with a message on stderr when the port cannot be bound or a file is missing;
// otherwise serves until the process ends (or, for a live source, `exit_when_ended` and the
// producer has stopped: returns 0).
int Serve(Source* source, const ServerOptions& options, bool exit_when_ended);

}  // namespace ohrp::view
