#!/usr/bin/env python3
"""Plots of a sweep (ohrp_sweep, docs/sweep.md): a check's value against a parameter.

    plot_sweep.py sweep.csv --plot CHECK PARAMETER OUT.png linear|log [--plot ...]

One figure per --plot: CHECK's value (a column of sweep.csv: a check, real_time_factor,
wall_time or sim_time) against PARAMETER, one line per combination of the other parameters (those
zipped with it, --zip P1|P2|..., left out: they vary along the same line);
a variant whose check failed is drawn with a red cross, one that gave no value (it failed to
run, timed out, was cancelled) is listed under the axes. Exit 2 on bad input.
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    """a finite number, else None (empty, inf, nan: listed as without a value)"""
    try:
        v = float(text)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--plot", nargs=4, action="append", required=True,
                    metavar=("CHECK", "PARAMETER", "OUT", "SCALE"))
    ap.add_argument("--zip", action="append", default=[], metavar="P1|P2|...",
                    help="parameters varied together (a zip group, e.g. random draws): a plot "
                         "against one of them does not split its lines by the others")
    a = ap.parse_args()
    try:
        with open(a.csv, newline="") as f:
            reader = csv.DictReader(f)
            rows = list(reader)
            columns = reader.fieldnames or []
    except OSError as e:
        print(f"plot_sweep.py: cannot read {a.csv}: {e}", file=sys.stderr)
        return 2
    # the parameters are the columns between 'variant' and 'status'
    if "variant" not in columns or "status" not in columns:
        print(f"plot_sweep.py: {a.csv} is not a sweep.csv (no variant/status columns)", file=sys.stderr)
        return 2
    params = columns[columns.index("variant") + 1:columns.index("status")]
    for check, param, out, scale in a.plot:
        if param not in params:
            print(f"plot_sweep.py: no parameter '{param}' (have {', '.join(params)})", file=sys.stderr)
            return 2
        group = next((z.split("|") for z in a.zip if param in z.split("|")), [param])
        others = [p for p in params if p not in group]
        series, missing = {}, []
        for r in rows:
            x, y = number(r[param]), number(r.get(check, ""))
            if y is None or x is None:
                value = r.get(check, "")
                missing.append(f"{r['variant']} ({r['status']}{', ' + value if value else ''})")
                continue
            label = ", ".join(f"{p}={r[p]}" for p in others) or check
            passed = r.get(check + "_passed", "true") == "true"
            series.setdefault(label, []).append((x, y, passed))
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for label, pts in series.items():
            pts.sort()
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=label)
            bad = [p for p in pts if not p[2]]
            if bad:
                ax.plot([p[0] for p in bad], [p[1] for p in bad], "rx", markersize=10)
        if scale == "log":
            ax.set_xscale("log")
        ax.set_xlabel(param)
        ax.set_ylabel(check)
        ax.grid(True, alpha=0.3)
        title = f"{check} against {param}"
        if missing:
            title += "\nno value: variants " + ", ".join(missing)
        ax.set_title(title, fontsize=9)
        if len(series) > 1:
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out, dpi=100)
        plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
