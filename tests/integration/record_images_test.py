#!/usr/bin/env python3
"""sim_host --record-images (issue 33 item 5): the cameras' images kept in the run folder.

Runs scenarios/vision_ball.yaml with `--record-images {out}/images` and checks, from the files:
- images.csv indexes both cameras at the camera rate (30 per simulated second: each camera's
  frames 1/30 s apart within one control period), and every file it names exists;
- the PNGs decode (a minimal decoder here: zlib and the five PNG filters) at the camera size,
  8-bit RGB and 16-bit grey;
- the last LeftCamera frame shows the red ball at the image centre (track_ball centred it: the
  scenario's own ball_centred check projects it through the camera independently), and its
  depth there is nearer than the floor around it and within the scene's bounds (0.3-5 m);
- a robot without a camera is refused with exit 2 before anything runs.

Usage: record_images_test.py BIN_DIR SOURCE_DIR OUT_DIR
"""
import csv
import os
import struct
import subprocess
import sys
import zlib

BIN, SRC, OUT = sys.argv[1], sys.argv[2], sys.argv[3]
WIDTH, HEIGHT, RATE, PERIOD = 320, 240, 30.0, 0.005
failures = []


def check(ok, what):
    print(("ok      " if ok else "FAILED  ") + what)
    if not ok:
        failures.append(what)


def read_png(path):
    """(width, height, bit depth, colour type, rows of integers per channel value)"""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    at, idat = 8, b""
    while at < len(data):
        n, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
        elif kind == b"IDAT":
            idat += body
        at += 12 + n
    channels = {0: 1, 2: 3}[colour]
    bpp = channels * depth // 8
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        prev = line
        if depth == 16:
            rows.append(list(struct.unpack(">%dH" % (stride // 2), bytes(line))))
        else:
            rows.append(list(line))
    return w, h, depth, colour, rows


os.makedirs(OUT, exist_ok=True)
with open(os.path.join(SRC, "scenarios", "vision_ball.yaml")) as f:
    text = f.read()
text = text.replace("name: vision_ball", "name: vision_ball_recorded").replace(
    "sim_args: [--camera-size, 320x240]",
    "sim_args: [--camera-size, 320x240, --record-images, \"{out}/images\"]")
scenario = os.path.join(OUT, "vision_ball_recorded.yaml")
with open(scenario, "w") as f:
    f.write(text)
run = os.path.join(OUT, "run")
r = subprocess.run([os.path.join(BIN, "ohrp_run"), "-q", "--no-plot", "--out", run, scenario],
                   capture_output=True, text=True)
check(r.returncode == 0, "the recorded vision run passes (exit %d)%s" % (r.returncode, "" if r.returncode == 0 else "\n" + r.stdout))
images = os.path.join(run, "images")
with open(os.path.join(images, "images.csv")) as f:
    rows = list(csv.DictReader(f))
by_camera = {}
for row in rows:
    by_camera.setdefault(row["camera"], []).append(row)
check(sorted(by_camera) == ["LeftCamera", "RightCamera"], "both cameras recorded: %s" % sorted(by_camera))
duration = 8.0
for cam, frames in by_camera.items():
    times = [float(x["time"]) for x in frames]
    gaps = [b - a for a, b in zip(times, times[1:])]
    check(abs(len(frames) - duration * RATE) <= 2,
          "%s: %d frames in %g s at %g per second" % (cam, len(frames), duration, RATE))
    check(all(abs(g - 1 / RATE) <= PERIOD + 1e-9 for g in gaps),
          "%s: frames %.4f-%.4f s apart (1/%g s within one control period)" % (cam, min(gaps), max(gaps), RATE))
    missing = [x["rgb"] for x in frames if not os.path.isfile(os.path.join(images, x["rgb"]))] + \
              [x["depth"] for x in frames if not os.path.isfile(os.path.join(images, x["depth"]))]
    check(not missing, "%s: every indexed file exists (%d missing)" % (cam, len(missing)))

last = by_camera["LeftCamera"][-1]
w, h, depth, colour, rgb = read_png(os.path.join(images, last["rgb"]))
check((w, h, depth, colour) == (WIDTH, HEIGHT, 8, 2), "RGB: %dx%d, %d bits, colour type %d" % (w, h, depth, colour))
red = [(x, y) for y in range(h) for x in range(w)
       if rgb[y][3 * x] > 150 and rgb[y][3 * x + 1] < 80 and rgb[y][3 * x + 2] < 80]
check(len(red) > 20, "the ball's red pixels in the last frame: %d" % len(red))
if red:
    cx = sum(p[0] for p in red) / len(red)
    cy = sum(p[1] for p in red) / len(red)
    check(abs(cx - (w - 1) / 2) <= 10 and abs(cy - (h - 1) / 2) <= 10,
          "the ball at (%.1f, %.1f) px, the image centre (%.1f, %.1f) within 10 px (rows top-down)"
          % (cx, cy, (w - 1) / 2, (h - 1) / 2))
    w2, h2, depth2, colour2, dmm = read_png(os.path.join(images, last["depth"]))
    check((w2, h2, depth2, colour2) == (WIDTH, HEIGHT, 16, 0), "depth: %dx%d, %d bits, grey" % (w2, h2, depth2))
    ball = sorted(dmm[y][x] for x, y in red)[len(red) // 2] / 1000.0
    row = int(round(cy))
    floor = [dmm[row][x] / 1000.0 for x in range(w) if (x, row) not in set(red) and dmm[row][x] > 0]
    floor_median = sorted(floor)[len(floor) // 2] if floor else 0
    check(0.3 < ball < 5.0, "the ball %.3f m from the camera (within the scene's 0.3-5 m)" % ball)
    check(ball < floor_median, "the ball (%.3f m) nearer than the floor behind it on its row (%.3f m)" % (ball, floor_median))

# a robot without a camera: a hinged arm on a fixed base
nocam = os.path.join(OUT, "arm_without_camera.xml")
with open(nocam, "w") as f:
    f.write('<mujoco model="arm"><worldbody><body name="link"><joint name="j" type="hinge" range="-1 1" '
            'limited="true"/><geom type="capsule" size="0.05" fromto="0 0 0 0.3 0 0"/></body></worldbody>'
            '<actuator><motor name="j" joint="j" gear="1"/></actuator></mujoco>')
r = subprocess.run([os.path.join(BIN, "sim_host"), "--scene", nocam,
                    "--record-images", os.path.join(OUT, "none"), "--segment", "rec_none_%d" % os.getpid(),
                    "--duration", "0.01", "--wait-controller", "0"], capture_output=True, text=True, timeout=60)
check(r.returncode == 2 and "has no camera" in r.stderr,
      "a robot without a camera is refused: exit %d, %s" % (r.returncode, r.stderr.strip()))
print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
