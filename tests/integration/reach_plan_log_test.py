#!/usr/bin/env python3
"""reach --plan-log with several goals (--goals): every goal's plan and measured motion, told
apart by the goal column (docs/planning.md). Reads the plan log of scenario
reach_scene_sequence and checks what must hold whatever the planner's random tree: each goal was
solved; its waypoints start at t = 0 and its timed path (every 10 ms) ends on its last waypoint;
its measured motion ends within 10 mrad of the plan's end; the next goal is planned from
where the measured motion held (the previous goal's hold). Usage: reach_plan_log_test.py PLAN_CSV
GOALS"""
import csv
import sys


def fail(why):
    print("FAIL: " + why)
    sys.exit(1)


def main():
    path, goals = sys.argv[1], int(sys.argv[2])
    with open(path) as f:
        first = f.readline()
        rows = list(csv.reader(f))
    want = "; ".join("goal %d: solved" % (k + 1) for k in range(goals))
    if first.strip() != "# reach plan: " + want:
        fail("first line %r, want '# reach plan: %s'" % (first.strip(), want))
    head, rows = rows[0], rows[1:]
    if head[:3] != ["goal", "kind", "t"] or len(head) < 4:
        fail("header %r" % head)
    by = {}
    for r in rows:
        by.setdefault((int(r[0]), r[1]), []).append([float(x) for x in r[2:]])
    tol = 0.01  # [rad] a tenth of reach's default --tolerance: the held arm is at rest
    last_measured = None
    for k in range(1, goals + 1):
        way, plan, meas = (by.get((k, kind), []) for kind in ("waypoint", "planned", "measured"))
        if len(way) < 2 or not plan or not meas:
            fail("goal %d: %d waypoints, %d planned, %d measured rows" % (k, len(way), len(plan), len(meas)))
        if way[0][0] != 0 or plan[0][0] != 0:
            fail("goal %d: the plan does not start at t = 0" % k)
        steps = [b[0] - a[0] for a, b in zip(plan, plan[1:])]
        if any(abs(s - 0.01) > 1e-6 for s in steps):
            fail("goal %d: the timed path is not sampled every 10 ms" % k)
        end = max(abs(a - b) for a, b in zip(plan[-1][1:], way[-1][1:]))
        if end > 2e-3:
            fail("goal %d: the timed path ends %.4f rad from its last waypoint" % (k, end))
        err = max(abs(a - b) for a, b in zip(meas[-1][1:], way[-1][1:]))
        if err > tol:
            fail("goal %d: the measured motion ends %.4f rad from the plan's end" % (k, err))
        if last_measured is not None:
            gap = max(abs(a - b) for a, b in zip(way[0][1:], last_measured[1:]))
            if gap > tol:
                fail("goal %d: planned from %.4f rad away from where goal %d held" % (k, gap, k - 1))
        last_measured = meas[-1]
        print("goal %d: %d waypoints, %.2f s planned, %d measured rows, ends %.4f rad from the plan"
              % (k, len(way), plan[-1][0], len(meas), err))
    print("PASS")


if __name__ == "__main__":
    main()
