#!/usr/bin/env python3
"""Reads an hrpsys SequencePlayer recording and puts the robot's model on it.

A recording is four text files sharing a prefix (hrpsys-base's `loadPattern` format), one row
per sample (2 ms), the time [s] first:
  PREFIX.pos           the joint angles [rad] in jointId order (SampleRobot: 29)
  PREFIX.waist         the waist's position [m] and roll, pitch, yaw [rad] (R = Rz Ry Rx)
  PREFIX.zmp           the reference ZMP [m] relative to the waist, in the waist's frame
  PREFIX.optionaldata  hrpsys's optional data: the contact state of each end effector (1 on the
                       floor) then the time left in its current phase [s], four of each
The model is an MJCF whose actuators are listed in jointId order (mjcf/hrp1s/hrp1s.xml, the
same SampleRobot): its bodies give the kinematic tree, the masses and the soles, so that the
recording gains what it does not hold: the CoM and both soles (centre of the bottom face) in
the world, by forward kinematics. Uses numpy only; errors are ValueError naming file and line.
"""
import xml.etree.ElementTree as ET

import numpy as np

SUFFIXES = {"pos": None, "waist": 6, "zmp": 3, "optionaldata": 8}  # values per row (pos: model)
SOLES = {"left": "LLEG_SOLE", "right": "RLEG_SOLE"}                   # MJCF geom names


def read_table(path, width):
    """(time, values) of a whitespace table with `width` values after the time (None: any)."""
    rows = []
    with open(path) as f:
        for line_no, line in enumerate(f, start=1):
            if not line.strip():
                continue
            try:
                row = [float(v) for v in line.split()]
            except ValueError:
                raise ValueError("%s:%d: not a row of numbers" % (path, line_no)) from None
            expect = width if width is not None else (len(rows[0]) - 1 if rows else None)
            if expect is not None and len(row) != expect + 1:
                raise ValueError("%s:%d: %d values after the time, expected %d"
                                 % (path, line_no, len(row) - 1, expect))
            rows.append(row)
    if len(rows) < 2:
        raise ValueError("%s: fewer than two rows" % path)
    a = np.array(rows)
    if np.any(np.diff(a[:, 0]) <= 0):
        raise ValueError("%s:%d: time does not increase"
                         % (path, int(np.argmax(np.diff(a[:, 0]) <= 0)) + 2))
    return a[:, 0], a[:, 1:]


def axis_rotations(axis, q):
    """(N, 3, 3) rotations by angles q [rad] about the unit `axis` (Rodrigues)."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    s, c = np.sin(q)[:, None, None], np.cos(q)[:, None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def vec(element, key, default):
    text = element.get(key)
    return np.array([float(v) for v in text.split()]) if text else np.array(default, dtype=float)


class Model:
    """The kinematic tree of an MJCF humanoid: bodies, hinge joints, masses, soles."""

    def __init__(self, path):
        root = ET.parse(path).getroot()
        self.path = path
        # jointId order: the actuators' order
        self.joint_ids = {m.get("joint"): i for i, m in
                          enumerate(root.find("actuator") if root.find("actuator") is not None
                                    else [])}
        base = root.find("worldbody/body")
        if base is None or base.find("freejoint") is None:
            raise ValueError("%s: no free-floating body under <worldbody>" % path)
        self.base = base
        self.mass = sum(float(i.get("mass")) for i in base.iter("inertial"))
        for b in base.iter("body"):
            if any(b.get(k) for k in ("quat", "euler", "axisangle", "xyaxes", "zaxis")):
                raise ValueError("%s: body %s is rotated in its parent (not supported)"
                                 % (path, b.get("name")))
        for j in base.iter("joint"):
            if j.get("type", "hinge") != "hinge" or j.get("name") not in self.joint_ids:
                raise ValueError("%s: joint %s is not a hinge with an actuator"
                                 % (path, j.get("name")))

    def forward(self, p_base, R_base, q):
        """CoM (N, 3) and the soles {side: (N, 3)} in the world for the base pose and joints q."""
        com = np.zeros_like(p_base)
        soles = {}
        names = {v: k for k, v in SOLES.items()}
        # depth first: each body's frame from its parent's, its pos, then its joints in order
        stack = [(self.base, p_base, R_base, True)]
        while stack:
            body, p, R, is_base = stack.pop()
            if not is_base:
                p = p + R @ vec(body, "pos", [0, 0, 0])
                for j in body.findall("joint"):
                    angle = q[:, self.joint_ids[j.get("name")]]
                    R = R @ axis_rotations(vec(j, "axis", [0, 0, 1]), angle)
            inertial = body.find("inertial")
            if inertial is not None:
                com += float(inertial.get("mass")) * (p + R @ vec(inertial, "pos", [0, 0, 0]))
            for g in body.findall("geom"):
                if g.get("name") in names:
                    # the centre of the box's bottom face
                    bottom = vec(g, "pos", [0, 0, 0]) - [0, 0, vec(g, "size", [0, 0, 0])[2]]
                    soles[names[g.get("name")]] = p + R @ bottom
            stack.extend((child, p, R, False) for child in body.findall("body"))
        if set(soles) != set(SOLES):
            raise ValueError("%s: sole geoms %s not found" % (self.path, ", ".join(SOLES.values())))
        return com / self.mass, soles


def rpy_matrices(rpy):
    """(N, 3, 3) R = Rz(yaw) Ry(pitch) Rx(roll) of (N, 3) roll, pitch, yaw [rad]."""
    return (axis_rotations([0, 0, 1], rpy[:, 2]) @ axis_rotations([0, 1, 0], rpy[:, 1])
            @ axis_rotations([1, 0, 0], rpy[:, 0]))


def read_recording(prefix, model_path):
    """The recording as a dict of arrays in the world: t, waist (N, 3), zmp (N, 2), com (N, 3),
    left / right soles (N, 3), contact (N, 2) (the first two end effectors' states)."""
    model = Model(model_path)
    data = {}
    t0 = None
    for suffix, width in SUFFIXES.items():
        path = "%s.%s" % (prefix, suffix)
        t, values = read_table(path, len(model.joint_ids) if width is None else width)
        if t0 is not None and (len(t) != len(t0) or np.max(np.abs(t - t0)) > 1e-9):
            raise ValueError("%s: its times differ from %s.pos's" % (path, prefix))
        t0 = t
        data[suffix] = values
    p_waist = data["waist"][:, :3]
    R_waist = rpy_matrices(data["waist"][:, 3:])
    zmp = p_waist + (R_waist @ data["zmp"][:, :, None])[:, :, 0]
    com, soles = model.forward(p_waist, R_waist, data["pos"])
    return {"t": t0, "waist": p_waist, "zmp": zmp[:, :2], "com": com,
            "left": soles["left"], "right": soles["right"],
            "contact": data["optionaldata"][:, :2]}
