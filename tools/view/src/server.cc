// The viewer's HTTP + WebSocket server (server.h): Boost.Beast, synchronous, one thread per
// connection.
#include "view/server.h"

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

namespace ohrp::view {

namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = boost::asio::ip::tcp;

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Asset {
  const char* target;
  std::string path;
  const char* type;
};

// pages' WebSockets open now (their threads use the source: it must outlive them)
std::atomic<int> open_connections{0};
struct Counted {
  Counted() { ++open_connections; }
  ~Counted() { --open_connections; }
};

// live: push the newest frame whenever there is one; close once the last one is sent
void PushFrames(websocket::stream<tcp::socket>& ws, Source* source) {
  uint64_t version = 0;
  for (;;) {
    const bool ended = source->ended();
    uint64_t v = 0;
    std::shared_ptr<const std::string> frame = source->Newest(version, ended ? 0.0 : 1.0, &v);
    if (ended && v == version) {
      ws.close(websocket::close_code::normal);
      return;
    }
    if (!frame || v == version) {
      // nothing new: a ping keeps a dead page from holding its thread forever
      ws.ping({});
      continue;
    }
    version = v;
    ws.write(boost::asio::buffer(*frame));
  }
}

// live images: while this page is connected the source asks the producer for the camera
// images. Only the newest images are ever sent, never a queue: the page answers each image once
// it has drawn it (any message), and at most kInFlight images per camera are sent and not yet
// answered; meanwhile newer images replace older ones in the source. A slow page therefore gets
// the newest image when it is ready again instead of a backlog queued in socket buffers (images
// ran seconds behind the robot). The send buffer is kept small for the same reason.
constexpr int kInFlight = 2;
void PushImages(websocket::stream<tcp::socket>& ws, Source* source) {
  struct Watching {
    Source* s;
    explicit Watching(Source* source) : s(source) { s->WatchImages(+1); }
    ~Watching() { s->WatchImages(-1); }
  } watching(source);
  ws.binary(true);
  ws.next_layer().set_option(boost::asio::socket_base::send_buffer_size(64 * 1024));
  // The server never pings this socket: the page sends its answers, then its close. Looked at
  // every 0.2 s without blocking (the first image may take seconds: a producer may start its
  // renderer only when asked, and the socket stays open meanwhile): something readable while
  // answers are owed is read (an answer; a close frame throws, which ends this thread and the
  // watch), with none owed it is the close. At the limit of unanswered images read() blocks
  // until the page answers. Each read takes one message, so none is counted twice or lost (an
  // answer that Beast has already buffered is taken by the next read). A page that went away
  // without a word fails a read or a write.
  auto readable = [&] {
    pollfd p{ws.next_layer().native_handle(), POLLIN, 0};
    return ::poll(&p, 1, 0) != 0;
  };
  auto read_answer = [&] {
    beast::flat_buffer answer;
    ws.read(answer);
  };
  uint64_t sent[shm::kMaxCameras] = {};
  std::shared_ptr<const std::string> images[shm::kMaxCameras];
  int unanswered = 0, cameras = 0;
  bool seen[shm::kMaxCameras] = {};
  while (!source->ended()) {
    if (readable()) {
      if (unanswered == 0) return;  // the page's close
      read_answer();
      --unanswered;
      continue;
    }
    if (cameras > 0 && unanswered >= kInFlight * cameras) {
      read_answer();  // blocks until the page has drawn one
      --unanswered;
      continue;
    }
    if (!source->NewestImages(sent, 0.2, images)) continue;
    for (int c = 0; c < shm::kMaxCameras; ++c)
      if (images[c]) {
        ws.write(boost::asio::buffer(*images[c]));
        ++unanswered;
        if (!seen[c]) ++cameras;
        seen[c] = true;
      }
  }
  // returning closes the socket (and ends the watch)
}

// replay: answer each {"t": ...} with the frame at that time, each {"column": NAME} with the
// log column's curve
void AnswerFrames(websocket::stream<tcp::socket>& ws, Source* source) {
  for (;;) {
    beast::flat_buffer buffer;
    ws.read(buffer);
    nlohmann::json answer;
    try {
      const nlohmann::json ask = nlohmann::json::parse(beast::buffers_to_string(buffer.data()));
      answer = ask.contains("column") ? source->Column(ask.at("column").get<std::string>())
                                      : source->FrameAt(ask.value("t", 0.0));
    } catch (const std::exception&) {
      continue;  // not ours: ignored
    }
    const std::string text = answer.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    ws.write(boost::asio::buffer(text));
  }
}

// one connection: HTTP requests until it upgrades to the WebSocket or closes
void Serve1(tcp::socket socket, Source* source, const std::vector<Asset>* assets,
            const ControlOptions* control) {
  try {
    beast::flat_buffer buffer;
    for (;;) {
      http::request<http::string_body> req;
      http::read(socket, buffer, req);
      if (websocket::is_upgrade(req) && req.target() == "/ws/images") {
        const Counted counted;
        websocket::stream<tcp::socket> ws(std::move(socket));
        ws.accept(req);
        if (source->live())
          PushImages(ws, source);
        else
          ws.close({websocket::close_code::normal, "no images in a run folder"});
        return;
      }
      if (websocket::is_upgrade(req) && req.target() == "/ws") {
        const Counted counted;
        websocket::stream<tcp::socket> ws(std::move(socket));
        ws.accept(req);
        ws.text(true);
        const std::string hello = source->Hello().dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
        ws.write(boost::asio::buffer(hello));
        if (source->live())
          PushFrames(ws, source);
        else
          AnswerFrames(ws, source);
        return;
      }
      // the page and its scripts (the query string is the page's business)
      std::string target(req.target());
      target = target.substr(0, target.find('?'));
      http::response<http::string_body> res;
      res.version(req.version());
      res.keep_alive(req.keep_alive());
      res.result(http::status::not_found);
      res.set(http::field::content_type, "text/plain");
      res.body() = "not found\n";
      // replay: a recorded camera image, only the files the run's index names (source.h)
      if (std::string file; target.rfind("/recorded/", 0) == 0 &&
                            source->RecordedImage(target.substr(10), &file)) {
        res.result(http::status::ok);
        res.set(http::field::content_type, "image/png");
        res.body() = ReadFile(file);
      }
      if (target == "/control") {
        std::string body;
        double t = -1;  // the newest frame's simulated time, for the record
        uint64_t v = 0;
        if (const auto frame = source->Newest(0, 0.0, &v))
          t = nlohmann::json::parse(*frame, nullptr, false).value("t", -1.0);
        res.result(static_cast<http::status>(AnswerControl(std::string(req.target()), *control, &body, t)));
        res.set(http::field::cache_control, "no-store");
        res.body() = body;
      }
      for (const Asset& a : *assets)
        if (target == a.target) {
          res.result(http::status::ok);
          res.set(http::field::content_type, a.type);
          res.set(http::field::cache_control, "no-store");
          res.body() = ReadFile(a.path);
        }
      res.prepare_payload();
      http::write(socket, res);
      if (!res.keep_alive()) return;
    }
  } catch (const std::exception&) {
    // the page went away: its thread ends, nothing else is affected
  }
}

}  // namespace

int Serve(Source* source, const ServerOptions& options, bool exit_when_ended) {
  static std::vector<Asset> assets;
  assets = {{"/", options.web_dir + "/index.html", "text/html; charset=utf-8"},
            {"/index.html", options.web_dir + "/index.html", "text/html; charset=utf-8"},
            {"/view.js", options.web_dir + "/view.js", "text/javascript"},
            {"/plots.js", options.web_dir + "/plots.js", "text/javascript"},
            {"/overlays.js", options.web_dir + "/overlays.js", "text/javascript"},
            {"/plan.js", options.web_dir + "/plan.js", "text/javascript"},
            {"/reach.js", options.web_dir + "/reach.js", "text/javascript"},
            {"/recorded.js", options.web_dir + "/recorded.js", "text/javascript"},
            {"/control.js", options.web_dir + "/control.js", "text/javascript"},
            {"/workbench.js", options.web_dir + "/workbench.js", "text/javascript"},
            {"/pace.js", options.web_dir + "/pace.js", "text/javascript"},
            {"/scene.js", options.web_dir + "/scene.js", "text/javascript"},
            {"/images.js", options.web_dir + "/images.js", "text/javascript"},
            {"/lib/three.min.js", options.three_js, "text/javascript"},
            {"/lib/chart.min.js", options.chart_js, "text/javascript"}};
  for (const Asset& a : assets)
    if (!std::ifstream(a.path)) {
      std::fprintf(stderr, "ohrp_view: missing '%s' (%s; './ohrp setup' installs libjs-three and "
                           "libjs-chart.js)\n", a.path.c_str(), a.target);
      return 2;
    }
  boost::asio::io_context io;
  tcp::acceptor acceptor(io);
  boost::system::error_code ec;
  const tcp::endpoint at(boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(options.port));
  acceptor.open(at.protocol(), ec);
  if (!ec) acceptor.set_option(boost::asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(at, ec);
  if (!ec) acceptor.listen(boost::asio::socket_base::max_listen_connections, ec);
  if (ec) {
    std::fprintf(stderr, "ohrp_view: cannot listen on 127.0.0.1:%d: %s (choose another --port, or 0 "
                         "for a free one)\n", options.port, ec.message().c_str());
    return 2;
  }
  // with --control the URL carries the run's token: only who reads this line can control the run
  const std::string query = options.control.on ? "?token=" + options.control.token : "";
  std::printf("ohrp_view: serving http://127.0.0.1:%d/%s (Ctrl-C ends)\n",
              acceptor.local_endpoint().port(), query.c_str());
  std::fflush(stdout);
  // a live viewer told to end with its producer: a watcher closes the acceptor
  std::thread watcher;
  if (exit_when_ended && source->live()) {
    watcher = std::thread([&] {
      while (!source->ended()) usleep(50000);
      usleep(500000);  // the last frame reaches the pages
      ::shutdown(acceptor.native_handle(), SHUT_RDWR);  // ends the blocking accept
    });
  }
  for (;;) {
    tcp::socket socket(io);
    acceptor.accept(socket, ec);
    if (ec) break;
    std::thread(Serve1, std::move(socket), source, &assets, &options.control).detach();
  }
  if (watcher.joinable()) watcher.join();
  // the pages' threads end after the last frame; one stuck on a stalled page cannot be joined:
  // then the process ends without tearing the source down under it
  for (int i = 0; i < 40 && open_connections > 0; ++i) usleep(50000);
  if (open_connections > 0) {
    std::fflush(stdout);
    std::_Exit(0);
  }
  return 0;
}

}  // namespace ohrp::view
