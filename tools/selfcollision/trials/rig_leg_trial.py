#!/usr/bin/env python3
"""HRP-1S's leg driven into the other on its rig, judged on the simulated robot
(docs/selfcollision.md, "A leg whose foot is in the air is braked").

  rig_leg_trial.py OUT_DIR [--runner BUILD/bin/ohrp_run] [--source ROOT] [--ramps 1,0.25,0]
                   [--guard on,off] [--require]

HRP-1S hung on its rig (mjcf/hrp1s/scene_hung.xml: the WAIST welded, no floor; keyframe rig:
the legs spread, hip rolls 0.2 rad outwards), as scenarios/excite_knee_hung.yaml; `posture
--pose` drives the right hip roll inwards (from -0.2 to 0.35 rad): the right foot and ankle go
into the left ones. Both feet are in the air (their F/T sensors read the soles' own weight),
so the guard may brake both legs. Each --ramps value is posture's --ramp [s] (shorter:
faster; 0: a jump), with HRP-1S's shipped file (the controllers' default) or the check off.
The figure of a trial is sim_host's closest approach of any two non-adjacent links over the
run (its `self_collisions` check over every pair, independent of the guard; negative: overlap).

--require: exit 1 unless every guard-on trial keeps the links at or above the file's margin
less 0.5 mm and every guard-off trial overlaps (the motion is a colliding one).
"""
import argparse
import os
import subprocess
import sys

from selfcollision_trial import TOLERANCE_MM, closest_approach, margin_mm

FILE = "mjcf/hrp1s/selfcollision.yaml"  # the controllers' default for HRP-1S
POSE = {"RLEG_HIP_R": 0.35}


def scenario(name, pose, ramp, guard, root):
    args = ["--pose", pose, "--ramp", "%g" % ramp]
    args += [] if guard == "on" else ["--no-self-collision"]  # on: the default, FILE
    return ("# written by tools/selfcollision/trials/rig_leg_trial.py\n"
            "name: %s\n" % name +
            "description: HRP-1S on its rig, the right leg driven into the left (a self-collision trial)\n"
            "scene: mjcf/hrp1s/scene_hung.xml\n"
            "keyframe: rig\n"
            "duration: %.3f\n" % (ramp + 1.5) +
            "physics_dt: 0.001\n"
            "control_period: 0.005\n"
            "integrator: euler\n"
            "contact: native\n"
            "on_controller_loss: end\n"
            "controllers:\n"
            "  - program: posture\n"
            "    args: [%s]\n" % ", ".join('"%s"' % a for a in args) +
            "checks:\n"
            "  - type: self_collisions\n"
            "    min_distance_mm: -1000\n")


def run(runner, root, out, name, ramp, guard):
    folder = os.path.join(out, name)
    os.makedirs(folder, exist_ok=True)
    pose = os.path.join(folder, "pose.yaml")
    with open(pose, "w") as f:
        f.write("description: HRP-1S's right hip rolled inwards into the left leg\njoints:\n")
        for k, v in POSE.items():
            f.write("  %s: %g\n" % (k, v))
    path = os.path.join(folder, "scenario.yaml")
    with open(path, "w") as f:
        f.write(scenario(name, pose, ramp, guard, root))
    subprocess.run([runner, path, "--out", os.path.join(folder, "run")], cwd=root,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    row = {"trial": name, "ramp": ramp, "guard": guard}
    row.update(closest_approach(os.path.join(folder, "run")))
    return row


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    p.add_argument("out_dir")
    p.add_argument("--source", default=os.path.normpath(os.path.join(here, "../../..")))
    p.add_argument("--runner", default=None, help="ohrp_run (default: SOURCE/build/bin/ohrp_run)")
    p.add_argument("--ramps", default="1,0.25,0")
    p.add_argument("--guard", default="on,off")
    p.add_argument("--require", action="store_true")
    a = p.parse_args()
    try:
        ramps = [float(v) for v in a.ramps.split(",") if v]
    except ValueError:
        p.error("--ramps: numbers [s]")
    if not ramps or any(not 0 <= r <= 10 for r in ramps):
        p.error("--ramps: each in [0, 10] s")
    guards = [g for g in a.guard.split(",") if g]
    if not guards or any(g not in ("on", "off") for g in guards):
        p.error("--guard: on, off or both")
    root = os.path.abspath(a.source)
    runner = a.runner or os.path.join(root, "build/bin/ohrp_run")
    margin = margin_mm(root, FILE)
    out = os.path.abspath(a.out_dir)
    rows = []
    for g in guards:
        for r in (ramps if g == "on" else ramps[:1]):  # off: one colliding run shows the motion
            rows.append(run(runner, root, out, "rig_leg_ramp%g_%s" % (r, g), r, g))
            x = rows[-1]
            print("%-26s %s" % (x["trial"], x.get("error") or "closest %.1f mm (%s), %d holds, %s"
                                % (x["closest_mm"], x["pair"], x["holds"], x["outcome"])), flush=True)
    failed = [r for r in rows if "error" in r]
    if a.require:
        failed += [r for r in rows if "error" not in r and r["guard"] == "on" and
                   r["closest_mm"] < margin - TOLERANCE_MM]
        failed += [r for r in rows if "error" not in r and r["guard"] == "off" and
                   r["closest_mm"] >= 0]
    for r in failed:
        print("rig_leg_trial: FAILED: %s: %s" % (r["trial"], r.get("error") or
              "closest approach %.1f mm (%s): guard %s needs %s" % (
                  r["closest_mm"], r["pair"], r["guard"],
                  ">= %.1f mm" % (margin - TOLERANCE_MM) if r["guard"] == "on" else "an overlap")),
              file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
