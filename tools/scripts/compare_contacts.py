#!/usr/bin/env python3
"""Compares the foot forces of one scenario run with several contact models (the paper's
figures 13-14): compare_contacts.py OUT.png RUN_DIR... [--sensor rfsensor] [--require-least soft].

Each RUN_DIR is an ohrp_run output folder (log.csv, summary.json). Draws the sensor's vertical
force against time for every run, one above the other, and prints each run's high-frequency
content (RMS of the force less its 20 ms moving average, as the force_ringing check computes
it). With --require-least NAME, exits 1 unless the run whose contact is NAME rings least.
Uses Debian's python3-matplotlib.
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
    ap.add_argument("--sensor", default="rfsensor")
    ap.add_argument("--after", type=float, default=2.0, help="start of the compared window [s]")
    ap.add_argument("--require-least", default="")
    a = ap.parse_args()

    results = []
    fig, ax = plt.subplots(len(a.runs), 1, figsize=(10, 2.6 * len(a.runs)), sharex=True, squeeze=False)
    for i, run in enumerate(a.runs):
        contact = json.load(open(os.path.join(run, "sim_summary.json"))).get("contact", "?")
        t, f = [], []
        with open(os.path.join(run, "log.csv"), newline="") as fh:
            for row in csv.DictReader(fh):
                t.append(float(row["time"]))
                f.append(float(row[a.sensor + "_fz"]))
        w = [k for k in range(len(t)) if t[k] >= a.after]
        r = ringing([t[k] for k in w], [f[k] for k in w])
        results.append((contact, r))
        ax[i][0].plot(t, f, lw=0.7)
        ax[i][0].set_ylabel("%s fz [N]" % a.sensor)
        ax[i][0].set_title("%s contact: high-frequency RMS %.1f N" % (contact, r), fontsize=10)
        ax[i][0].grid(True, alpha=0.3)
        print("%-8s ringing %.2f N (%s)" % (contact, r, run))
    ax[-1][0].set_xlabel("simulated time [s]")
    fig.tight_layout()
    fig.savefig(a.out, dpi=80)
    if a.require_least:
        mine = [r for c, r in results if c == a.require_least]
        others = [r for c, r in results if c != a.require_least]
        if not mine or not others or any(mine[0] >= o for o in others):
            sys.exit("compare_contacts: the %s contact does not ring least" % a.require_least)


if __name__ == "__main__":
    main()
