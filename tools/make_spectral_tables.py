#!/usr/bin/env python3
"""Generate the data of Photon's spectral rendering (`src/spectrum/`).

What it makes
=============

``src/spectrum/tables.rs`` (generated Rust; do not edit it by hand):

* ``CIE_X``, ``CIE_Y``, ``CIE_Z``: the CIE 1931 2-degree colour-matching functions at 1 nm,
  360..=830 nm (471 entries each), and ``CIE_Y_INTEGRAL`` = sum of y-bar times 1 nm
  (about 106.857), the normalisation that gives a constant spectrum of 1 a luminance Y of 1.
* ``D65``: the CIE standard illuminant D65 relative spectral power distribution (100 at
  560 nm), the official 5 nm table over 360..=830 nm (95 entries; the CIE table starts at
  300 nm, the part below 360 nm is outside the renderer's range and left out), with
  ``D65_LAMBDA_START`` and ``D65_LAMBDA_STEP``.
* ``LINEAR_SRGB_TO_XYZ`` and ``XYZ_TO_LINEAR_SRGB``: the Rec. 709 / sRGB matrices, derived
  from the primaries (0.64, 0.33), (0.30, 0.60), (0.15, 0.06) and the D65 white
  (0.3127, 0.3290) (they agree with the 4-decimal matrix of IEC 61966-2-1 to 5e-5).
* ``D65_Y_NORMALIZATION``, ``A_Y_NORMALIZATION``: the factors that give the relative D65
  (linearly interpolated in its 5 nm table, as the Rust code does) and CIE illuminant A (its
  defining formula) a luminance of Y = 1, i.e. ``CIE_Y_INTEGRAL / sum(S * ybar)`` over the
  1 nm nodes; ``D65_LINEAR_SRGB``, ``A_LINEAR_SRGB``: their linear sRGB colours at Y = 1.

``src/spectrum/rgb_to_spectrum.bin``: a Jakob & Hanika 2019 table ("A Low-Dimensional Function
Space for Efficient Spectral Upsampling", Computer Graphics Forum 38(2), Eurographics 2019)
for linear sRGB (Rec. 709 primaries, D65 white). A reflectance s(lambda) is represented by
three coefficients as

    s(lambda) = sigmoid(c0 lambda^2 + c1 lambda + c2),   lambda in nm,
    sigmoid(x) = 0.5 + x / (2 sqrt(1 + x^2)).

Binary layout (all little-endian):

    offset 0   8 bytes   magic b"PHRGB2SP"
    offset 8   u32       version = 1
    offset 12  u32       RES (= 32)
    offset 16  RES f32   z nodes: z_k = smoothstep(smoothstep(k / (RES - 1))),
                         smoothstep(t) = t^2 (3 - 2 t); z_0 = 0, z_{RES-1} = 1
    then       3*RES*RES*RES*3 f32 coefficients, index order [maxc][z][y][x][c]:
               ((((maxc * RES + k) * RES + j) * RES + i) * 3 + c)

Entry (maxc, k, j, i) is the fit of the colour whose component ``maxc`` (0 = R, 1 = G, 2 = B)
is the largest and equals z = z_k, with component (maxc + 1) % 3 = x z and component
(maxc + 2) % 3 = y z, where x = i / (RES - 1) and y = j / (RES - 1). A lookup of an rgb in
[0, 1]^3 takes maxc = its largest component, z = rgb[maxc], x = rgb[(maxc+1)%3] / z,
y = rgb[(maxc+2)%3] / z and interpolates the coefficients trilinearly (x, y uniform; z in the
node list). The file is 16 + 4 RES + 36 RES^3 bytes (1 179 792 bytes at RES = 32).

The fit
=======

Each entry minimises the CIE76 colour difference (Euclidean distance in CIELAB) between the
target rgb and the colour of the reflectance s(lambda) lit by D65:

    XYZ = sum_lambda s(lambda) D65(lambda) xyzbar(lambda) / sum_lambda D65(lambda) ybar(lambda)

over the 1 nm nodes 360..=830 (D65 linearly interpolated there), with the Lab white point
the XYZ of s = 1 and the target's XYZ = LINEAR_SRGB_TO_XYZ rgb. The solver is Gauss-Newton
with an analytic Jacobian and Levenberg-Marquardt damping (a step is taken only if it lowers
the residual), on the polynomial in the normalised wavelength t = (lambda - 360) / 470, whose
coefficient vector is capped at a max-abs norm of 1000 (``--cap``; black and white want
infinite coefficients; the paper's reference code caps at 200, which leaves the darkest
saturated entries at up to 1.4 Delta E, against 0.05 here, while f32 evaluation stays
accurate); the result is converted to coefficients in nm and stored as f32. All entries of
one z slice (3 x RES x RES of them) are solved together with numpy. Warm start: the slice
at k = RES/5 (as the paper's reference code) is solved from c = 0, then z is swept outward
from it, up to 1 and down to 0, each slice starting from its neighbour's solution; entries
still poor after that (Delta E > 1e-3) are retried from zero and from the solutions of
their x/y neighbours.

The script then reports the fit quality (Delta E 76, the f32 coefficients evaluated in f32 as
the Rust code does): over the table entries and over random rgb in [0, 1]^3 looked up with
trilinear interpolation exactly as ``src/spectrum/mod.rs`` does.

Data sources
============

* CIE 1931 2-degree CMFs, 1 nm, 360..=830: colour-science
  (``pip install "colour-science==0.4.6"``; 0.4.6 works with numpy 1.26, 0.4.7 wants
  numpy 2) ``colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]``, the CIE table as
  distributed by the CVRL (cvrl.org, "Older CIE standards").
* D65, 5 nm, 360..=830: the CIE table (CIE 15:2004 Table T.1 / ISO 11664-2) as it stands in
  Mitsuba 3 (``mitsuba/include/mitsuba/core/spectrum.h``, ``d65_table``, of the ``mitsuba``
  pip package, tested with 3.9.1), checked value by value against colour-science's D65
  (``colour.SDS_ILLUMINANTS["D65"]``, whose table stops at 780 nm).
* Illuminant A: its CIE definition (CIE 15:2004, ISO 11664-2),
  S_A(lambda) = 100 (560/lambda)^5 (exp(c2 / (2848 * 560)) - 1) / (exp(c2 / (2848 lambda)) - 1),
  c2 = 1.435e7 nm K.

How to run
==========

From the repository root, with a Python that has numpy, colour-science and mitsuba::

    nice -n 10 python tools/make_spectral_tables.py [--out-dir src/spectrum] [--res 32]
        [--samples 10000] [--seed 1]

It takes 10 to 25 s on one core (the fit is nearly all of it) and prints the fit quality
(with RES = 32: Delta E 76 over the table entries mean 0.0001, max 0.05; over 10 000
random rgb after interpolation mean 0.11, 99th percentile 0.47, max 3.15). It is
deterministic: the same inputs give the same files.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import re
import struct
import sys
import time
import warnings

# One core: BLAS threads only fight each other over the small matrix products here.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

LAMBDA_MIN = 360
LAMBDA_MAX = 830
N_LAMBDA = LAMBDA_MAX - LAMBDA_MIN + 1  # 471 nodes at 1 nm
D65_STEP = 5
MAGIC = b"PHRGB2SP"
VERSION = 1
COEFF_CAP = 1000.0  # max |c| in the normalised-wavelength parameterisation

# Rec. 709 primaries and the D65 white (IEC 61966-2-1).
PRIMARIES = np.array([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]])
WHITE = np.array([0.3127, 0.3290])


# --------------------------------------------------------------------------------------------
# Data


def load_cmfs() -> np.ndarray:
    """The CIE 1931 2-degree CMFs at 1 nm over 360..=830 as a (471, 3) array."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour  # noqa: PLC0415 (slow import, and noisy about optional packages)

        cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
        wl = np.asarray(cmfs.wavelengths, dtype=np.float64)
        values = np.asarray(cmfs.values, dtype=np.float64)
    expected = np.arange(LAMBDA_MIN, LAMBDA_MAX + 1, dtype=np.float64)
    if wl.shape != expected.shape or np.any(wl != expected):
        sys.exit("colour-science's CIE 1931 CMFs are not at 1 nm over 360..=830")
    return values


def load_d65() -> np.ndarray:
    """The CIE D65 relative SPD at 5 nm over 360..=830 (95 values), from Mitsuba's header."""
    import mitsuba  # noqa: PLC0415

    header = pathlib.Path(mitsuba.__file__).parent / "include/mitsuba/core/spectrum.h"
    text = header.read_text()
    match = re.search(r"d65_table\[MI_CIE_SAMPLES\]\s*=\s*\{([^}]*)\}", text)
    if not match:
        sys.exit(f"no d65_table in {header}")
    values = np.array([float(v.rstrip("f")) for v in re.findall(r"[-0-9.e]+f?", match.group(1))])
    if values.shape != ((LAMBDA_MAX - LAMBDA_MIN) // D65_STEP + 1,):
        sys.exit(f"d65_table in {header} has {values.size} values, not 95")
    # Check against colour-science's copy of the CIE table (it stops at 780 nm).
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour  # noqa: PLC0415

        d65 = colour.SDS_ILLUMINANTS["D65"]
        wl = np.arange(LAMBDA_MIN, 781, D65_STEP)
        theirs = np.array([d65[w] for w in wl])
    if np.max(np.abs(theirs - values[: wl.size])) > 1e-4:
        sys.exit("Mitsuba's and colour-science's D65 tables disagree")
    if values[(560 - LAMBDA_MIN) // D65_STEP] != 100.0:
        sys.exit("D65 is not 100 at 560 nm")
    return values


def illuminant_a(lam: np.ndarray) -> np.ndarray:
    """CIE illuminant A by its definition (relative, 100 at 560 nm)."""
    c2 = 1.435e7  # nm K
    ratio = np.expm1(c2 / (2848.0 * 560.0)) / np.expm1(c2 / (2848.0 * lam))
    return 100.0 * (560.0 / lam) ** 5 * ratio


def srgb_matrices() -> tuple[np.ndarray, np.ndarray]:
    """(linear sRGB -> XYZ, XYZ -> linear sRGB) from the primaries and the white point."""
    xyz = np.column_stack([[x / y, 1.0, (1.0 - x - y) / y] for x, y in PRIMARIES])
    w = np.array([WHITE[0] / WHITE[1], 1.0, (1.0 - WHITE[0] - WHITE[1]) / WHITE[1]])
    m = xyz * np.linalg.solve(xyz, w)[None, :]
    return m, np.linalg.inv(m)


# --------------------------------------------------------------------------------------------
# Colour science


DELTA = 6.0 / 29.0


def lab_f(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """CIELAB's f(t) and its derivative."""
    t = np.maximum(t, 0.0)
    cube = t > DELTA**3
    tc = np.cbrt(np.where(cube, t, 1.0))
    f = np.where(cube, tc, t / (3 * DELTA**2) + 4.0 / 29.0)
    df = np.where(cube, 1.0 / (3.0 * tc * tc), 1.0 / (3 * DELTA**2))
    return f, df


def xyz_to_lab(xyz: np.ndarray, white: np.ndarray) -> np.ndarray:
    f, _ = lab_f(xyz / white)
    fx, fy, fz = f[..., 0], f[..., 1], f[..., 2]
    return np.stack([116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)], axis=-1)


def sigmoid(x: np.ndarray) -> np.ndarray:
    return 0.5 + x / (2.0 * np.sqrt(1.0 + x * x))


class Fitter:
    """Reflectance-under-D65 colour of sigmoid polynomials and their Gauss-Newton fit."""

    def __init__(self, cmfs: np.ndarray, d65_1nm: np.ndarray, rgb_to_xyz: np.ndarray, cap: float):
        # XYZ = K @ s, K[c, l] = D65(l) cmf_c(l) / sum D65 ybar (1 nm rectangle rule).
        self.k = (d65_1nm[:, None] * cmfs).T / np.sum(d65_1nm * cmfs[:, 1])
        self.white = self.k.sum(axis=1)  # XYZ of s = 1
        self.rgb_to_xyz = rgb_to_xyz
        self.cap = cap
        t = np.arange(N_LAMBDA, dtype=np.float64) / (N_LAMBDA - 1)
        self.basis = np.stack([t * t, t, np.ones_like(t)], axis=1)  # (471, 3)
        # dXYZ_a/dc_j = sum_l sigmoid'(p_l) K[a, l] B[l, j] = sigmoid'(p) @ kb, kb: (471, 9)
        kb = self.k[:, :, None] * self.basis[None, :, :]  # (3, 471, 3)
        self.kb = kb.transpose(1, 0, 2).reshape(N_LAMBDA, 9)

    def lab_target(self, rgb: np.ndarray) -> np.ndarray:
        return xyz_to_lab(rgb @ self.rgb_to_xyz.T, self.white)

    def residual(self, c: np.ndarray, lab_t: np.ndarray, jacobian: bool):
        """Lab(c) - Lab_target, and optionally d/dc, for (n, 3) coefficient vectors."""
        p = c @ self.basis.T  # (n, 471)
        q = 1.0 / np.sqrt(1.0 + p * p)
        s = 0.5 + 0.5 * p * q  # the sigmoid
        xyz = s @ self.k.T  # (n, 3)
        f, df = lab_f(xyz / self.white)
        fx, fy, fz = f[:, 0], f[:, 1], f[:, 2]
        lab = np.stack([116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)], axis=1)
        r = lab - lab_t
        if not jacobian:
            return r, None
        dxyz = ((0.5 * q * q * q) @ self.kb).reshape(-1, 3, 3)  # sigmoid' = 0.5 (1 + p^2)^-1.5
        g = df / self.white  # d f(X/Xn) / dX, ...
        dlab_dxyz = np.zeros((c.shape[0], 3, 3))
        dlab_dxyz[:, 0, 1] = 116 * g[:, 1]
        dlab_dxyz[:, 1, 0] = 500 * g[:, 0]
        dlab_dxyz[:, 1, 1] = -500 * g[:, 1]
        dlab_dxyz[:, 2, 1] = 200 * g[:, 1]
        dlab_dxyz[:, 2, 2] = -200 * g[:, 2]
        return r, dlab_dxyz @ dxyz

    def fit(
        self, lab_t: np.ndarray, c0: np.ndarray, max_iter: int = 100
    ) -> tuple[np.ndarray, np.ndarray]:
        """Minimise |Lab(c) - lab_t| from c0 (damped Gauss-Newton); returns (c, Delta E)."""
        c = c0.copy()
        n = c.shape[0]
        r, _ = self.residual(c, lab_t, False)
        cost = np.sum(r * r, axis=1)
        mu = np.full(n, 1e-4)
        active = np.ones(n, dtype=bool)
        for _ in range(max_iter):
            idx = np.nonzero(active)[0]
            if idx.size == 0:
                break
            ci = c[idx]
            r, jac = self.residual(ci, lab_t[idx], True)
            jt = np.swapaxes(jac, 1, 2)
            jtj = jt @ jac
            jtr = (jt @ r[:, :, None])[:, :, 0]
            diag = np.einsum("nii->ni", jtj)
            a = jtj + (mu[idx, None] * (diag + 1e-12))[:, :, None] * np.eye(3)
            try:
                step = -np.linalg.solve(a, jtr[:, :, None])[:, :, 0]
            except np.linalg.LinAlgError:
                step = -(np.linalg.pinv(a) @ jtr[:, :, None])[:, :, 0]
            cand = ci + step
            big = np.max(np.abs(cand), axis=1)
            cand *= np.where(big > self.cap, self.cap / np.maximum(big, 1e-300), 1.0)[:, None]
            rc, _ = self.residual(cand, lab_t[idx], False)
            cost_c = np.sum(rc * rc, axis=1)
            old = cost[idx]
            ok = np.isfinite(cost_c) & (cost_c < old)
            c[idx[ok]] = cand[ok]
            cost[idx[ok]] = cost_c[ok]
            mu[idx] = np.where(ok, np.maximum(mu[idx] / 3.0, 1e-12), mu[idx] * 8.0)
            # Done: converged (dE < 1e-7), stuck (the damping has grown huge), or crawling
            # (an accepted step that gains almost nothing, as towards infinite coefficients).
            crawl = ok & (old - cost_c < 1e-10 * old)
            done = (cost[idx] < 1e-14) | (mu[idx] > 1e10) | crawl
            active[idx[done]] = False
        return c, np.sqrt(cost)


def to_nm_coefficients(c: np.ndarray) -> np.ndarray:
    """Coefficients of the polynomial in t = (lambda - 360)/470 -> in lambda (nm)."""
    a, b, c2 = c[..., 0], c[..., 1], c[..., 2]
    w = float(LAMBDA_MAX - LAMBDA_MIN)
    l0 = float(LAMBDA_MIN)
    return np.stack(
        [a / (w * w), b / w - 2.0 * a * l0 / (w * w), c2 - b * l0 / w + a * l0 * l0 / (w * w)],
        axis=-1,
    )


def smoothstep(t: np.ndarray) -> np.ndarray:
    return t * t * (3.0 - 2.0 * t)


def table_rgb(res: int, znodes: np.ndarray) -> np.ndarray:
    """The target rgb of every entry, shape (3, RES, RES, RES, 3) = [maxc][z][y][x][rgb]."""
    u = np.arange(res) / (res - 1)
    rgb = np.zeros((3, res, res, res, 3))
    for l in range(3):
        z = znodes[:, None, None]
        rgb[l, :, :, :, l] = np.broadcast_to(z, (res, res, res))
        rgb[l, :, :, :, (l + 1) % 3] = u[None, None, :] * z
        rgb[l, :, :, :, (l + 2) % 3] = u[None, :, None] * z
    return rgb


def fit_table(fitter: Fitter, res: int, znodes: np.ndarray, log) -> tuple[np.ndarray, np.ndarray]:
    """Fit all entries; returns (coefficients in t, Delta E) shaped [maxc][z][y][x](3)."""
    rgb = table_rgb(res, znodes)
    coeffs = np.zeros((3, res, res, res, 3))
    de = np.zeros((3, res, res, res))

    def solve_slice(k: int, init: np.ndarray) -> None:
        lab_t = fitter.lab_target(rgb[:, k].reshape(-1, 3))
        c, d = fitter.fit(lab_t, init.reshape(-1, 3))
        # Retry the poor ones from their x/y neighbours' solutions (and from zero).
        for _ in range(2):
            if not np.any(d > 1e-3):
                break
            cs = c.reshape(3, res, res, 3)
            for cand in [np.zeros_like(cs)] + [
                np.roll(cs, s, axis=ax) for ax in (1, 2) for s in (1, -1)
            ]:
                cand = cand.reshape(-1, 3)
                bad = np.nonzero(d > 1e-3)[0]
                if bad.size == 0:
                    break
                c2, d2 = fitter.fit(lab_t[bad], cand[bad])
                better = d2 < d[bad]
                c[bad[better]] = c2[better]
                d[bad[better]] = d2[better]
        coeffs[:, k] = c.reshape(3, res, res, 3)
        de[:, k] = d.reshape(3, res, res)

    start = res // 5
    solve_slice(start, np.zeros((3, res, res, 3)))
    for k in range(start + 1, res):
        solve_slice(k, coeffs[:, k - 1])
    for k in range(start - 1, -1, -1):
        solve_slice(k, coeffs[:, k + 1])
    log(f"  fit: max dE (in f64, before f32 rounding) {de.max():.3g}")
    return coeffs, de


# --------------------------------------------------------------------------------------------
# The table as the Rust code uses it


def eval_f32(c_nm: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """s(lambda) for f32 nm-coefficients (n, 3), evaluated in f32 like `SigmoidPolynomial`."""
    c = c_nm.astype(np.float32)
    lam = lam.astype(np.float32)
    x = (c[:, 0:1] * lam[None, :] + c[:, 1:2]) * lam[None, :] + c[:, 2:3]
    with np.errstate(over="ignore", invalid="ignore"):
        s = np.float32(0.5) + x / (np.float32(2.0) * np.sqrt(np.float32(1.0) + x * x))
    s = np.where(np.isinf(x), np.where(x > 0, 1.0, 0.0), s)
    return s.astype(np.float64)


def lookup(table: np.ndarray, znodes: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    """Trilinear lookup of nm-coefficients for rgb in [0,1]^3 (not all equal), as mod.rs."""
    res = znodes.size
    r, g, b = rgb[:, 0], rgb[:, 1], rgb[:, 2]
    maxc = np.where(r > g, np.where(r > b, 0, 2), np.where(g > b, 1, 2))
    n = np.arange(rgb.shape[0])
    z = rgb[n, maxc]
    x = rgb[n, (maxc + 1) % 3] / z * (res - 1)
    y = rgb[n, (maxc + 2) % 3] / z * (res - 1)
    xi = np.minimum(np.floor(x).astype(int), res - 2)
    yi = np.minimum(np.floor(y).astype(int), res - 2)
    zi = np.clip(np.searchsorted(znodes, z, side="right") - 1, 0, res - 2)
    dx, dy = x - xi, y - yi
    dz = (z - znodes[zi]) / (znodes[zi + 1] - znodes[zi])
    out = np.zeros((rgb.shape[0], 3))
    for oz in (0, 1):
        for oy in (0, 1):
            for ox in (0, 1):
                w = (dz if oz else 1 - dz) * (dy if oy else 1 - dy) * (dx if ox else 1 - dx)
                out += w[:, None] * table[maxc, zi + oz, yi + oy, xi + ox]
    return out


def delta_e_of(fitter: Fitter, c_nm: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    lam = np.arange(LAMBDA_MIN, LAMBDA_MAX + 1, dtype=np.float64)
    out = np.empty(rgb.shape[0])
    for lo in range(0, rgb.shape[0], 4096):
        s = eval_f32(c_nm[lo : lo + 4096], lam)
        lab = xyz_to_lab(s @ fitter.k.T, fitter.white)
        out[lo : lo + 4096] = np.linalg.norm(lab - fitter.lab_target(rgb[lo : lo + 4096]), axis=1)
    return out


# --------------------------------------------------------------------------------------------
# Output


def f32_literal(v: float) -> str:
    """The shortest decimal that reads back as the same f32."""
    s = np.format_float_positional(np.float32(v), unique=True, trim="0")
    if s.startswith("-0.0") and float(s) == 0.0:
        s = "0.0"
    return s


def rust_array(name: str, values, doc: str) -> str:
    items = [f32_literal(v) for v in values]
    lines, line = [], "   "
    for it in items:
        if len(line) + len(it) + 2 > 96:
            lines.append(line)
            line = "   "
        line += " " + it + ","
    lines.append(line)
    body = "\n".join(lines)
    return f"{doc}#[rustfmt::skip]\npub const {name}: [f32; {len(items)}] = [\n{body}\n];\n"


def rust_matrix(name: str, m: np.ndarray, doc: str) -> str:
    rows = ",\n".join("    [" + ", ".join(f32_literal(v) for v in row) + "]" for row in m)
    return f"{doc}#[rustfmt::skip]\npub const {name}: [[f32; 3]; 3] = [\n{rows},\n];\n"


def write_tables_rs(
    path: pathlib.Path, cmfs, y_integral, d65, m_to_xyz, m_to_rgb, norms, rgbs
) -> None:
    parts = [
        "//! CIE data and colour-space constants of the spectral renderer.\n"
        "//!\n"
        "//! GENERATED by `tools/make_spectral_tables.py`; do not edit: change the script and run\n"
        "//! it again. Sources: the CIE 1931 2-degree colour-matching functions (1 nm, CVRL's copy\n"
        "//! of the CIE table, via colour-science), the CIE D65 table (5 nm, CIE 15:2004), CIE\n"
        "//! illuminant A by its defining formula, Rec. 709 primaries with the D65 white.\n"
        "\n"
        "#![allow(\n"
        "    clippy::approx_constant,\n"
        "    clippy::excessive_precision,\n"
        "    clippy::unreadable_literal\n"
        ")]\n"
        "\n"
        "/// Shortest wavelength of the CIE tables, nm.\n"
        f"pub const CIE_LAMBDA_START: f32 = {LAMBDA_MIN}.0;\n"
        "/// Number of 1 nm entries of the CIE tables (360..=830 nm).\n"
        f"pub const CIE_SAMPLES: usize = {N_LAMBDA};\n",
        rust_array("CIE_X", cmfs[:, 0], "/// CIE 1931 2-degree x-bar at 360, 361, ..., 830 nm.\n"),
        rust_array("CIE_Y", cmfs[:, 1], "/// CIE 1931 2-degree y-bar at 360, 361, ..., 830 nm.\n"),
        rust_array("CIE_Z", cmfs[:, 2], "/// CIE 1931 2-degree z-bar at 360, 361, ..., 830 nm.\n"),
        "/// Sum of `CIE_Y` times 1 nm: the integral of y-bar, so that a spectrum S has luminance\n"
        "/// Y = sum(S y-bar) / CIE_Y_INTEGRAL and a constant spectrum of 1 has Y = 1.\n"
        f"pub const CIE_Y_INTEGRAL: f32 = {f32_literal(y_integral)};\n",
        "/// Wavelength of the first `D65` entry, nm.\n"
        f"pub const D65_LAMBDA_START: f32 = {LAMBDA_MIN}.0;\n"
        "/// Spacing of the `D65` entries, nm.\n"
        f"pub const D65_LAMBDA_STEP: f32 = {D65_STEP}.0;\n",
        rust_array(
            "D65",
            d65,
            "/// CIE standard illuminant D65, relative spectral power (100 at 560 nm), the CIE's 5 nm\n"
            "/// table over 360, 365, ..., 830 nm (the part of the CIE table below 360 nm is left out).\n",
        ),
        "/// Factor that gives `D65` (linearly interpolated) a luminance Y of 1: CIE_Y_INTEGRAL /\n"
        "/// sum over the 1 nm nodes of D65 y-bar.\n"
        f"pub const D65_Y_NORMALIZATION: f32 = {f32_literal(norms[0])};\n"
        "/// Factor that gives CIE illuminant A (100 at 560 nm) a luminance Y of 1.\n"
        f"pub const A_Y_NORMALIZATION: f32 = {f32_literal(norms[1])};\n"
        "/// Linear sRGB of D65 at luminance 1 (close to (1, 1, 1): the table's white is not\n"
        "/// exactly the rounded (0.3127, 0.3290) of sRGB).\n"
        f"pub const D65_LINEAR_SRGB: [f32; 3] = [{', '.join(f32_literal(v) for v in rgbs[0])}];\n"
        "/// Linear sRGB of CIE illuminant A at luminance 1.\n"
        f"pub const A_LINEAR_SRGB: [f32; 3] = [{', '.join(f32_literal(v) for v in rgbs[1])}];\n",
        rust_matrix(
            "LINEAR_SRGB_TO_XYZ",
            m_to_xyz,
            "/// Linear sRGB (Rec. 709 primaries, D65 white) to CIE 1931 XYZ, row-major: XYZ = M rgb.\n",
        ),
        rust_matrix(
            "XYZ_TO_LINEAR_SRGB",
            m_to_rgb,
            "/// CIE 1931 XYZ to linear sRGB, row-major: the inverse of `LINEAR_SRGB_TO_XYZ`.\n",
        ),
    ]
    path.write_text("\n".join(parts))


def write_bin(path: pathlib.Path, res: int, znodes: np.ndarray, table_nm: np.ndarray) -> int:
    data = MAGIC + struct.pack("<II", VERSION, res) + znodes.astype("<f4").tobytes()
    data += np.ascontiguousarray(table_nm, dtype="<f4").tobytes()
    path.write_bytes(data)
    return len(data)


# --------------------------------------------------------------------------------------------


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    root = pathlib.Path(__file__).resolve().parent.parent
    parser.add_argument("--out-dir", type=pathlib.Path, default=root / "src" / "spectrum")
    parser.add_argument("--res", type=int, default=32)
    parser.add_argument("--samples", type=int, default=10000, help="random rgb for the report")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--cap", type=float, default=COEFF_CAP, help="coefficient cap (in t)")
    args = parser.parse_args()
    t_start = time.perf_counter()

    def log(msg: str) -> None:
        print(f"[{time.perf_counter() - t_start:7.1f} s] {msg}", flush=True)

    res = args.res
    cmfs = load_cmfs()
    d65 = load_d65()
    lam = np.arange(LAMBDA_MIN, LAMBDA_MAX + 1, dtype=np.float64)
    d65_1nm = np.interp(lam, np.arange(LAMBDA_MIN, LAMBDA_MAX + 1, D65_STEP), d65)
    y_integral = float(np.sum(cmfs[:, 1]))
    m_to_xyz, m_to_rgb = srgb_matrices()

    norms, rgbs = [], []
    for name, spd in (("D65", d65_1nm), ("A", illuminant_a(lam))):
        norm = y_integral / float(np.sum(spd * cmfs[:, 1]))
        xyz = (spd * norm) @ cmfs / y_integral
        norms.append(norm)
        rgbs.append(m_to_rgb @ xyz)
        xy = xyz[:2] / xyz.sum()
        log(f"  {name}: Y-normalisation {norm:.6g}, xy ({xy[0]:.5f}, {xy[1]:.5f})")
    log(f"loaded data: CIE_Y_INTEGRAL = {y_integral:.6f}")

    fitter = Fitter(cmfs, d65_1nm, m_to_xyz, args.cap)
    znodes = smoothstep(smoothstep(np.arange(res) / (res - 1)))
    coeffs_t, _ = fit_table(fitter, res, znodes, log)
    table_nm = to_nm_coefficients(coeffs_t).astype(np.float32)
    log("fitted the table")

    # Report: the stored (f32) entries, evaluated in f32.
    rgb = table_rgb(res, znodes).reshape(-1, 3)
    de_entries = delta_e_of(fitter, table_nm.reshape(-1, 3), rgb).reshape(3, res, res, res)
    interior = de_entries[:, 1:]  # z = 0 is black whatever x, y say
    worst = np.unravel_index(np.argmax(de_entries), de_entries.shape)
    print(
        f"table entries ({de_entries.size}): dE76 mean {de_entries.mean():.3g}, "
        f"max {de_entries.max():.3g} at [maxc, z, y, x] = {tuple(int(i) for i in worst)} "
        f"rgb {np.round(table_rgb(res, znodes)[worst], 4)}; "
        f"99th pct {np.percentile(de_entries, 99):.3g}; share > 1: {np.mean(de_entries > 1):.4f}; "
        f"excluding z = 0: max {interior.max():.3g}"
    )
    rng = np.random.default_rng(args.seed)
    samples = rng.random((args.samples, 3))
    de_rand = delta_e_of(fitter, lookup(table_nm.astype(np.float64), znodes, samples), samples)
    worst = samples[np.argmax(de_rand)]
    print(
        f"random rgb in [0,1]^3 ({args.samples}, trilinear): dE76 mean {de_rand.mean():.3g}, "
        f"median {np.median(de_rand):.3g}, 99th pct {np.percentile(de_rand, 99):.3g}, "
        f"max {de_rand.max():.3g} at rgb {np.round(worst, 4)}"
    )
    inner = np.all((samples > 0.02) & (samples < 0.98), axis=1)
    print(f"  of them inside [0.02, 0.98]^3 ({inner.sum()}): max dE76 {de_rand[inner].max():.3g}")

    out = args.out_dir
    out.mkdir(parents=True, exist_ok=True)
    write_tables_rs(out / "tables.rs", cmfs, y_integral, d65, m_to_xyz, m_to_rgb, norms, rgbs)
    size = write_bin(out / "rgb_to_spectrum.bin", res, znodes, table_nm)
    log(f"wrote {out / 'tables.rs'} and {out / 'rgb_to_spectrum.bin'} ({size} bytes)")


if __name__ == "__main__":
    main()
