// Which joints each motor board carries (see protocol.h, BoardLayout).
#include <algorithm>
#include <cstdlib>

#include "hw_udp/protocol.h"

namespace ohrp::hw::udp {
namespace {

constexpr int kSmallGroup = 3;  // limb groups below this many joints share a board [joints]

std::string Prefix(const std::string& name) { return name.substr(0, name.find('_')); }

}  // namespace

BoardLayout DefaultLayout(const std::vector<std::string>& joint_names) {
  // limb groups: consecutive joints sharing a name prefix, split to fit a board
  std::vector<BoardLayout::Range> groups;
  const int n = static_cast<int>(joint_names.size());
  for (int i = 0; i < n;) {
    int j = i + 1;
    while (j < n && Prefix(joint_names[j]) == Prefix(joint_names[i])) ++j;
    for (int k = i; k < j; k += kMaxBoardJoints)
      groups.push_back({k, std::min(kMaxBoardJoints, j - k)});
    i = j;
  }
  // runs of small groups share one board while they fit
  BoardLayout layout;
  bool last_small = false;
  for (const BoardLayout::Range& g : groups) {
    const bool small = g.count < kSmallGroup;
    if (small && last_small && layout.motor.back().count + g.count <= kMaxBoardJoints) {
      layout.motor.back().count += g.count;
    } else {
      layout.motor.push_back(g);
      last_small = small;
    }
  }
  return layout;
}

bool ParseLayout(const std::string& spec, int njoint, BoardLayout* layout, std::string* error) {
  BoardLayout out;
  int next = 0;
  size_t pos = 0;
  while (pos <= spec.size()) {
    const size_t comma = spec.find(',', pos);
    const std::string item = spec.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    pos = comma == std::string::npos ? spec.size() + 1 : comma + 1;
    const size_t dash = item.find('-');
    char* end = nullptr;
    const long a = std::strtol(item.c_str(), &end, 10);
    long b = a;
    bool ok = !item.empty() && end != item.c_str();
    if (ok && dash != std::string::npos) {
      ok = end == item.c_str() + dash;
      const char* s = item.c_str() + dash + 1;
      b = std::strtol(s, &end, 10);
      ok = ok && end != s && *end == 0;
    } else if (ok) {
      ok = *end == 0;
    }
    if (!ok) {
      *error = "board layout '" + spec + "': '" + item +
               "' is not a joint range like 6-12 (ranges are inclusive, comma-separated)";
      return false;
    }
    if (a != next || b < a) {
      *error = "board layout '" + spec + "': range '" + item + "' should start at joint " +
               std::to_string(next) + " (the ranges cover every joint once, in order)";
      return false;
    }
    if (b - a + 1 > kMaxBoardJoints) {
      *error = "board layout '" + spec + "': range '" + item + "' has more than " +
               std::to_string(kMaxBoardJoints) + " joints (one board's capacity)";
      return false;
    }
    out.motor.push_back({static_cast<int>(a), static_cast<int>(b - a + 1)});
    next = static_cast<int>(b + 1);
  }
  if (next != njoint) {
    *error = "board layout '" + spec + "' covers joints 0-" + std::to_string(next - 1) +
             " but the robot has " + std::to_string(njoint) + " joints";
    return false;
  }
  if (out.nboards() > kMaxBoards) {
    *error = "board layout '" + spec + "' has more than " + std::to_string(kMaxBoards - 1) +
             " motor boards";
    return false;
  }
  *layout = out;
  return true;
}

std::string LayoutString(const BoardLayout& layout) {
  std::string s;
  for (const BoardLayout::Range& r : layout.motor) {
    if (!s.empty()) s += ',';
    s += std::to_string(r.first) + "-" + std::to_string(r.first + r.count - 1);
  }
  return s;
}

}  // namespace ohrp::hw::udp
