#!/usr/bin/env python3
"""H1's left arm folded into its torso, judged on the simulated robot (docs/selfcollision.md,
"Other robots").

  h1_arm_trial.py OUT_DIR [--runner BUILD/bin/ohrp_run] [--source ROOT] [--ramps 1,0.25,0]
                  [--guard on,off] [--require]

menagerie's Unitree H1 through its profile (robots/h1.yaml), standing free on its soft soles
from the profile's stance; `posture --pose` folds the left arm across the chest (shoulder roll
-0.34, pitch -0.3, yaw 1.2, elbow 1.6 rad): the upper arm goes into the torso. Each --ramps
value is posture's --ramp [s] (0: a jump). The guard's file is the profile's default
(`self_collision: h1_selfcollision.yaml`, not given on the command line), or the check off. The
figure of a trial is sim_host's closest approach of any two non-adjacent links over the run
(its `self_collisions` check, independent of the guard; negative: overlap).

--require: see posture_trial.py (which runs it).
"""
import sys

from posture_trial import PostureTrial, main

TRIAL = PostureTrial(
    name="h1_arm", script="tools/selfcollision/trials/h1_arm_trial.py",
    guard_file="robots/h1_selfcollision.yaml", give_file=False,
    pose={"left_shoulder_roll": -0.34, "left_shoulder_pitch": -0.3, "left_shoulder_yaw": 1.2,
          "left_elbow": 1.6},
    pose_description="H1's left arm folded across the chest",
    description="H1's left arm folded into its torso (a self-collision trial)",
    scene="robots/h1.yaml", keyframe="stand", settings=["control_period: 0.004"],
    default_ramps="1,0.25,0")


if __name__ == "__main__":
    sys.exit(main(TRIAL, __doc__))
