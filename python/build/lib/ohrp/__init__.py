"""ohrp: controllers and observers of a robot segment in Python, and run folders as numpy.

Standard library and numpy only; the segment's protocol is the project's C library
(libohrp_shm_c.so, built with the project), loaded with ctypes the first time a segment name
(Robot, SegmentError, MODE_*) is used, so that reading run folders needs no build. See
docs/python.md.
"""

from .run import Run, load_run, read_log

_SEGMENT_NAMES = ("Robot", "SegmentError")
_MODE_NAMES = ("MODE_OFF", "MODE_POSITION", "MODE_VELOCITY", "MODE_TORQUE")

__all__ = ["Run", "load_run", "read_log", *_SEGMENT_NAMES, *_MODE_NAMES]


def __getattr__(name):
    if name in _SEGMENT_NAMES:
        from . import segment
        return getattr(segment, name)
    if name in _MODE_NAMES:
        from . import _capi
        return getattr(_capi, name)
    raise AttributeError("module 'ohrp' has no attribute '%s'" % name)
