"""ctypes binding of the C API (shm_bridge/include/ohrp_shm.h, library libohrp_shm_c.so).

The library is looked for, in order: the file named by the environment variable OHRP_LIB, the
build tree of this checkout (build/lib next to python/, when the package is imported from a
checkout), the installed ohrp whose programs are on PATH (<prefix>/lib beside the <prefix>/bin
holding sim_host), then the system's library path.
"""

import ctypes
import ctypes.util
import os
import shutil

_HERE = os.path.dirname(os.path.abspath(__file__))
_LIB_NAME = "libohrp_shm_c.so"

# results (ohrp_shm.h)
(OK, TIMEOUT, PRODUCER_GONE, PRODUCER_STOPPED, NOT_OPEN, DROPPED, NOT_CONTROLLER,
 SYNC_CORRUPTED, SEGMENT_CORRUPTED) = range(9)
# joint modes
MODE_OFF, MODE_POSITION, MODE_VELOCITY, MODE_TORQUE = range(4)


def _candidates():
    env = os.environ.get("OHRP_LIB")
    if env:
        yield env
        return
    yield os.path.join(_HERE, "..", "..", "build", "lib", _LIB_NAME)
    program = shutil.which("sim_host")
    if program:
        yield os.path.join(os.path.dirname(os.path.realpath(program)), "..", "lib", _LIB_NAME)
    found = ctypes.util.find_library("ohrp_shm_c")
    if found:
        yield found


def _load():
    tried = []
    for path in _candidates():
        if os.path.sep in path and not os.path.exists(path):
            tried.append(path)
            continue
        try:
            return ctypes.CDLL(path)
        except OSError as e:
            tried.append("%s (%s)" % (path, e))
    raise ImportError(
        "ohrp: the C library %s was not found (tried: %s); build the project first "
        "(./ohrp build, or cmake --build build), put an installed ohrp's bin/ on PATH, or set "
        "OHRP_LIB to its path"
        % (_LIB_NAME, ", ".join(tried) or "nothing"))


lib = _load()

_robot = ctypes.c_void_p
_dp = ctypes.POINTER(ctypes.c_double)
_ip = ctypes.POINTER(ctypes.c_int32)
_cp = ctypes.c_char_p


def _sig(name, restype, *argtypes):
    f = getattr(lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)


for _n in ("ohrp_max_joints", "ohrp_max_force_sensors", "ohrp_max_imus"):
    _sig(_n, ctypes.c_int)
_sig("ohrp_open", _robot, _cp, ctypes.c_double, ctypes.c_char_p, ctypes.c_size_t)
_sig("ohrp_observe", _robot, _cp, ctypes.c_double, ctypes.c_char_p, ctypes.c_size_t)
_sig("ohrp_close", None, _robot)
for _n in ("ohrp_is_controller", "ohrp_producer_kind", "ohrp_njoint", "ohrp_nforce", "ohrp_nimu",
           "ohrp_npassive", "ohrp_read", "ohrp_producer_failed"):
    _sig(_n, ctypes.c_int, _robot)
_sig("ohrp_robot_name", _cp, _robot)
for _n in ("ohrp_joint_name", "ohrp_force_name", "ohrp_imu_name", "ohrp_passive_name"):
    _sig(_n, _cp, _robot, ctypes.c_int)
for _n in ("ohrp_joint_index", "ohrp_force_index", "ohrp_imu_index"):
    _sig(_n, ctypes.c_int, _robot, _cp)
for _n in ("ohrp_control_period", "ohrp_physics_period", "ohrp_time"):
    _sig(_n, ctypes.c_double, _robot)
_sig("ohrp_joint_limits", None, _robot, _dp, _dp, _dp)
_sig("ohrp_default_gains", None, _robot, _dp, _dp)
_sig("ohrp_cycle", ctypes.c_uint64, _robot)
_sig("ohrp_status", ctypes.c_uint32, _robot)
for _n in ("ohrp_get_q", "ohrp_get_dq", "ohrp_get_tau", "ohrp_get_force", "ohrp_get_imu",
           "ohrp_get_passive_q", "ohrp_get_passive_dq"):
    _sig(_n, None, _robot, _dp)
_sig("ohrp_get_sim_truth", ctypes.c_int, _robot, _dp)
_sig("ohrp_write", ctypes.c_int, _robot, _ip, _dp, _dp, _dp, _dp, _dp)
_sig("ohrp_last_commands", ctypes.c_int, _robot, _ip, _dp, _dp, _dp, _dp, _dp)
_sig("ohrp_last_guard", ctypes.c_int, _robot, _ip, ctypes.POINTER(ctypes.c_uint64), _dp,
     ctypes.c_char_p, ctypes.c_char_p)
_sig("ohrp_result_name", _cp, ctypes.c_int)
# camera images
_sig("ohrp_ncamera", ctypes.c_int, _robot)
_sig("ohrp_camera_name", _cp, _robot, ctypes.c_int)
_sig("ohrp_camera_index", ctypes.c_int, _robot, _cp)
_sig("ohrp_camera_info", ctypes.c_int, _robot, ctypes.c_int, ctypes.POINTER(ctypes.c_int),
     ctypes.POINTER(ctypes.c_int), _dp)
_sig("ohrp_request_images", ctypes.c_int, _robot, ctypes.c_uint32)
_sig("ohrp_read_image", ctypes.c_int, _robot, ctypes.c_int, ctypes.c_uint64,
     ctypes.POINTER(ctypes.c_uint64), _dp, ctypes.POINTER(ctypes.c_int),
     ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_uint8),
     ctypes.c_size_t, ctypes.POINTER(ctypes.c_float), ctypes.c_size_t)
(IMAGE_OK, IMAGE_NO_FRAME, IMAGE_BUSY, IMAGE_BAD_CAMERA, IMAGE_TOO_SMALL, IMAGE_NOT_OPEN) = range(6)


def result_name(code):
    return lib.ohrp_result_name(code).decode()
