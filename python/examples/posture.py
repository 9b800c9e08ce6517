#!/usr/bin/python3
"""posture.py: the posture controller in Python (the C++ `posture` is its model).

Attaches to a robot segment (sim_host or hw_driver: it cannot tell which), reads the joint
positions, ramps them to a pose along a minimum-jerk profile over --ramp seconds of the
producer's time, then holds the pose until the producer stops or SIGINT/SIGTERM. Position
mode, gains = the producer's default gains times --kp-scale / --kd-scale.

Exit codes (as every controller of the project): 0 the producer ended its run (or a signal),
2 bad command line, 3 a pose file that is malformed or does not fit the robot, 4 could not
attach, 5 the producer is gone or silent, 6 the producer failed (e.g. diverged), 7 dropped.
"""

import argparse
import os
import signal
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(REPO, "python"))

import numpy as np  # noqa: E402

import ohrp  # noqa: E402

DEFAULT_POSE = os.path.join(REPO, "controllers", "poses", "hrp1s_halfsit.yaml")


def read_pose(path):
    """The `joints:` mapping of a pose file (controllers/poses/*.yaml): one `NAME: radians`
    per line under `joints:`. Only this subset of YAML is read (no third-party parser)."""
    pose, in_joints = {}, False
    with open(path) as f:
        for line_no, raw in enumerate(f, start=1):
            line = raw.split("#", 1)[0].rstrip()
            if not line.strip():
                continue
            if not line.startswith((" ", "\t")):
                in_joints = line.strip() == "joints:"
                continue
            if not in_joints:
                continue
            name, sep, value = line.strip().partition(":")
            try:
                if not sep:
                    raise ValueError("expected 'NAME: radians'")
                pose[name.strip()] = float(value)
            except ValueError as e:
                raise ValueError("%s:%d: joints: '%s': %s" % (path, line_no, line.strip(), e))
    if not pose:
        raise ValueError("%s: no 'joints:' mapping of NAME: radians" % path)
    return pose


def min_jerk(s):
    s = min(max(s, 0.0), 1.0)
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)


def attach(segment, timeout):
    deadline = time.monotonic() + timeout
    while True:
        try:
            return ohrp.Robot.controller(segment)
        except ohrp.SegmentError as e:
            if time.monotonic() >= deadline or "no segment" not in str(e):
                raise


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[1])
    ap.add_argument("--segment", required=True, help="the robot segment's name (e.g. hrp1s)")
    ap.add_argument("--pose", default=DEFAULT_POSE,
                    help="pose file by joint name [rad] (joints not named: 0)")
    ap.add_argument("--ramp", type=float, default=2.0,
                    help="ramp duration [s of producer time], 0 = jump (default 2)")
    ap.add_argument("--kp-scale", type=float, default=1.0)
    ap.add_argument("--kd-scale", type=float, default=1.0)
    ap.add_argument("--attach-timeout", type=float, default=0.0,
                    help="wait up to this long [s] for the segment to appear (default 0)")
    args = ap.parse_args()
    if not (args.ramp >= 0 and args.kp_scale >= 0 and args.kd_scale >= 0):
        ap.error("--ramp, --kp-scale and --kd-scale must be >= 0")
    try:
        pose = read_pose(args.pose)
    except (OSError, ValueError) as e:
        print("posture.py: %s" % e, file=sys.stderr)
        return 3 if isinstance(e, ValueError) else 2

    stop = []
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.append(1))
    try:
        robot = attach(args.segment, args.attach_timeout)
    except ohrp.SegmentError as e:
        print("posture.py: %s" % e, file=sys.stderr)
        return 4
    with robot:
        unknown = sorted(set(pose) - set(robot.joint_names))
        if unknown:
            print("posture.py: %s: joints the robot '%s' does not have: %s"
                  % (args.pose, robot.robot_name, ", ".join(unknown)), file=sys.stderr)
            return 3
        target = np.array([pose.get(n, 0.0) for n in robot.joint_names])
        target = np.clip(target, robot.q_min, robot.q_max)
        kp, kd = robot.default_kp * args.kp_scale, robot.default_kd * args.kd_scale
        start, t0, cycles, wall0 = None, 0.0, 0, time.monotonic()
        try:
            while not stop and robot.read():
                if start is None:
                    start, t0 = robot.q.copy(), robot.time
                s = 1.0 if args.ramp == 0 else min_jerk((robot.time - t0) / args.ramp)
                if not robot.write(q_ref=start + s * (target - start), kp=kp, kd=kd):
                    break  # the producer ended its run between the read and the write
                cycles += 1
        except ohrp.SegmentError as e:
            print("posture.py: %s" % e, file=sys.stderr)
            return 7 if "dropped" in str(e) else 5
        wall = time.monotonic() - wall0
        print("posture.py: %d cycles, %.2f s of producer time in %.2f s wall (%.1fx real time)"
              % (cycles, robot.time - t0, wall, (robot.time - t0) / wall if wall > 0 else 0.0),
              file=sys.stderr)
        if robot.producer_failed():
            print("posture.py: the producer ended reporting a failure", file=sys.stderr)
            return 6
    return 0


if __name__ == "__main__":
    sys.exit(main())
