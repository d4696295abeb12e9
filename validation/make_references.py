#!/usr/bin/env python3
"""Render the Mitsuba 3 references of the validation scenes.

    pip install mitsuba numpy
    python validation/make_references.py              # every scene
    python validation/make_references.py NAME ...     # some scenes

For each scene directory validation/NAME/ this reads NAME.xml, renders it with the integrator
the XML names (max_depth = -1, box pixel filter) at the sample count given by the
`<default name="spp" .../>` line of the XML, and writes NAME/reference.exr (float32 RGB; a scene
made for a study rather than the suite writes the file its `<!-- reference-file: ... -->` line
names, study-reference.exr). The
scenes choose their integrator in generate_scenes.py (`Scene.integrator`): Mitsuba's `path` for
surfaces only, `volpath` for scenes with participating media (and for the Blender scenes that need
its shadow rays through masked or null surfaces); --integrator overrides it for a test.

The samples are rendered in passes of at most --pass-spp samples per pixel, each with its own
seed; the passes are split into two independent halves (seeds 0, 2, 4, ... and 1, 3, 5, ...),
and the reference is their mean. The relMSE of one half against the other,
mean((a - b)^2 / (((a + b) / 2)^2 + 0.01)) over pixels and channels, is printed as the noise
estimate: the reference's own relMSE against the converged image is about a quarter of it. A
pixel that comes out of a pass not finite (one NaN sample spoils it) is left out of that pass's
half, and the script lists such pixels (pass, row, column).

The references in the repository were made with Mitsuba 3.9.1 (drjit 1.5.0), variant
`llvm_ad_rgb` (LLVM 19 on 2 x86-64 cores); `scalar_rgb` gives the same image, slower. A spectral
variant (`--variant llvm_ad_spectral`, falling back to `scalar_spectral`) writes
NAME/reference-spectral.exr instead (the reference file's name with `-spectral` before `.exr`;
still linear sRGB: Mitsuba's film converts the spectral samples). For the LLVM variants, Dr.Jit
must find libLLVM: on Debian `apt-get install libllvm19`, then
`export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1` (this script tries
that path itself when the variable is unset).

Photon's `pbr` material (the glTF 2.0 metallic-roughness BRDF) has no Mitsuba plugin: the
scenes use `gltf_pbr`, the Python plugin in validation/gltf_pbr.py, registered here. It works in
RGB; in a spectral variant this script registers a subclass that upsamples its base colour and f0
as Mitsuba upsamples any RGB reflectance (the `srgb` model, Jakob and Hanika 2019).

Options: --variant (default llvm_ad_rgb, falling back to scalar_rgb; a spectral one to
scalar_spectral), --spp N (override the scene's count, e.g. for a quick look), --output FILE
(only with one scene), --pass-spp N,
--threads N (Dr.Jit's worker threads; default: all cores), --integrator NAME (override the
XML's, max_depth -1).
"""

import argparse
import glob
import os
import re
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MITSUBA_VERSION_USED = "3.9.1"
DEFAULT_VARIANT = "llvm_ad_rgb"


def scene_names():
    return sorted(
        os.path.basename(d)
        for d in glob.glob(os.path.join(HERE, "*"))
        if os.path.isfile(os.path.join(d, os.path.basename(d) + ".xml"))
    )


def scene_spp(xml_path):
    with open(xml_path) as f:
        m = re.search(r'<default\s+name="spp"\s+value="(\d+)"', f.read())
    if not m:
        raise SystemExit(f"{xml_path}: no <default name=\"spp\" value=\"...\"/>")
    return int(m.group(1))


def set_variant(mi, wanted):
    if wanted.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ:
        for cand in sorted(glob.glob("/usr/lib/x86_64-linux-gnu/libLLVM.so.*")) + sorted(
            glob.glob("/usr/lib/llvm-*/lib/libLLVM*.so*")
        ):
            os.environ["DRJIT_LIBLLVM_PATH"] = cand
            break
    try:
        mi.set_variant(wanted)
        return wanted
    except Exception as e:  # no LLVM: the scalar variant gives the same image, slower
        fallback = "scalar_spectral" if "spectral" in wanted else "scalar_rgb"
        print(f"variant {wanted} unavailable ({e}); using {fallback}", file=sys.stderr)
        mi.set_variant(fallback)
        return fallback


def register_gltf_pbr(mi):
    """Register the `gltf_pbr` plugin (validation/gltf_pbr.py). Its colours are RGB (mi.Color3f);
    in a spectral variant, register a subclass instead whose base colour and f0 are spectra:
    each RGB upsampled with Mitsuba's `srgb` model (Jakob and Hanika 2019, as Mitsuba upsamples
    any `<rgb>` reflectance) at the path's wavelengths, which eval/sample/eval_pdf note first.
    f0 = mix(0.04, base, metallic) is upsampled as an RGB: a grey 0.04 stays exactly flat, and
    for metallic 0 or 1 (the scenes' values) that is the mix of the upsampled colours."""
    import gltf_pbr  # the glTF metallic-roughness BRDF (Photon's pbr) as a Mitsuba plugin

    base_class = gltf_pbr.register()
    if not mi.is_spectral:
        return

    class SpectralGltfPbr(base_class):
        def __init__(self, props):
            base_class.__init__(self, props)
            self._wavelengths = None

        def _color(self, c):
            coeff = mi.srgb_model_fetch(mi.ScalarColor3f(c[0], c[1], c[2]))
            return mi.srgb_model_eval(coeff, self._wavelengths)

        def _eval(self, ctx, wi, wo):  # as the base class, with a spectrum for mi.Color3f(0)
            value = mi.Spectrum(0.0)
            if ctx.is_enabled(self.lobes[1], 1):
                value += self._diffuse(wi, wo)
            if not self.delta and ctx.is_enabled(self.lobes[0], 0):
                value += self._specular(wi, wo)
            return value * mi.Frame3f.cos_theta(wo)

        def eval(self, ctx, si, wo, active=True):
            self._wavelengths = si.wavelengths
            return base_class.eval(self, ctx, si, wo, active)

        def eval_pdf(self, ctx, si, wo, active=True):
            self._wavelengths = si.wavelengths
            return base_class.eval_pdf(self, ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            self._wavelengths = si.wavelengths
            return base_class.sample(self, ctx, si, sample1, sample2, active)

    mi.register_bsdf("gltf_pbr", lambda props: SpectralGltfPbr(props))


def half_rel_mse(a, b):
    import numpy as np

    m = 0.5 * (a + b)
    return float(np.mean((a - b) ** 2 / (m * m + 0.01)))


def reference_file(xml_path, spectral=False):
    """The reference's file name: `reference.exr`, or the one a `<!-- reference-file: NAME -->`
    line names (study-reference.exr for a scene made for an equal-time study, which stays out of
    `photon validate` and the tests); with `-spectral` before `.exr` for a spectral variant."""
    with open(xml_path) as f:
        m = re.search(r"<!--\s*reference-file:\s*(\S+)\s*-->", f.read())
    name = m.group(1) if m else "reference.exr"
    if spectral:
        stem, ext = os.path.splitext(name)
        name = f"{stem}-spectral{ext}"
    return name


def scene_integrator(xml_path):
    with open(xml_path) as f:
        m = re.search(r'<integrator\s+type="(\w+)"', f.read())
    return m.group(1) if m else "path"


def render(mi, name, spp, pass_spp, output, integrator=None):
    import numpy as np

    xml = os.path.join(HERE, name, f"{name}.xml")
    passes = max(2, -(-spp // pass_spp))
    passes += passes % 2  # an even number: two equal halves
    per_pass = spp // passes
    if per_pass * passes != spp:
        raise SystemExit(f"{name}: {spp} spp do not split into {passes} equal passes")
    # The sampler is made for one pass's count. Made for the whole count and asked for one
    # pass's samples, the multijitter sampler drew from a pattern meant for far more samples:
    # at 98304 spp the light-strip reference came out 6% dark, with deceptively low noise.
    import drjit as dr

    threads = dr.thread_count()
    if threads < 2:
        # Reading an EXR (env-spheres' sky.exr) hangs with one thread, as writing one does
        # (below): load the scene with two, then go back.
        dr.set_thread_count(2)
    scene = mi.load_file(xml, spp=per_pass)
    dr.set_thread_count(threads)
    used = scene_integrator(xml)
    override = None
    if integrator and integrator != used:
        override = mi.load_dict({"type": integrator, "max_depth": -1})
        used = integrator
    halves = [None, None]
    counts = [0.0, 0.0]  # per half: passes, or per pixel once a pass has a non-finite pixel
    dropped = []
    start = time.time()
    for k in range(passes):
        img = np.array(mi.render(scene, spp=per_pass, seed=k, integrator=override), dtype=np.float64)[:, :, :3]
        h = k % 2
        finite = np.isfinite(img).all(axis=2, keepdims=True)
        if not finite.all():
            # A NaN (or inf) sample spoils its pixel's whole pass: leave that pixel out of this
            # pass (the smoke-grid reference had 4 such pixels in 6144 spp, Mitsuba 3.9.1's
            # volpath in a heterogeneous medium). Without them nothing changes.
            bad = np.argwhere(~finite[:, :, 0])
            dropped += [(k, int(y), int(x)) for y, x in bad]
            img = np.where(finite, img, 0.0)
            counts[h] = counts[h] + finite.astype(np.float64)
        else:
            counts[h] = counts[h] + 1.0
        halves[h] = img if halves[h] is None else halves[h] + img
    secs = time.time() - start
    if dropped:
        print(f"{name}: {len(dropped)} non-finite pixel(s) left out of their pass (pass, row, column): "
              + ", ".join(map(str, dropped[:20])), flush=True)
    a, b = halves[0] / counts[0], halves[1] / counts[1]
    ref = (0.5 * (a + b)).astype(np.float32)
    noise = half_rel_mse(a, b)
    out = output or os.path.join(HERE, name, reference_file(xml, mi.is_spectral))
    if threads < 2:
        # Mitsuba 3.9.1 / Dr.Jit 1.5.0: after dr.set_thread_count(1), Bitmap.write of an EXR
        # never returns (seen here, cause not looked into): write it with two, then go back.
        dr.set_thread_count(2)
    mi.Bitmap(ref, pixel_format=mi.Bitmap.PixelFormat.RGB).write(out)
    dr.set_thread_count(threads)
    mean = ref.reshape(-1, 3).mean(axis=0)
    print(
        f"{name}: {used}, {spp} spp ({passes} passes) in {secs:.0f} s; half-vs-half relMSE {noise:.2e}; "
        f"mean RGB {mean[0]:.4f} {mean[1]:.4f} {mean[2]:.4f} -> {os.path.relpath(out)}",
        flush=True,
    )
    return secs, noise


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("names", nargs="*", help="scenes (default: all)")
    p.add_argument("--variant", default=DEFAULT_VARIANT)
    p.add_argument("--spp", type=int, help="override the scene's sample count")
    p.add_argument("--pass-spp", type=int, default=256, help="samples per pixel per pass")
    p.add_argument("--output", help="output file (one scene only)")
    p.add_argument("--threads", type=int, help="Dr.Jit worker threads (default: all cores)")
    p.add_argument("--integrator", help="override the XML's integrator (e.g. path, volpath)")
    a = p.parse_args()
    names = a.names or scene_names()
    unknown = [n for n in names if n not in scene_names()]
    if unknown:
        raise SystemExit(f"unknown scene(s): {', '.join(unknown)}; known: {', '.join(scene_names())}")
    if a.output and len(names) != 1:
        raise SystemExit("--output needs exactly one scene")

    import mitsuba as mi

    variant = set_variant(mi, a.variant)
    if a.threads:
        import drjit as dr

        dr.set_thread_count(a.threads)
    sys.path.insert(0, HERE)
    register_gltf_pbr(mi)
    mi.set_log_level(mi.LogLevel.Error)  # the samplers' "sample count rounded" warnings
    if mi.__version__ != MITSUBA_VERSION_USED:
        print(f"note: Mitsuba {mi.__version__}; the references were made with {MITSUBA_VERSION_USED}", file=sys.stderr)
    print(f"Mitsuba {mi.__version__}, variant {variant}", flush=True)
    total = 0.0
    for name in names:
        spp = a.spp or scene_spp(os.path.join(HERE, name, f"{name}.xml"))
        secs, _ = render(mi, name, spp, a.pass_spp, a.output, a.integrator)
        total += secs
    print(f"total {total:.0f} s")


if __name__ == "__main__":
    main()
