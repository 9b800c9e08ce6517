#!/usr/bin/env python3
"""Writes the colliding motions of HRP-1S that judge the self-collision guard (issue 29;
docs/selfcollision.md, "Judging the guard") into scenarios/trajectories/selfcollision_*.dat,
and the arm pose of the posture trials into scenarios/params/selfcollision_forearm_pose.yaml.

Each motion starts at the halfsit keyframe, holds it 0.5 s, moves through a safe preparation
(joints at a constant 0.5 rad/s, all of them together, in straight lines), then drives the
joints of one group into the body at the file's speed (the posture at the end of each motion
is deep inside another link: without a guard the links pass through each other), holds it 1 s,
goes back to halfsit the same way at 0.5 rad/s (a guard that holds at the body and lets the
arm go back lets the motion complete) and holds halfsit 1 s: one file per speed of the
collision phase, selfcollision_<motion>_<factor>x.dat (0.5x .. 8x of 0.5 rad/s).
arm_jump_past_thigh instead holds the prepared pose 1 s, jumps (one row) to an end pose clear
of the body whose straight path goes through the thigh, holds it 1 s and jumps back (one file).
The format is playback's (arm_into_leg.dat): time [s], then the 29 joints in joint-id order.

  python3 tools/selfcollision/trials/make_trajectories.py   (from the source tree's root)
"""
import os

JOINTS = ["RLEG_HIP_R", "RLEG_HIP_P", "RLEG_HIP_Y", "RLEG_KNEE", "RLEG_ANKLE_P", "RLEG_ANKLE_R",
          "RARM_SHOULDER_P", "RARM_SHOULDER_R", "RARM_SHOULDER_Y", "RARM_ELBOW", "RARM_WRIST_Y",
          "RARM_WRIST_P", "RARM_WRIST_R",
          "LLEG_HIP_R", "LLEG_HIP_P", "LLEG_HIP_Y", "LLEG_KNEE", "LLEG_ANKLE_P", "LLEG_ANKLE_R",
          "LARM_SHOULDER_P", "LARM_SHOULDER_R", "LARM_SHOULDER_Y", "LARM_ELBOW", "LARM_WRIST_Y",
          "LARM_WRIST_P", "LARM_WRIST_R",
          "WAIST_P", "WAIST_R", "CHEST"]
# the halfsit keyframe of mjcf/hrp1s/hrp1s.xml [rad]
HALFSIT = {"RLEG_HIP_P": -0.349066, "RLEG_KNEE": 0.698132, "RLEG_ANKLE_P": -0.349066,
           "LLEG_HIP_P": -0.349066, "LLEG_KNEE": 0.698132, "LLEG_ANKLE_P": -0.349066,
           "RARM_SHOULDER_P": 0.174533, "RARM_SHOULDER_R": -0.174533, "RARM_ELBOW": -0.523599,
           "LARM_SHOULDER_P": 0.174533, "LARM_SHOULDER_R": 0.174533, "LARM_ELBOW": -0.523599}
SPEED = 0.5   # [rad/s] of the fastest joint of a phase at 1x
STEP = 0.05   # [s] between rows
HOLD_START, HOLD_END = 0.5, 1.0  # [s]

# name: (what, preparation targets, collision targets)
MOTIONS = {
    "forearm_into_waist": (
        "the right forearm, bent forward, swung across (shoulder yaw inwards) into the waist "
        "column",
        {"RARM_SHOULDER_P": 0.0, "RARM_ELBOW": -1.5708},
        {"RARM_SHOULDER_Y": 1.5}),
    "hands_together": (
        "both forearms, bent forward at chest height, swung towards each other (shoulder yaws "
        "inwards) until the hands meet in front of the chest",
        {"RARM_SHOULDER_P": -0.5, "RARM_ELBOW": -1.5708, "LARM_SHOULDER_P": -0.5,
         "LARM_ELBOW": -1.5708},
        {"RARM_SHOULDER_Y": 1.2, "LARM_SHOULDER_Y": -1.2}),
    "waist_into_thighs": (
        "the arms straightened, then the waist pitched forward 1.0 rad while the shoulders "
        "pitch back as much (the arms keep hanging down) and roll inwards to their limits (the "
        "hands over the thighs): the hands come down between the thighs into each other (the "
        "wrists meet; from 4x the robot falls forward)",
        {"RARM_ELBOW": 0.0, "LARM_ELBOW": 0.0},
        {"WAIST_P": 1.0, "RARM_SHOULDER_P": 1.174533, "LARM_SHOULDER_P": 1.174533,
         "RARM_SHOULDER_R": 0.261799, "LARM_SHOULDER_R": -0.261799}),
    "arm_jump_past_thigh": (
        "the right arm, straight, swung back 1.0 rad and rolled inwards to its limit (the hand "
        "behind the thigh, clear of it), then commanded in one row (a jump: 0.05 s) to 1.0 rad "
        "forward (in front of the thigh, clear of it): the straight path between the two goes "
        "through the thigh",
        {"RARM_SHOULDER_P": 1.0, "RARM_ELBOW": 0.0, "RARM_SHOULDER_R": 0.261799},
        {"RARM_SHOULDER_P": -1.0}),
}
JUMPS = {"arm_jump_past_thigh"}  # the collision phase in one row


def ramp(start, target, t0, jump=False, factor=1.0):
    """Rows from `start` (t0) to `target` with the fastest joint at `factor` x SPEED; returns
    (rows, end time, end posture)."""
    span = max(abs(target.get(j, start[j]) - start[j]) for j in JOINTS)
    step = STEP / 5 if factor > 1 else STEP
    duration = STEP if jump else max(step, round(span / (SPEED * factor) / step) * step)
    if not jump:
        step = duration / max(1, round(duration / step))
    rows = []
    n = 1 if jump else round(duration / step)
    for k in range(1, n + 1):
        s = k / n
        rows.append((t0 + k * duration / n, {j: start[j] + s * (target.get(j, start[j]) - start[j])
                                     for j in JOINTS}))
    end = dict(start)
    end.update(target)
    return rows, t0 + duration, end


def motion_rows(prep, collide, jump=False, factor=1.0):
    q = {j: HALFSIT.get(j, 0.0) for j in JOINTS}
    rows = [(k * STEP, dict(q)) for k in range(round(HOLD_START / STEP) + 1)]
    t = HOLD_START
    more, t, q = ramp(q, prep, t)
    rows += more
    prepared = dict(q)
    if jump:  # hold the prepared pose a while: the arm settles before the jump
        rows += [(t + k * STEP, dict(q)) for k in range(1, round(HOLD_END / STEP) + 1)]
        t += HOLD_END
    more, t, q = ramp(q, collide, t, jump, factor)
    rows += more
    if not jump:  # hold, then back out the same way to halfsit: a guard that let the links
        # part again lets the motion complete (playback ends with exit 0)
        rows += [(t + k * STEP, dict(q)) for k in range(1, round(HOLD_END / STEP) + 1)]
        t += HOLD_END
        end = q
        # the way it came: the collision phase backwards (at 0.5 rad/s), then the preparation
        for target in (prepared, {j: HALFSIT.get(j, 0.0) for j in JOINTS}):
            more, t, q = ramp(q, target, t)
            rows += more
        rows += [(t + k * STEP, dict(q)) for k in range(1, round(HOLD_END / STEP) + 1)]
        return rows, end
    # a jump: hold the far pose, jump back to the prepared pose (a guard that held there sees
    # its held pose commanded again and lets the motion complete)
    end = q
    rows += [(t + k * STEP, dict(q)) for k in range(1, round(HOLD_END / STEP) + 1)]
    t += HOLD_END
    more, t, q = ramp(q, prepared, t, True)
    rows += more
    rows += [(t + k * STEP, dict(q)) for k in range(1, round(HOLD_END / STEP) + 1)]
    return rows, q


def write(path, what, rows):
    with open(path, "w") as f:
        f.write("# Written by tools/selfcollision/trials/make_trajectories.py (issue 29's trials of\n"
                "# the self-collision guard, docs/selfcollision.md): " + what + ".\n"
                "# Halfsit until %.1f s, then the joints at %.2f rad/s.\n" % (HOLD_START, SPEED) +
                "# Columns: time [s], then the 29 joints of HRP-1S in joint-id order [rad].\n")
        for t, q in rows:
            f.write("%.2f " % t + " ".join("%.6f" % q[j] for j in JOINTS) + "\n")


SPEEDS = [0.5, 1, 2, 4, 8]  # factors on SPEED of the collision phase (the rest at SPEED)


def main():
    root = os.getcwd()
    for name, (what, prep, collide) in MOTIONS.items():
        jump = name in JUMPS
        for v in [1] if jump else SPEEDS:
            rows, end = motion_rows(prep, collide, jump, v)
            suffix = "" if jump else "_%gx" % v
            speed = "" if jump else " The collision phase at %g rad/s (%gx)." % (SPEED * v, v)
            write(os.path.join(root, "scenarios/trajectories/selfcollision_%s%s.dat" % (name, suffix)),
                  what + "." + speed, rows)
        if name == "forearm_into_waist":
            rows, end = motion_rows(prep, collide)
            # the posture trials: the same end pose, reached by posture's own ramp or a jump
            with open(os.path.join(root, "scenarios/params/selfcollision_forearm_pose.yaml"), "w") as f:
                f.write("# Written by tools/selfcollision/trials/make_trajectories.py: the end pose\n"
                        "# of selfcollision_forearm_into_waist_*.dat (the right forearm inside the\n"
                        "# waist column), for posture --pose [rad]; the joints not named hold\n"
                        "# where they are (halfsit)\n"
                        "description: the right forearm swung across into the waist column\n"
                        "joints:\n")
                for j in JOINTS:
                    if abs(end[j] - HALFSIT.get(j, 0.0)) > 1e-9:
                        f.write("  %s: %.6f\n" % (j, end[j]))


if __name__ == "__main__":
    main()
