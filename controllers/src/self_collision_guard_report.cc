// The online self-collision check's summaries: its holds and the measured distances below a
// limit, said after the run (see self_collision_guard.h; the check: self_collision_guard.cc).
#include <cstdio>
#include <ostream>
#include <string>

#include "controllers/self_collision_guard.h"

namespace ohrp::controllers {

std::string SelfCollisionGuard::HoldSummary() const {
  if (holds_ == 0) return "";
  char b[400];
  const auto name = [&](collision::LinkPair p) {
    return p.a < 0 ? std::string("(none: a measurement was not finite)")
                   : file_.robot.links[p.a].name + " / " + file_.robot.links[p.b].name;
  };
  std::snprintf(b, sizeof(b), "self-collision guard braked and held %llu time(s), closest pair %s "
                "at %.1f mm (predicted lower bound; margin %.1f mm)",
                static_cast<unsigned long long>(holds_), name(closest_pair_).c_str(),
                1e3 * closest_distance_, 1e3 * file_.margin);
  return b;
}

std::string SelfCollisionGuard::ViolationSummary() const {
  if (violations_ == 0 || violation_pair_.a < 0) return "";
  char b[400];
  std::snprintf(b, sizeof(b), "links measured closer than their limit %ld time(s), closest %s / %s "
                "at %.1f mm (margin %.1f mm)", violations_,
                file_.robot.links[violation_pair_.a].name.c_str(),
                file_.robot.links[violation_pair_.b].name.c_str(), 1e3 * violation_distance_,
                1e3 * file_.margin);
  return b;
}

void SelfCollisionGuard::Report(const std::string& program, std::ostream& out) const {
  if (unjudged_cycles_ > 0)
    out << program << ": self-collision: not judged in " << unjudged_cycles_
        << " cycles (a measurement was not finite: no prediction; the commands left alone)\n";
  if (warned_cycles_ > 0 && warned_pair_.a >= 0) {
    char w[400];
    std::snprintf(w, sizeof(w), "%s: self-collision: not certified but not braked in %ld cycles "
                  "(%s), closest %s / %s at %.1f mm predicted\n",
                  program.c_str(), warned_cycles_,
                  monitor_only_ ? "monitoring only" : "a pair moved by support legs only", file_.robot.links[warned_pair_.a].name.c_str(),
                  file_.robot.links[warned_pair_.b].name.c_str(), 1e3 * warned_distance_);
    out << w;
  }
  if (retreat_cycles_ > 0)
    out << program << ": self-collision: retreated from a pair a support leg was closing in "
        << retreat_cycles_ << " cycles (" << retreats_ << " retreats)\n";
  if (held_cycles_ == 0 && violations_ == 0) return;
  const auto name = [&](collision::LinkPair p) {
    return p.a < 0 ? std::string("(none)")
                   : file_.robot.links[p.a].name + " / " + file_.robot.links[p.b].name;
  };
  char b[768];
  std::snprintf(b, sizeof(b),
                "%s: self-collision: braked and held in %ld cycles (%llu holds); first at %.3f "
                "s, pair %s at %.1f mm predicted; closest %s at %.1f mm predicted (margin %.1f "
                "mm); %ld cycles not certified within the work bound, %ld measured distances "
                "below their limit\n",
                program.c_str(), held_cycles_, static_cast<unsigned long long>(holds_),
                first_time_, name(first_pair_).c_str(), 1e3 * first_distance_,
                name(closest_pair_).c_str(), 1e3 * closest_distance_, 1e3 * file_.margin,
                uncertified_cycles_, violations_);
  out << b;
}

}  // namespace ohrp::controllers
