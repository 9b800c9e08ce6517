#!/usr/bin/env python3
"""Polar plot of ohrp_push's push.csv: the largest impulse survived against the push direction,
one series per controller. Usage: plot_push.py push.csv push.png"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    series = {}
    with open(sys.argv[1]) as f:
        for row in csv.DictReader(f):
            if row["failed"] == "1":
                continue
            series.setdefault(row["controller"], []).append(
                (float(row["direction_deg"]), float(row["largest_impulse_Ns"])))
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="polar")
    for name, points in series.items():
        points.sort()
        # close the loop when the directions go all round
        if len(points) > 2:
            points.append(points[0])
        ax.plot([math.radians(d) for d, _ in points], [v for _, v in points], "o-", label=name)
    ax.set_theta_zero_location("N")  # forward (+x) up, left (+y) to the left
    ax.set_title("largest impulse survived [N s] vs push direction\n(0 deg = +x forward, 90 deg = +y left)")
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=100)


if __name__ == "__main__":
    main()
