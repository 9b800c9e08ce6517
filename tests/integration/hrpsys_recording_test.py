#!/usr/bin/env python3
"""Tests tools/scripts/hrpsys_recording.py on hrpsys's samplerobot-gopos000 recording.

Usage: hrpsys_recording_test.py SCRIPTS_DIR MODEL RECORDING_PREFIX OUT_DIR. The forward
kinematics is checked against what the recording must satisfy whatever the generator did: a
sole hrpsys says is on the floor is on it (height within 1 mm, level with the other), the
soles stand at the model's hip width, hrpsys's reference ZMP lies inside the stance sole in
single support, and the CoM stands over the ZMP at the start and at the end (the robot is at
rest there). A malformed row is refused with its file and line.
"""
import os
import shutil
import sys
import unittest

import numpy as np

SCRIPTS, MODEL, PREFIX, OUT = sys.argv[1:5]
sys.path.insert(0, SCRIPTS)
import hrpsys_recording  # noqa: E402

HIP_HALF_WIDTH = 0.09              # [m] the hips' y in mjcf/hrp1s/hrp1s.xml
SOLE_HALF = np.array([0.125, 0.07])  # [m] HRP-1S's sole box, half length and width
TOL = 0.001                        # [m]


class HrpsysRecording(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.r = hrpsys_recording.read_recording(PREFIX, MODEL)

    def test_a_sole_in_contact_is_on_the_floor(self):
        # the first contact column is the left foot (the walk's first swing)
        for k, side in enumerate(("left", "right")):
            on = self.r["contact"][:, k] >= 0.5
            self.assertTrue(on.any() and (~on).any(), side)
            self.assertLess(np.max(np.abs(self.r[side][on, 2])), TOL, side)
            self.assertGreater(np.max(self.r[side][~on, 2]), 0.03, side)

    def test_soles_stand_at_the_hip_width(self):
        for i in (0, -1):
            self.assertAlmostEqual(self.r["left"][i, 1], HIP_HALF_WIDTH, delta=TOL)
            self.assertAlmostEqual(self.r["right"][i, 1], -HIP_HALF_WIDTH, delta=TOL)

    def test_zmp_lies_inside_the_stance_sole_in_single_support(self):
        contact = self.r["contact"] >= 0.5
        for k, stance in ((0, "right"), (1, "left")):
            single = ~contact[:, k] & contact[:, 1 - k]
            inside = np.abs(self.r["zmp"][single] - self.r[stance][single, :2]) <= SOLE_HALF
            self.assertTrue(single.any() and inside.all(), stance)

    def test_com_stands_over_the_zmp_at_rest(self):
        for i in (0, -1):
            np.testing.assert_allclose(self.r["com"][i, :2], self.r["zmp"][i], atol=0.005)

    def test_a_malformed_row_names_its_file_and_line(self):
        os.makedirs(OUT, exist_ok=True)
        bad = os.path.join(OUT, "bad")
        for suffix in hrpsys_recording.SUFFIXES:
            shutil.copyfile("%s.%s" % (PREFIX, suffix), "%s.%s" % (bad, suffix))
        with open(bad + ".zmp") as f:
            lines = f.readlines()
        lines[9] = "0.018 0.01 x -0.66\n"
        with open(bad + ".zmp", "w") as f:
            f.writelines(lines)
        with self.assertRaisesRegex(ValueError, r"bad\.zmp:10: not a row of numbers"):
            hrpsys_recording.read_recording(bad, MODEL)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
