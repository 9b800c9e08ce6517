"""ohrp: controllers and observers of a robot segment in Python, and run folders as numpy.

Standard library and numpy only; the segment's protocol is the project's C library
(libohrp_shm_c.so, built with the project), loaded with ctypes. See docs/python.md.
"""

from ._capi import MODE_OFF, MODE_POSITION, MODE_TORQUE, MODE_VELOCITY
from .run import Run, load_run, read_log
from .segment import Robot, SegmentError

__all__ = ["Robot", "SegmentError", "Run", "load_run", "read_log", "MODE_OFF", "MODE_POSITION",
           "MODE_VELOCITY", "MODE_TORQUE"]
