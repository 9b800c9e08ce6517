#!/usr/bin/env python3
"""Writes a parametric test humanoid as MJCF (issue 31 item 3, "robots nobody here has seen").

A robot that is neither HRP-1S nor G1 nor H1, for checking that the robot profile, balance and
walk need nothing tuned on those: 6-joint legs (hip yaw, roll, pitch, knee, ankle pitch, roll),
a torso and a head on the pelvis (no waist joint), two 4-joint arms (shoulder pitch, roll, yaw,
elbow), box feet, an IMU site (gyro + accelerometer) on the pelvis and a force/torque site
(force + torque) at each ankle. No keyframe and no *_SOLE box: a user's `ohrp profile --init`
derives the soles and the stance must be reviewed, as for a robot brought from elsewhere.

Parameters (all optional):
  --scale S        overall size, 0.5-1.5 of a 1.5 m robot (lengths scale with S)
  --mass M         total mass [kg], 5-200 (shared among the links in fixed fractions)
  --names snake|camel   joint and body names: l_hip_yaw / LeftHipYaw
  --actuator motor|position   <motor gear=1> or a position servo (<general>, kp and kv), torque-limited
  --timestep T     the physics step [s]
  --out FILE       the MJCF to write (default: stdout)

The torque limits and the position servo's stiffness follow the robot's weight and leg length:
a leg joint's limit is 0.4 m g L (L the hip height), an arm's 0.1 m g L; kp = 3 m g L for a leg
joint (G1's 500 N m/rad is 2.4 of its own), 0.5 m g L for an arm. Stdlib only.

Usage: make_humanoid.py --scale 0.6 --mass 20 --names snake --actuator position --out child.xml
"""
import argparse
import math
import sys

# mass fractions of the links (sum 1)
FRACTIONS = {"pelvis": 0.14, "torso": 0.30, "head": 0.06, "thigh": 0.10, "shin": 0.05,
             "ankle": 0.005, "foot": 0.02, "upper_arm": 0.025, "forearm": 0.015}
LEG = [("hip_yaw", "0 0 1", (-0.8, 0.8)), ("hip_roll", "1 0 0", (-0.5, 0.5)),
       ("hip_pitch", "0 1 0", (-2.0, 0.8)), ("knee", "0 1 0", (0.0, 2.4)),
       ("ankle_pitch", "0 1 0", (-0.9, 0.7)), ("ankle_roll", "1 0 0", (-0.4, 0.4))]
ARM = [("shoulder_pitch", "0 1 0", (-3.0, 1.5)), ("shoulder_roll", "1 0 0", (-1.5, 1.5)),
       ("shoulder_yaw", "0 0 1", (-1.5, 1.5)), ("elbow", "0 1 0", (-2.4, 0.0))]


def name(style, side, part):
    """l_hip_yaw (snake) or LeftHipYaw (camel); side '' for an unsided part."""
    if style == "snake":
        return (side[0] + "_" if side else "") + part
    words = ([side.capitalize()] if side else []) + [w.capitalize() for w in part.split("_")]
    return "".join(words)


def check(args):
    """Refuses parameters outside the ranges the proportions below were written for."""
    errors = []
    if not 0.5 <= args.scale <= 1.5:
        errors.append(f"--scale {args.scale}: outside [0.5, 1.5]")
    if not 5 <= args.mass <= 200:
        errors.append(f"--mass {args.mass}: outside [5, 200] kg")
    if not 0.0002 <= args.timestep <= 0.005:
        errors.append(f"--timestep {args.timestep}: outside [0.0002, 0.005] s")
    if errors:
        sys.exit("make_humanoid.py: " + "; ".join(errors))


def dimensions(s):
    """Lengths [m] of the 1.5 m robot times s."""
    d = {"thigh": 0.32, "shin": 0.32, "ankle_h": 0.07, "hip_y": 0.085, "hip_drop": 0.06,
         "foot_x": 0.22, "foot_y": 0.11, "foot_z": 0.03, "foot_fwd": 0.03,
         "pelvis_r": 0.10, "torso_x": 0.10, "torso_y": 0.15, "torso_z": 0.22,
         "head_r": 0.09, "shoulder_y": 0.20, "shoulder_z": 0.40, "upper_arm": 0.26,
         "forearm": 0.24, "arm_r": 0.035, "leg_r": 0.045}
    return {k: v * s for k, v in d.items()}


def joint_xml(n, axis, rng, armature, damping):
    return (f'<joint name="{n}" axis="{axis}" range="{rng[0]:g} {rng[1]:g}" '
            f'armature="{armature:g}" damping="{damping:g}"/>')


def leg_xml(a, d, side, sign):
    """The chain pelvis -> foot, one body per joint; returns (xml, joint names)."""
    m, st = a.mass, a.names
    y = sign * d["hip_y"]
    joints, lines = [], []
    n = lambda p: name(st, side, p)
    # hip yaw, roll, pitch at one point below the pelvis, then knee, ankle pitch, ankle roll
    bodies = [("hip_yaw", f"0 {y:g} {-d['hip_drop']:g}", None),
              ("hip_roll", "0 0 0", None),
              ("hip_pitch", "0 0 0",
               f'<geom type="capsule" fromto="0 0 0 0 0 {-d["thigh"]:g}" size="{d["leg_r"]:g}" '
               f'mass="{FRACTIONS["thigh"] * m:g}"/>'),
              ("knee", f"0 0 {-d['thigh']:g}",
               f'<geom type="capsule" fromto="0 0 0 0 0 {-d["shin"]:g}" size="{0.8 * d["leg_r"]:g}" '
               f'mass="{FRACTIONS["shin"] * m:g}"/>'),
              ("ankle_pitch", f"0 0 {-d['shin']:g}",
               f'<geom type="sphere" size="{0.6 * d["leg_r"]:g}" mass="{FRACTIONS["ankle"] * m:g}"/>'),
              ("ankle_roll", "0 0 0", None)]
    depth = 0
    for i, (part, pos, geom) in enumerate(bodies):
        _, axis, rng = LEG[i]
        link = n(part + "_link") if st == "snake" else n(part) + "Link"
        lines.append("  " * depth + f'<body name="{link}" pos="{pos}">')
        lines.append("  " * depth + "  " + joint_xml(n(part), axis, rng, a.armature, a.damping))
        joints.append(n(part))
        if geom is None and part in ("hip_yaw", "hip_roll"):
            geom = f'<geom type="sphere" size="{0.5 * d["leg_r"]:g}" mass="{0.005 * m:g}"/>'
        if part == "ankle_roll":
            fz = -d["ankle_h"] + d["foot_z"] / 2
            geom = (f'<geom name="{n("foot") if st == "snake" else n("foot") + "Geom"}" type="box" '
                    f'pos="{d["foot_fwd"]:g} 0 {fz:g}" '
                    f'size="{d["foot_x"] / 2:g} {d["foot_y"] / 2:g} {d["foot_z"] / 2:g}" '
                    f'mass="{FRACTIONS["foot"] * m:g}" contype="1" conaffinity="1" friction="1"/>')
            ft = n("ankle_ft")
            geom += f'\n{"  " * depth}  <site name="{ft}" pos="0 0 0" size="0.01"/>'
        if geom:
            lines.append("  " * depth + "  " + geom)
        depth += 1
    for k in range(depth - 1, -1, -1):
        lines.append("  " * k + "</body>")
    return lines, joints


def arm_xml(a, d, side, sign):
    m, st = a.mass, a.names
    n = lambda p: name(st, side, p)
    y = sign * d["shoulder_y"]
    lines, joints = [], []
    parts = [("shoulder_pitch", f"0 {y:g} {d['shoulder_z']:g}", None),
             ("shoulder_roll", "0 0 0", None),
             ("shoulder_yaw", "0 0 0",
              f'<geom type="capsule" fromto="0 0 0 0 0 {-d["upper_arm"]:g}" size="{d["arm_r"]:g}" '
              f'mass="{FRACTIONS["upper_arm"] * m:g}"/>'),
             ("elbow", f"0 0 {-d['upper_arm']:g}",
              f'<geom type="capsule" fromto="0 0 0 0 0 {-d["forearm"]:g}" size="{0.8 * d["arm_r"]:g}" '
              f'mass="{FRACTIONS["forearm"] * m:g}"/>')]
    for i, (part, pos, geom) in enumerate(parts):
        _, axis, rng = ARM[i]
        link = n(part + "_link") if st == "snake" else n(part) + "Link"
        lines.append("  " * i + f'<body name="{link}" pos="{pos}">')
        lines.append("  " * i + "  " + joint_xml(n(part), axis, rng, a.armature, a.damping))
        joints.append(n(part))
        if geom is None:
            geom = f'<geom type="sphere" size="{0.5 * d["arm_r"]:g}" mass="{0.003 * m:g}"/>'
        lines.append("  " * i + "  " + geom)
    for k in range(len(parts) - 1, -1, -1):
        lines.append("  " * k + "</body>")
    return lines, joints


def actuators_xml(a, d, legs, arms):
    """One actuator per joint, the torque limits and servo from the weight and leg length."""
    L = d["thigh"] + d["shin"] + d["ankle_h"] + d["hip_drop"]
    mgl = a.mass * 9.81 * L
    out = []
    for joints, tau, kp in ((legs, 0.4 * mgl, 3.0 * mgl), (arms, 0.1 * mgl, 0.5 * mgl)):
        for j in joints:
            if a.actuator == "motor":
                out.append(f'<motor name="{j}_motor" joint="{j}" gear="1" '
                           f'ctrlrange="{-tau:.4g} {tau:.4g}" ctrllimited="true"/>')
            else:
                kv = 0.05 * kp  # damping time constant 50 ms
                # MuJoCo 2.2.2's <position> has no kv: the same servo as a <general> (as G1's)
                out.append(f'<general name="{j}_servo" joint="{j}" gaintype="fixed" biastype="affine" '
                           f'gainprm="{kp:.4g}" biasprm="0 {-kp:.4g} {-kv:.4g}" '
                           f'forcerange="{-tau:.4g} {tau:.4g}" forcelimited="true"/>')
    return out


def command_line(a):
    """The parameters that made the model (not --out: the text is the same wherever it goes)."""
    return (f"--scale {a.scale:g} --mass {a.mass:g} --names {a.names} --actuator {a.actuator} "
            f"--timestep {a.timestep:g} --armature {a.armature:g} --damping {a.damping:g}")


def model_xml(a):
    d = dimensions(a.scale)
    st = a.names
    pelvis_z = d["hip_drop"] + d["thigh"] + d["shin"] + d["ankle_h"]
    body = []
    legs, arms = [], []
    for side, sign in (("left", 1), ("right", -1)):
        lines, joints = leg_xml(a, d, side, sign)
        body += lines
        legs += joints
    for side, sign in (("left", 1), ("right", -1)):
        lines, joints = arm_xml(a, d, side, sign)
        body += lines
        arms += joints
    m = a.mass
    pelvis = "pelvis" if st == "snake" else "Pelvis"
    torso = "torso" if st == "snake" else "Torso"
    imu = "imu" if st == "snake" else "ImuSite"
    tz = d["torso_z"] + 0.05 * a.scale
    head_z = 2 * d["torso_z"] + 0.05 * a.scale + d["head_r"]
    lines = [
        f'<mujoco model="test_humanoid_{st}_{a.actuator}_{a.scale:g}_{a.mass:g}">',
        f'  <!-- written by tests/robots/make_humanoid.py {command_line(a)} -->',
        '  <compiler autolimits="true" angle="radian"/>',
        f'  <option timestep="{a.timestep:g}"/>',
        '  <default><geom contype="0" conaffinity="0" rgba="0.7 0.7 0.75 1"/></default>',
        '  <worldbody>',
        '    <light pos="0 0 4" dir="0 0 -1"/>',
        '    <geom name="floor" type="plane" size="0 0 0.05" contype="1" conaffinity="1" rgba="0.5 0.6 0.5 1"/>',
        f'    <body name="{pelvis}" pos="0 0 {pelvis_z + 0.002:g}">',
        '      <freejoint/>',
        f'      <geom type="sphere" size="{d["pelvis_r"]:g}" mass="{FRACTIONS["pelvis"] * m:g}"/>',
        f'      <site name="{imu}" pos="0 0 0" size="0.01"/>',
        f'      <body name="{torso}" pos="0 0 0">',
        f'        <geom type="box" pos="0 0 {tz:g}" size="{d["torso_x"]:g} {d["torso_y"]:g} {d["torso_z"]:g}" '
        f'mass="{FRACTIONS["torso"] * m:g}"/>',
        f'        <geom type="sphere" pos="0 0 {head_z:g}" size="{d["head_r"]:g}" mass="{FRACTIONS["head"] * m:g}"/>',
        '      </body>',
    ]
    lines += ["      " + s for s in body]
    lines += ['    </body>', '  </worldbody>', '  <actuator>']
    lines += ["    " + s for s in actuators_xml(a, d, legs, arms)]
    lines += ['  </actuator>', '  <sensor>',
              f'    <gyro name="{imu}_gyro" site="{imu}"/>',
              f'    <accelerometer name="{imu}_acc" site="{imu}"/>']
    for side in ("left", "right"):
        ft = name(st, side, "ankle_ft")
        lines += [f'    <force name="{ft}_force" site="{ft}"/>',
                  f'    <torque name="{ft}_torque" site="{ft}"/>']
    lines += ['  </sensor>', '</mujoco>', '']
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scale", type=float, default=1.0)
    p.add_argument("--mass", type=float, default=40.0)
    p.add_argument("--names", choices=["snake", "camel"], default="snake")
    p.add_argument("--actuator", choices=["motor", "position"], default="motor")
    p.add_argument("--timestep", type=float, default=0.002)
    p.add_argument("--armature", type=float, default=0.01, help="rotor inertia per joint [kg m^2]")
    p.add_argument("--damping", type=float, default=0.1, help="joint damping [N m s/rad]")
    p.add_argument("--out", default="-")
    a = p.parse_args()
    check(a)
    text = model_xml(a)
    if a.out == "-":
        sys.stdout.write(text)
    else:
        with open(a.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
