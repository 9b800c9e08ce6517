#!/usr/bin/env python3
"""vrml2mjcf.py - convert an OpenHRP VRML97 humanoid (PROTOs Humanoid / Joint / Segment /
ForceSensor / Gyro / AccelerationSensor / VisionSensor) into a MuJoCo 2.2.2 MJCF file.

How to run (from the repository root, Python 3 standard library only):

    python3 tools/scripts/vrml2mjcf.py \
        ../shared/external/openhrp3-sample/sample1.wrl \
        -o mjcf/hrp1s/hrp1s.xml --source-label openhrp3-sample/sample1.wrl

    (the default output is stdout; the diagnostics go to stderr)

What it does
  * tokenises and parses the VRML97 node tree, including PROTO interface declarations (their
    field defaults are applied, e.g. Joint.jointAxis = 0 0 1, VisionSensor.fieldOfView =
    0.785398), DEF/USE sharing, MF lists, comments; ROUTEs and PROTO bodies are skipped;
  * every Joint becomes a <body> named after the Joint's DEF name (OpenHRP's link name); the
    body frame is the composition of all Transform/Joint translation+rotation (axis-angle,
    also `center`) between the parent Joint and this Joint; jointType free -> <freejoint>,
    rotate -> hinge, slide -> slide, fixed -> no joint; jointAxis (vector or "X"/"Y"/"Z") is
    expressed in the Joint's own frame, as in OpenHRP;
  * Segment mass/centerOfMass/momentsOfInertia (the inertia tensor about the CoM in the
    segment frame, OpenHRP's convention) become <inertial>; segments under rotated
    Transforms are rotated (R I R^T) and several segments of one link are merged with the
    parallel-axis theorem; diaginertia if the tensor is diagonal, fullinertia otherwise;
  * Shapes (Box, Cylinder, Sphere) below Segments/Transforms/sensors become visual geoms;
    VRML cylinders run along their local Y, MuJoCo's along Z, so an extra -90 deg rotation
    about X is appended; the lowest Box of each configured foot link becomes the collision
    sole (see SOLES); every other geom collides with nothing;
  * armature = rotorInertia * gearRatio^2; range = [llimit, ulimit] (or MISSING_LIMITS);
  * ForceSensor -> site + <force>/<torque> ("<name>_f", "<name>_t"); Gyro and
    AccelerationSensor -> one site "imu" + <gyro>/<accelerometer>/<framequat>;
    VisionSensor -> <camera> (both look along their -Z, fovy converted to degrees);
  * one <motor> per jointId (in jointId order), jointpos/jointvel/actuatorfrc sensors;
  * computes the root height so that the soles touch z=0 (forward kinematics of the box
    corners) for the zero pose and for the half-sitting pose, and writes both keyframes.

The robot-specific choices (torque limits, missing joint ranges, sole links, sensor order,
half-sitting pose) are the tables below; mjcf/hrp1s/README.md explains them.
"""

import argparse
import math
import re
import sys

# ----------------------------------------------------------------------------------------
# robot-specific tables (SampleRobot / HRP-1S class). Patterns are matched with re.fullmatch
# against the joint name, first match wins.

# torque limit per joint [N m] (assumption, see mjcf/hrp1s/README.md)
TORQUE_LIMITS = [
    (r"[RL]LEG_HIP_R", 400.0),
    (r"[RL]LEG_HIP_P", 400.0),
    (r"[RL]LEG_HIP_Y", 300.0),
    (r"[RL]LEG_KNEE", 500.0),
    (r"[RL]LEG_ANKLE_P", 400.0),
    (r"[RL]LEG_ANKLE_R", 300.0),
    (r"[RL]ARM_SHOULDER_[PR]", 200.0),
    (r"[RL]ARM_SHOULDER_Y", 100.0),
    (r"[RL]ARM_ELBOW", 150.0),
    (r"[RL]ARM_WRIST_[YPR]", 100.0),
    (r"WAIST_[PR]", 400.0),
    (r"CHEST", 300.0),
]

# ranges for joints where the VRML gives no llimit/ulimit [rad] (assumption, see README)
MISSING_LIMITS = [
    (r"[RL]LEG_HIP_R", (-0.6109, 0.6109)),      # +-35 deg
    (r"[RL]LEG_HIP_P", (-2.0944, 0.7854)),      # -120 .. +45 deg
    (r"[RL]LEG_HIP_Y", (-0.7854, 0.7854)),      # +-45 deg
    (r"[RL]LEG_KNEE", (-0.0873, 2.6180)),       # -5 .. +150 deg
    (r"[RL]LEG_ANKLE_P", (-1.3090, 0.7854)),    # -75 .. +45 deg
    (r"[RL]LEG_ANKLE_R", (-0.6109, 0.6109)),    # +-35 deg
    (r"WAIST_P", (-0.5236, 1.0472)),            # -30 .. +60 deg
    (r"WAIST_R", (-0.5236, 0.5236)),            # +-30 deg
    (r"CHEST", (-1.5708, 1.5708)),              # +-90 deg
]
FALLBACK_LIMIT = (-math.pi, math.pi)

# foot link (body = Joint name) -> name of its sole box geom (lowest Box in that link)
SOLES = [("RLEG_ANKLE_R", "RLEG_SOLE"), ("LLEG_ANKLE_R", "LLEG_SOLE")]

# force sensors first in this order, the rest by sensorId
FORCE_SENSOR_ORDER = ["rfsensor", "lfsensor", "rhsensor", "lhsensor"]

# half-sitting pose [rad], joints not listed are 0
HALFSIT = [
    (r"[RL]LEG_HIP_P", -0.35),
    (r"[RL]LEG_KNEE", 0.70),
    (r"[RL]LEG_ANKLE_P", -0.35),
    (r"[RL]ARM_SHOULDER_P", 0.17),
    (r"RARM_SHOULDER_R", -0.17),
    (r"LARM_SHOULDER_R", 0.17),
    (r"[RL]ARM_ELBOW", -0.52),
]

JOINT_DAMPING = 0.1
SOLE_FRICTION = "1 0.005 0.0001"


def lookup(table, name, default=None):
    for pat, val in table:
        if re.fullmatch(pat, name):
            return val
    return default


# ----------------------------------------------------------------------------------------
# small rigid-body math: quaternions are (w, x, y, z), poses are (pos, quat)

def qmul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def qnorm(q):
    n = math.sqrt(sum(c * c for c in q))
    return tuple(c / n for c in q)


def axisangle2quat(axis, angle):
    n = math.sqrt(sum(c * c for c in axis))
    if n < 1e-12 or abs(angle) < 1e-15:
        return (1.0, 0.0, 0.0, 0.0)
    s = math.sin(angle / 2) / n
    return qnorm((math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s))


def qrot(q, v):
    w, x, y, z = q
    vq = (0.0, v[0], v[1], v[2])
    r = qmul(qmul(q, vq), (w, -x, -y, -z))
    return (r[1], r[2], r[3])


def quat2mat(q):
    w, x, y, z = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def vadd(a, b):
    return tuple(x + y for x, y in zip(a, b))


def vsub(a, b):
    return tuple(x - y for x, y in zip(a, b))


IDENT = ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0))


def compose(p1, p2):
    """pose p2 expressed in frame p1 -> pose in p1's parent frame"""
    return (vadd(p1[0], qrot(p1[1], p2[0])), qnorm(qmul(p1[1], p2[1])))


def transform_pose(fields):
    """VRML Transform: T(translation) T(center) R(rotation) T(-center); scale must be 1"""
    t = tuple(fields.get("translation", (0, 0, 0)))
    c = tuple(fields.get("center", (0, 0, 0)))
    r = fields.get("rotation", (0, 0, 1, 0))
    s = fields.get("scale", (1, 1, 1))
    if any(abs(x - 1) > 1e-9 for x in s):
        warn("Transform scale %s ignored" % (s,))
    q = axisangle2quat(r[:3], r[3])
    pos = vadd(vadd(t, c), qrot(q, tuple(-x for x in c)))
    return (pos, q)


def warn(msg):
    print("vrml2mjcf: warning: " + msg, file=sys.stderr)


# ----------------------------------------------------------------------------------------
# VRML97 tokenizer and parser

TOKEN_RE = re.compile(r'''
    (?P<ws>[\s,]+) |
    (?P<comment>\#[^\n]*) |
    (?P<string>"(?:[^"\\]|\\.)*") |
    (?P<punct>[\[\]{}]) |
    (?P<word>[^\s,\[\]{}"\#]+)
''', re.VERBOSE)
NUMBER_RE = re.compile(r'[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$|0[xX][0-9a-fA-F]+$')


class Tok:
    __slots__ = ("kind", "val", "line")

    def __init__(self, kind, val, line):
        self.kind, self.val, self.line = kind, val, line


def tokenize(text):
    toks = []
    line = 1
    pos = 0
    while pos < len(text):
        m = TOKEN_RE.match(text, pos)
        if not m:
            raise SyntaxError("line %d: cannot tokenize %r" % (line, text[pos:pos + 20]))
        kind = m.lastgroup
        s = m.group(kind)
        if kind == "string":
            toks.append(Tok("str", bytes(s[1:-1], "utf-8").decode("unicode_escape"), line))
        elif kind == "punct":
            toks.append(Tok(s, s, line))
        elif kind == "word":
            if NUMBER_RE.match(s):
                toks.append(Tok("num", float(int(s, 16)) if s[:2] in ("0x", "0X") else float(s),
                                line))
            else:
                toks.append(Tok("id", s, line))
        line += s.count("\n")
        pos = m.end()
    return toks


class Node:
    def __init__(self, ntype, defname, fields):
        self.type, self.defname, self.fields = ntype, defname, fields

    def get(self, key, default=None):
        return self.fields.get(key, default)

    def __repr__(self):
        return "<%s %s>" % (self.type, self.defname or "")


# defaults of the standard VRML97 nodes the converter interprets
BUILTIN_DEFAULTS = {
    "Transform": {"translation": [0, 0, 0], "rotation": [0, 0, 1, 0], "scale": [1, 1, 1],
                  "center": [0, 0, 0], "children": []},
    "Group": {"children": []},
    "Box": {"size": [2, 2, 2]},
    "Cylinder": {"radius": [1], "height": [2]},
    "Sphere": {"radius": [1]},
    "Material": {"diffuseColor": [0.8, 0.8, 0.8], "transparency": [0]},
}


class Parser:
    def __init__(self, text):
        self.toks = tokenize(text)
        self.i = 0
        self.defs = {}
        self.protos = {}     # name -> {field: default value}

    def peek(self, k=0):
        j = self.i + k
        return self.toks[j] if j < len(self.toks) else None

    def next(self):
        t = self.peek()
        if t is None:
            raise SyntaxError("unexpected end of file")
        self.i += 1
        return t

    def expect(self, kind):
        t = self.next()
        if t.kind != kind:
            raise SyntaxError("line %d: expected %s, got %r" % (t.line, kind, t.val))
        return t

    def skip_balanced(self, open_kind, close_kind):
        self.expect(open_kind)
        depth = 1
        while depth:
            t = self.next()
            if t.kind == open_kind:
                depth += 1
            elif t.kind == close_kind:
                depth -= 1

    def parse_file(self):
        roots = []
        while self.peek() is not None:
            t = self.peek()
            if t.kind == "id" and t.val == "PROTO":
                self.parse_proto()
            elif t.kind == "id" and t.val == "EXTERNPROTO":
                self.next()
                name = self.expect("id").val
                self.skip_balanced("[", "]")
                self.parse_value()   # url
                warn("EXTERNPROTO %s not interpreted" % name)
            elif t.kind == "id" and t.val == "ROUTE":
                self.i += 4
            else:
                roots.append(self.parse_node())
        return roots

    def parse_proto(self):
        self.next()
        name = self.expect("id").val
        self.expect("[")
        defaults = {}
        while self.peek().kind != "]":
            kind = self.expect("id").val
            self.expect("id")              # field type
            fname = self.expect("id").val
            if kind in ("field", "exposedField"):
                defaults[fname] = self.parse_value()
        self.expect("]")
        self.skip_balanced("{", "}")       # the body is interpreted by type name instead
        self.protos[name] = defaults

    def parse_node(self):
        t = self.next()
        defname = None
        if t.kind == "id" and t.val == "USE":
            name = self.expect("id").val
            if name not in self.defs:
                raise SyntaxError("line %d: USE of undefined %s" % (t.line, name))
            return self.defs[name]
        if t.kind == "id" and t.val == "NULL":
            return None
        if t.kind == "id" and t.val == "DEF":
            defname = self.expect("id").val
            t = self.next()
        if t.kind != "id":
            raise SyntaxError("line %d: expected a node type, got %r" % (t.line, t.val))
        ntype = t.val
        fields = dict(BUILTIN_DEFAULTS.get(ntype, {}))
        fields.update(self.protos.get(ntype, {}))
        node = Node(ntype, defname, fields)
        if defname:
            self.defs[defname] = node      # a later DEF of the same name wins, as in VRML
        self.expect("{")
        while self.peek().kind != "}":
            ft = self.next()
            if ft.kind != "id":
                raise SyntaxError("line %d: expected a field name, got %r" % (ft.line, ft.val))
            if ft.val == "ROUTE":
                self.i += 3
                continue
            fields[ft.val] = self.parse_value()
        self.expect("}")
        return node

    def parse_value(self):
        t = self.peek()
        if t.kind == "[":
            self.next()
            out = []
            while self.peek().kind != "]":
                v = self.parse_single()
                if isinstance(v, list):
                    out.extend(v)
                else:
                    out.append(v)
            self.next()
            return out
        return self.parse_single()

    def parse_single(self):
        t = self.peek()
        if t.kind == "num":
            nums = []
            while self.peek() is not None and self.peek().kind == "num":
                nums.append(self.next().val)
            return nums
        if t.kind == "str":
            return self.next().val
        if t.kind == "id" and t.val in ("TRUE", "FALSE"):
            return self.next().val == "TRUE"
        if t.kind == "id":
            return self.parse_node()
        raise SyntaxError("line %d: unexpected %r" % (t.line, t.val))


# ----------------------------------------------------------------------------------------
# model building

class Body:
    def __init__(self, name, pose, joint):
        self.name = name
        self.pose = pose           # in the parent body frame
        self.joint = joint         # dict or None
        self.segments = []         # (mass, com, I3x3) in body frame
        self.geoms = []            # dicts
        self.sites = []            # dicts
        self.cameras = []          # dicts
        self.children = []


def kids(fields):
    """children as a list: an SFNode-style single child is allowed (children USE X)"""
    c = fields.get("children", [])
    if c is None:
        return []
    return c if isinstance(c, list) else [c]


def num(fields, key, default=0.0):
    v = fields.get(key)
    if v is None or v == []:
        return default
    return v[0] if isinstance(v, list) else v


def vec(fields, key, n, default):
    v = fields.get(key)
    if not isinstance(v, list) or len(v) < n:
        return tuple(default)
    return tuple(v[:n])


def joint_axis(fields):
    a = fields.get("jointAxis", [0, 0, 1])
    if isinstance(a, str):   # older dialect: "X", "Y", "Z"
        return {"X": (1, 0, 0), "Y": (0, 1, 0), "Z": (0, 0, 1)}[a.strip().upper()]
    return tuple(a[:3])


def material_rgba(shape):
    app = shape.get("appearance")
    if not isinstance(app, Node):
        return None
    mat = app.get("material")
    if not isinstance(mat, Node):
        return None
    c = vec(mat.fields, "diffuseColor", 3, (0.8, 0.8, 0.8))
    a = 1.0 - num(mat.fields, "transparency", 0.0)
    return tuple(c) + (a,)


CYL_FIX = axisangle2quat((1, 0, 0), -math.pi / 2)   # MuJoCo Z onto VRML Y


class Converter:
    def __init__(self):
        self.bodies = []
        self.joints = {}          # jointId -> body

    def convert_root(self, node, pose):
        return self.visit_joint(node, pose, None)

    def visit_joint(self, node, pose_in_parent, parent):
        f = node.fields
        name = node.defname or f.get("name") or "joint%d" % len(self.bodies)
        jtype = f.get("jointType", "")
        pose = compose(pose_in_parent, transform_pose(f))
        joint = None
        if jtype in ("rotate", "slide"):
            jid = int(num(f, "jointId", -1))
            lo = f.get("llimit") or []
            hi = f.get("ulimit") or []
            joint = {
                "name": name,
                "type": "hinge" if jtype == "rotate" else "slide",
                "axis": joint_axis(f),
                "id": jid,
                "range": (lo[0], hi[0]) if lo and hi else None,
                "armature": num(f, "rotorInertia", 0.0) * num(f, "gearRatio", 1.0) ** 2,
            }
            if jid >= 0:
                if jid in self.joints:
                    raise ValueError("duplicate jointId %d" % jid)
                self.joints[jid] = joint
        elif jtype == "free":
            joint = {"name": name, "type": "free"}
        elif jtype not in ("fixed", ""):
            raise ValueError("unsupported jointType %r of %s" % (jtype, name))
        body = Body(name, pose, joint)
        self.bodies.append(body)
        if parent is not None:
            parent.children.append(body)
        for child in kids(f):
            self.visit(child, IDENT, body)
        return body

    def visit(self, node, pose, body):
        """pose = frame of `node`'s parent relative to `body`"""
        if node is None:
            return
        t, f = node.type, node.fields
        if t == "Joint":
            self.visit_joint(node, pose, body)
        elif t == "Segment":
            m = num(f, "mass", 0.0)
            com = vec(f, "centerOfMass", 3, (0, 0, 0))
            I = list(f.get("momentsOfInertia", [0] * 9))
            if len(I) != 9:
                raise ValueError("momentsOfInertia of %s needs 9 numbers" % node.defname)
            I = [I[0:3], I[3:6], I[6:9]]
            R = quat2mat(pose[1])
            IR = [[sum(R[i][k] * I[k][l] * R[j][l] for k in range(3) for l in range(3))
                   for j in range(3)] for i in range(3)]
            body.segments.append((m, vadd(pose[0], qrot(pose[1], com)), IR, node.defname))
            for child in kids(f):
                self.visit(child, pose, body)
        elif t in ("Transform", "Group", "Collision", "Anchor", "Billboard"):
            p = compose(pose, transform_pose(f)) if t == "Transform" else pose
            for child in kids(f):
                self.visit(child, p, body)
        elif t == "Shape":
            self.shape(node, pose, body)
        elif t == "ForceSensor":
            p = compose(pose, transform_pose(f))
            body.sites.append({"kind": "force", "name": node.defname, "pose": p,
                               "id": int(num(f, "sensorId", -1))})
        elif t in ("Gyro", "AccelerationSensor"):
            p = compose(pose, transform_pose(f))
            body.sites.append({"kind": "gyro" if t == "Gyro" else "accel",
                               "name": node.defname, "pose": p,
                               "id": int(num(f, "sensorId", -1))})
        elif t == "VisionSensor":
            p = compose(pose, transform_pose(f))
            body.cameras.append({"name": f.get("name") or node.defname, "pose": p,
                                 "fov": num(f, "fieldOfView", 0.785398),
                                 "near": num(f, "frontClipDistance", 0.01),
                                 "id": int(num(f, "sensorId", -1))})
            for child in kids(f):
                self.visit(child, p, body)
        elif t in ("Appearance", "Material", "Viewpoint", "NavigationInfo", "Background",
                   "DirectionalLight", "PointLight", "SpotLight"):
            pass
        else:
            warn("node type %s (%s) ignored" % (t, node.defname))

    def shape(self, node, pose, body):
        g = node.get("geometry")
        if not isinstance(g, Node):
            return
        rgba = material_rgba(node)
        gf = g.fields
        if g.type == "Box":
            s = vec(gf, "size", 3, (2, 2, 2))
            geom = {"type": "box", "size": tuple(x / 2 for x in s), "pose": pose}
        elif g.type == "Cylinder":
            geom = {"type": "cylinder",
                    "size": (num(gf, "radius", 1.0), num(gf, "height", 2.0) / 2),
                    "pose": (pose[0], qnorm(qmul(pose[1], CYL_FIX)))}
        elif g.type == "Sphere":
            geom = {"type": "sphere", "size": (num(gf, "radius", 1.0),), "pose": pose}
        else:
            warn("geometry %s in %s ignored" % (g.type, body.name))
            return
        geom["rgba"] = rgba
        body.geoms.append(geom)


def merged_inertia(segments):
    """total mass, CoM and 3x3 inertia about the CoM of several segments (body frame)"""
    M = sum(s[0] for s in segments)
    if M <= 0:
        return 0.0, (0, 0, 0), [[0] * 3 for _ in range(3)]
    c = tuple(sum(s[0] * s[1][k] for s in segments) / M for k in range(3))
    I = [[0.0] * 3 for _ in range(3)]
    for m, p, Is, _ in segments:
        d = vsub(p, c)
        dd = sum(x * x for x in d)
        for i in range(3):
            for j in range(3):
                I[i][j] += Is[i][j] + m * ((dd if i == j else 0.0) - d[i] * d[j])
    return M, c, I


# ----------------------------------------------------------------------------------------
# forward kinematics (for the root height that puts the soles on z=0)

def lowest_box_z(geom, world_pose):
    p = compose(world_pose, geom["pose"])
    R = quat2mat(p[1])
    return p[0][2] - sum(abs(R[2][k]) * geom["size"][k] for k in range(3))


def sole_bottoms(root, qmap):
    """{sole name: lowest z} with the root body at the origin (identity orientation)"""
    out = {}

    def rec(body, world):
        j = body.joint
        if j and j["type"] == "hinge":
            world = compose(world, ((0, 0, 0), axisangle2quat(j["axis"], qmap.get(j["name"], 0))))
        elif j and j["type"] == "slide":
            a = j["axis"]
            q = qmap.get(j["name"], 0)
            world = compose(world, ((a[0] * q, a[1] * q, a[2] * q), (1, 0, 0, 0)))
        for g in body.geoms:
            if g.get("name"):
                out[g["name"]] = lowest_box_z(g, world)
        for c in body.children:
            rec(c, compose(world, c.pose))

    rec(root, ((0, 0, 0), (1, 0, 0, 0)))
    return out


# ----------------------------------------------------------------------------------------
# MJCF writer

def fmt(x):
    if abs(x) < 1e-12:
        return "0"
    s = "%.9g" % x
    return s


def fv(v):
    return " ".join(fmt(x) for x in v)


def quat_attr(q):
    if abs(q[0] - 1) < 1e-12:
        return ""
    if q[0] < 0:
        q = tuple(-x for x in q)
    return ' quat="%s"' % fv(q)


def pos_attr(p):
    if all(abs(x) < 1e-12 for x in p):
        return ""
    return ' pos="%s"' % fv(p)


def write_mjcf(conv, root, args, out):
    jids = sorted(conv.joints)
    if jids != list(range(len(jids))):
        raise ValueError("jointIds are not 0..n-1: %s" % jids)
    joints = [conv.joints[i] for i in jids]

    # name the soles
    sole_of = dict(SOLES)
    for b in conv.bodies:
        if b.name in sole_of:
            boxes = [g for g in b.geoms if g["type"] == "box"]
            if not boxes:
                raise ValueError("foot link %s has no Box" % b.name)
            low = min(boxes, key=lambda g: lowest_box_z(g, IDENT))
            low["name"] = sole_of[b.name]
    missing = set(sole_of) - {b.name for b in conv.bodies}
    if missing:
        raise ValueError("foot links not found: %s" % sorted(missing))

    # root heights
    init_soles = sole_bottoms(root, {})
    z_init = -min(init_soles.values()) + args.clearance
    half = {j["name"]: lookup(HALFSIT, j["name"], 0.0) for j in joints}
    half_soles = sole_bottoms(root, half)
    z_half = -min(half_soles.values()) + args.clearance
    for name, tab in (("init", init_soles), ("halfsit", half_soles)):
        spread = max(tab.values()) - min(tab.values())
        if spread > 1e-6:
            warn("%s: soles not level (spread %.6f m)" % (name, spread))
    vrml_z = root.pose[0][2]
    print("vrml2mjcf: root z: VRML %.6f, init %.6f, halfsit %.6f" % (vrml_z, z_init, z_half),
          file=sys.stderr)

    total = sum(s[0] for b in conv.bodies for s in b.segments)
    print("vrml2mjcf: %d bodies, %d joints, total mass %.6f kg"
          % (len(conv.bodies), len(joints), total), file=sys.stderr)

    W = out.write
    W('<?xml version="1.0" encoding="utf-8"?>\n')
    W("<!-- GENERATED by tools/scripts/vrml2mjcf.py from %s: do not edit by hand,\n"
      "     change the converter (or its tables) and regenerate. See mjcf/hrp1s/README.md. -->\n"
      % args.source_label)
    W('<mujoco model="%s">\n' % args.model)
    W('  <compiler angle="radian"/>\n')
    W('  <option timestep="0.001" integrator="Euler"/>\n\n')
    W("  <default>\n")
    W('    <default class="%s_visual">\n' % args.model)
    W('      <geom contype="0" conaffinity="0" group="1"/>\n')
    W("    </default>\n")
    W('    <default class="%s_sole">\n' % args.model)
    W('      <geom contype="1" conaffinity="1" group="0" condim="3" friction="%s"/>\n'
      % SOLE_FRICTION)
    W("    </default>\n")
    W("  </default>\n\n")
    W("  <worldbody>\n")

    def write_body(b, depth, is_root):
        ind = "  " * depth
        pos = b.pose[0]
        if is_root:
            pos = (pos[0], pos[1], z_init)
        W('%s<body name="%s"%s%s>\n' % (ind, b.name, pos_attr(pos), quat_attr(b.pose[1])))
        ind2 = ind + "  "
        j = b.joint
        if j and j["type"] == "free":
            W('%s<freejoint name="%s"/>\n' % (ind2, args.root_joint))
        elif j:
            rng = j["range"]
            note = ""
            if rng is None:
                rng = lookup(MISSING_LIMITS, j["name"], FALLBACK_LIMIT)
                note = "  <!-- range not in VRML: assumed -->"
            W('%s<joint name="%s" type="%s" axis="%s" limited="true" range="%s %s" '
              'armature="%s" damping="%s"/>%s\n'
              % (ind2, j["name"], j["type"], fv(j["axis"]), fmt(rng[0]), fmt(rng[1]),
                 fmt(j["armature"]), fmt(JOINT_DAMPING), note))
        if b.segments:
            M, c, I = merged_inertia(b.segments)
            segs = ", ".join(s[3] or "?" for s in b.segments)
            off = max(abs(I[0][1]), abs(I[0][2]), abs(I[1][2]))
            if off < 1e-12:
                inert = 'diaginertia="%s"' % fv((I[0][0], I[1][1], I[2][2]))
            else:
                inert = 'fullinertia="%s"' % fv((I[0][0], I[1][1], I[2][2],
                                                 I[0][1], I[0][2], I[1][2]))
            W('%s<inertial pos="%s" mass="%s" %s/>  <!-- Segment %s -->\n'
              % (ind2, fv(c), fmt(M), inert, segs))
        for g in b.geoms:
            cls = "%s_sole" % args.model if g.get("name") else "%s_visual" % args.model
            name = ' name="%s"' % g["name"] if g.get("name") else ""
            rgba = ' rgba="%s"' % fv(g["rgba"]) if g.get("rgba") else ""
            W('%s<geom%s class="%s" type="%s" size="%s"%s%s%s/>\n'
              % (ind2, name, cls, g["type"], fv(g["size"]), pos_attr(g["pose"][0]),
                 quat_attr(g["pose"][1]), rgba))
        imu_written = False
        for s in b.sites:
            if s["kind"] == "force":
                W('%s<site name="%s" size="0.01"%s%s rgba="1 0.5 0 1"/>  '
                  '<!-- ForceSensor sensorId %d -->\n'
                  % (ind2, s["name"], pos_attr(s["pose"][0]), quat_attr(s["pose"][1]), s["id"]))
            elif not imu_written:
                q = s["pose"][1] if args.keep_imu_rotation else (1, 0, 0, 0)
                W('%s<site name="%s" size="0.01"%s%s rgba="0 0.5 1 1"/>  '
                  '<!-- Gyro/AccelerationSensor position; VRML rotation %s -->\n'
                  % (ind2, args.imu_site, pos_attr(s["pose"][0]), quat_attr(q),
                     "kept" if args.keep_imu_rotation else "dropped (see README)"))
                imu_written = True
        for cam in b.cameras:
            W('%s<camera name="%s"%s%s fovy="%s"/>  <!-- VisionSensor sensorId %d, '
              'fieldOfView %s rad -->\n'
              % (ind2, cam["name"], pos_attr(cam["pose"][0]), quat_attr(cam["pose"][1]),
                 fmt(math.degrees(cam["fov"])), cam["id"], fmt(cam["fov"])))
        for c in b.children:
            write_body(c, depth + 1, False)
        W("%s</body>\n" % ind)

    write_body(root, 2, True)
    W("  </worldbody>\n\n")

    # the two soles must not collide with each other
    soles = [b for b in conv.bodies if b.name in sole_of]
    W("  <contact>\n")
    for i in range(len(soles)):
        for k in range(i + 1, len(soles)):
            W('    <exclude body1="%s" body2="%s"/>\n' % (soles[i].name, soles[k].name))
    W("  </contact>\n\n")

    W("  <!-- actuator i drives the joint with VRML jointId i: this is the platform's joint order -->\n")
    W("  <actuator>\n")
    for j in joints:
        tl = lookup(TORQUE_LIMITS, j["name"])
        if tl is None:
            raise ValueError("no torque limit for %s" % j["name"])
        W('    <motor name="%s" joint="%s" gear="1" ctrllimited="true" ctrlrange="%s %s" '
          'forcelimited="true" forcerange="%s %s"/>  <!-- jointId %d -->\n'
          % (j["name"], j["name"], fmt(-tl), fmt(tl), fmt(-tl), fmt(tl), j["id"]))
    W("  </actuator>\n\n")

    W("  <sensor>\n")
    for j in joints:
        W('    <jointpos name="q_%s" joint="%s"/>\n' % (j["name"], j["name"]))
    for j in joints:
        W('    <jointvel name="dq_%s" joint="%s"/>\n' % (j["name"], j["name"]))
    for j in joints:
        W('    <actuatorfrc name="tau_%s" actuator="%s"/>\n' % (j["name"], j["name"]))
    fsites = [s for b in conv.bodies for s in b.sites if s["kind"] == "force"]
    order = {n: i for i, n in enumerate(FORCE_SENSOR_ORDER)}
    fsites.sort(key=lambda s: (order.get(s["name"], len(order)), s["id"]))
    for s in fsites:
        W('    <force name="%s_f" site="%s"/>\n' % (s["name"], s["name"]))
        W('    <torque name="%s_t" site="%s"/>\n' % (s["name"], s["name"]))
    imu = [s for b in conv.bodies for s in b.sites if s["kind"] in ("gyro", "accel")]
    for s in imu:
        if s["kind"] == "gyro":
            W('    <gyro name="%s" site="%s"/>\n' % (s["name"], args.imu_site))
    for s in imu:
        if s["kind"] == "accel":
            W('    <accelerometer name="%s" site="%s"/>\n' % (s["name"], args.imu_site))
    if imu:
        W('    <framequat name="%s_quat" objtype="site" objname="%s"/>\n'
          % (args.imu_site, args.imu_site))
    W("  </sensor>\n\n")

    # qpos follows the kinematic tree (depth-first, as the bodies are written), NOT jointId
    tree_order = []

    def dfs(b):
        if b.joint and b.joint["type"] in ("hinge", "slide"):
            tree_order.append(b.joint["name"])
        for c in b.children:
            dfs(c)

    dfs(root)

    def key(name, z, qmap):
        qpos = [0.0, 0.0, z, 1.0, 0.0, 0.0, 0.0] + [qmap.get(n, 0.0) for n in tree_order]
        return '    <key name="%s" qpos="%s"/>\n' % (name, fv(qpos))

    W("  <!-- qpos = root x y z, root quat w x y z, then the hinges in TREE order (not jointId!):\n"
      "       %s;\n" % " ".join(tree_order))
    W("       z puts the sole bottoms on z=0 (clearance %s m) -->\n" % fmt(args.clearance))
    W("  <keyframe>\n")
    W(key("init", z_init, {}))
    W(key("halfsit", z_half, half))
    W("  </keyframe>\n")
    W("</mujoco>\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("wrl", help="OpenHRP VRML97 model (e.g. sample1.wrl)")
    ap.add_argument("-o", "--output", help="MJCF file to write (default stdout)")
    ap.add_argument("--model", default="hrp1s", help="MJCF model name / class prefix")
    ap.add_argument("--source-label", help="how the header comment names the input file")
    ap.add_argument("--root-joint", default="root", help="name of the free joint")
    ap.add_argument("--imu-site", default="imu", help="name of the IMU site")
    ap.add_argument("--keep-imu-rotation", action="store_true",
                    help="keep the VRML Gyro/AccelerationSensor rotation on the IMU site")
    ap.add_argument("--clearance", type=float, default=0.0,
                    help="height of the sole bottoms above z=0 in the keyframes [m]")
    args = ap.parse_args()
    if not args.source_label:
        args.source_label = args.wrl

    with open(args.wrl, encoding="utf-8", errors="replace") as fh:
        text = fh.read()
    parser = Parser(text)
    roots = parser.parse_file()

    conv = Converter()
    root = None
    for node in roots:
        if node is None:
            continue
        if node.type == "Humanoid":
            hpose = transform_pose(node.fields)
            for b in node.get("humanoidBody", []):
                if isinstance(b, Node) and b.type == "Joint":
                    if root is not None:
                        raise ValueError("more than one root Joint")
                    root = conv.convert_root(b, hpose)
        elif node.type == "Joint" and root is None:
            root = conv.convert_root(node, IDENT)
    if root is None:
        raise ValueError("no Humanoid/Joint found")

    if args.output:
        with open(args.output, "w", encoding="utf-8") as out:
            write_mjcf(conv, root, args, out)
    else:
        write_mjcf(conv, root, args, sys.stdout)


if __name__ == "__main__":
    main()
