#!/usr/bin/env python3
"""Equal-time comparison on a validation scene: Photon's integrators (`photon`, `sppm` and
`path` unless --integrators says) beside Mitsuba 3 (the integrator the scene's XML names:
`path`, or `volpath` for scenes with media), each given the same wall-clock budget, against
the scene's converged reference. Prints a Markdown table of relMSE, and relMSE and RMSE in a
crop (by default the glossy Cornell box's caustic under its rough glass sphere).

    cargo build --release
    python validation/equal_time.py                       # glossy-cornell, budgets 1, 4, 12 s
    python validation/equal_time.py --scene env-spheres --crop 0,0,128,128 --budgets 2 8
    python validation/equal_time.py --scene volumetric-caustic --integrators sppm ppm path \
        --crop 52,60,76,118 --budgets 12 60
    python validation/equal_time.py --scene cornell --scene-file cornell \
        --xml bench/mitsuba/cornell/cornell.xml --reference bench/references/cornell.exr \
        --integrators vcm sppm photon path --budgets 12 60 --crop 290,326,390,344

Budgets are met by calibration: a short run measures the fixed cost (photon tracing, JIT) and
the cost per sample, and the real run asks for the samples that fill the budget (`sppm` and
`ppm` take `--time` directly). Mitsuba renders passes of 8 samples with their own seeds until the next
would overrun the budget, and averages them; its first render compiles its kernels and is not
counted. Times are wall clock on the machine that runs it, with every core; the table reports the time each
run really took. Needs `pip install mitsuba numpy`.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PHOTON = os.environ.get("PHOTON", os.path.join(ROOT, "target", "release", "photon"))


def compare(image, reference, crop):
    """relMSE of the whole image, and relMSE and RMSE in the crop."""
    out = subprocess.run(
        [PHOTON, "compare", image, reference, "--json"], capture_output=True, text=True, check=True
    )
    whole = json.loads(out.stdout)["overall"]
    out = subprocess.run(
        [PHOTON, "compare", image, reference, "--json", "--crop", crop],
        capture_output=True,
        text=True,
        check=True,
    )
    in_crop = json.loads(out.stdout)["overall"]
    return whole["rel_mse"], in_crop["rel_mse"], in_crop["rmse"]


def photon_run(scene, integrator, args, out):
    start = time.time()
    r = subprocess.run(
        [PHOTON, "render", scene, "--integrator", integrator, "-q", "-o", out] + args,
        capture_output=True,
        text=True,
    )
    if r.returncode != 0:
        raise SystemExit(r.stderr)
    return time.time() - start


def photon_at(scene, integrator, budget, out):
    """Render with Photon's `integrator` in about `budget` seconds."""
    if integrator in ("sppm", "ppm", "vcm", "bdpt", "lighttrace"):
        secs = photon_run(scene, integrator, ["--time", str(budget)], out)
        return secs, f"--time {budget}"
    # Calibrate: fixed cost from a 1-spp run, per-sample cost from a 5-spp run.
    t1 = photon_run(scene, integrator, ["--spp", "1"], out)
    t5 = photon_run(scene, integrator, ["--spp", "5"], out)
    per_spp = max((t5 - t1) / 4, 1e-4)
    fixed = max(t1 - per_spp, 0.0)
    spp = max(1, int((budget - fixed) / per_spp))
    secs = photon_run(scene, integrator, ["--spp", str(spp)], out)
    return secs, f"{spp} spp"


def mitsuba_at(xml, budget, out, pass_spp=8):
    """Mitsuba's path tracer for about `budget` seconds: passes of `pass_spp` samples with their
    own seeds, averaged, until the next pass would overrun (its kernels compiled beforehand)."""
    import mitsuba as mi
    import numpy as np

    scene = mi.load_file(xml, spp=pass_spp)
    mi.render(scene, spp=pass_spp, seed=10_000)  # compile the kernels
    total = None
    passes = 0
    start = time.time()
    while True:
        t = time.time()
        img = np.array(mi.render(scene, spp=pass_spp, seed=passes), dtype=np.float64)[:, :, :3]
        total = img if total is None else total + img
        passes += 1
        elapsed = time.time() - start
        if elapsed + (time.time() - t) > budget:
            break
    secs = time.time() - start
    mi.Bitmap((total / passes).astype(np.float32), pixel_format=mi.Bitmap.PixelFormat.RGB).write(out)
    return secs, f"{passes * pass_spp} spp"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", default="glossy-cornell")
    p.add_argument("--budgets", type=float, nargs="+", default=[1.0, 4.0, 12.0])
    p.add_argument("--crop", default="90,100,112,110", help="x0,y0,x1,y1 (the caustic by default)")
    p.add_argument("--no-mitsuba", action="store_true")
    p.add_argument("--integrators", nargs="+", default=["photon", "sppm", "path"])
    p.add_argument("--scene-file", help="a scene outside the suite (a file or a built-in name)")
    p.add_argument("--xml", help="its Mitsuba twin")
    p.add_argument("--reference", help="its reference")
    a = p.parse_args()
    scene = a.scene_file or os.path.join(HERE, a.scene, f"{a.scene}.toml")
    xml = a.xml or os.path.join(HERE, a.scene, f"{a.scene}.xml")
    # A scene made for this study keeps its reference apart from the suite's.
    reference = os.path.join(HERE, a.scene, "study-reference.exr")
    if not os.path.exists(reference):
        reference = os.path.join(HERE, a.scene, "reference.exr")
    reference = a.reference or reference
    if not a.no_mitsuba:
        import mitsuba as mi

        sys.path.insert(0, HERE)
        from make_references import set_variant

        variant = set_variant(mi, "llvm_ad_rgb")
        import gltf_pbr

        gltf_pbr.register()
        mi.set_log_level(mi.LogLevel.Error)
        print(f"Mitsuba {mi.__version__} ({variant})", file=sys.stderr)
    m = None
    if not a.no_mitsuba:
        with open(xml) as f:
            m = re.search(r'<integrator\s+type="(\w+)"', f.read())
    mitsuba_name = f"Mitsuba 3 {m.group(1) if m else 'path'}"
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for budget in a.budgets:
            runs = [(name, lambda o, n=name: photon_at(scene, n, budget, o)) for name in a.integrators]
            if not a.no_mitsuba:
                runs.append((mitsuba_name, lambda o: mitsuba_at(xml, budget, o)))
            for name, run in runs:
                out = os.path.join(tmp, re.sub(r"\W", "_", name) + ".exr")
                secs, what = run(out)
                rel_mse, crop_rel_mse, crop_rmse = compare(out, reference, a.crop)
                rows.append((budget, name, secs, what, rel_mse, crop_rel_mse, crop_rmse))
                print(f"{budget:>5} s {name:<18} {secs:6.2f} s ({what}): relMSE {rel_mse:.5f}, crop relMSE {crop_rel_mse:.5f}, RMSE {crop_rmse:.4f}", file=sys.stderr, flush=True)
    print(f"| budget | renderer | time (s) | samples | relMSE | crop ({a.crop}) relMSE | crop RMSE |")
    print("|---:|---|---:|---|---:|---:|---:|")
    for budget, name, secs, what, rel_mse, crop_rel_mse, crop_rmse in rows:
        print(f"| {budget:g} s | {name} | {secs:.2f} | {what} | {rel_mse:.5f} | {crop_rel_mse:.5f} | {crop_rmse:.4f} |")


if __name__ == "__main__":
    main()
