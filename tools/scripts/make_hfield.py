#!/usr/bin/env python3
"""Writes the heightfield of mjcf/hrp1s/scene_uneven.xml: make_hfield.py OUT.bin.

MuJoCo's own binary heightfield format: int32 nrow, int32 ncol, then nrow*ncol float32
elevations, row-major, rows along +y (MuJoCo normalises them to [0, 1] and scales them by the
hfield's elevation size). The surface is a smooth pattern of gentle waves (wavelengths 0.4 m
along x and 0.5 m along y), so that each sole stands on a slope of a few degrees that differs
between the feet. Standard library only.
"""
import math
import struct
import sys

N = 101          # samples per side over 2 m x 2 m: 2 cm cells
HALF = 1.0       # [m] half extent (the hfield's radius_x and radius_y)


def height(x, y):
    return 0.5 + 0.25 * math.sin(2 * math.pi * x / 0.4 + 0.3) + 0.25 * math.sin(2 * math.pi * y / 0.5 + 1.1)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__.splitlines()[0])
    with open(sys.argv[1], "wb") as f:
        f.write(struct.pack("<ii", N, N))
        for r in range(N):
            y = -HALF + 2 * HALF * r / (N - 1)
            for c in range(N):
                x = -HALF + 2 * HALF * c / (N - 1)
                f.write(struct.pack("<f", height(x, y)))


if __name__ == "__main__":
    main()
