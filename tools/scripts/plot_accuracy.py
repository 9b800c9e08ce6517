#!/usr/bin/env python3
"""Charts of bench_accuracy's CSV: one PNG per scene, error against real-time factor, log-log.

Usage: plot_accuracy.py ACCURACY_CSV OUT_DIR

Left: mean body position error [m]; right: mean error of the 16 ms-average contact normal
force [N] (scenes with contact). One curve per integrator and contact model over the time step
(the step in ms is written at each point); solver and geometry rows as separate markers.
Diverged or refused settings, zero errors and the reference's own integrator and step (which
reproduces it to rounding) are left out (the CSV has them). Needs matplotlib (Debian's python3-matplotlib).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def drawable(x, y):
    return math.isfinite(x) and math.isfinite(y) and x > 0 and y > 0


def main():
    if len(sys.argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    path, out = sys.argv[1], sys.argv[2]
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.stderr.write(f"plot_accuracy.py: cannot read {path}: {e}\n")
        return 2
    need = {"scene", "sweep", "integrator", "dt", "contact", "rtf", "pos_error_m",
            "force_error_N", "diverged", "iterations", "tolerance", "geometry"}
    if not rows or not need.issubset(rows[0].keys()):
        sys.stderr.write(f"plot_accuracy.py: {path} is not bench_accuracy's CSV\n")
        return 2
    os.makedirs(out, exist_ok=True)
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    styles = {"euler": "o-", "rk4": "s-", "implicit": "^-"}
    colors = {"none": "black", "soft": "tab:green", "native": "tab:blue", "rigid": "tab:red"}
    for scene in scenes:
        # the reference's own integrator and step reproduces it to rounding: left out, it
        # would only stretch the log axis
        sr = [r for r in rows if r["scene"] == scene and r["diverged"] == "no"
              and "reference's integrator" not in r.get("note", "")]
        has_force = any(r["contact"] != "none" for r in sr)
        fig, axes = plt.subplots(1, 2 if has_force else 1, figsize=(13 if has_force else 7, 5.5),
                                 squeeze=False)
        metrics = [("pos_error_m", "mean body position error [m]")]
        if has_force:
            metrics.append(("force_error_N", "mean contact normal force error [N]"))
        drawn = 0
        for ax, (key, label) in zip(axes[0], metrics):
            curves = {}
            for r in sr:
                if r["sweep"] == "dt":
                    curves.setdefault((r["integrator"], r["contact"]), []).append(r)
            for (integ, contact), cr in sorted(curves.items()):
                cr.sort(key=lambda r: number(r["dt"]))
                pts = [(number(r["rtf"]), number(r[key]), number(r["dt"])) for r in cr]
                pts = [p for p in pts if drawable(p[0], p[1])]
                if not pts:
                    continue
                ax.plot([p[0] for p in pts], [p[1] for p in pts], styles.get(integ, "o-"),
                        color=colors.get(contact, "gray"), label=f"{integ}, {contact}",
                        markersize=4, linewidth=1.2,
                        alpha=0.9 if integ != "implicit" else 0.6)
                for x, y, dt in pts:
                    ax.annotate(f"{dt * 1e3:g}", (x, y), fontsize=6, alpha=0.7,
                                xytext=(2, 2), textcoords="offset points")
                drawn += len(pts)
            for sweep, marker in (("solver", "x"), ("geometry", "D")):
                pr = [r for r in sr if r["sweep"] == sweep]
                for contact in sorted({r["contact"] for r in pr}):
                    cr = [r for r in pr if r["contact"] == contact]
                    pts = [(number(r["rtf"]), number(r[key]), r) for r in cr]
                    pts = [p for p in pts if drawable(p[0], p[1])]
                    if not pts:
                        continue
                    ax.scatter([p[0] for p in pts], [p[1] for p in pts], marker=marker,
                               color=colors.get(contact, "gray"), s=30,
                               label=f"{sweep} rows, {contact}")
                    for x, y, r in pts:
                        text = (f"it{r['iterations']} {r['tolerance']}" if sweep == "solver"
                                else f"{r['geometry']} {number(r['dt']) * 1e3:g}")
                        ax.annotate(text, (x, y), fontsize=5, alpha=0.7, xytext=(2, -7),
                                    textcoords="offset points")
                    drawn += len(pts)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("real-time factor (simulated time / CPU time)")
            ax.set_ylabel(label)
            ax.axvline(1.0, color="gray", linewidth=0.6, linestyle=":")
            ax.grid(True, which="both", alpha=0.3)
        axes[0][0].legend(fontsize=7, loc="best")
        fig.suptitle(f"{scene}: error against speed (numbers: time step [ms])")
        fig.tight_layout()
        target = os.path.join(out, f"{scene}.png")
        fig.savefig(target, dpi=110)
        plt.close(fig)
        if drawn == 0:
            sys.stderr.write(f"plot_accuracy.py: {scene}: nothing drawable (all diverged?)\n")
        print(f"wrote {target} ({drawn} points)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
