//! Every BSDF with a density, tested the way Mitsuba 3 tests its plugins: a χ² test of its
//! sampling against its own `pdf`, `eval`/`pdf` consistency with `sample`, reciprocity, and a
//! white furnace (energy ≤ 1, with the loss of single-scattering microfacets at high roughness
//! stated).

use crate::common;

use photon::material::microfacet::Ggx;
use photon::material::{
    Conductor, ConductorFresnel, Dielectric, Lambertian, Material, Metal, Part, Pbr,
    RoughDielectric, TransportMode,
};
use photon::math::{Rgb, Vec3};
use photon::sampling::{Rng, uniform_sphere};

fn gold(alpha_x: f32, alpha_y: f32) -> Material {
    let (eta, k) = Metal::Gold.ior();
    Material::Conductor(Conductor {
        ggx: Ggx { alpha_x, alpha_y },
        fresnel: ConductorFresnel::Complex { eta, k },
    })
}

fn white_metal(alpha: f32) -> Material {
    Material::Conductor(Conductor {
        ggx: Ggx::isotropic(alpha),
        fresnel: ConductorFresnel::Schlick { f0: Rgb::ONE },
    })
}

fn rough_glass(alpha: f32) -> Material {
    Material::RoughDielectric(RoughDielectric::new(1.5, Ggx::isotropic(alpha), Rgb::ONE))
}

fn pbr(base: f32, metallic: f32, roughness: f32) -> Material {
    Material::Pbr(Pbr::new(Rgb::splat(base), metallic, roughness))
}

fn direction(cos: f32, phi: f32) -> Vec3 {
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

/// χ² test of `sample_part` against `pdf_part` (see [`common::chi2_directions`]).
fn chi2(name: &str, m: &Material, wo: Vec3, part: Part, n: u64) {
    let z = common::chi2_directions(
        n,
        11,
        |rng| {
            let s = m.sample_part(
                wo,
                rng.next_f32(),
                rng.next_2d(),
                TransportMode::Radiance,
                part,
            )?;
            assert!(!s.is_specular(), "{name}: a delta lobe in a χ² test");
            Some(s.wi)
        },
        |wi| f64::from(m.pdf_part(wo, wi, part)),
    );
    assert!(z < 4.0, "{name}: χ² z-score {z:.2} (p < 3e-5)");
}

#[test]
fn sampling_matches_the_pdf_chi2() {
    let wo = Vec3::new(0.5, 0.2, 0.6).normalize();
    let inside = Vec3::new(-0.3, 0.4, -0.7).normalize();
    let cases: [(&str, Material, Vec3, Part); 9] = [
        (
            "lambertian",
            Material::Lambertian(Lambertian { albedo: Rgb::ONE }),
            wo,
            Part::All,
        ),
        ("gold α 0.3", gold(0.3, 0.3), wo, Part::All),
        ("gold α 0.15 × 0.5", gold(0.15, 0.5), wo, Part::All),
        (
            "rough glass α 0.3 from outside",
            rough_glass(0.3),
            wo,
            Part::All,
        ),
        (
            "rough glass α 0.5 from inside",
            rough_glass(0.5),
            inside,
            Part::All,
        ),
        ("pbr dielectric r 0.7", pbr(0.8, 0.0, 0.7), wo, Part::All),
        ("pbr half metal r 0.6", pbr(0.6, 0.5, 0.6), wo, Part::All),
        (
            "pbr rough part of r 0.3",
            pbr(0.8, 0.0, 0.3),
            wo,
            Part::Rough,
        ),
        (
            "pbr smooth part of r 0.5",
            pbr(0.8, 0.0, 0.5),
            wo,
            Part::Smooth,
        ),
    ];
    for (name, m, wo, part) in cases {
        if !m.has(part) {
            continue;
        }
        chi2(name, &m, wo, part, 400_000);
    }
}

/// `sample` returns the density `pdf` gives and the weight f·|cos|/pdf that `eval` gives.
#[test]
fn sample_agrees_with_eval_and_pdf() {
    let mut rng = Rng::keyed(12, &[]);
    for m in [
        gold(0.2, 0.2),
        gold(0.1, 0.6),
        rough_glass(0.1),
        rough_glass(0.6),
        pbr(0.7, 0.0, 0.5),
        pbr(0.7, 1.0, 0.2),
        pbr(0.7, 0.3, 0.9),
    ] {
        for mode in [TransportMode::Radiance, TransportMode::Importance] {
            for _ in 0..20_000 {
                let wo = uniform_sphere(rng.next_2d());
                let wo = if m.is_two_sided() {
                    Vec3::new(wo.x, wo.y, wo.z.abs())
                } else {
                    wo
                };
                let Some(s) = m.sample(wo, rng.next_f32(), rng.next_2d(), mode) else {
                    continue;
                };
                let pdf = m.pdf(wo, s.wi);
                assert!(
                    (s.pdf - pdf).abs() <= 1e-3 * pdf.max(1.0),
                    "{m:?}: pdf {} vs {pdf}",
                    s.pdf
                );
                let expect = m.eval(wo, s.wi, mode) * (s.wi.z.abs() / pdf);
                let err = (s.weight - expect).abs().max_element();
                assert!(
                    err <= 1e-3 * expect.max_element().max(1.0),
                    "{m:?}: weight {} vs {expect}",
                    s.weight
                );
            }
        }
    }
}

/// A sample's `eta` is the relative index across the refraction it took (1 on reflection),
/// and undoes the 1/eta² that radiance, and not importance, takes on crossing (Veach 1997,
/// §5.2): the path tracer's Russian roulette relies on it.
#[test]
fn a_refracted_sample_reports_the_index_it_crossed() {
    let mut rng = Rng::keyed(14, &[]);
    let smooth = Material::Dielectric(Dielectric::new(1.5, Rgb::ONE));
    let (mut entering, mut leaving) = (0, 0);
    for m in [
        rough_glass(0.1),
        rough_glass(0.5),
        smooth,
        gold(0.2, 0.2),
        pbr(0.7, 0.3, 0.5),
    ] {
        for _ in 0..5_000 {
            let wo = uniform_sphere(rng.next_2d());
            let wo = if m.is_two_sided() {
                wo.with_z(wo.z.abs())
            } else {
                wo
            };
            let (u_lobe, u) = (rng.next_f32(), rng.next_2d());
            let Some(radiance) = m.sample(wo, u_lobe, u, TransportMode::Radiance) else {
                continue;
            };
            let importance = m
                .sample(wo, u_lobe, u, TransportMode::Importance)
                .expect("the same numbers give a sample in either mode");
            assert_eq!(radiance.wi, importance.wi);
            let refracted = radiance.wi.z * wo.z < 0.0;
            let expected = match (refracted, wo.z > 0.0) {
                (false, _) => 1.0,
                (true, true) => 1.5,
                (true, false) => 1.0 / 1.5,
            };
            assert_eq!(radiance.eta, expected, "{m:?}: {wo} to {}", radiance.wi);
            if refracted {
                if wo.z > 0.0 {
                    entering += 1;
                } else {
                    leaving += 1;
                }
                let undone = radiance.weight * (radiance.eta * radiance.eta);
                assert!(
                    (undone - importance.weight).abs().max_element()
                        <= 1e-4 * importance.weight.max_element().max(1.0),
                    "{m:?}: {undone} vs {}",
                    importance.weight
                );
            }
        }
    }
    assert!(
        entering > 1000 && leaving > 1000,
        "{entering} in, {leaving} out"
    );
}

/// Reflection is symmetric; refraction obeys the adjoint relation of Veach (1997, §5.2): the
/// BSDF for importance is the radiance BSDF with its arguments swapped.
#[test]
fn bsdfs_are_reciprocal() {
    let mut rng = Rng::keyed(13, &[]);
    let reflective = [
        gold(0.3, 0.3),
        gold(0.2, 0.7),
        pbr(0.8, 0.0, 0.5),
        pbr(0.5, 0.5, 0.9),
    ];
    for m in reflective {
        for _ in 0..10_000 {
            let a = uniform_sphere(rng.next_2d());
            let b = uniform_sphere(rng.next_2d());
            let (a, b) = (a.with_z(a.z.abs()), b.with_z(b.z.abs()));
            let (f_ab, f_ba) = (
                m.eval(a, b, TransportMode::Radiance),
                m.eval(b, a, TransportMode::Radiance),
            );
            assert!(
                (f_ab - f_ba).abs().max_element() <= 1e-4 * f_ab.max_element().max(1.0),
                "{m:?}: {f_ab} vs {f_ba}"
            );
        }
    }
    let glass = rough_glass(0.4);
    let mut crossings = 0;
    for _ in 0..10_000 {
        let a = uniform_sphere(rng.next_2d());
        let b = uniform_sphere(rng.next_2d());
        let radiance = glass.eval(a, b, TransportMode::Radiance);
        let importance = glass.eval(b, a, TransportMode::Importance);
        if a.z * b.z < 0.0 && radiance != Rgb::ZERO {
            crossings += 1;
        }
        assert!(
            (radiance - importance).abs().max_element() <= 1e-3 * radiance.max_element().max(1.0),
            "{a} {b}: {radiance} vs {importance}"
        );
    }
    assert!(crossings > 1000, "the test saw refraction ({crossings})");
}

/// ∫ f |cos| dω from `n` samples of the BSDF.
fn directional_albedo(m: &Material, wo: Vec3, mode: TransportMode, n: u32) -> f64 {
    let mut rng = Rng::keyed(14, &[]);
    let mut sum = 0.0;
    for _ in 0..n {
        if let Some(s) = m.sample(wo, rng.next_f32(), rng.next_2d(), mode) {
            sum += f64::from(s.weight.x);
        }
    }
    sum / f64::from(n)
}

/// ∫ f |cos| dω of the lobes of one part, from `n` samples of that part.
fn part_albedo(m: &Material, wo: Vec3, part: Part, n: u32) -> f64 {
    let mut rng = Rng::keyed(15, &[]);
    let mut sum = 0.0;
    for _ in 0..n {
        if let Some(s) = m.sample_part(
            wo,
            rng.next_f32(),
            rng.next_2d(),
            TransportMode::Radiance,
            part,
        ) {
            sum += f64::from(s.weight.x);
        }
    }
    sum / f64::from(n)
}

/// A white conductor (F = 1) and clear rough glass lose energy only to the multiple scattering
/// between microfacets that a single-scattering model leaves out (Heitz et al. 2016): none
/// when smooth; measured for the metal, 0.3% at α = 0.05, 5% at α = 0.2, 31% at α = 0.5 and
/// 69% at α = 1 at normal incidence (GGX's long tail sends half of the reflections below the
/// horizon at α = 1; an independent implementation, `validation/gltf_pbr.py`, gives the same
/// 0.31). A white glTF material's lobes each stay within 1 (their sum does not, by its
/// specification).
#[test]
fn white_furnace_energy_is_at_most_one() {
    let n = 200_000;
    let mut losses = Vec::new();
    let mut last: Vec<(f32, f32, f64)> = Vec::new();
    for alpha in [0.05f32, 0.2, 0.5, 1.0] {
        for cos in [1.0f32, 0.5, 0.1] {
            let wo = direction(cos, 0.3);
            let metal = directional_albedo(&white_metal(alpha), wo, TransportMode::Radiance, n);
            let glass = directional_albedo(&rough_glass(alpha), wo, TransportMode::Importance, n);
            for (what, e) in [("metal", metal), ("glass", glass)] {
                assert!(e <= 1.0 + 1e-6, "{what} α {alpha} cos {cos}: {e}");
            }
            // The loss grows with roughness and is small for near-smooth lobes.
            if alpha <= 0.05 && cos >= 0.5 {
                assert!(metal > 0.99 && glass > 0.99, "α {alpha}: {metal} {glass}");
            }
            if let Some(&(a, c, before)) = last.iter().find(|l: &&(f32, f32, f64)| l.1 == cos) {
                assert!(
                    metal <= before + 0.005,
                    "loss shrinks from α {a} to {alpha} at cos {c}"
                );
            }
            last.retain(|l| l.1 != cos);
            last.push((alpha, cos, metal));
            losses.push(format!(
                "α {alpha} cos {cos}: metal {metal:.3}, glass {glass:.3}"
            ));
        }
    }
    let rough_grazing = directional_albedo(
        &white_metal(1.0),
        direction(0.1, 0.3),
        TransportMode::Radiance,
        n,
    );
    assert!(
        (0.5..0.8).contains(&rough_grazing),
        "the single-scattering loss at α = 1, grazing, is known to be large: {rough_grazing}"
    );
    // The glTF specification weights its diffuse term by 1 − F(v·h), with h the half vector
    // of the diffuse direction itself, not by what the specular lobe reflects from `wo`. Each
    // lobe alone conserves energy; their sum does not at oblique angles, most with a polished
    // coat: a white base reflects 1.03 at cos 0.5 and 1.55 at cos 0.1 (measured). Photon
    // follows the specification, as the glTF viewers its users compare with do.
    for cos in [1.0f32, 0.5, 0.1] {
        let wo = direction(cos, 1.0);
        for roughness in [0.0, 0.2] {
            let m = pbr(1.0, 0.0, roughness);
            for part in [Part::Rough, Part::Smooth] {
                let e = part_albedo(&m, wo, part, n);
                assert!(e <= 1.0 + 2e-3, "pbr r {roughness} {part:?} cos {cos}: {e}");
            }
        }
        for (metallic, roughness) in [(1.0, 0.0), (1.0, 0.5), (0.0, 0.5), (0.0, 1.0)] {
            let e = directional_albedo(
                &pbr(1.0, metallic, roughness),
                wo,
                TransportMode::Radiance,
                n,
            );
            let limit = if metallic == 1.0 { 1.0 + 1e-6 } else { 1.12 };
            assert!(e <= limit, "pbr m {metallic} r {roughness} cos {cos}: {e}");
        }
    }
    println!("{}", losses.join("\n"));
}
