#!/usr/bin/env python3
"""Draws the plot of one scenario run: plot_run.py LOG.csv SUMMARY.json OUT.png [--joints A,B].

Panels: base height, base position in the plane, the vertical force of each force/torque
sensor (and their sum beside the weight they carry), and a few joints against their references.
When the run folder (LOG.csv's) holds the walk controller's walk.csv (or --walk names one), the
walk's panels of plot_walk.py follow: seen from above and x, y against time.
Uses Debian's python3-matplotlib (installed by ./ohrp setup); no other dependency.
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_walk  # noqa: E402  (it puts python/ on the path)
from ohrp.run import read_log  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log")
    ap.add_argument("summary")
    ap.add_argument("out")
    ap.add_argument("--joints", default="", help="comma-separated joint names to draw")
    ap.add_argument("--torques", default="",
                    help="comma-separated joints whose torque gets a panel, with the F/T sensors' pitch moment")
    ap.add_argument("--walk", default=None,
                    help="the walk controller's walk.csv (default: walk.csv beside LOG.csv, when there)")
    a = ap.parse_args()

    log = read_log(a.log)
    summary = json.load(open(a.summary))
    t = log["time"]
    if len(t) == 0:
        sys.exit("plot_run: the log has no rows")
    forces = sorted({n[:-3] for n in log if n.endswith("_fz")})
    joints = [j for j in a.joints.split(",") if j] or \
        [n[2:] for n in log if n.startswith("q_")][:4]

    torques = [j for j in a.torques.split(",") if j]
    panels = 5 if torques else 4

    # the walk's log, when there is one: its panels follow the run's
    walk_path = a.walk or os.path.join(os.path.dirname(os.path.abspath(a.log)), "walk.csv")
    walk, walk_error = None, None
    if a.walk or os.path.exists(walk_path):
        try:
            walk = plot_walk.read_walk(walk_path)
        except (OSError, ValueError) as e:
            walk_error = "plot_run: the walk panels are left out: %s" % e
    ratios = [1] * panels + ([2.5, 1, 1] if walk else [])
    fig = plt.figure(figsize=(10, 3 * sum(ratios)))
    grid = fig.add_gridspec(len(ratios), 1, height_ratios=ratios)
    ax = [fig.add_subplot(grid[0])]
    ax += [fig.add_subplot(grid[i], sharex=ax[0]) for i in range(1, panels)]
    ax[0].plot(t, log["base_z"], label="base z")
    ax[0].set_ylabel("base height [m]")
    ax[1].plot(t, log["base_x"], label="base x")
    ax[1].plot(t, log["base_y"], label="base y")
    ax[1].set_ylabel("base position [m]")
    total = [0.0] * len(t)
    for f in forces:
        ax[2].plot(t, log[f + "_fz"], label=f + " fz", lw=0.8)
        if "fsensor" in f or "ankle" in f.lower() or "foot" in f.lower():
            total = [s + v for s, v in zip(total, log[f + "_fz"])]
    if any(total):
        ax[2].plot(t, total, "k", lw=1, label="sum of the feet")
    ax[2].set_ylabel("vertical force [N]")
    for j in joints:
        if "q_" + j in log:
            line, = ax[3].plot(t, log["q_" + j], label=j)
            ax[3].plot(t, log["qref_" + j], "--", color=line.get_color(), lw=0.8)
    ax[3].set_ylabel("joint angle (dashed: reference) [rad]")
    if torques:
        for j in torques:
            if "tau_" + j in log:
                ax[4].plot(t, log["tau_" + j], label=j + " motor torque", lw=0.8)
        for f in forces:
            if "fsensor" in f:
                ax[4].plot(t, log[f + "_ty"], "--", label=f + " pitch moment (F/T)", lw=0.8)
        ax[4].set_ylabel("ankle pitch torque [N m]")
    ax[-1].set_xlabel("simulated time [s]")
    for x in ax[:-1]:
        x.tick_params(labelbottom=False)
    for x in ax:
        x.grid(True, alpha=0.3)
        x.legend(loc="best", fontsize=8)
    if walk:
        ax_walk_x = fig.add_subplot(grid[panels + 1])
        plot_walk.add_walk_panels(fig.add_subplot(grid[panels]), ax_walk_x,
                                  fig.add_subplot(grid[panels + 2], sharex=ax_walk_x), walk)
    verdict = summary.get("verdict", "?")
    fig.suptitle("%s: %s (%.1f s simulated, %.2fx real time)" % (
        summary.get("scenario", "?"), verdict.upper(), summary.get("sim_time", 0),
        summary.get("real_time_factor", 0)))
    fig.tight_layout()
    fig.savefig(a.out, dpi=80)
    if walk_error:
        sys.exit(walk_error)


if __name__ == "__main__":
    main()
