#!/usr/bin/env python3
"""Writes the smoke density of bench/scenes/mitsuba/media_smoke.xml: a
Mitsuba 3 `.vol` grid (one float channel, 32³ cells over the unit cube)
made procedurally, the same bytes on every run.

    python bench/smoke_volume.py [OUT]   # default: scenes/mitsuba/volumes/smoke.vol

The density is a rising plume: a column of blobs that widen and drift
with height, modulated by a sum of sines (a deterministic stand-in for
turbulence), zero at the grid's faces, at most 1.

Format (Mitsuba's `gridvolume`): the bytes `VOL`, version 3, encoding 1
(float32), the resolutions x, y, z and the channel count as int32, the
bounding box (min x, y, z, max x, y, z) as float32, then the values with
x varying fastest, little-endian.
"""

import struct
import sys
from pathlib import Path

import numpy as np

N = 32


def density(n=N):
    c = (np.arange(n) + 0.5) / n
    z, y, x = np.meshgrid(c, c, c, indexing="ij")
    # The plume's axis drifts in x and z as it rises; it widens with height.
    ax = 0.5 + 0.12 * np.sin(5.0 * y)
    az = 0.5 + 0.08 * np.cos(4.0 * y + 0.5)
    width = 0.09 + 0.16 * y
    r2 = ((x - ax) ** 2 + (z - az) ** 2) / width**2
    plume = np.exp(-r2) * np.clip(1.2 - y, 0.0, 1.0)
    swirl = (
        np.sin(13.0 * x + 7.0 * y) * np.sin(11.0 * z - 5.0 * y) * 0.5
        + np.sin(23.0 * y + 9.0 * x * z) * 0.25
    )
    d = plume * (0.75 + 0.35 * swirl)
    # Zero at the faces so the grid's box needs no padding.
    edge = np.minimum.reduce([x, 1 - x, y, 1 - y, z, 1 - z]) * n
    d *= np.clip(edge - 0.5, 0.0, 1.0)
    d = np.clip(d, 0.0, None)
    return (d / d.max()).astype("<f4")


def write_vol(path, values):
    nz, ny, nx = values.shape
    head = b"VOL" + bytes([3]) + struct.pack("<iiiii", 1, nx, ny, nz, 1)
    head += struct.pack("<6f", 0.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(head + values.tobytes(order="C"))


def main():
    here = Path(__file__).resolve().parent
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else here / "scenes" / "mitsuba" / "volumes" / "smoke.vol"
    write_vol(out, density())
    print(out)


if __name__ == "__main__":
    main()
