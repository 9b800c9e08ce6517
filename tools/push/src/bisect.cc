// Every controller x direction: bisection of the largest impulse survived, or one settle trial,
// with up to `jobs` trials at once (see push/push.h).
#include <atomic>
#include <cstdio>
#include <mutex>
#include <thread>

#include "push/push.h"

namespace ohrp::push {
namespace {

// shared by the workers: the next task, the trial counter and the progress lines
struct Pool {
  std::atomic<size_t> next{0};
  std::atomic<int> trials{0};
  std::mutex print;
};

void Progress(Pool* pool, int index, const Trial& t, const char* what) {
  std::lock_guard<std::mutex> lock(pool->print);
  std::fprintf(stderr, "ohrp_push: [%3d] %-12s %6.1f deg %7.2f N s: %s%s%s\n", index,
               t.controller.c_str(), t.direction, t.impulse,
               !t.ok ? "TRIAL FAILED" : t.standing ? "standing" : "fell", what,
               t.ok && t.standing ? "" : (" - " + t.detail).c_str());
}

// the largest impulse survived in one direction
Limit Bisect(const PushOptions& o, const std::string& controller, double direction, Pool* pool) {
  std::string detail;
  Limit l = BisectLargest(o.max_impulse, o.tolerance, [&](double impulse) {
    const int index = ++pool->trials;
    const Trial t = RunTrial(o, controller, direction, impulse, index);
    Progress(pool, index, t, "");
    if (!t.ok) detail = t.detail;
    return !t.ok ? Outcome::kFailed : t.standing ? Outcome::kStanding : Outcome::kFell;
  });
  l.controller = controller;
  l.direction = direction;
  l.detail = detail;
  return l;
}

// settle mode: one trial at the fixed impulse
Limit Settle(const PushOptions& o, const std::string& controller, double direction, Pool* pool) {
  Limit l;
  l.controller = controller;
  l.direction = direction;
  const int index = ++pool->trials;
  l.settle = RunTrial(o, controller, direction, o.settle_impulse, index);
  l.trials = 1;
  if (!l.settle.ok) {
    l.failed = true;
    l.detail = l.settle.detail;
  }
  char what[160];
  std::snprintf(what, sizeof(what), ", base settles in %.3f s, ankle torques in %.3f s",
                l.settle.base_time, l.settle.torque_time);
  Progress(pool, index, l.settle, l.settle.ok ? what : "");
  return l;
}

}  // namespace

Limit BisectLargest(double max_impulse, double tolerance, const std::function<Outcome(double)>& trial) {
  Limit l;
  auto run = [&](double impulse) {
    ++l.trials;
    const Outcome r = trial(impulse);
    l.failed = r == Outcome::kFailed;
    return r;
  };
  // the top of the bracket first
  double lo = 0, hi = max_impulse;
  const Outcome top = run(hi);
  if (l.failed) return l;
  if (top == Outcome::kStanding) {
    l.largest = l.smallest_fall = hi;
    l.above_max = true;
    return l;
  }
  // halve [lo, hi]: lo survived (0 by assumption), hi fell
  while (hi - lo > tolerance) {
    const double mid = 0.5 * (lo + hi);
    const Outcome r = run(mid);
    if (l.failed) return l;
    (r == Outcome::kStanding ? lo : hi) = mid;
  }
  l.largest = lo;
  l.smallest_fall = hi;
  return l;
}

std::vector<Limit> RunAll(const PushOptions& o) {
  struct Task {
    std::string controller;
    double direction;
  };
  std::vector<Task> tasks;
  for (const auto& c : o.controllers)
    for (double d : o.directions) tasks.push_back({c, d});
  std::vector<Limit> results(tasks.size());
  Pool pool;
  unsigned jobs = o.jobs > 0 ? static_cast<unsigned>(o.jobs) : std::max(1u, std::thread::hardware_concurrency());
  jobs = std::min<unsigned>(jobs, tasks.size());
  std::fprintf(stderr, "ohrp_push: %zu controller(s) x %zu direction(s), %s, %u trial(s) at a time -> %s\n",
               o.controllers.size(), o.directions.size(),
               o.settle_impulse > 0 ? "settling after a fixed push" : "bisection of the largest push",
               jobs, o.out_dir.c_str());

  // workers take the next task until none is left
  auto work = [&]() {
    for (size_t i; (i = pool.next++) < tasks.size();) {
      const Task& t = tasks[i];
      results[i] = o.settle_impulse > 0 ? Settle(o, t.controller, t.direction, &pool)
                                        : Bisect(o, t.controller, t.direction, &pool);
    }
  };
  std::vector<std::thread> workers;
  for (unsigned k = 0; k < jobs; ++k) workers.emplace_back(work);
  for (auto& w : workers) w.join();
  return results;
}

}  // namespace ohrp::push
