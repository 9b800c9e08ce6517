#!/usr/bin/env python3
"""The trials that judge the self-collision guard on the simulated robot (issue 29;
docs/selfcollision.md, "Judging the guard").

  selfcollision_trial.py OUT_DIR [--runner BUILD/bin/ohrp_run] [--source ROOT]
                         [--motions a,b] [--speeds 0.5,1,2,4] [--guard on,off]
                         [--table OUT.md] [--require]

Runs HRP-1S in lock-step (sim_host + playback or posture, from the halfsit keyframe) through
colliding motions of each joint group (scenarios/trajectories/selfcollision_*.dat, written by
make_trajectories.py) at increasing speeds of the colliding joints (--speeds: the files'
factors on 0.5 rad/s, 0.5x .. 8x; the preparation always at 0.5 rad/s), a jump whose end
points are clear and whose path goes through the thigh, and posture into the
forearm pose with its default 2 s ramp and with --ramp 0 (a jump), each with the controller's
guard on and off. Each run is a scenario of ohrp_run (written into OUT_DIR/<trial>/) whose
`self_collisions` check switches on sim_host's self_collision effect over every non-adjacent
pair of links (not the guard's pruned list): the figure of a trial is the closest approach of
the SIMULATED links over the run (the summary's self_collision.closest_mm, the smallest signed
distance of any pair: negative means the links overlap), independent of what the guard
predicted. Also given: the guard's hold episodes as sim_host recorded them, the controller's
exit code (9: its motion was not completed, the guard held to the end) and sim_host's outcome.

--require: exit 1 unless every guard-on trial kept the links at or above the margin of the
guard's file (mjcf/hrp1s/selfcollision.yaml) less 0.5 mm. A trial that could not run (no
summary) exits 1 always.
"""
import argparse
import json
import os
import subprocess
import sys

MOTIONS = ["forearm_into_waist", "hands_together", "waist_into_thighs", "arm_jump_past_thigh"]
POSTURES = {"posture_ramp": [], "posture_jump": ["--ramp", "0"]}  # posture's default ramp: 2 s
POSE = "scenarios/params/selfcollision_forearm_pose.yaml"
GUARD_FILE = "mjcf/hrp1s/selfcollision.yaml"
TOLERANCE_MM = 0.5
# the controllers' fall watch reads the base tilt from the IMU, which HRP-1S carries in its
# chest, above WAIST_P: the waist pitched 1.0 rad reads as a fall (base tilt 51 deg) while the
# simulated base stays upright. sim_host's own fall watch (the simulated bodies) stays on.
NO_CONTROLLER_FALL_WATCH = {"waist_into_thighs"}
JUMPS = {"arm_jump_past_thigh"}  # one trajectory (a jump), no speeds


def trajectory_duration(path):
    last = 0.0
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                last = float(line.split()[0])
    return last


def margin_mm(root, guard_file=GUARD_FILE):
    """The margin of a self-collision file [mm] (its `margin:` line)."""
    with open(os.path.join(root, guard_file)) as f:
        for line in f:
            if line.startswith("margin:"):
                return 1e3 * float(line.split(":")[1].split("#")[0])
    raise SystemExit("%s: %s has no margin" % (os.path.basename(sys.argv[0]), guard_file))


def closest_approach(run_dir):
    """The figures of a trial from its run folder's sim_summary.json: sim_host's closest
    approach of the simulated links (closest_mm, exact, pair, t), the guard's hold episodes and
    sim_host's outcome; with "error" when there is no summary or no closest approach in it."""
    try:
        with open(os.path.join(run_dir, "sim_summary.json")) as f:
            s = json.load(f)
    except (OSError, ValueError) as e:
        return {"error": "no summary: %s" % e}
    sc = s.get("self_collision") or {}
    g = s.get("self_collision_guard") or {}
    out = {"closest_mm": sc.get("closest_mm"), "exact": sc.get("closest_exact", False),
           "pair": sc.get("closest_pair", ""), "t": sc.get("closest_t"),
           "holds": g.get("hold_episodes", 0), "outcome": s.get("outcome", "?")}
    if out["closest_mm"] is None:
        out["error"] = "no closest approach in the summary"
    return out


def scenario(name, program, args, duration):
    quoted = ", ".join('"%s"' % a for a in args)
    return ("# written by tools/selfcollision/trials/selfcollision_trial.py\n"
            "name: %s\n" % name +
            "description: a self-collision trial (issue 29)\n"
            "scene: mjcf/hrp1s/scene_flat.xml\n"
            "keyframe: halfsit\n"
            "duration: %.3f\n" % duration +
            "physics_dt: 0.001\n"
            "control_period: 0.005\n"
            "integrator: euler\n"
            "on_controller_loss: end\n"
            "controllers:\n"
            "  - program: %s\n" % program +
            "    args: [%s]\n" % quoted +
            "checks:\n"
            "  - type: self_collisions\n"
            "    min_distance_mm: -1000\n")


def trials(root, motions, speeds, guards):
    out = []
    for m in motions:
        if m in POSTURES:
            for g in guards:
                args = ["--pose", POSE] + POSTURES[m] + ([] if g == "on" else ["--no-self-collision"])
                ramp = 0.0 if POSTURES[m] else 2.0
                out.append(("%s_%s" % (m, g), m, "-", g, "posture", args, ramp + 1.5))
            continue
        for v in [1.0] if m in JUMPS else speeds:
            suffix = "" if m in JUMPS else "_%gx" % v
            dat = "scenarios/trajectories/selfcollision_%s%s.dat" % (m, suffix)
            if not os.path.exists(os.path.join(root, dat)):
                raise SystemExit("selfcollision_trial: no %s (make_trajectories.py writes the "
                                 "speeds %s)" % (dat, "0.5, 1, 2, 4, 8"))
            length = trajectory_duration(os.path.join(root, dat))
            for g in guards:
                args = ["--angles", dat, "--ramp", "0.5"]
                if m in NO_CONTROLLER_FALL_WATCH:
                    args.append("--no-fall-watch")
                if g == "off":
                    args.append("--no-self-collision")
                out.append(("%s%s_%s" % (m, suffix, g), m, "jump" if m in JUMPS else "%gx" % v,
                            g, "playback", args, 0.5 + length + 0.3))
    return out


def run(runner, root, out_dir, t):
    name, motion, speed, guard, program, args, duration = t
    folder = os.path.join(out_dir, name)
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "scenario.yaml")
    with open(path, "w") as f:
        f.write(scenario("selfcollision_trial_" + name, program, args, duration))
    done = subprocess.run([runner, path, "--out", os.path.join(folder, "run"), "--quiet",
                           "--no-plot"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                          cwd=root)
    row = {"trial": name, "motion": motion, "speed": speed, "guard": guard,
           "runner_exit": done.returncode}
    row.update(closest_approach(os.path.join(folder, "run")))
    if "error" in row:
        return row
    try:  # the controller's exit code: 9 when its motion was not completed (a hold to the end)
        with open(os.path.join(folder, "run", "summary.json")) as f:
            row["controller_exit"] = [p["exit_code"] for p in json.load(f)["processes"]
                                      if p.get("name") != "sim_host"][0]
    except (OSError, ValueError, KeyError, IndexError):
        row["controller_exit"] = "?"
    return row


def table(rows, margin, tolerance_mm=TOLERANCE_MM):
    lines = ["| motion | speed | guard | closest approach of the simulated links [mm] | pair | "
             "t [s] | guard holds | controller exit | sim_host outcome |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append("| %s | %s | %s | (failed: %s) | | | | | |" % (r["motion"], r["speed"],
                                                                   r["guard"], r["error"]))
            continue
        d = ("%.1f" % r["closest_mm"]) if r["exact"] else ("> %.0f" % r["closest_mm"])
        lines.append("| %s | %s | %s | %s | %s | %.3f | %d | %s | %s |" % (
            r["motion"], r["speed"], r["guard"], d, r["pair"], r["t"] or 0.0, r["holds"],
            r["controller_exit"], r["outcome"]))
    lines.append("")
    lines.append("margin of the guard's file: %.1f mm; a guard-on trial passes at >= %.1f mm"
                 % (margin, margin - tolerance_mm))
    return "\n".join(lines) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    p.add_argument("out_dir")
    p.add_argument("--source", default=os.path.normpath(os.path.join(here, "../../..")))
    p.add_argument("--runner", default=None, help="ohrp_run (default: SOURCE/build/bin/ohrp_run)")
    p.add_argument("--motions", default=",".join(MOTIONS + list(POSTURES)))
    p.add_argument("--speeds", default="0.5,1,2,4")
    p.add_argument("--guard", default="on,off")
    p.add_argument("--table", default=None)
    p.add_argument("--require", action="store_true")
    p.add_argument("--tolerance-mm", type=float, default=TOLERANCE_MM,
                   help="--require passes a guard-on trial at >= margin less this [mm] (default "
                        "%.1f; the margin itself: the links apart)" % TOLERANCE_MM)
    a = p.parse_args()
    root = os.path.abspath(a.source)
    runner = a.runner or os.path.join(root, "build/bin/ohrp_run")
    motions = [m for m in a.motions.split(",") if m]
    for m in motions:
        if m not in MOTIONS and m not in POSTURES:
            p.error("--motions: unknown motion '%s' (known: %s)" % (m, ", ".join(MOTIONS + list(POSTURES))))
    speeds = [float(v) for v in a.speeds.split(",") if v]
    if any(not 0.05 <= v <= 10 for v in speeds):
        p.error("--speeds: each factor in [0.05, 10]")
    guards = [g for g in a.guard.split(",") if g]
    if any(g not in ("on", "off") for g in guards):
        p.error("--guard: on, off or both")
    if not 0 <= a.tolerance_mm <= 50:
        p.error("--tolerance-mm: in [0, 50] mm")
    margin = margin_mm(root)
    os.makedirs(a.out_dir, exist_ok=True)
    rows = []
    for t in trials(root, motions, speeds, guards):
        rows.append(run(runner, root, os.path.abspath(a.out_dir), t))
        r = rows[-1]
        print("%-34s %s" % (r["trial"], r.get("error") or "closest %.1f mm (%s), %d holds, %s" % (
            r["closest_mm"], r["pair"], r["holds"], r["outcome"])), flush=True)
    text = table(rows, margin, a.tolerance_mm)
    if a.table:
        with open(a.table, "w") as f:
            f.write(text)
    print(text)
    failed = [r for r in rows if "error" in r]
    if a.require:
        failed += [r for r in rows if r["guard"] == "on" and "error" not in r and
                   r["closest_mm"] < margin - a.tolerance_mm]
    for r in failed:
        print("selfcollision_trial: FAILED: %s: %s" % (r["trial"], r.get("error") or
              "closest approach %.1f mm (%s at %.3f s) below %.1f mm" % (
                  r["closest_mm"], r["pair"], r["t"], margin - a.tolerance_mm)), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
