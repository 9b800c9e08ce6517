#!/usr/bin/env python3
"""Does a page disturb a real-time walk? (issue 33 item 6, docs/view.md "The page's cost")

Runs HRP-1S walking in real time (sim_host --realtime, walk --command 'velocity 0.2 0 0 T')
RUNS times without a viewer and RUNS times with ohrp_view and a headless Chromium page open on
it (the 3D view and the plots live), alternating, and prints each run's late commands (sim_host's
summary: cycles whose command came after the cycle's deadline), those of them after walk's first
command (the others are walk setting up), commands, and the load average at the start; then the
means and the ratios.

  tools/view/page_cost.py --build build --runs 3 --seconds 12
  tools/view/page_cost.py --build build --runs 4 --seconds 10 --rt-priority 70
"""
import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def wait_for(pred, timeout):
    end = time.time() + timeout
    while time.time() < end:
        if pred():
            return True
        time.sleep(0.05)
    return False


def stop(p, timeout=10):
    if p.poll() is None:
        p.send_signal(signal.SIGTERM)
        try:
            p.wait(timeout)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()


def cpu_seconds(root):
    """CPU time [s] of process `root` and its descendants (user + system, from /proc)"""
    stats = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                f = open("/proc/%s/stat" % d).read().rsplit(")", 1)[1].split()
                stats[int(d)] = (int(f[1]), (int(f[11]) + int(f[12])) / os.sysconf("SC_CLK_TCK"))
            except (OSError, IndexError, ValueError):
                pass
    total, todo = 0.0, [root]
    while todo:
        p = todo.pop()
        total += stats.get(p, (0, 0.0))[1]
        todo += [c for c, (pp, _) in stats.items() if pp == p]
    return total


def one_run(bin_dir, seconds, page, work, index, viewer_args=(), query="", rt_priority=0):
    out = os.path.join(work, "run%d_%s" % (index, "page" if page else "none"))
    os.makedirs(out)
    segment = "pagecost%d_%d" % (os.getpid(), index)
    summary = os.path.join(out, "sim_summary.json")
    # sim_host has no --rt-priority of its own: chrt starts it SCHED_FIFO (all its threads)
    chrt = ["chrt", "-f", str(rt_priority)] if rt_priority > 0 else []
    rt_walk = ["--rt-priority", str(rt_priority)] if rt_priority > 0 else []
    sim = subprocess.Popen(
        chrt + [os.path.join(bin_dir, "sim_host"), os.path.join(SOURCE, "mjcf/hrp1s/scene_flat.xml"),
         "--segment", segment, "--realtime", "--duration", str(seconds + 2), "--progress", "0",
         "--wait-controller", "20", "--keyframe", "halfsit", "--summary", summary],
        stdout=open(os.path.join(out, "sim_host.txt"), "w"), stderr=subprocess.STDOUT)
    procs = []
    viewer_out = os.path.join(out, "viewer.txt")
    if page:  # the viewer first, so that it watches the whole walk
        procs.append(subprocess.Popen(
            [os.path.join(bin_dir, "ohrp_view"), segment, "--attach-timeout", "20", "--port", "0"] +
            list(viewer_args),
            stdout=open(viewer_out, "w"), stderr=subprocess.STDOUT))
        url = []

        def found():
            for word in open(viewer_out).read().split():
                if word.startswith("http://"):
                    url.append(word)
                    return True
            return False
        if not wait_for(found, 30):
            sys.exit("page_cost: ohrp_view printed no URL: " + open(viewer_out).read())
        profile = os.path.join(out, "chromium")
        procs.append(subprocess.Popen(
            ["chromium", "--headless", "--no-sandbox", "--enable-unsafe-swiftshader",
             "--remote-debugging-port=0", "--no-first-run", "--user-data-dir=" + profile,
             "--window-size=1280,720", url[0] + query],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=dict(os.environ, TMPDIR=out)))
    # the page loads and starts drawing; without a page the same wait, so that walk starts as
    # long after sim_host in both kinds of run (sim_host's own start-up not overlapping either)
    time.sleep(3)
    load = os.getloadavg()[0]
    walk = subprocess.Popen(
        [os.path.join(bin_dir, "walk"), "--segment", segment, "--attach-timeout", "20",
         "--command", "velocity 0.2 0 0 %g" % (seconds - 2)] + rt_walk,
        stdout=open(os.path.join(out, "walk.txt"), "w"), stderr=subprocess.STDOUT)
    cpu = [cpu_seconds(p.pid) for p in procs]  # the viewer's and the browser's, before the walk
    sim.wait(seconds + 60)
    cpu = [cpu_seconds(p.pid) - c for p, c in zip(procs, cpu)]
    stop(walk)
    for p in reversed(procs):
        stop(p)
    s = json.load(open(summary))
    return {"page": page, "late": s["late_commands"], "commands": s["commands"], "load": load,
            "rtf": s.get("real_time_factor"), "cpu": cpu,
            "late_walking": s["late_commands"] - cycles_before_walk(os.path.join(out, "walk.txt"),
                                                                    s["control_period"])}


def cycles_before_walk(walk_txt, period):
    """the cycles before walk's first command (late by definition: walk still setting up), from
    walk's report 'stopped after N cycles (producer time T0 .. T1 s)': T0 / period"""
    text = open(walk_txt).read()
    at = text.find("(producer time ")
    if at < 0:
        sys.exit("page_cost: walk did not report its first cycle's time: " + walk_txt)
    return int(round(float(text[at + len("(producer time "):].split()[0]) / period))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(SOURCE, "build"), help="the build folder (bin/ in it)")
    ap.add_argument("--runs", type=int, default=3, help="runs of each kind (alternating)")
    ap.add_argument("--seconds", type=float, default=12, help="simulated seconds of each run")
    ap.add_argument("--viewer-arg", action="append", default=[],
                    help="an option for ohrp_view (repeatable; e.g. --viewer-arg=--rate --viewer-arg=10)")
    ap.add_argument("--query", default="", help="appended to the page's URL (e.g. '?fps=10')")
    ap.add_argument("--rt-priority", type=int, default=0,
                    help="run sim_host (through chrt) and walk (its --rt-priority) SCHED_FIFO at this "
                         "priority (1-99; 0: SCHED_OTHER, the default)")
    ap.add_argument("--keep", action="store_true", help="keep the runs' folders (printed)")
    a = ap.parse_args()
    bin_dir = os.path.join(a.build, "bin")
    for b in ("sim_host", "walk", "ohrp_view"):
        if not os.access(os.path.join(bin_dir, b), os.X_OK):
            print("page_cost: no %s in %s (build first)" % (b, bin_dir), file=sys.stderr)
            return 2
    if not shutil.which("chromium"):
        print("page_cost: no chromium (./ohrp setup)", file=sys.stderr)
        return 2
    if a.runs < 1 or not 4 <= a.seconds <= 600 or not 0 <= a.rt_priority <= 99:
        print("page_cost: --runs at least 1, --seconds in [4, 600], --rt-priority in [0, 99]", file=sys.stderr)
        return 2
    if a.rt_priority > 0 and subprocess.call(["chrt", "-f", str(a.rt_priority), "true"]) != 0:
        print("page_cost: SCHED_FIFO refused (chrt -f %d): run as root or with CAP_SYS_NICE"
              % a.rt_priority, file=sys.stderr)
        return 2
    work = tempfile.mkdtemp(prefix="page_cost_")
    rows = []
    for i in range(2 * a.runs):
        r = one_run(bin_dir, a.seconds, i % 2 == 1, work, i, a.viewer_arg, a.query, a.rt_priority)
        rows.append(r)
        print("run %d %-9s late %5d of %6d commands (%.2f %%), %d of them after walk's first command, "
              "load %.2f at the start%s"
              % (i, "page" if r["page"] else "no page", r["late"], r["commands"],
                 100.0 * r["late"] / max(1, r["commands"]), r["late_walking"], r["load"],
                 "; CPU during the walk: viewer %.1f s, browser %.1f s" % tuple(r["cpu"]) if r["cpu"] else ""),
              flush=True)
    for key, what in (("late", "late commands"), ("late_walking", "late commands while walking")):
        mean = {}
        for page in (False, True):
            sel = [r[key] for r in rows if r["page"] == page]
            mean[page] = sum(sel) / len(sel)
            print("%-8s mean %s %.1f (min %d, max %d)" % ("page" if page else "no page", what, mean[page],
                  min(sel), max(sel)))
        print("%s with a page / without: %s" % (what, "%.2f" % (mean[True] / mean[False]) if mean[False] > 0
                                               else "n/a (none late without)"))
    if a.keep:
        print("the runs' folders: " + work)
    else:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
