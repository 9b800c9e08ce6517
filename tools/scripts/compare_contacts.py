#!/usr/bin/env python3
"""Compares the foot forces of one scenario run with several contact models (the paper's
figures 13-14): compare_contacts.py OUT.png RUN_DIR... [--sensor rfsensor[,lfsensor]]
[--require-least soft] [--require-below soft=0.8] [--require-quieter soft:rigid].

Each RUN_DIR is an ohrp_run output folder (log.csv, sim_summary.json). Draws the sensors'
vertical force against time for every run, one above the other, and prints each run's
high-frequency content (RMS of the force less its 20 ms moving average, as the force_ringing
check computes it; the largest over the sensors). Requirements, each exiting 1 when it fails:
--require-least NAME (the run whose contact is NAME rings least), --require-below NAME=N (it
rings at most N newtons), --require-quieter A:B (A rings less than B). Uses Debian's
python3-matplotlib (run it with /usr/bin/python3 if another python3 comes first on PATH).
"""
import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def ringing(t, f, window=0.02):
    dt = (t[-1] - t[0]) / (len(t) - 1)
    half = max(1, round(0.5 * window / dt))
    s2 = 0.0
    for k in range(len(f)):
        lo, hi = max(0, k - half), min(len(f) - 1, k + half)
        mean = sum(f[lo:hi + 1]) / (hi - lo + 1)
        s2 += (f[k] - mean) ** 2
    return math.sqrt(s2 / len(f))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--sensor", default="rfsensor", help="sensor(s), comma-separated")
    ap.add_argument("--after", type=float, default=2.0, help="start of the compared window [s]")
    ap.add_argument("--require-least", default="")
    ap.add_argument("--require-below", action="append", default=[], metavar="NAME=N")
    ap.add_argument("--require-quieter", action="append", default=[], metavar="A:B")
    a = ap.parse_args()

    results = []
    fig, ax = plt.subplots(len(a.runs), 1, figsize=(10, 2.6 * len(a.runs)), sharex=True, squeeze=False)
    for i, run in enumerate(a.runs):
        contact = json.load(open(os.path.join(run, "sim_summary.json"))).get("contact", "?")
        sensors = a.sensor.split(",")
        t, f = [], {name: [] for name in sensors}
        with open(os.path.join(run, "log.csv"), newline="") as fh:
            for row in csv.DictReader(fh):
                t.append(float(row["time"]))
                for name in sensors:
                    f[name].append(float(row[name + "_fz"]))
        w = [k for k in range(len(t)) if t[k] >= a.after]
        r = max(ringing([t[k] for k in w], [f[name][k] for k in w]) for name in sensors)
        results.append((contact, r))
        for name in sensors:
            ax[i][0].plot(t, f[name], lw=0.7, label=name)
        # the y range of the compared window: the landing's spike would flatten the rest
        lo = min(f[name][k] for name in sensors for k in w)
        hi = max(f[name][k] for name in sensors for k in w)
        pad = 0.1 * (hi - lo) + 5
        ax[i][0].set_ylim(lo - pad, hi + pad)
        ax[i][0].axvspan(t[0], a.after, color="0.9", zorder=0)
        ax[i][0].set_ylabel("fz [N]")
        ax[i][0].legend(loc="upper right", fontsize=8)
        ax[i][0].set_title("%s contact: high-frequency RMS %.2f N (after %g s)" % (contact, r, a.after), fontsize=10)
        ax[i][0].grid(True, alpha=0.3)
        print("%-8s ringing %.2f N (%s)" % (contact, r, run))
    ax[-1][0].set_xlabel("simulated time [s]")
    fig.tight_layout()
    fig.savefig(a.out, dpi=80)
    ring = dict(results)
    failures = []
    if a.require_least:
        mine = [r for c, r in results if c == a.require_least]
        others = [r for c, r in results if c != a.require_least]
        if not mine or not others or any(mine[0] >= o for o in others):
            failures.append("the %s contact does not ring least" % a.require_least)
    for req in a.require_below:
        name, _, limit = req.partition("=")
        if name not in ring:
            failures.append("no run with the %s contact" % name)
        elif ring[name] > float(limit):
            failures.append("the %s contact rings %.2f N, above %s N" % (name, ring[name], limit))
    for req in a.require_quieter:
        x, _, y = req.partition(":")
        if x not in ring or y not in ring:
            failures.append("need runs with the %s and %s contacts" % (x, y))
        elif ring[x] >= ring[y]:
            failures.append("the %s contact (%.2f N) does not ring less than %s (%.2f N)" % (x, ring[x], y, ring[y]))
    if failures:
        sys.exit("compare_contacts: " + "; ".join(failures))

if __name__ == "__main__":
    main()
