#!/usr/bin/env python3
"""G1's arm driven into its leg, judged on the simulated robot (docs/selfcollision.md, "G1").

  g1_arm_trial.py OUT_DIR [--runner BUILD/bin/ohrp_run] [--source ROOT] [--ramps 1,0.5,0.25,0]
                  [--guard on,off] [--require]

menagerie's Unitree G1 through its profile (robots/g1.yaml), standing free on its soft soles
from the profile's stance; `posture --pose` swings the right arm in (shoulder roll 0.6 rad,
yaw 0.8 rad from the stance's -0.35 and 0): the wrist goes into the right hip links. Each
--ramps value is posture's --ramp [s] (shorter: faster; 0: a jump), with G1's self-collision
file given explicitly (--self-collision robots/g1_selfcollision.yaml) or the check off. The
figure of a trial is sim_host's closest approach of any two non-adjacent links over the run
(its `self_collisions` check over every pair, independent of the guard; negative: overlap).

--require: see posture_trial.py (which runs it).
"""
import sys

from posture_trial import PostureTrial, main

TRIAL = PostureTrial(
    name="g1_arm", script="tools/selfcollision/trials/g1_arm_trial.py",
    guard_file="robots/g1_selfcollision.yaml", give_file=True,
    pose={"right_shoulder_roll_joint": 0.6, "right_shoulder_yaw_joint": 0.8},
    pose_description="G1's right arm swung in across the hip",
    description="G1's right arm swung into its hip (a self-collision trial)",
    scene="robots/g1.yaml", keyframe="stand", settings=["control_period: 0.004"],
    default_ramps="1,0.5,0.25,0")


if __name__ == "__main__":
    sys.exit(main(TRIAL, __doc__))
