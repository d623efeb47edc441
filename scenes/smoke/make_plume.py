#!/usr/bin/python3
"""Writes plume.vdb: a procedural plume of smoke rising from the floor of the Cornell box.

The density (a float grid named "density", 0 to about 1.3) is a Gaussian column whose radius
grows with height and whose axis sways, modulated by a few sine waves for texture and faded out
towards its top. Voxels of 7.5 mm in the Cornell box's file frame (metres, +Y up, the floor at
y = 0); only voxels above 1e-3 are active, the background 0.

Needs Debian's python3-openvdb and python3-numpy (both for /usr/bin/python3). Run from anywhere:

    /usr/bin/python3 scenes/smoke/make_plume.py
"""
import math
import pathlib

import numpy as np
import pyopenvdb as vdb

VOXEL = 0.0075
# The plume's bounds in the file frame: over the middle of the floor, up to 0.45 m.
LO = np.array([0.128, 0.0, 0.13])
HI = np.array([0.428, 0.45, 0.43])


def density(x, y, z):
    h = np.clip(y / HI[1], 0.0, 1.0)
    axis_x = 0.278 + 0.03 * np.sin(7.0 * h)
    axis_z = 0.28 + 0.03 * np.cos(5.0 * h)
    radius = 0.035 + 0.08 * h
    r2 = ((x - axis_x) ** 2 + (z - axis_z) ** 2) / radius**2
    column = np.exp(-r2) * (1.0 - h**3)
    texture = 1.0 + 0.45 * np.sin(40.0 * x + 3.0 * np.sin(30.0 * y)) * np.sin(35.0 * z + 25.0 * y)
    return np.maximum(column * texture, 0.0)


def main():
    first = np.round(LO / VOXEL).astype(int)
    last = np.round(HI / VOXEL).astype(int)
    i, j, k = (np.arange(a, b + 1) for a, b in zip(first, last))
    x, y, z = np.meshgrid(i * VOXEL, j * VOXEL, k * VOXEL, indexing="ij")
    values = density(x, y, z).astype(np.float32)
    values[values < 1e-3] = 0.0

    grid = vdb.FloatGrid(0.0)
    grid.copyFromArray(values, ijk=tuple(int(v) for v in first), tolerance=0.0)
    grid.transform = vdb.createLinearTransform(voxelSize=VOXEL)
    grid.name = "density"
    grid.gridClass = vdb.GridClass.FOG_VOLUME
    out = pathlib.Path(__file__).with_name("plume.vdb")
    vdb.write(str(out), grids=[grid])
    print(f"{out}: {grid.activeVoxelCount()} active voxels, max {values.max():.3f}, "
          f"index box {grid.evalActiveVoxelBoundingBox()}")


if __name__ == "__main__":
    main()
