#!/usr/bin/env python3
"""Compares a run of our walk with hrpsys's own recording of SampleRobot walking.

Usage: compare_hrpsys.py RUN_DIR OUT.png [--recording PREFIX] [--model MJCF] [--table OUT.md]
                         [--require-match]
RUN_DIR is an ohrp_run output folder holding walk.csv (the walk controller's log, plan frame)
and log.csv (sim_host's, for the base); PREFIX names hrpsys's four files (hrpsys_recording.py),
by default ../shared/external/hrpsys-samplerobot/samplerobot-gopos000 beside the repository.
Both walks are reduced to the same figures: the single-support phases (ours: the plan's support
columns; hrpsys: the contact states of .optionaldata, the swing foot found by forward
kinematics), the steps' timing, stride and apex (the swing sole), the reference ZMP's dwell on
each foot and its transfers, the lateral sway and height of the CoM (reference) and the waist.
Prints the table (markdown; also to --table) and draws OUT.png: lateral and forward ZMP, CoM and
waist against time, both walks aligned at their first lift-off. --require-match exits 1 unless
both walks take the same steps with the same feet and the figures of MATCHED agree within their
tolerances (what the scenario set to hrpsys's values). Bad input exits 2 naming the file.
Uses Debian's python3-numpy and python3-matplotlib.
"""
import argparse
import os
import sys

import numpy as np

import hrpsys_recording
import plot_walk  # noqa: E402  (it puts python/ on the path)
from ohrp.run import read_log  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
DEFAULT_RECORDING = os.path.join(REPO, "..", "shared", "external", "hrpsys-samplerobot",
                                 "samplerobot-gopos000")
DEFAULT_MODEL = os.path.join(REPO, "mjcf", "hrp1s", "hrp1s.xml")
DWELL_BAND = 0.005  # [m] the ZMP dwells while within this of its value at mid single support
MOVE_BAND = 0.001   # [m] the CoM has started once this far from where it stood
# figures the scenario sets to hrpsys's values, and how close they must come
MATCHED = {"step period [s]": 0.011, "single support [s]": 0.011,
           "double support between steps [s]": 0.011, "stride [m]": 0.005,
           "step height, swing sole apex [m]": 0.005, "CoM height while walking [m]": 0.003}


def ours(run_dir):
    """Our walk from walk.csv (plan frame) and log.csv (the base, world): dict of arrays."""
    w = plot_walk.read_walk(os.path.join(run_dir, "walk.csv"))
    log = read_log(os.path.join(run_dir, "log.csv"), required=("time", "base_x", "base_y", "base_z"))
    t = w["t"]
    # the base at the walk log's times (sim_host logs on its own clock, from t = 0)
    waist = np.stack([np.interp(t, log["time"], log[k]) for k in ("base_x", "base_y", "base_z")], 1)
    return {"t": t, "zmp": np.stack([w["zmp_ref_x"], w["zmp_ref_y"]], 1),
            "zmp_measured": np.stack([w["zmp_x"], w["zmp_y"]], 1),
            "com": np.stack([w["com_ref_x"], w["com_ref_y"], w["com_ref_z"]], 1),
            "com_measured": np.stack([w["com_x"], w["com_y"], w["com_z"]], 1), "waist": waist,
            "left": np.stack([w["left_x"], w["left_y"], w["left_z"]], 1),
            "right": np.stack([w["right_x"], w["right_y"], w["right_z"]], 1),
            "support": np.stack([w["support_left"], w["support_right"]], 1) >= 0.5}


def theirs(prefix, model):
    """hrpsys's walk, its contact columns mapped to the feet by the soles' heights."""
    r = hrpsys_recording.read_recording(prefix, model)
    contact = r["contact"] >= 0.5
    # a column is the left foot's when the left sole is the higher one while it is off the floor
    lifted = ~contact[:, 0]
    if not lifted.any():
        raise ValueError("%s.optionaldata: the first foot never leaves the floor" % prefix)
    first_is_left = r["left"][lifted, 2].mean() > r["right"][lifted, 2].mean()
    r["support"] = contact if first_is_left else contact[:, ::-1]
    r["contact_order"] = "left, right" if first_is_left else "right, left"
    return r


def phases(walk):
    """[(swing foot 0 left / 1 right, lift index, land index)] of the single supports."""
    single = walk["support"][:, 0] != walk["support"][:, 1]
    out, start = [], None
    for i, s in enumerate(single):
        if s and start is None:
            start = i
        if (not s or i == len(single) - 1) and start is not None:
            out.append((0 if walk["support"][start, 1] else 1, start, i))
            start = None
    return out


def dwells(walk, steps):
    """[(t0, t1)] around each single support's middle where the ZMP stays within DWELL_BAND."""
    zmp, t = walk["zmp"], walk["t"]
    out = []
    for _, a, b in steps:
        m = (a + b) // 2
        near = np.linalg.norm(zmp - zmp[m], axis=1) <= DWELL_BAND
        i0, i1 = m, m
        while i0 > 0 and near[i0 - 1]:
            i0 -= 1
        while i1 < len(t) - 1 and near[i1 + 1]:
            i1 += 1
        out.append((t[i0], t[i1]))
    return out


def figures(walk):
    """The table's figures of one walk (an ordered dict of name -> value)."""
    t, steps = walk["t"], phases(walk)
    if not steps:
        raise ValueError("no single-support phase found (no step)")
    lift = np.array([t[a] for _, a, _ in steps])
    land = np.array([t[b] for _, _, b in steps])
    feet = ("left", "right")
    swing = [walk[feet[f]] for f, _, _ in steps]
    d = dwells(walk, steps)
    # the walk itself: from a second before the first lift-off to a second after the last landing
    span = (t >= lift[0] - 1.0) & (t <= land[-1] + 1.0)
    com0 = walk["com"][0, :2]
    started = np.nonzero(np.linalg.norm(walk["com"][:, :2] - com0, axis=1) > MOVE_BAND)[0]
    ss = np.mean(land - lift)
    ds = np.mean(lift[1:] - land[:-1]) if len(steps) > 1 else np.nan
    f = {"steps (single supports)": len(steps),
         "swing feet in order": " ".join(feet[s][0].upper() for s, _, _ in steps),
         "step period [s]": np.mean(np.diff(lift)) if len(steps) > 1 else np.nan,
         "single support [s]": ss, "double support between steps [s]": ds,
         "double-support share [-]": ds / (ds + ss)}
    f["stride [m]"] = np.mean([s[b, 0] - s[a, 0] for s, (_, a, b) in zip(swing, steps)])
    f["step height, swing sole apex [m]"] = np.mean([s[a:b + 1, 2].max() - s[a, 2]
                                                    for s, (_, a, b) in zip(swing, steps)])
    # where the ZMP sits under the stance sole at mid single support (x along, y inward)
    mids = [((a + b) // 2, walk[feet[1 - s]]) for s, a, b in steps]
    zmp = walk["zmp"]
    f["ZMP ahead of the stance sole's centre [m]"] = np.mean([zmp[m, 0] - st[m, 0]
                                                            for m, st in mids])
    f["ZMP inward of the stance sole's centre [m]"] = np.mean([abs(st[m, 1]) - abs(zmp[m, 1])
                                                             for m, st in mids])
    f["ZMP dwell per foot [s]"] = np.mean([b - a for a, b in d])
    gaps = [d[k + 1][0] - d[k][1] for k in range(len(d) - 1)]
    f["ZMP transfer foot to foot [s]"] = np.mean(gaps) if gaps else np.nan
    # from standing to the first stance foot, and from the last back to standing
    left_start = np.nonzero(np.linalg.norm(zmp - zmp[0], axis=1) > DWELL_BAND)[0]
    f["ZMP from standing to the first foot [s]"] = (d[0][0] - t[left_start[0]]
                                                    if len(left_start) else np.nan)
    settled = np.nonzero(np.linalg.norm(zmp - zmp[-1], axis=1) > DWELL_BAND)[0]
    f["ZMP from the last foot back to standing [s]"] = (t[settled[-1] + 1] - d[-1][1]
                                                        if len(settled) and settled[-1] + 1 < len(t)
                                                        else np.nan)
    f["CoM starts before the first lift-off [s]"] = (lift[0] - t[started[0]] if len(started)
                                                     else np.nan)
    f["CoM lateral sway, half peak-to-peak [m]"] = np.ptp(walk["com"][span, 1]) / 2
    if "com_measured" in walk:
        f["CoM lateral sway, measured [m]"] = np.ptp(walk["com_measured"][span, 1]) / 2
    f["waist lateral sway, half peak-to-peak [m]"] = np.ptp(walk["waist"][span, 1]) / 2
    f["waist height while walking [m]"] = np.mean(walk["waist"][span, 2])
    f["CoM height while walking [m]"] = np.mean(walk["com"][span, 2])
    return f


def table(hrpsys, ours_f):
    """Markdown: one row per figure, hrpsys's then ours ("-" where a walk has none)."""
    def cell(v):
        if isinstance(v, str):
            return v
        if v is None or (isinstance(v, float) and np.isnan(v)):
            return "-"
        return "%d" % v if isinstance(v, int) else "%.3f" % v
    rows = ["| figure | hrpsys | ours |", "|---|---|---|"]
    for k in ours_f:
        rows.append("| %s | %s | %s |" % (k, cell(hrpsys.get(k)), cell(ours_f[k])))
    return "\n".join(rows)


def mismatches(hrpsys, ours_f):
    """What --require-match refuses: other steps, or a MATCHED figure beyond its tolerance."""
    out = []
    for k in ("steps (single supports)", "swing feet in order"):
        if hrpsys[k] != ours_f[k]:
            out.append("%s: hrpsys %s, ours %s" % (k, hrpsys[k], ours_f[k]))
    for k, tol in MATCHED.items():
        if not abs(hrpsys[k] - ours_f[k]) <= tol:
            out.append("%s: hrpsys %.4f, ours %.4f (tolerance %g)" % (k, hrpsys[k], ours_f[k], tol))
    return out


def draw(path, walks):
    """Lateral and forward ZMP, CoM and waist against time since each walk's first lift-off."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 1, figsize=(11, 8), sharex=True)
    for (name, walk, colour) in walks:
        steps = phases(walk)
        t = walk["t"] - walk["t"][steps[0][1]]
        # the origin between the soles' centres at the start (hrpsys's world, our plan frame)
        o = (walk["left"][0, :2] + walk["right"][0, :2]) / 2
        for _, a, b in steps:
            for ax in axes:
                ax.axvspan(t[a], t[b], color=colour, alpha=0.08, lw=0)
        for i, ax in enumerate(axes):
            k = 1 - i
            ax.plot(t, walk["zmp"][:, k] - o[k], color=colour, lw=1.8,
                    label="%s ZMP reference" % name)
            ax.plot(t, walk["com"][:, k] - o[k], color=colour, lw=1.2, ls=":",
                    label="%s CoM" % name)
            ax.plot(t, walk["waist"][:, k] - walk["waist"][0, k] + walk["com"][0, k] - o[k],
                    color=colour, lw=1.0, ls="--",
                    label="%s waist (shifted onto the CoM at the start)" % name)
            if "zmp_measured" in walk:
                ax.plot(t, walk["zmp_measured"][:, k] - o[k], color=colour, lw=0.5, alpha=0.5,
                        label="%s ZMP measured" % name)
    axes[0].set_ylabel("lateral y [m]")
    axes[1].set_ylabel("forward x [m] from the soles' centres at the start")
    axes[1].set_xlabel("time since the first lift-off [s] (shaded: single support)")
    axes[0].set_title("our walk against hrpsys's recording (same robot, same steps)")
    axes[0].legend(fontsize=7, ncol=2, loc="upper left")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=80)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir", help="ohrp_run output folder with walk.csv and log.csv")
    ap.add_argument("out", help="PNG to write")
    ap.add_argument("--recording", default=DEFAULT_RECORDING, help="hrpsys files' common prefix")
    ap.add_argument("--model", default=DEFAULT_MODEL, help="MJCF of SampleRobot (jointId order)")
    ap.add_argument("--table", help="also write the table (markdown) here")
    ap.add_argument("--require-match", action="store_true",
                    help="exit 1 unless the steps and the matched figures agree")
    a = ap.parse_args()
    try:
        hrpsys_walk = theirs(a.recording, a.model)
        our_walk = ours(a.run_dir)
        f_hrpsys = figures(hrpsys_walk)
    except (OSError, ValueError) as e:
        print("compare_hrpsys: %s" % e, file=sys.stderr)
        return 2
    try:
        f_ours = figures(our_walk)
    except ValueError as e:
        print("compare_hrpsys: %s: %s" % (os.path.join(a.run_dir, "walk.csv"), e), file=sys.stderr)
        return 2
    text = table(f_hrpsys, f_ours)
    print("hrpsys: %s (contact columns: %s); ours: %s" % (a.recording, hrpsys_walk["contact_order"],
                                                         a.run_dir))
    print(text)
    if a.table:
        with open(a.table, "w") as f:
            f.write(text + "\n")
    draw(a.out, [("hrpsys", hrpsys_walk, "black"), ("ours", our_walk, "tab:blue")])
    if a.require_match:
        bad = mismatches(f_hrpsys, f_ours)
        for m in bad:
            print("compare_hrpsys: no match: %s" % m, file=sys.stderr)
        return 1 if bad else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
