#!/usr/bin/env python3
"""Overlaid plots of two compared data logs (the paper's figures 12-14: simulation and robot on
the same axes): plot_compare.py COMPARE.json OUT.png.

COMPARE.json is what ohrp_compare_logs wrote: the two logs, their labels, the lag of B behind A
and the channels to plot ("plot"). One panel per channel: A solid, B dashed and shifted by the
lag onto A's time, the compared window shaded, the RMS and peak of B - A in the title, and for
an oscillating channel the extrema used and each log's frequency and log decrement. Uses Debian's
python3-matplotlib (run it with /usr/bin/python3 if another python3 comes first on PATH).
"""
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path, names):
    t, cols = [], {n: [] for n in names}
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            t.append(float(row["time"]))
            for n in names:
                cols[n].append(float(row[n]))
    return t, cols


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_compare.py COMPARE.json OUT.png")
    c = json.load(open(sys.argv[1]))
    names = c.get("plot", [])
    if not names:
        sys.exit("plot_compare.py: no channel to plot")
    lag = c["lag"]
    la, lb = c["a"]["label"], c["b"]["label"]
    ta, a = read(c["a"]["log"], names)
    tb, b = read(c["b"]["log"], names)
    tb = [t - lag for t in tb]
    by_name = {ch["name"]: ch for ch in c["channels"]}
    fig, ax = plt.subplots(len(names), 1, figsize=(10, 2.6 * len(names)), sharex=True, squeeze=False)
    lo, hi = c["window"]
    for i, n in enumerate(names):
        p = ax[i][0]
        p.plot(ta, a[n], "-", lw=1.0, color="tab:blue", label=la, zorder=3)
        p.plot(tb, b[n], "--", lw=1.0, color="tab:red", label="%s (shifted by %+.3f s)" % (lb, -lag))
        p.axvspan(lo, hi, color="0.93", zorder=0)
        ch = by_name.get(n, {})
        title = n
        if ch:
            title += ": rms(B-A) %.4g, peak %.4g at %.2f s" % (ch["rms"], ch["peak"], ch["peak_time"])
        osc = ch.get("oscillation")
        if osc:
            parts = []
            for key, label, color, shift in (("a", la, "tab:blue", 0.0), ("b", lb, "tab:red", lag)):
                o = osc[key]
                if o.get("found"):
                    p.plot([t - shift for t in o["extremum_times"]], o["extremum_values"], "o",
                           ms=3, color=color)
                    parts.append("%s %.3f Hz, delta %.3f" % (label, o["frequency"], o["log_decrement"]))
                else:
                    parts.append("%s: no oscillation (%s)" % (label, o.get("why", "")))
            title += "\n" + "; ".join(parts)
        p.set_title(title, fontsize=9)
        p.set_ylabel(n, fontsize=8)
        p.grid(True, alpha=0.3)
        p.legend(loc="upper right", fontsize=8)
    ax[-1][0].set_xlabel("time [s] (%s's clock)" % la)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=80)


if __name__ == "__main__":
    main()
