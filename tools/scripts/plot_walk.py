#!/usr/bin/env python3
"""Draws a walk from the walk controller's log: plot_walk.py WALK.csv OUT.png.

walk.csv holds one row per control cycle, everything in the walk's plan frame, SI units
(metres, seconds, radians); its columns are COLUMNS below (support_*: 1 when that sole carries
the robot in the plan; zmp_x/y: measured from the F/T sensors; zmp_des: the stabilizer's).
Two views:
  seen from above: the footprints (a SOLE_LENGTH x SOLE_WIDTH rectangle centred on the sole's
  pose at each landing, i.e. where its support column turns to 1, and where each foot stands at
  the start), the CoM (reference and measured) and the ZMP (reference and measured);
  over time: x and y of the CoM reference, the ZMP reference, the desired ZMP and the measured
  ZMP, the single-support phases shaded.
plot_run.py imports it (add_walk_panels) to add the same panels to a run's plot.png when the run
folder holds a walk.csv. Uses Debian's python3-matplotlib; no other dependency.
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from ohrp.run import read_log  # noqa: E402  (the one CSV reader of the project's Python)

COLUMNS = ("t,com_ref_x,com_ref_y,com_ref_z,com_x,com_y,com_z,zmp_ref_x,zmp_ref_y,zmp_des_x,"
           "zmp_des_y,zmp_x,zmp_y,dcm_x,dcm_y,left_x,left_y,left_z,left_yaw,right_x,right_y,"
           "right_z,right_yaw,support_left,support_right").split(",")
SOLE_LENGTH = 0.25  # [m] along the foot
SOLE_WIDTH = 0.14   # [m] across it
SIDES = (("left", "tab:blue"), ("right", "tab:red"))


def read_walk(path):
    """The columns of walk.csv by name (arrays); ValueError naming what is missing."""
    cols = read_log(path, required=COLUMNS)
    if len(cols["t"]) == 0:
        raise ValueError("%s: no rows" % path)
    return cols


def landings(walk, side):
    """(x, y, yaw) of the sole `side` at the start and wherever its support column turns to 1."""
    support = walk["support_" + side]
    out = []
    for i, s in enumerate(support):
        if s >= 0.5 and (i == 0 or support[i - 1] < 0.5):
            out.append((walk[side + "_x"][i], walk[side + "_y"][i], walk[side + "_yaw"][i]))
    return out


def sole_corners(x, y, yaw):
    """The four corners of a sole rectangle centred on (x, y), turned by yaw."""
    c, s = math.cos(yaw), math.sin(yaw)
    half = [(SOLE_LENGTH / 2, SOLE_WIDTH / 2), (-SOLE_LENGTH / 2, SOLE_WIDTH / 2),
            (-SOLE_LENGTH / 2, -SOLE_WIDTH / 2), (SOLE_LENGTH / 2, -SOLE_WIDTH / 2)]
    return [(x + c * a - s * b, y + s * a + c * b) for a, b in half]


def single_support(walk):
    """[(t0, t1)] of the phases with exactly one sole carrying the robot in the plan."""
    t = walk["t"]
    spans, start = [], None
    for i in range(len(t)):
        single = (walk["support_left"][i] >= 0.5) != (walk["support_right"][i] >= 0.5)
        if single and start is None:
            start = t[i]
        if not single and start is not None:
            spans.append((start, t[i]))
            start = None
    if start is not None:
        spans.append((start, t[-1]))
    return spans


def draw_top(ax, walk):
    """The walk seen from above: footprints, CoM and ZMP, reference and measured."""
    # footprints at each landing
    for side, colour in SIDES:
        for k, (x, y, yaw) in enumerate(landings(walk, side)):
            ax.add_patch(Polygon(sole_corners(x, y, yaw), closed=True, fill=False, ec=colour, lw=1,
                                 label="%s sole at landing" % side if k == 0 else None))
    # the CoM and the ZMP
    ax.plot(walk["zmp_x"], walk["zmp_y"], ".", color="0.6", ms=1, label="ZMP measured (F/T)")
    ax.plot(walk["zmp_ref_x"], walk["zmp_ref_y"], "g-", lw=1, label="ZMP reference")
    ax.plot(walk["com_ref_x"], walk["com_ref_y"], "k--", lw=1, label="CoM reference")
    ax.plot(walk["com_x"], walk["com_y"], "m-", lw=1, label="CoM measured")
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale_view()
    ax.set_xlabel("x [m] (plan frame)")
    ax.set_ylabel("y [m]")
    ax.set_title("walk seen from above", fontsize=9)


def draw_time(ax, walk, axis):
    """One coordinate (x or y) of the CoM reference and the ZMPs against time, single support shaded."""
    t = walk["t"]
    # single support
    for k, (t0, t1) in enumerate(single_support(walk)):
        ax.axvspan(t0, t1, color="0.9", label="single support" if k == 0 else None)
    ax.plot(t, walk["zmp_" + axis], color="0.6", lw=0.6, label="ZMP measured (F/T)")
    ax.plot(t, walk["zmp_ref_" + axis], "g-", lw=1, label="ZMP reference")
    ax.plot(t, walk["zmp_des_" + axis], "c-", lw=0.8, label="ZMP desired (stabilizer)")
    ax.plot(t, walk["com_ref_" + axis], "k--", lw=1, label="CoM reference")
    ax.set_ylabel("%s [m] (plan frame)" % axis)


def add_walk_panels(ax_top, ax_x, ax_y, walk):
    """Draws the walk on three axes: from above, x against time, y against time."""
    draw_top(ax_top, walk)
    draw_time(ax_x, walk, "x")
    draw_time(ax_y, walk, "y")
    ax_y.set_xlabel("walk time [s] (walk.csv's t)")
    for ax in (ax_top, ax_x, ax_y):
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=7)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("walk", help="walk.csv")
    ap.add_argument("out", help="PNG to write")
    a = ap.parse_args()
    try:
        walk = read_walk(a.walk)
    except (OSError, ValueError) as e:
        sys.exit("plot_walk: %s" % e)
    fig = plt.figure(figsize=(10, 12))
    grid = fig.add_gridspec(3, 1, height_ratios=[2, 1, 1])
    ax_top = fig.add_subplot(grid[0])
    ax_x = fig.add_subplot(grid[1])
    ax_y = fig.add_subplot(grid[2], sharex=ax_x)
    add_walk_panels(ax_top, ax_x, ax_y, walk)
    fig.tight_layout()
    fig.savefig(a.out, dpi=80)


if __name__ == "__main__":
    main()
