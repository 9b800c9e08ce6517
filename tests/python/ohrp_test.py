"""Tests the Python package python/ohrp: a controller and an observer attached to a real
sim_host (HRP-1S on the flat floor, lock-step), the header's names and limits, commands that
move the robot, the observer's read-only view, and the errors (missing segment, an observer
writing, wrong array sizes, malformed logs), and camera images from an observer."""

import os
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(REPO, "python"))

import numpy as np  # noqa: E402

import ohrp  # noqa: E402

BIN = os.environ.get("OHRP_BIN_DIR", os.path.join(REPO, "build", "bin"))
SCENE = os.path.join(REPO, "mjcf", "hrp1s", "scene_flat.xml")


def attach_when_ready(make, timeout=20.0):
    deadline = time.monotonic() + timeout
    while True:
        try:
            return make()
        except ohrp.SegmentError as e:
            if time.monotonic() > deadline or "no segment" not in str(e):
                raise
            time.sleep(0.01)


def start_sim_host(scene, segment, *args):
    """sim_host on `scene` serving `segment`; its stderr goes to a file (a pipe nobody reads
    could fill up and stall it), printed when the test fails."""
    log = tempfile.TemporaryFile(mode="w+")
    sim = subprocess.Popen([os.path.join(BIN, "sim_host"), scene, "--segment", segment,
                            "--quiet", *args], stderr=log)
    sim.log = log
    return sim


def stop_sim_host(sim):
    if sim.poll() is None:
        sim.terminate()
    sim.wait(timeout=30)
    sim.log.seek(0)
    text = sim.log.read()
    if text.strip():
        print("sim_host (exit %s) said:\n%s" % (sim.returncode, text), file=sys.stderr)


class LiveSegment(unittest.TestCase):
    """sim_host runs 1 s of HRP-1S; the test is its controller, an observer watches."""

    def setUp(self):
        self.segment = "pytest_%d" % os.getpid()
        # the knee bent at once from the straight-legged start topples HRP-1S within 1 s:
        # sim_host runs on through the fall and says so at the end (exit 6)
        self.sim = start_sim_host(SCENE, self.segment, "--duration", "1.0", "--on-fall", "continue")

    def tearDown(self):
        stop_sim_host(self.sim)

    def test_controller_and_observer(self):
        robot = attach_when_ready(lambda: ohrp.Robot.controller(self.segment))
        watcher = ohrp.Robot.observer(self.segment, read_timeout=0.5)
        with robot, watcher:
            # the header, as the producer declared it
            self.assertTrue(robot.is_controller)
            self.assertFalse(watcher.is_controller)
            self.assertEqual(robot.producer_kind, "simulation")
            self.assertEqual(robot.njoint, 29)
            self.assertEqual(robot.joint_names, watcher.joint_names)
            knee = robot.index("RLEG_KNEE")
            self.assertGreater(robot.q_max[knee], robot.q_min[knee])
            self.assertTrue(np.all(robot.default_kp > 0))
            self.assertEqual(robot.force_names[:2], ["rfsensor", "lfsensor"])
            self.assertAlmostEqual(robot.control_period, 0.005)
            with self.assertRaisesRegex(ValueError, "no joint 'NOSE'"):
                robot.index("NOSE")
            # bend the right knee to 0.5 rad; the rest holds where it is
            self.assertTrue(robot.read())
            target = robot.q.copy()
            target[knee] = 0.5
            cycles, first = 0, robot.cycle
            while True:
                if not robot.write(q_ref=target) or not robot.read():
                    break
                cycles += 1
                self.assertEqual(robot.cycle, first + cycles)  # lock-step: no cycle skipped
                if cycles == 100:
                    truth = robot.sim_truth()
                    self.assertIsNotNone(truth)
                    self.assertAlmostEqual(np.linalg.norm(truth["quat"]), 1.0, places=6)
                    self.assertEqual(robot.force.shape, (robot.nforce, 6))
                    self.assertGreater(robot.force[:2, 2].sum(), 500.0)  # the feet carry it
                    # the observer sees the same robot and the commands just written
                    self.assertTrue(watcher.read())
                    self.assertLessEqual(abs(int(watcher.cycle) - int(robot.cycle)), 1)
                    last = watcher.last_commands()
                    self.assertEqual(last["q_ref"][knee], 0.5)
                    self.assertEqual(last["kp"][knee], robot.default_kp[knee])
                    # a Python controller has no self-collision guard: its record is zero
                    self.assertEqual(watcher.last_guard(), {"holding": False, "holds": 0,
                                                            "distance": 0.0, "pair": ""})
                    with self.assertRaisesRegex(ohrp.SegmentError, "observer cannot write"):
                        watcher.write(q_ref=target)
                    with self.assertRaisesRegex(ValueError, "29 values expected"):
                        robot.write(q_ref=target[:3])
            self.assertGreater(cycles, 150)  # 1 s at 5 ms
            self.assertLess(abs(robot.q[knee] - 0.5), 0.02)
            self.assertFalse(robot.producer_failed())
        self.assertEqual(self.sim.wait(timeout=30), 6)  # it ran 1 s and the robot fell


class PassiveJoints(unittest.TestCase):
    """Cassie (menagerie, unchanged, hung): an observer sees its passive shin and tarsus."""

    def test_cassie_passive_joints(self):
        scene = os.path.join(REPO, "scenarios", "scenes", "cassie_hung.xml")
        if not os.path.exists(os.path.join(REPO, "..", "shared", "external", "menagerie")):
            self.skipTest("../shared/external/menagerie is not there")
        segment = "pytest_cassie_%d" % os.getpid()
        sim = start_sim_host(scene, segment, "--duration", "0", "--wait-controller", "0")
        try:
            watcher = attach_when_ready(lambda: ohrp.Robot.observer(segment))
            with watcher:
                self.assertTrue(watcher.read())
                self.assertEqual(watcher.npassive, len(watcher.passive_names))
                names = " ".join(watcher.passive_names)
                self.assertIn("shin", names)
                self.assertIn("tarsus", names)
                self.assertEqual(watcher.passive_q.shape, (watcher.npassive,))
                self.assertTrue(np.all(np.isfinite(watcher.passive_q)))
                self.assertGreater(np.abs(watcher.passive_q).max(), 0.1)  # the tarsus is bent
        finally:
            stop_sim_host(sim)


class CameraImages(unittest.TestCase):
    def test_camera_images(self):
        """An observer asks for the left camera of scene_ball.xml: frames arrive as arrays of
        the camera's size, the red ball in the left half of the image (it lies 20 deg to the
        left of the optical axis), the depth positive and finite; after the request is
        withdrawn no new frame comes."""
        scene = os.path.join(REPO, "mjcf", "hrp1s", "scene_ball.xml")
        segment = "pytest_cams_%d" % os.getpid()
        sim = start_sim_host(scene, segment, "--duration", "0", "--wait-controller", "0",
                             "--keyframe", "halfsit", "--realtime", "--camera-size", "160x120")
        try:
            watcher = attach_when_ready(lambda: ohrp.Robot.observer(segment))
            with watcher:
                self.assertEqual(watcher.camera_names, ["LeftCamera", "RightCamera"])
                self.assertEqual(watcher.camera_sizes[0], (160, 120))
                self.assertIsNone(watcher.read_image("LeftCamera"))  # nobody asked yet
                watcher.request_images(["LeftCamera"])
                image = None
                deadline = time.monotonic() + 20
                while image is None and time.monotonic() < deadline:
                    watcher.read()
                    image = watcher.read_image("LeftCamera")
                self.assertIsNotNone(image)
                self.assertEqual(image["rgb"].shape, (120, 160, 3))
                self.assertEqual(image["depth"].shape, (120, 160))
                self.assertTrue(np.all(np.isfinite(image["depth"])) and image["depth"].min() > 0)
                rgb = image["rgb"].astype(int)
                red = (rgb[:, :, 0] >= 80) & (rgb[:, :, 0] > 1.8 * rgb[:, :, 1]) & \
                      (rgb[:, :, 0] > 1.8 * rgb[:, :, 2])
                self.assertGreater(red.sum(), 10)
                self.assertLess(np.nonzero(red)[1].mean(), 80)  # left of the centre column
                watcher.request_images([])
                withdrawn = watcher.time
                while watcher.read() and watcher.time < withdrawn + 0.05:
                    pass
                watcher.read_image("LeftCamera")  # a frame begun before the withdrawal
                drained = watcher.time
                while watcher.read() and watcher.time < drained + 0.5:
                    pass
                self.assertIsNone(watcher.read_image("LeftCamera"))
                with self.assertRaises(ValueError):
                    watcher.read_image("NoseCamera")
        finally:
            stop_sim_host(sim)


class Errors(unittest.TestCase):
    def test_missing_segment(self):
        with self.assertRaisesRegex(ohrp.SegmentError, "no segment 'pytest_none'.*--segment"):
            ohrp.Robot.controller("pytest_none")
        with self.assertRaisesRegex(ohrp.SegmentError, "no segment"):
            ohrp.Robot.observer("pytest_none")
        with self.assertRaisesRegex(ValueError, "read_timeout"):
            ohrp.Robot.controller("x", read_timeout=-1)


class RunFolders(unittest.TestCase):
    def test_log_and_summary(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "log.csv"), "w") as f:
                f.write("time,base_z,q_RLEG_KNEE\n0,0.7,0.1\n0.005,0.69,0.2\n")
            with open(os.path.join(d, "summary.json"), "w") as f:
                f.write('{"verdict": "pass"}')
            run = ohrp.load_run(d)
            self.assertEqual(run.summary["verdict"], "pass")
            np.testing.assert_array_equal(run.time, [0.0, 0.005])
            np.testing.assert_array_equal(run.joint("RLEG_KNEE"), [0.1, 0.2])
            with self.assertRaisesRegex(KeyError, "no column 'q_NOSE'.*RLEG_KNEE"):
                run.joint("NOSE")

    def test_malformed_log_names_file_and_line(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "log.csv")
            with open(path, "w") as f:
                f.write("time,x\n0,1\n0.1\n")
            with self.assertRaisesRegex(ValueError, "log.csv:3: 1 fields, the header has 2"):
                ohrp.read_log(path)
            with open(path, "w") as f:
                f.write("time,x\n0,abc\n")
            with self.assertRaisesRegex(ValueError, "log.csv:2: could not convert"):
                ohrp.read_log(path)
        with self.assertRaisesRegex(FileNotFoundError, "not a run folder"):
            ohrp.load_run("/nonexistent/run")


if __name__ == "__main__":
    unittest.main()
