#!/usr/bin/env python3
"""The glTF 2.0 metallic-roughness BRDF as a Mitsuba 3 BSDF plugin, `gltf_pbr`, for the
validation references of Photon's `type = "pbr"` material. Mitsuba has no such plugin; this one
is written from the glTF 2.0 specification, Appendix B (sections "Specular BRDF", "Diffuse
BRDF", "Fresnel", "Metal BRDF and Dielectric BRDF"), not from Photon's code.

    import gltf_pbr; gltf_pbr.register()   # after mi.set_variant(...): registers "gltf_pbr"
    python validation/gltf_pbr.py  # self-test: white furnace, pdf integral, chi^2, weights

XML (one-sided like Mitsuba's `diffuse`: wrap it in `twosided` where the back can be seen):

    <bsdf type="twosided"><bsdf type="gltf_pbr">
        <rgb name="base_color" value="0.9, 0.5, 0.3"/>
        <float name="metallic" value="0"/>      <!-- default 0 -->
        <float name="roughness" value="0.5"/>   <!-- perceptual; default 0.5 -->
    </bsdf></bsdf>

The BRDF, with V the direction toward the eye, L toward the light, H = normalize(L + V),
alpha = roughness^2 and w = (1 - |V.H|)^5:

    f = (1 - m) [(1 - F_d) base / pi + F_d D Vis] + m F_m D Vis
    F_d = 0.04 + 0.96 w,   F_m = base + (1 - base) w
    D   = alpha^2 / (pi ((N.H)^2 (alpha^2 - 1) + 1)^2)                    (GGX)
    Vis = 1 / (2 (|N.V| sqrt(alpha^2 + (1 - alpha^2) (N.L)^2)
                  + |N.L| sqrt(alpha^2 + (1 - alpha^2) (N.V)^2)))        (height-correlated Smith)

Roughness 0: with alpha below 1e-3 (roughness below about 0.03) the specular part is a delta
mirror lobe of weight F(cos theta) = f0 + (1 - f0) (1 - cos theta)^5, f0 = mix(0.04, base, m)
(the limit of the GGX term as alpha -> 0, where Vis D -> delta and H -> N), plus the same diffuse
part (its F_d still uses the H of L and V). No clamping of alpha.

Sampling: the specular lobe by GGX visible normals (Mitsuba's MicrofacetDistribution, GGX,
sample_visible) or the mirror direction, the diffuse lobe by the cosine; the lobe is picked with
probability P_spec = S / (S + (1 - m) lum(base) (1 - S)), S = lum(Schlick(f0, cos theta_i)),
and the pdf of a rough sample is the mixture of both, so eval / pdf is the weight either way.
"""

import drjit as dr
import mitsuba as mi


def _lum(c):
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]


def _positive(x):
    """x where it is positive, else 1: a denominator safe in the scalar variants too, where both
    sides of a select are computed (the JIT variants would give a harmless inf)."""
    return dr.select(x > 0, x, 1.0)


def register():
    """Define the plugin for the current variant and register it as "gltf_pbr" (Mitsuba's
    classes depend on the variant: call after mi.set_variant)."""

    class GltfPbr(mi.BSDF):
        DELTA_ALPHA = 1e-3

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            base = props.get("base_color", mi.ScalarColor3f(0.8, 0.8, 0.8))
            if isinstance(base, (int, float)):
                base = [base, base, base]
            self.base = [float(base[0]), float(base[1]), float(base[2])]
            self.metallic = float(props.get("metallic", 0.0))
            self.roughness = float(props.get("roughness", 0.5))
            self.alpha = self.roughness * self.roughness
            self.delta = self.alpha < self.DELTA_ALPHA
            m = self.metallic
            self.f0 = [0.04 * (1 - m) + b * m for b in self.base]
            self.diffuse_weight = (1 - m) * _lum(self.base)  # for the lobe choice only
            spec = mi.BSDFFlags.DeltaReflection if self.delta else mi.BSDFFlags.GlossyReflection
            self.lobes = [spec, mi.BSDFFlags.DiffuseReflection]  # components 0 and 1
            self.m_components = [lobe | mi.BSDFFlags.FrontSide for lobe in self.lobes]
            self.m_flags = self.m_components[0] | self.m_components[1]
            if not self.delta:
                self.distr = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.alpha, True)

        # The BRDF -------------------------------------------------------------------------------
        def _color(self, c):
            return mi.Color3f(c[0], c[1], c[2])

        def _diffuse(self, wi, wo):
            """(1 - m) (1 - F_d) base / pi, F_d with H = normalize(wi + wo)."""
            h = dr.normalize(wi + wo)
            w = dr.power(1 - dr.abs(dr.dot(wi, h)), 5)
            fd = 0.04 + 0.96 * w
            return (1 - self.metallic) * (1 - fd) * self._color(self.base) * dr.inv_pi

        def _specular(self, wi, wo):
            """[(1 - m) F_d + m F_m] D Vis (the rough lobe)."""
            h = dr.normalize(wi + wo)
            w = dr.power(1 - dr.abs(dr.dot(wi, h)), 5)
            a2 = self.alpha * self.alpha
            nh = mi.Frame3f.cos_theta(h)
            d = a2 / (dr.pi * dr.square(nh * nh * (a2 - 1) + 1))
            nv, nl = dr.abs(mi.Frame3f.cos_theta(wi)), dr.abs(mi.Frame3f.cos_theta(wo))
            vis = 0.5 / _positive(nv * dr.sqrt(a2 + (1 - a2) * nl * nl) + nl * dr.sqrt(a2 + (1 - a2) * nv * nv))
            vis = dr.select((dr.dot(h, wi) > 0) & (dr.dot(h, wo) > 0) & (nh > 0), vis, 0.0)
            f0 = self._color(self.f0)
            fresnel = f0 + (1 - f0) * w  # = (1 - m) F_d + m F_m
            return fresnel * d * vis

        def _mirror_weight(self, cos_i):
            f0 = self._color(self.f0)
            return f0 + (1 - f0) * dr.power(1 - cos_i, 5)

        # Lobe choice and pdf ----------------------------------------------------------------------
        def _p_spec(self, ctx, cos_i):
            has_spec, has_diff = ctx.is_enabled(self.lobes[0], 0), ctx.is_enabled(self.lobes[1], 1)
            if not has_diff:
                return mi.Float(1.0 if has_spec else 0.0)
            if not has_spec:
                return mi.Float(0.0)
            f0 = _lum(self.f0)
            s = f0 + (1 - f0) * dr.power(1 - cos_i, 5)
            return s / _positive(s + self.diffuse_weight * (1 - s))

        def _spec_pdf(self, wi, wo):
            h = dr.normalize(wi + wo)
            return self.distr.pdf(wi, h) / _positive(4 * dr.abs(dr.dot(wo, h)))

        def _pdf(self, ctx, wi, wo):
            p = self._p_spec(ctx, mi.Frame3f.cos_theta(wi))
            pdf = (1 - p) * mi.warp.square_to_cosine_hemisphere_pdf(wo)
            if not self.delta:
                pdf += p * self._spec_pdf(wi, wo)
            return pdf

        def _eval(self, ctx, wi, wo):
            value = mi.Color3f(0.0)
            if ctx.is_enabled(self.lobes[1], 1):
                value += self._diffuse(wi, wo)
            if not self.delta and ctx.is_enabled(self.lobes[0], 0):
                value += self._specular(wi, wo)
            return value * mi.Frame3f.cos_theta(wo)

        # The BSDF interface ------------------------------------------------------------------------
        def _front(self, si, wo, active):
            return active & (mi.Frame3f.cos_theta(si.wi) > 0) & (mi.Frame3f.cos_theta(wo) > 0)

        def eval(self, ctx, si, wo, active=True):
            return dr.select(self._front(si, wo, active), self._eval(ctx, si.wi, wo), 0.0)

        def pdf(self, ctx, si, wo, active=True):
            return dr.select(self._front(si, wo, active), self._pdf(ctx, si.wi, wo), 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            ok = self._front(si, wo, active)
            return dr.select(ok, self._eval(ctx, si.wi, wo), 0.0), dr.select(ok, self._pdf(ctx, si.wi, wo), 0.0)

        def sample(self, ctx, si, sample1, sample2, active=True):
            wi = si.wi
            cos_i = mi.Frame3f.cos_theta(wi)
            active = active & (cos_i > 0)
            p = self._p_spec(ctx, cos_i)
            pick_spec = sample1 < p
            bs = dr.zeros(mi.BSDFSample3f)
            wo_diff = mi.warp.square_to_cosine_hemisphere(sample2)
            if self.delta:
                wo_spec = mi.Vector3f(-wi.x, -wi.y, wi.z)
            else:
                m, _ = self.distr.sample(wi, sample2)
                wo_spec = mi.reflect(wi, m)
            bs.wo = dr.select(pick_spec, wo_spec, wo_diff)
            bs.eta = 1.0
            bs.sampled_component = dr.select(pick_spec, mi.UInt32(0), mi.UInt32(1))
            spec_type = mi.UInt32(+(mi.BSDFFlags.DeltaReflection if self.delta else mi.BSDFFlags.GlossyReflection))
            bs.sampled_type = dr.select(pick_spec, spec_type, mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
            ok = active & (mi.Frame3f.cos_theta(bs.wo) > 0)
            if self.delta:
                # The mirror sample scores the delta lobe alone; a diffuse sample, the diffuse lobe.
                pdf_diff = (1 - p) * mi.warp.square_to_cosine_hemisphere_pdf(bs.wo)
                bs.pdf = dr.select(pick_spec, p, pdf_diff)
                value = dr.select(pick_spec, self._mirror_weight(cos_i),
                                  self._diffuse(wi, bs.wo) * mi.Frame3f.cos_theta(bs.wo))
            else:
                bs.pdf = self._pdf(ctx, wi, bs.wo)
                value = self._eval(ctx, wi, bs.wo)
            ok &= bs.pdf > 0
            bs.pdf = dr.select(ok, bs.pdf, 0.0)
            return bs, dr.select(ok, value / _positive(bs.pdf), 0.0)

        def to_string(self):
            return (f"GltfPbr[base_color={self.base}, metallic={self.metallic}, roughness={self.roughness}"
                    f"{', delta specular' if self.delta else ''}]")

    mi.register_bsdf("gltf_pbr", lambda props: GltfPbr(props))
    return GltfPbr


# ------------------------------------------------------------------------------------------------
# Self-test


def _self_test():
    """White furnace, integral of the pdf, sample weights against eval, and Mitsuba's chi^2 test
    of sample() against pdf(). Returns True when every check passes."""
    import numpy as np
    from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain

    ctx = mi.BSDFContext()
    n = 1 << 21
    rng = np.random.default_rng(7)
    ok = True

    def bsdf(base, metallic, roughness):
        return mi.load_dict({"type": "gltf_pbr", "base_color": {"type": "rgb", "value": base},
                             "metallic": metallic, "roughness": roughness})

    def rand(*shape):
        return rng.random(shape if len(shape) > 1 else shape[0]).astype(np.float32)

    def test_mixture(si, alpha, cos_i):
        """Directions from an independent mixture: half cosine-weighted, half by D(h) cos(h)
        half vectors (inverted here, not Mitsuba's visible-normal sampler) reflected about h;
        returns wo and its density."""
        u1, u2, pick = rand(n), rand(n), rand(n) < 0.5
        a2 = max(alpha, 1e-3) ** 2
        cos_h = np.sqrt((1 - u1) / (1 + (a2 - 1) * u1))
        sin_h, phi = np.sqrt(1 - cos_h * cos_h), 2 * np.pi * u2
        h = mi.Vector3f(sin_h * np.cos(phi), sin_h * np.sin(phi), cos_h)
        wo_h = mi.reflect(si.wi, h)
        wo_c = mi.warp.square_to_cosine_hemisphere(mi.Point2f(u1, u2))
        wo = dr.select(mi.Bool(pick), wo_h, wo_c)
        hh = dr.normalize(si.wi + wo)
        d = a2 / (dr.pi * dr.square(hh.z * hh.z * (a2 - 1) + 1))
        pdf_h = dr.select(hh.z > 0, d * hh.z / (4 * dr.abs(dr.dot(wo, hh))), 0.0)
        return wo, 0.5 * pdf_h + 0.5 * mi.warp.square_to_cosine_hemisphere_pdf(wo)

    print("directional albedo (red) = mean sample weight, and by integrating eval with an independent "
          "estimator (+ the mirror's F(cos) when roughness is 0); integral of the pdf over the "
          "hemisphere against the fraction of samples that score (the rest fall below it)")
    for base, metallic in [(1.0, 1.0), (1.0, 0.0), ([0.9, 0.5, 0.3], 0.0), ([0.9, 0.5, 0.3], 1.0)]:
        for roughness in [0.0, 0.25, 0.5, 1.0]:
            b = bsdf(base, metallic, roughness)
            base3 = np.array(base if isinstance(base, list) else [base] * 3)
            f0 = 0.04 * (1 - metallic) + base3[0] * metallic
            for cos_i in [1.0, 0.5, 0.1]:
                si = dr.zeros(mi.SurfaceInteraction3f, n)
                si.wi = mi.Vector3f(float(np.sqrt(1 - cos_i * cos_i)), 0.0, cos_i)
                bs, w = b.sample(ctx, si, mi.Float(rand(n)), mi.Point2f(rand(n), rand(n)))
                by_sampling = float(np.mean(np.array(w[0])))
                scoring = float(np.mean(np.array(bs.pdf) > 0))
                wo, q = test_mixture(si, roughness * roughness, cos_i)
                q = dr.select(q > 0, q, 1.0)
                by_eval = float(np.mean(np.array(b.eval(ctx, si, wo)[0] / q)))
                pdf_int = float(np.mean(np.array(b.pdf(ctx, si, wo) / q)))
                if roughness == 0.0:
                    p = b.sample(ctx, si, mi.Float(np.zeros(n, np.float32)), mi.Point2f(rand(n), rand(n)))[0].pdf
                    by_eval += f0 + (1 - f0) * (1 - cos_i) ** 5
                    pdf_int += float(np.array(p)[0])  # the mirror's probability
                good = abs(by_sampling - by_eval) < 0.003 + 0.005 * by_eval and abs(pdf_int - scoring) < 0.005
                if base == 1.0 and metallic == 1.0:
                    good &= by_sampling <= 1.0 + 2e-3
                ok &= good
                print(f"  base {base} m={metallic:.0f} r={roughness:.2f} cos_i={cos_i:.1f}: albedo {by_sampling:.4f} "
                      f"(eval {by_eval:.4f}), pdf integral {pdf_int:.4f} (scoring {scoring:.4f})"
                      f"{'' if good else '  <-- FAILED'}")

    print("chi^2 test of sample() against pdf() (mitsuba.chi2; roughness 0: the diffuse lobe only)")
    for metallic, roughness in [(0.0, 0.5), (1.0, 0.25), (0.0, 1.0), (0.3, 0.75), (0.0, 0.0)]:
        params = {"type": "gltf_pbr", "base_color": {"type": "rgb", "value": [0.9, 0.5, 0.3]},
                  "metallic": metallic, "roughness": roughness}
        for cos_i in [0.9, 0.3]:
            wi = [float(np.sqrt(1 - cos_i * cos_i)), 0.0, cos_i]
            c = None if roughness > 0 else mi.BSDFContext(mi.TransportMode.Radiance, mi.BSDFFlags.DiffuseReflection)
            sample_func, pdf_func = BSDFAdapter("gltf_pbr", params, wi=wi, ctx=c)
            chi = ChiSquareTest(domain=SphericalDomain(), sample_func=sample_func, pdf_func=pdf_func,
                                sample_dim=3, res=101, ires=16)
            passed = chi.run()
            ok &= bool(passed)
            print(f"  m={metallic} r={roughness} cos_i={cos_i}: {'passed' if passed else 'FAILED: ' + chi.messages}")
    print("all checks passed" if ok else "SOME CHECKS FAILED")
    return ok


if __name__ == "__main__":
    import os
    import sys

    if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists("/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"):
        os.environ["DRJIT_LIBLLVM_PATH"] = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"
    mi.set_variant(sys.argv[1] if len(sys.argv) > 1 else "llvm_ad_rgb")
    register()
    sys.exit(0 if _self_test() else 1)
