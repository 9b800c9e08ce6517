#!/usr/bin/env python3
"""Tests tools/scripts/plot_walk.py and the walk panels of plot_run.py on a synthetic walk.csv.

Usage: plot_walk_test.py SCRIPTS_DIR OUT_DIR. The synthetic walk: standing 0.8 s on soles at
y = +-0.09 m, then four steps of 0.2 m forward (0.8 s each, the first 0.16 s of each on both
feet), then 0.8 s on both feet; the ZMP reference at the stance sole, the CoM a smoothed copy,
the measured ZMP the reference plus a 1 cm wobble. Its landings and single-support phases are
known; both scripts must write a PNG, plot_run.py a taller one with the walk, and a walk.csv
without its columns must be refused by name.
"""
import json
import math
import os
import subprocess
import sys
import unittest

SCRIPTS, OUT = sys.argv[1], sys.argv[2]
sys.path.insert(0, SCRIPTS)
import plot_walk  # noqa: E402

DT = 0.005        # [s] control cycle
STEP = 0.8        # [s] per step
DS = 0.16         # [s] double support at the start of a step
STRIDE = 0.2      # [m] the swing foot lands STRIDE ahead of the other
HALF_WIDTH = 0.09  # [m]
STEPS = 4
PNG = b"\x89PNG\r\n\x1a\n"


def plan(t):
    """(left (x, y), right (x, y), support_left, support_right, ZMP reference (x, y)) at t."""
    left, right = [0.0, HALF_WIDTH], [0.0, -HALF_WIDTH]
    k = int((t - STEP) // STEP) if t >= STEP else -1
    for j in range(min(k, STEPS - 1) + 1):   # steps before, and the one under way, land at their end
        foot = right if j % 2 == 0 else left  # the right foot swings first
        if j < k or t >= STEP * (j + 2):
            foot[0] = STRIDE * (j + 1)
    if 0 <= k < STEPS and t - STEP * (k + 1) >= DS:
        swing_left = k % 2 == 1
        stance = right if swing_left else left
        return left, right, 0 if swing_left else 1, 1 if swing_left else 0, stance
    return left, right, 1, 1, [(left[0] + right[0]) / 2, 0.0]


def write_walk(path, columns=plot_walk.COLUMNS):
    rows = int(round((STEP * (STEPS + 2)) / DT)) + 1
    com = [0.0, 0.0]
    with open(path, "w") as f:
        f.write(",".join(columns) + "\n")
        for i in range(rows):
            t = i * DT
            left, right, sl, sr, zmp = plan(t)
            com = [c + 0.05 * (z - c) for c, z in zip(com, zmp)]
            wob = 0.01 * math.sin(40 * t)
            v = {"t": t, "com_ref_x": com[0], "com_ref_y": com[1], "com_ref_z": 0.6,
                 "com_x": com[0] + 0.3 * wob, "com_y": com[1], "com_z": 0.6,
                 "zmp_ref_x": zmp[0], "zmp_ref_y": zmp[1], "zmp_des_x": zmp[0] + 0.5 * wob,
                 "zmp_des_y": zmp[1], "zmp_x": zmp[0] + wob, "zmp_y": zmp[1] - wob,
                 "dcm_x": com[0], "dcm_y": com[1], "left_x": left[0], "left_y": left[1],
                 "left_z": 0.0, "left_yaw": 0.0, "right_x": right[0], "right_y": right[1],
                 "right_z": 0.0, "right_yaw": 0.0, "support_left": sl, "support_right": sr}
            f.write(",".join("%.9g" % v[c] for c in columns) + "\n")


def png_height(path):
    """Height in pixels from the PNG's IHDR chunk."""
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == PNG, path + " is not a PNG"
    return int.from_bytes(head[20:24], "big")


def run(*args):
    return subprocess.run([sys.executable] + list(args), capture_output=True, text=True)


class PlotWalk(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        os.makedirs(OUT, exist_ok=True)
        cls.walk_csv = os.path.join(OUT, "walk.csv")
        write_walk(cls.walk_csv)
        cls.walk = plot_walk.read_walk(cls.walk_csv)

    def test_landings_are_the_start_and_each_touchdown(self):
        left = plot_walk.landings(self.walk, "left")
        right = plot_walk.landings(self.walk, "right")
        # right lands at 0.2 and 0.6 m, left at 0.4 and 0.8 m, after each stands at 0
        self.assertEqual([round(x, 9) for x, _, _ in right], [0.0, 0.2, 0.6])
        self.assertEqual([round(x, 9) for x, _, _ in left], [0.0, 0.4, 0.8])
        self.assertTrue(all(abs(y - HALF_WIDTH) < 1e-9 for _, y, _ in left))

    def test_single_support_phases_are_the_steps_less_their_double_support(self):
        spans = plot_walk.single_support(self.walk)
        self.assertEqual(len(spans), STEPS)
        for k, (t0, t1) in enumerate(spans):
            self.assertAlmostEqual(t0, STEP * (k + 1) + DS, delta=1.01 * DT)
            self.assertAlmostEqual(t1 - t0, STEP - DS, delta=1.01 * DT)

    def test_sole_rectangle_turns_with_the_foot(self):
        corners = plot_walk.sole_corners(1.0, 2.0, math.pi / 2)
        xs = sorted(round(x, 9) for x, _ in corners)
        ys = sorted(round(y, 9) for _, y in corners)
        self.assertEqual((xs[0], xs[-1]), (0.93, 1.07))  # the width now along x
        self.assertEqual((ys[0], ys[-1]), (1.875, 2.125))

    def test_plot_walk_writes_a_png(self):
        out = os.path.join(OUT, "walk.png")
        r = run(os.path.join(SCRIPTS, "plot_walk.py"), self.walk_csv, out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertGreater(png_height(out), 500)

    def test_plot_walk_refuses_a_log_without_its_columns(self):
        bad = os.path.join(OUT, "bad", "walk.csv")
        os.makedirs(os.path.dirname(bad), exist_ok=True)
        write_walk(bad, [c for c in plot_walk.COLUMNS if c != "zmp_des_y"])
        r = run(os.path.join(SCRIPTS, "plot_walk.py"), bad, os.path.join(OUT, "bad.png"))
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("missing column(s) zmp_des_y", r.stderr)

    def test_plot_run_adds_the_walk_panels_when_the_run_has_a_walk(self):
        # a run folder with sim_host's log (the robot standing) and the walk beside it
        heights = {}
        for name, with_walk in (("run_plain", False), ("run_walk", True)):
            d = os.path.join(OUT, name)
            os.makedirs(d, exist_ok=True)
            if with_walk:
                write_walk(os.path.join(d, "walk.csv"))
            elif os.path.exists(os.path.join(d, "walk.csv")):
                os.remove(os.path.join(d, "walk.csv"))
            with open(os.path.join(d, "log.csv"), "w") as f:
                f.write("time,base_x,base_y,base_z,rfsensor_fz,lfsensor_fz,q_J,qref_J\n")
                for i in range(200):
                    f.write("%g,0,0,0.68,300,300,0.1,0.1\n" % (0.005 * i))
            with open(os.path.join(d, "summary.json"), "w") as f:
                json.dump({"scenario": name, "verdict": "pass", "sim_time": 1.0}, f)
            out = os.path.join(d, "plot.png")
            r = run(os.path.join(SCRIPTS, "plot_run.py"), os.path.join(d, "log.csv"),
                    os.path.join(d, "summary.json"), out)
            self.assertEqual(r.returncode, 0, r.stderr)
            heights[name] = png_height(out)
        self.assertGreater(heights["run_walk"], heights["run_plain"] * 1.5)

    def test_plot_run_names_a_bad_walk_and_still_draws_the_run(self):
        d = os.path.join(OUT, "run_bad_walk")
        os.makedirs(d, exist_ok=True)
        write_walk(os.path.join(d, "walk.csv"), [c for c in plot_walk.COLUMNS if c != "t"])
        with open(os.path.join(d, "log.csv"), "w") as f:
            f.write("time,base_x,base_y,base_z\n0,0,0,0.68\n0.005,0,0,0.68\n")
        with open(os.path.join(d, "summary.json"), "w") as f:
            json.dump({"scenario": "bad_walk", "verdict": "pass"}, f)
        out = os.path.join(d, "plot.png")
        if os.path.exists(out):
            os.remove(out)
        r = run(os.path.join(SCRIPTS, "plot_run.py"), os.path.join(d, "log.csv"),
                os.path.join(d, "summary.json"), out)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("the walk panels are left out", r.stderr)
        self.assertIn("missing column(s) t", r.stderr)
        self.assertGreater(png_height(out), 100)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
