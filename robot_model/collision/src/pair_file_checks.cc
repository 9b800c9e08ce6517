// What a self-collision file must satisfy besides its syntax: lists that account for every pair
// once and agree with each other and the joints, and a checksum of its text
// (collision/pair_file.h).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <map>
#include <utility>

#include "collision/pair_file.h"
#include "collision/prune.h"

namespace ohrp::collision {
namespace {

const char kRegenerate[] = "regenerate the file with ohrp_selfcollision (docs/selfcollision.md)";

std::string PairName(const RobotGeometry& r, LinkPair p) {
  return "[" + r.links[p.a].name + ", " + r.links[p.b].name + "]";
}

std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.6g", v);
  return b;
}

uint64_t Fnv1a64(const std::string& text) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (const unsigned char ch : text) {
    h ^= ch;
    h *= 0x100000001b3ull;
  }
  return h;
}

bool Fail(FileProblem* problem, const std::string& key, int item, const std::string& what) {
  *problem = {key, item, what};
  return false;
}

// online, structural and never: non-adjacent pairs, each listed once in them all
bool CheckLists(const SelfCollisionFile& f, const std::vector<LinkPair>& all,
                std::map<std::pair<int, int>, std::string>* listed, FileProblem* problem) {
  const std::pair<const char*, const std::vector<LinkPair>*> lists[] = {
      {"online", &f.online}, {"structural", &f.structural}, {"never", &f.never}};
  for (const auto& [key, list] : lists) {
    for (size_t k = 0; k < list->size(); ++k) {
      const LinkPair p = (*list)[k];
      if (std::find(all.begin(), all.end(), p) == all.end())
        return Fail(problem, key, static_cast<int>(k),
                    "pair " + PairName(f.robot, p) +
                        " is not a pair to check (parent and child, or a link without shapes)");
      const auto [at, fresh] = listed->emplace(std::make_pair(p.a, p.b), key);
      if (!fresh)
        return Fail(problem, key, static_cast<int>(k),
                    "pair " + PairName(f.robot, p) + " is also in " + at->second +
                        " (each pair in one list only: " + kRegenerate + ")");
    }
  }
  return true;
}

// each range: one per joint, inside the limits and narrower, its joint between its pairs'
// links, its pairs in no other list
bool CheckRanges(const SelfCollisionFile& f, const std::vector<LinkPair>& all,
                 std::map<std::pair<int, int>, std::string>* listed, FileProblem* problem) {
  const RobotGeometry& r = f.robot;
  std::vector<char> seen(static_cast<size_t>(NumJoints(r)), 0);
  std::map<std::pair<int, int>, std::string> ranged;
  for (size_t k = 0; k < f.ranges.size(); ++k) {
    const SafeRange& s = f.ranges[k];
    const int item = static_cast<int>(k);
    const std::string name = JointName(r, s.joint);
    const double lo = r.q_min[s.joint], hi = r.q_max[s.joint];
    if (seen[s.joint]++)
      return Fail(problem, "safe_ranges", item, "joint " + name + " has a second range (one per joint)");
    if (s.lo < lo || s.hi > hi)
      return Fail(problem, "safe_ranges", item,
                  "the range " + Num(s.lo) + " .. " + Num(s.hi) + " of " + name +
                      " goes beyond its limits " + Num(lo) + " .. " + Num(hi));
    if (s.lo <= lo && s.hi >= hi)
      return Fail(problem, "safe_ranges", item,
                  "the range of " + name + " covers its whole range " + Num(lo) + " .. " + Num(hi) +
                      ": it restricts nothing (its pairs would be never pairs: " + kRegenerate + ")");
    if (s.pairs.empty())
      return Fail(problem, "safe_ranges", item, "the range of " + name + " prunes no pair");
    for (const LinkPair& p : s.pairs) {
      if (std::find(all.begin(), all.end(), p) == all.end())
        return Fail(problem, "safe_ranges", item,
                    "pair " + PairName(r, p) + " is not a pair to check (parent and child)");
      const auto other = listed->find({p.a, p.b});
      if (other != listed->end())
        return Fail(problem, "safe_ranges", item,
                    "pair " + PairName(r, p) + " of the range of " + name + " is also in " +
                        other->second + " (" + kRegenerate + ")");
      const std::vector<int> between = JointsBetween(r, p.a, p.b);
      if (std::find(between.begin(), between.end(), s.joint) == between.end())
        return Fail(problem, "safe_ranges", item,
                    "joint " + name + " does not move pair " + PairName(r, p) +
                        " (a range prunes pairs whose links it moves apart)");
      ranged.emplace(std::make_pair(p.a, p.b), "safe_ranges");
    }
  }
  listed->insert(ranged.begin(), ranged.end());
  return true;
}

}  // namespace

bool ValidateSelfCollisionFile(const SelfCollisionFile& f, FileProblem* problem) {
  const std::vector<LinkPair> all = NonAdjacentPairs(f.robot);
  std::map<std::pair<int, int>, std::string> listed;  // pair -> its list
  if (!CheckLists(f, all, &listed, problem) || !CheckRanges(f, all, &listed, problem)) return false;
  for (const LinkPair& p : all)
    if (!listed.count({p.a, p.b}))
      return Fail(problem, "online", -1,
                  "pair " + PairName(f.robot, p) +
                      " is in no list (every pair of links that are not parent and child is "
                      "online, structural, never or a safe range's: " + kRegenerate + ")");
  if (!f.structural_floor.empty() && f.structural_floor.size() != f.structural.size())
    return Fail(problem, "structural_floor", -1,
                "has " + std::to_string(f.structural_floor.size()) + " floors for " +
                    std::to_string(f.structural.size()) + " structural pairs (one each)");
  return true;
}

std::string ChecksumLine(const std::string& body) {
  char b[64];
  std::snprintf(b, sizeof(b), "checksum: \"0x%016llx\"\n",
                static_cast<unsigned long long>(Fnv1a64(body)));
  return b;
}

bool ChecksumMatches(const std::string& text, int* line, std::string* what) {
  // the last line, past any trailing newline
  size_t end = text.size();
  while (end > 0 && text[end - 1] == '\n') --end;
  const size_t start = text.rfind('\n', end == 0 ? 0 : end - 1);
  const size_t from = start == std::string::npos ? 0 : start + 1;
  *line = static_cast<int>(std::count(text.begin(), text.begin() + from, '\n')) + 1;
  const std::string last = text.substr(from, end - from);
  if (last.rfind("checksum:", 0) != 0) {
    *what = std::string("checksum: missing (the writer ends the file with it): ") + kRegenerate;
    return false;
  }
  const std::string body = text.substr(0, from);
  if (ChecksumLine(body) != last + "\n") {
    *what = std::string("checksum: the text does not hash to it: edited by hand: ") + kRegenerate +
            " instead of editing it";
    return false;
  }
  return true;
}

}  // namespace ohrp::collision
