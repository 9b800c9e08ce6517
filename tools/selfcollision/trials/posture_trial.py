"""A self-collision trial driven by `posture` (docs/selfcollision.md, "Judging the guard"): one
pose ramped into at several speeds with the guard on and off, each a scenario of ohrp_run,
judged by sim_host's closest approach of any two non-adjacent links over the run (its
`self_collisions` check over every pair, independent of the guard; negative: overlap).

A trial is described by a PostureTrial (g1_arm_trial.py, rig_leg_trial.py) and run by main():

  TRIAL.py OUT_DIR [--runner BUILD/bin/ohrp_run] [--source ROOT] [--ramps R,R,...]
           [--guard on,off] [--require]

Each --ramps value is posture's --ramp [s] (shorter: faster; 0: a jump). --require: exit 1 unless
every guard-on trial keeps the links at or above the file's margin less 0.5 mm and every
guard-off trial overlaps (the motion is a colliding one).
"""
import argparse
import os
import subprocess
import sys
from dataclasses import dataclass, field

from selfcollision_trial import TOLERANCE_MM, closest_approach, margin_mm


@dataclass
class PostureTrial:
    name: str               # the trials' prefix and the program's name in messages
    script: str             # the file that describes it (named in the scenarios it writes)
    guard_file: str         # the self-collision file the guard uses (its margin is the bar)
    give_file: bool         # pass --self-collision FILE (else the controllers' default is FILE)
    pose: dict              # joint -> angle [rad] posture goes to
    pose_description: str
    description: str        # the scenario's
    scene: str
    keyframe: str
    settings: list = field(default_factory=list)  # extra scenario lines ("key: value")
    default_ramps: str = "1,0.25,0"


def scenario(t, name, pose_file, ramp, guard, root):
    args = ["--pose", pose_file, "--ramp", "%g" % ramp]
    if guard == "off":
        args.append("--no-self-collision")
    elif t.give_file:
        args += ["--self-collision", os.path.join(root, t.guard_file)]
    lines = ["# written by %s" % t.script, "name: %s" % name,
             "description: %s" % t.description, "scene: %s" % t.scene,
             "keyframe: %s" % t.keyframe, "duration: %.3f" % (ramp + 1.5)] + t.settings + [
             "on_controller_loss: end", "controllers:", "  - program: posture",
             "    args: [%s]" % ", ".join('"%s"' % a for a in args), "checks:",
             "  - type: self_collisions", "    min_distance_mm: -1000"]
    return "\n".join(lines) + "\n"


def run(t, runner, root, out, name, ramp, guard):
    folder = os.path.join(out, name)
    os.makedirs(folder, exist_ok=True)
    pose = os.path.join(folder, "pose.yaml")
    with open(pose, "w") as f:
        f.write("description: %s\njoints:\n" % t.pose_description)
        for k, v in t.pose.items():
            f.write("  %s: %g\n" % (k, v))
    path = os.path.join(folder, "scenario.yaml")
    with open(path, "w") as f:
        f.write(scenario(t, name, pose, ramp, guard, root))
    subprocess.run([runner, path, "--out", os.path.join(folder, "run")], cwd=root,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    row = {"trial": name, "ramp": ramp, "guard": guard}
    row.update(closest_approach(os.path.join(folder, "run")))
    return row


def failures(rows, margin, require):
    failed = [r for r in rows if "error" in r]
    if require:
        failed += [r for r in rows if "error" not in r and r["guard"] == "on" and
                   r["closest_mm"] < margin - TOLERANCE_MM]
        failed += [r for r in rows if "error" not in r and r["guard"] == "off" and
                   r["closest_mm"] >= 0]
    return failed


def main(t, doc):
    p = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    p.add_argument("out_dir")
    p.add_argument("--source", default=os.path.normpath(os.path.join(here, "../../..")))
    p.add_argument("--runner", default=None, help="ohrp_run (default: SOURCE/build/bin/ohrp_run)")
    p.add_argument("--ramps", default=t.default_ramps)
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
    margin = margin_mm(root, t.guard_file)
    out = os.path.abspath(a.out_dir)
    rows = []
    for g in guards:
        for r in (ramps if g == "on" else ramps[:1]):  # off: one colliding run shows the motion
            rows.append(run(t, runner, root, out, "%s_ramp%g_%s" % (t.name, r, g), r, g))
            x = rows[-1]
            print("%-26s %s" % (x["trial"], x.get("error") or "closest %.1f mm (%s), %d holds, %s"
                                % (x["closest_mm"], x["pair"], x["holds"], x["outcome"])), flush=True)
    failed = failures(rows, margin, a.require)
    for r in failed:
        print("%s_trial: FAILED: %s: %s" % (t.name, r["trial"], r.get("error") or
              "closest approach %.1f mm (%s): guard %s needs %s" % (
                  r["closest_mm"], r["pair"], r["guard"],
                  ">= %.1f mm" % (margin - TOLERANCE_MM) if r["guard"] == "on" else "an overlap")),
              file=sys.stderr)
    return 1 if failed else 0
