#!/usr/bin/env python3
"""Make the references `photon bench` compares with, as half-float EXRs in bench/references/.

    cargo build --release
    pip install mitsuba numpy        # only for reading and writing EXR files here
    python bench/make_references.py --cornell tests/fixtures/shared/scenes/cornell-box/reference.exr
    python bench/make_references.py --seed-seconds 420

- cornell.exr: the shared Cornell box reference (Mitsuba 3.9 path tracer, 16384 spp), stored
  as half floats (relMSE 1e-8 against the float original).
- seed.exr: the original project's scene at 480², converged with Photon's own probabilistic
  PPM (Knaus & Zwicker 2011, consistent: its bias vanishes as passes grow): two independent
  runs of --seed-seconds each (seeds 101 and 202), averaged. The relMSE of one half against the
  other is printed; the reference's own relMSE is about a quarter of it. This reference
  measures how fast the integrators converge on the scene, not whether they converge to the
  right image: that is the validation suite's job (validation/, against Mitsuba 3).
"""

import argparse
import os
import subprocess
import tempfile

import mitsuba as mi
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PHOTON = os.environ.get("PHOTON", os.path.join(ROOT, "target", "release", "photon"))
OUT = os.path.join(HERE, "references")


def read(path):
    bitmap = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32)
    return np.array(bitmap)


def write_half(path, rgb):
    bitmap = mi.Bitmap(np.ascontiguousarray(rgb, dtype=np.float32), mi.Bitmap.PixelFormat.RGB)
    bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float16).write(path)
    print(f"wrote {path}")


def rel_mse(a, b):
    return float(np.mean((a - b) ** 2 / (((a + b) / 2) ** 2 + 0.01)))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cornell", help="the shared Cornell reference.exr to store as half floats")
    p.add_argument("--seed-seconds", type=float, help="seconds per half of the seed reference")
    a = p.parse_args()
    mi.set_variant("scalar_rgb")
    os.makedirs(OUT, exist_ok=True)
    if a.cornell:
        write_half(os.path.join(OUT, "cornell.exr"), read(a.cornell))
    if a.seed_seconds:
        halves = []
        with tempfile.TemporaryDirectory() as tmp:
            for seed in (101, 202):
                out = os.path.join(tmp, f"half{seed}.exr")
                subprocess.run(
                    [PHOTON, "render", "seed", "--integrator", "ppm", "--time",
                     str(a.seed_seconds), "--seed", str(seed), "-q", "-o", out],
                    check=True,
                )
                halves.append(read(out))
        print(f"relMSE of one half against the other: {rel_mse(*halves):.6f}")
        write_half(os.path.join(OUT, "seed.exr"), (halves[0] + halves[1]) / 2)


if __name__ == "__main__":
    main()
