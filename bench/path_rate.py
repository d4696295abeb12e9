#!/usr/bin/env python3
"""Path-traced samples per second: Photon's `path` against Mitsuba 3's `path`, in the same minutes.

    cargo build --release
    apt-get install libllvm19                  # Mitsuba's LLVM variant JIT-compiles with it
    pip install mitsuba
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 python bench/path_rate.py

Renders each scene with both renderers in turn, `--rounds` times (alternating, so that a
machine whose speed drifts slows both alike), on every core, and prints samples per pixel per
second for each run and the ratio of the medians. Photon's time is its render (the scene is
loaded before); Mitsuba's is `mi.render` of an already loaded scene whose kernels were
compiled by a first, untimed render, as `validation/equal_time.py` gives it.

The scenes: the built-in Cornell box at 512² (`scenes/cornell.toml` and its Mitsuba twin
`bench/mitsuba/cornell/cornell.xml`) and the validation suite's glossy box at 128²
(`validation/glossy-cornell/`). Both renderers run the same path tracer: next-event estimation
with multiple importance sampling, Russian roulette from the fifth or sixth bounce, no depth
limit. About two minutes with the defaults.
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PHOTON = os.environ.get("PHOTON", os.path.join(ROOT, "target", "release", "photon"))

# (name, Photon scene, Mitsuba scene, samples per pixel of each timed render)
SCENES = [
    ("cornell", "scenes/cornell.toml", "bench/mitsuba/cornell/cornell.xml", 32),
    (
        "glossy-cornell",
        "validation/glossy-cornell/glossy-cornell.toml",
        "validation/glossy-cornell/glossy-cornell.xml",
        1024,
    ),
]


def photon_rate(scene, spp, out):
    """Samples per pixel per second of one Photon `path` render."""
    r = subprocess.run(
        [PHOTON, "render", os.path.join(ROOT, scene), "--integrator", "path",
         "--spp", str(spp), "-o", out],
        capture_output=True, text=True,
    )
    if r.returncode != 0:
        raise SystemExit(r.stderr)
    m = re.search(r"render ([0-9.]+) s", r.stderr)
    if not m:
        raise SystemExit(f"no render time in Photon's output: {r.stderr}")
    return spp / float(m.group(1))


def mitsuba_rate(mi, scene, spp, seed):
    """Samples per pixel per second of one Mitsuba render of the loaded `scene`."""
    start = time.perf_counter()
    image = mi.render(scene, spp=spp, seed=seed)
    image.numpy()  # the render is lazy until its result is read
    return spp / (time.perf_counter() - start)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--rounds", type=int, default=3, help="runs of each renderer per scene")
    p.add_argument("--variant", default="llvm_ad_rgb", help="Mitsuba variant")
    a = p.parse_args()
    import mitsuba as mi

    mi.set_variant(a.variant)
    mi.set_log_level(mi.LogLevel.Error)
    print(f"Mitsuba {mi.__version__} ({a.variant}), Photon {PHOTON}", file=sys.stderr)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "image.exr")
        for name, toml, xml, spp in SCENES:
            scene = mi.load_file(os.path.join(ROOT, xml))
            mi.render(scene, spp=spp, seed=1_000).numpy()  # compile the kernels
            rates = {"photon": [], "mitsuba": []}
            for i in range(a.rounds):
                rates["photon"].append(photon_rate(toml, spp, out))
                rates["mitsuba"].append(mitsuba_rate(mi, scene, spp, i))
                print(f"{name}: Photon {rates['photon'][-1]:.1f}, "
                      f"Mitsuba {rates['mitsuba'][-1]:.1f} spp/s", flush=True)
            ratio = statistics.median(rates["mitsuba"]) / statistics.median(rates["photon"])
            print(f"{name}: Photon {min(rates['photon']):.1f}–{max(rates['photon']):.1f} spp/s, "
                  f"Mitsuba {min(rates['mitsuba']):.1f}–{max(rates['mitsuba']):.1f}: "
                  f"Mitsuba {ratio:.2f}× as fast")


if __name__ == "__main__":
    main()
