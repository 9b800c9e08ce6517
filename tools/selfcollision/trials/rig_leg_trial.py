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

--require: see posture_trial.py (which runs it).
"""
import sys

from posture_trial import PostureTrial, main

TRIAL = PostureTrial(
    name="rig_leg", script="tools/selfcollision/trials/rig_leg_trial.py",
    guard_file="mjcf/hrp1s/selfcollision.yaml",  # the controllers' default for HRP-1S
    give_file=False, pose={"RLEG_HIP_R": 0.35},
    pose_description="HRP-1S's right hip rolled inwards into the left leg",
    description="HRP-1S on its rig, the right leg driven into the left (a self-collision trial)",
    scene="mjcf/hrp1s/scene_hung.xml", keyframe="rig",
    settings=["physics_dt: 0.001", "control_period: 0.005", "integrator: euler",
              "contact: native"])


if __name__ == "__main__":
    sys.exit(main(TRIAL, __doc__))
