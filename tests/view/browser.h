// A headless Chromium driven through its DevTools protocol, for the viewer's tests: open a page,
// evaluate JavaScript in it, take screenshots (PNG files), count pixels of a colour in them.
// Debian's chromium, started as `chromium --headless --no-sandbox --enable-unsafe-swiftshader`
// (software WebGL) with its own temporary profile; the protocol goes over a WebSocket
// (Boost.Beast), one request at a time.
#pragma once

#include <png.h>
#include <unistd.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/scratch.h"

#include "../shm_bridge/test_util.h"  // WaitFor; common/process.h: Spawn, Terminate

namespace ohrp::view::testing {

namespace fs = std::filesystem;

// bytes of a base64 text (the screenshots' encoding)
inline std::string DecodeBase64(const std::string& in) {
  std::string out;
  int value = 0, bits = -8;
  for (unsigned char c : in) {
    int d = c >= 'A' && c <= 'Z' ? c - 'A' : c >= 'a' && c <= 'z' ? c - 'a' + 26
          : c >= '0' && c <= '9' ? c - '0' + 52 : c == '+' ? 62 : c == '/' ? 63 : -1;
    if (d < 0) continue;
    value = (value << 6) + d;
    bits += 6;
    if (bits >= 0) {
      out.push_back(static_cast<char>((value >> bits) & 0xff));
      bits -= 8;
    }
  }
  return out;
}

// pixels of a PNG file (RGB, rows top first) whose colour passes `match`, inside a rectangle
struct PixelCount {
  int n = 0;
  double x = 0, y = 0;  // their mean position [px]
  int y_max = -1;       // the lowest row that has one [px]
  int y_min = -1;       // the highest row that has one [px]
};
inline PixelCount CountPixels(const std::string& png_path, int x0, int y0, int x1, int y1,
                              const std::function<bool(int, int, int)>& match) {
  PixelCount c;
  FILE* f = std::fopen(png_path.c_str(), "rb");
  if (!f) return c;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_read_png(png, info, PNG_TRANSFORM_STRIP_ALPHA | PNG_TRANSFORM_STRIP_16, nullptr);
  const int w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  png_bytepp rows = png_get_rows(png, info);
  for (int y = std::max(0, y0); y < std::min(h, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(w, x1); ++x) {
      const png_bytep p = rows[y] + 3 * x;
      if (match(p[0], p[1], p[2])) {
        c.x += x;
        c.y += y;
        c.y_max = y;
        if (c.y_min < 0) c.y_min = y;
        ++c.n;
      }
    }
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(f);
  if (c.n) {
    c.x /= c.n;
    c.y /= c.n;
  }
  return c;
}

class Browser {
 public:
  // Starts chromium (window `width` x `height`) and opens `url` in a new page. ok() is false,
  // with error(), when chromium does not start or its protocol does not answer. `init_script`,
  // when given, runs in the page before any of its own scripts (DevTools
  // Page.addScriptToEvaluateOnNewDocument), e.g. to give it what a headless browser lacks.
  Browser(const std::string& url, int width = 1200, int height = 700, const std::string& init_script = "") {
    profile_ = ohrp::testing::ScratchFolder("chromium_profile");
    // chromium's own temporary folders (org.chromium.Chromium.*) go to the scratch folder too
    pid_ = ohrp::testing::Spawn(
        {"env", "TMPDIR=" + ohrp::testing::ScratchFolder("chromium_tmp"), "chromium",
         "--headless", "--no-sandbox", "--enable-unsafe-swiftshader",
         "--remote-debugging-port=0", "--no-first-run", "--hide-scrollbars",
         "--user-data-dir=" + profile_.string(),
         "--window-size=" + std::to_string(width) + "," + std::to_string(height), "about:blank"},
        {.out = "/dev/null", .err = "/dev/null"});
    // the protocol's port, then a page with the url
    std::string port, browser_path;
    shm::testing::WaitFor([&] {
      std::ifstream in(profile_ / "DevToolsActivePort");
      return in && std::getline(in, port) && std::getline(in, browser_path);
    }, 20.0);
    if (port.empty()) {
      error_ = "chromium did not start (is Debian's chromium installed? './ohrp setup')";
      return;
    }
    port_ = port;
    try {
      Connect(browser_path);
      const nlohmann::json target =
          Call("Target.createTarget", {{"url", init_script.empty() ? url : "about:blank"}});
      const std::string id = target["result"].value("targetId", "");
      ws_.reset();
      Connect("/devtools/page/" + id);
      Call("Page.enable", nlohmann::json::object());
      if (!init_script.empty()) {  // the script first, then the page
        Call("Page.addScriptToEvaluateOnNewDocument", {{"source", init_script}});
        Call("Page.navigate", {{"url", url}});
      }
    } catch (const std::exception& e) {
      error_ = std::string("chromium's protocol: ") + e.what();
    }
  }
  ~Browser() {
    try {
      if (ws_) ws_->close(boost::beast::websocket::close_code::normal);
    } catch (...) {
    }
    ws_.reset();
    ohrp::testing::Terminate(pid_, 5.0);  // killed when it has not ended within 5 s
    std::error_code ec;
    fs::remove_all(profile_, ec);
  }
  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }

  // The value of a JavaScript expression in the page (null when it threw).
  nlohmann::json Eval(const std::string& expression) {
    const nlohmann::json r =
        Call("Runtime.evaluate", {{"expression", expression}, {"returnByValue", true}});
    return r["result"]["result"].value("value", nlohmann::json());
  }

  // Waits up to `timeout` [s] until `expression` is true in the page.
  bool WaitTrue(const std::string& expression, double timeout = 15.0) {
    return shm::testing::WaitFor([&] { return Eval(expression) == true; }, timeout);
  }

  // A click of the left mouse button at (x, y) [CSS px of the page], as a user's (press, release)
  void Click(double x, double y) {
    for (const char* type : {"mousePressed", "mouseReleased"})
      Call("Input.dispatchMouseEvent",
           {{"type", type}, {"x", x}, {"y", y}, {"button", "left"}, {"clickCount", 1}});
  }

  // A drag with the left button from (x0, y0) to (x1, y1) [CSS px] in `steps` moves; `modifiers`
  // as the protocol's bits (8: shift)
  void Drag(double x0, double y0, double x1, double y1, int modifiers = 0, int steps = 5) {
    auto mouse = [&](const char* type, double x, double y) {
      Call("Input.dispatchMouseEvent", {{"type", type}, {"x", x}, {"y", y}, {"button", "left"},
                                        {"buttons", 1}, {"clickCount", 1}, {"modifiers", modifiers}});
    };
    mouse("mousePressed", x0, y0);
    for (int i = 1; i <= steps; ++i) mouse("mouseMoved", x0 + (x1 - x0) * i / steps, y0 + (y1 - y0) * i / steps);
    mouse("mouseReleased", x1, y1);
  }

  // A key pressed and released, as a user's: `key` and `code` as the DOM names them
  // ("ArrowUp", " " / "Space"), `vk` its Windows virtual key code (38, 32)
  void Key(const std::string& key, const std::string& code, int vk) {
    for (const char* type : {"keyDown", "keyUp"})
      Call("Input.dispatchKeyEvent", {{"type", type}, {"key", key}, {"code", code},
                                      {"windowsVirtualKeyCode", vk}, {"nativeVirtualKeyCode", vk}});
  }

  // Writes a screenshot of the page to `png_path`; false when none came.
  bool Screenshot(const std::string& png_path) {
    const nlohmann::json r = Call("Page.captureScreenshot", {{"format", "png"}});
    const std::string data = r["result"].value("data", "");
    if (data.empty()) return false;
    std::ofstream(png_path, std::ios::binary) << DecodeBase64(data);
    return true;
  }

 private:
  void Connect(const std::string& path) {
    namespace net = boost::asio;
    auto ws = std::make_unique<boost::beast::websocket::stream<net::ip::tcp::socket>>(io_);
    net::ip::tcp::resolver resolver(io_);
    net::connect(ws->next_layer(), resolver.resolve("127.0.0.1", port_));
    ws->handshake("127.0.0.1:" + port_, path);
    ws->text(true);
    ws_ = std::move(ws);
  }

  // one request; events that arrive before its answer are skipped
  nlohmann::json Call(const std::string& method, const nlohmann::json& params) {
    const int id = ++next_id_;
    ws_->write(boost::asio::buffer(nlohmann::json{{"id", id}, {"method", method}, {"params", params}}.dump()));
    for (;;) {
      boost::beast::flat_buffer buffer;
      ws_->read(buffer);
      nlohmann::json m = nlohmann::json::parse(boost::beast::buffers_to_string(buffer.data()));
      if (m.value("id", -1) == id) return m;
    }
  }

  fs::path profile_;
  pid_t pid_ = -1;
  std::string port_, error_;
  int next_id_ = 0;
  boost::asio::io_context io_;
  std::unique_ptr<boost::beast::websocket::stream<boost::asio::ip::tcp::socket>> ws_;
};

}  // namespace ohrp::view::testing
