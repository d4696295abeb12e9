#!/usr/bin/env python3
"""Convert a float grid of an OpenVDB file (e.g. a Blender smoke cache) to Mitsuba's .vol.

    /work/pyvenv/bin/python validation/vdb_to_vol.py IN.vdb OUT.vol [--grid density]

Needs the `bpy` module (pip install bpy; Blender 4.5 bundles OpenVDB 12's Python module,
`openvdb`) and numpy. Takes about a second for the small grids of the validation scenes
(smoke-grid: 26 x 17 x 36 voxels; most of it is importing bpy).

What it writes is the grid Photon reads from the .vdb itself (src/medium/grid_file.rs), so
that Mitsuba (whose `gridvolume` reads only .vol) sees the same densities:
- the dense box over the ACTIVE voxels' bounding box [index_min, index_max], as OpenVDB's
  copyToDense gives it (inactive voxels inside the box keep their stored values, the
  background outside the tree); negative and non-finite values become 0;
- Mitsuba's .vol layout: "VOL", version byte 3, int32 encoding 1 (float32), int32 nx, ny, nz,
  int32 channels 1, six float32 bounding box values (the unit cube: Mitsuba 3's gridvolume and
  Photon ignore them, a `to_world` / `transform` places the grid), then the float32 values with
  x fastest, data[(z * ny + y) * nx + x], all little-endian.

Both renderers put the grid in a unit cube, voxel centres at ((i + 1/2) / nx, ...). OpenVDB
puts voxel centres at integer index coordinates, so the unit cube spans index_min - 1/2 to
index_max + 1/2 in index space, and the file's (linear) index-to-world map takes it to the
file's world. The script prints that unit-cube-to-world affine (4 x 4, row-major): Photon's
`[media.NAME] transform` is applied after it (to the .vdb), and Mitsuba's gridvolume `to_world`
must be the product transform * affine (to the .vol). validation/generate_scenes.py
(smoke_grid) holds the numbers printed for the smoke-grid scene.
"""

import argparse
import os
import struct
import sys


def load_openvdb():
    import bpy

    sys.path.append(bpy.utils.resource_path("LOCAL") + "/python/lib/python3.11/site-packages")
    import openvdb

    return openvdb


def dense_active_box(openvdb, path, name):
    """(values as a numpy array indexed [x, y, z], index_min, unit-cube-to-world 4 x 4)."""
    import numpy as np

    grid = openvdb.read(path, name)
    if grid.valueTypeName != "float":
        raise SystemExit(f"{path}: grid '{name}' holds {grid.valueTypeName} values, expected float")
    lo, hi = grid.evalActiveVoxelBoundingBox()
    shape = tuple(h - l + 1 for l, h in zip(lo, hi))
    if min(shape) <= 0:
        raise SystemExit(f"{path}: grid '{name}' has no active voxels")
    values = np.zeros(shape, np.float32)
    grid.copyToArray(values, ijk=lo)  # OpenVDB tools::CopyToDense over the box
    values[~(values > 0.0)] = 0.0  # negative and NaN
    values[~np.isfinite(values)] = 0.0

    xf = grid.transform
    if not xf.isLinear:
        raise SystemExit(f"{path}: a {xf.typeName} (not linear) index-to-world map cannot be an affine")
    origin = np.array(xf.indexToWorld((0.0, 0.0, 0.0)))
    cols = [np.array(xf.indexToWorld(tuple(float(i == a) for i in range(3)))) - origin for a in range(3)]
    index_to_world = np.identity(4)
    for a in range(3):
        index_to_world[:3, a] = cols[a]
    index_to_world[:3, 3] = origin
    unit_to_index = np.identity(4)
    for a in range(3):
        unit_to_index[a, a] = shape[a]
        unit_to_index[a, 3] = lo[a] - 0.5
    return values, tuple(lo), index_to_world @ unit_to_index, xf.typeName


def vol_bytes(values):
    """Mitsuba .vol bytes of a numpy array indexed [x, y, z] (one channel)."""
    import numpy as np

    nx, ny, nz = values.shape
    head = b"VOL" + bytes([3]) + struct.pack("<5i", 1, nx, ny, nz, 1) + struct.pack("<6f", 0, 0, 0, 1, 1, 1)
    # [x, y, z] -> [z, y, x] in C order: x fastest.
    return head + np.ascontiguousarray(values.transpose(2, 1, 0), dtype="<f4").tobytes()


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("vdb")
    p.add_argument("vol")
    p.add_argument("--grid", default="density", help="the float grid's name (default: density)")
    a = p.parse_args()
    openvdb = load_openvdb()
    values, lo, m, map_type = dense_active_box(openvdb, a.vdb, a.grid)
    with open(a.vol, "wb") as f:
        f.write(vol_bytes(values))
    nx, ny, nz = values.shape
    print(f"{a.vdb}: grid '{a.grid}', {map_type}, active box index {list(lo)}..."
          f"{[l + n - 1 for l, n in zip(lo, values.shape)]}: {nx} x {ny} x {nz} voxels")
    print(f"density: max {values.max():.6g}, mean {values.mean():.6g}, "
          f"{(values > 0).mean() * 100:.1f}% of the voxels above 0")
    print(f"wrote {a.vol} ({os.path.getsize(a.vol)} bytes)")
    print("unit cube to file world (row-major 4 x 4):")
    for row in m:
        print("    [" + ", ".join(f"{x:.9g}" for x in row) + "]")
    sys.stdout.flush()
    # bpy's bundled nanobind modules report "leaked" objects at interpreter shutdown (harmless
    # noise on stderr): leave without the shutdown.
    os._exit(0)


if __name__ == "__main__":
    main()
