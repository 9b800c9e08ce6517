"""A robot segment from Python: attach as the controller or as an observer.

    import ohrp
    with ohrp.Robot.controller("hrp1s") as robot:
        kp, kd = robot.default_kp, robot.default_kd
        while robot.read():                  # False once the producer has ended its run
            robot.write(q_ref=target, kp=kp, kd=kd)   # likewise

After each read() the sensors of that cycle are in numpy arrays that read() refills in place:
q, dq, tau (njoint), passive_q, passive_dq (npassive: joints no actuator drives), force (nforce x 6: fx fy fz tx ty tz), imu (nimu x 10: gyro, accel,
quaternion wxyz), and the scalars time, cycle, status; sim_truth() gives the simulation's
ground truth (or None on hardware). Units and conventions are the segment's (SI, rad).

Cameras: camera_names, camera_sizes [(width, height)], camera_fovy [deg]; request_images(
["LeftCamera"]) asks the producer for them (it renders or delivers only what somebody asks
for; [] withdraws, close() too); read_image("LeftCamera") gives the latest new frame as a dict
(frame, time, rgb: height x width x 3 uint8, depth: height x width float32 [m] or None), or
None when there is no new frame.
"""

import ctypes

import numpy as np

from . import _capi

_lib = _capi.lib


class SegmentError(RuntimeError):
    """Attaching failed, or the segment's cycle failed (timeout, producer gone, dropped)."""

    def __init__(self, message, result=None):
        super().__init__(message)
        self.result = result


def _ptr(a):
    return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


def _names(handle, count, getter):
    return [getter(handle, i).decode() for i in range(count)]


class Robot:
    """One attachment to a segment (use Robot.controller or Robot.observer)."""

    def __init__(self, segment, read_timeout, as_controller):
        if read_timeout < 0:
            raise ValueError("read_timeout must be >= 0 [s]")
        err = ctypes.create_string_buffer(1024)
        attach = _lib.ohrp_open if as_controller else _lib.ohrp_observe
        self._h = attach(segment.encode(), float(read_timeout), err, len(err))
        if not self._h:
            raise SegmentError(err.value.decode())
        h = self._h
        self.segment = segment
        self.is_controller = bool(_lib.ohrp_is_controller(h))
        self.robot_name = _lib.ohrp_robot_name(h).decode()
        self.producer_kind = ("unknown", "simulation", "hardware", "replay")[
            _lib.ohrp_producer_kind(h)]
        self.njoint, self.nforce, self.nimu = (_lib.ohrp_njoint(h), _lib.ohrp_nforce(h),
                                               _lib.ohrp_nimu(h))
        self.joint_names = _names(h, self.njoint, _lib.ohrp_joint_name)
        self.force_names = _names(h, self.nforce, _lib.ohrp_force_name)
        self.imu_names = _names(h, self.nimu, _lib.ohrp_imu_name)
        # joints no actuator drives (e.g. Cassie's shin and tarsus): read-only
        self.npassive = _lib.ohrp_npassive(h)
        self.passive_names = _names(h, self.npassive, _lib.ohrp_passive_name)
        self.control_period = _lib.ohrp_control_period(h)
        self.physics_period = _lib.ohrp_physics_period(h)
        n = self.njoint
        self.q_min, self.q_max, self.tau_max = np.zeros(n), np.zeros(n), np.zeros(n)
        _lib.ohrp_joint_limits(h, _ptr(self.q_min), _ptr(self.q_max), _ptr(self.tau_max))
        self.default_kp, self.default_kd = np.zeros(n), np.zeros(n)
        _lib.ohrp_default_gains(h, _ptr(self.default_kp), _ptr(self.default_kd))
        # the sensors of the last cycle read, refilled in place by read()
        self.q, self.dq, self.tau = np.zeros(n), np.zeros(n), np.zeros(n)
        self.force = np.zeros((self.nforce, 6))
        self.imu = np.zeros((self.nimu, 10))
        self.passive_q, self.passive_dq = np.zeros(self.npassive), np.zeros(self.npassive)
        self.time, self.cycle, self.status = 0.0, 0, 0
        self._truth = np.zeros(13)
        # cameras: names, sizes, fields of view; one buffer per camera for read_image
        self.ncamera = _lib.ohrp_ncamera(h)
        self.camera_names = _names(h, self.ncamera, _lib.ohrp_camera_name)
        self.camera_sizes, self.camera_fovy = [], []
        for i in range(self.ncamera):
            w, hh, f = ctypes.c_int(), ctypes.c_int(), ctypes.c_double()
            _lib.ohrp_camera_info(h, i, ctypes.byref(w), ctypes.byref(hh), ctypes.byref(f))
            self.camera_sizes.append((w.value, hh.value))
            self.camera_fovy.append(f.value)
        self._last_frame = [0] * self.ncamera
        self._mode = (ctypes.c_int32 * max(n, 1))()

    @classmethod
    def controller(cls, segment, read_timeout=2.0):
        """Attaches as the segment's controller (the one that writes commands)."""
        return cls(segment, read_timeout, True)

    @classmethod
    def observer(cls, segment, read_timeout=2.0):
        """Attaches read-only: never slows the lock-step, many may watch at once."""
        return cls(segment, read_timeout, False)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        self.close()

    def close(self):
        """Detaches (a controller frees its slot). Safe to call twice."""
        h, self._h = getattr(self, "_h", None), None
        if h:
            _lib.ohrp_close(h)

    def _handle(self):
        if not self._h:
            raise SegmentError("segment '%s': not attached (closed)" % self.segment)
        return self._h

    def index(self, joint_name):
        """The id of a joint by name (ValueError when the robot has none of that name)."""
        i = _lib.ohrp_joint_index(self._handle(), joint_name.encode())
        if i < 0:
            raise ValueError("robot '%s' has no joint '%s' (joints: %s)"
                             % (self.robot_name, joint_name, ", ".join(self.joint_names)))
        return i

    def read(self):
        """Waits for the next cycle and refills q, dq, tau, force, imu, time, cycle, status.

        True on fresh sensors, False once the producer has ended its run (see
        producer_failed). Raises SegmentError on a timeout (for an observer: no new cycle
        within read_timeout), a dead producer, or a controller the producer let go.
        """
        h = self._handle()
        r = _lib.ohrp_read(h)
        if r == _capi.PRODUCER_STOPPED:
            return False
        if r != _capi.OK:
            raise SegmentError("segment '%s': read: %s" % (self.segment, _capi.result_name(r)), r)
        _lib.ohrp_get_q(h, _ptr(self.q))
        _lib.ohrp_get_dq(h, _ptr(self.dq))
        _lib.ohrp_get_tau(h, _ptr(self.tau))
        if self.nforce:
            _lib.ohrp_get_force(h, _ptr(self.force))
        if self.nimu:
            _lib.ohrp_get_imu(h, _ptr(self.imu))
        if self.npassive:
            _lib.ohrp_get_passive_q(h, _ptr(self.passive_q))
            _lib.ohrp_get_passive_dq(h, _ptr(self.passive_dq))
        self.time, self.cycle, self.status = (_lib.ohrp_time(h), _lib.ohrp_cycle(h),
                                              _lib.ohrp_status(h))
        return True

    def camera(self, name):
        """The index of a camera by name (ValueError when the robot has none of that name)."""
        i = _lib.ohrp_camera_index(self._handle(), name.encode())
        if i < 0:
            raise ValueError("robot '%s' has no camera '%s' (cameras: %s)"
                             % (self.robot_name, name, ", ".join(self.camera_names) or "none"))
        return i

    def request_images(self, cameras):
        """Asks the producer for the images of `cameras` (names; [] withdraws)."""
        mask = 0
        for name in cameras:
            mask |= 1 << self.camera(name)
        if not _lib.ohrp_request_images(self._handle(), mask):
            raise SegmentError("segment '%s': the producer refused the request for %s "
                               "(16 programs ask already?)" % (self.segment, list(cameras)))

    def read_image(self, name, with_depth=True):
        """The latest frame of camera `name` newer than the last one returned, as a dict
        (frame, time [s], rgb: height x width x 3 uint8, top row first, depth: height x width
        float32 [m] or None), or None when there is none yet (asked for too recently, or not
        asked for). Retries while the producer rewrites the slot."""
        i = self.camera(name)
        w, hh = self.camera_sizes[i]
        rgb = np.empty((hh, w, 3), dtype=np.uint8)
        depth = np.empty((hh, w), dtype=np.float32) if with_depth else None
        frame, t = ctypes.c_uint64(), ctypes.c_double()
        fw, fh, has_depth = ctypes.c_int(), ctypes.c_int(), ctypes.c_int()
        for _ in range(100):
            r = _lib.ohrp_read_image(
                self._handle(), i, self._last_frame[i], ctypes.byref(frame), ctypes.byref(t),
                ctypes.byref(fw), ctypes.byref(fh), ctypes.byref(has_depth),
                rgb.ctypes.data_as(ctypes.POINTER(ctypes.c_uint8)), rgb.size,
                depth.ctypes.data_as(ctypes.POINTER(ctypes.c_float)) if with_depth else None,
                depth.size if with_depth else 0)
            if r != _capi.IMAGE_BUSY:
                break
        if r == _capi.IMAGE_NO_FRAME:
            return None
        if r != _capi.IMAGE_OK:
            raise SegmentError("segment '%s': read_image('%s'): result %d" % (self.segment, name, r), r)
        self._last_frame[i] = frame.value
        n = fw.value * fh.value
        out_rgb = rgb.reshape(-1)[:3 * n].reshape(fh.value, fw.value, 3)
        out_depth = (depth.reshape(-1)[:n].reshape(fh.value, fw.value)
                     if with_depth and has_depth.value else None)
        return {"frame": frame.value, "time": t.value, "rgb": out_rgb, "depth": out_depth}

    def sim_truth(self):
        """The simulation's ground truth of the last cycle read, as a dict of arrays (base
        position p, quaternion quat wxyz, linear velocity v, angular velocity w, world
        frame), or None when the producer is not a simulation."""
        if not _lib.ohrp_get_sim_truth(self._handle(), _ptr(self._truth)):
            return None
        t = self._truth.copy()
        return {"p": t[0:3], "quat": t[3:7], "v": t[7:10], "w": t[10:13]}

    def _array(self, name, values):
        if values is None:
            return None
        a = np.ascontiguousarray(values, dtype=np.float64)
        if a.shape != (self.njoint,):
            raise ValueError("%s: %d values expected (njoint), got shape %s"
                             % (name, self.njoint, a.shape))
        return a

    def write(self, q_ref=None, dq_ref=None, tau_ff=None, kp=None, kd=None, mode=None):
        """Writes the commands answering the last cycle read (controller only).

        Each argument: njoint values or None. None means: mode position, q_ref the q just
        read, dq_ref 0, tau_ff 0, kp / kd the producer's default gains. mode: one of
        MODE_OFF, MODE_POSITION, MODE_VELOCITY, MODE_TORQUE, or njoint of them.
        Returns True when written, False once the producer has ended its run (a normal end,
        as read() returning False). Raises SegmentError when the producer let this controller
        go (it missed the producer's deadline) or the segment is corrupted.
        """
        h = self._handle()
        if not self.is_controller:
            raise SegmentError("segment '%s': an observer cannot write commands" % self.segment)
        arrays = [self._array(n, v) for n, v in
                  (("q_ref", q_ref), ("dq_ref", dq_ref), ("tau_ff", tau_ff), ("kp", kp),
                   ("kd", kd))]
        mode_ptr = None
        if mode is not None:
            modes = np.broadcast_to(np.asarray(mode, dtype=np.int32), (self.njoint,))
            for i, m in enumerate(modes):
                self._mode[i] = int(m)
            mode_ptr = self._mode
        r = _lib.ohrp_write(h, mode_ptr, *[None if a is None else _ptr(a) for a in arrays])
        if r == _capi.PRODUCER_STOPPED:
            return False
        if r != _capi.OK:
            raise SegmentError("segment '%s': write: %s" % (self.segment, _capi.result_name(r)), r)
        return True

    def last_commands(self):
        """The controller's last commands as a dict of arrays (mode, q_ref, dq_ref, tau_ff,
        kp, kd), or None when none were written yet."""
        n = self.njoint
        out = {k: np.zeros(n) for k in ("q_ref", "dq_ref", "tau_ff", "kp", "kd")}
        mode = (ctypes.c_int32 * max(n, 1))()
        if not _lib.ohrp_last_commands(self._handle(), mode, *[_ptr(out[k]) for k in
                                       ("q_ref", "dq_ref", "tau_ff", "kp", "kd")]):
            return None
        out["mode"] = np.array(mode[:n], dtype=np.int32)
        return out

    def last_guard(self):
        """The controller's self-collision guard in its last commands (the segment's guard
        record) as a dict: holding (bool, it held the motion that cycle), holds (episodes
        begun), distance (the held pair's predicted distance [m]), pair ("LINK_A/LINK_B", "" when
        not holding); None when no commands were written yet."""
        holding, holds, distance = ctypes.c_int32(), ctypes.c_uint64(), ctypes.c_double()
        a, b = ctypes.create_string_buffer(32), ctypes.create_string_buffer(32)
        if not _lib.ohrp_last_guard(self._handle(), ctypes.byref(holding), ctypes.byref(holds),
                                    ctypes.byref(distance), a, b):
            return None
        pair = "%s/%s" % (a.value.decode(), b.value.decode()) if a.value else ""
        return {"holding": bool(holding.value), "holds": holds.value,
                "distance": distance.value, "pair": pair}

    def producer_failed(self):
        """True when the producer ended its run after failing (e.g. a diverged simulation)."""
        return bool(_lib.ohrp_producer_failed(self._handle()))
