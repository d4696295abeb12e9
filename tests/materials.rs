//! BSDF properties: white Lambertian reflects everything, reciprocity, energy conservation,
//! and the dielectric's Fresnel split.

use photon::material::{
    Dielectric, Lambertian, Material, Mirror, TransportMode, fresnel_dielectric,
};
use photon::math::{Rgb, Vec3};
use photon::sampling::{Rng, uniform_sphere};

#[test]
fn white_lambertian_reflects_everything_and_is_reciprocal() {
    let m = Material::Lambertian(Lambertian { albedo: Rgb::ONE });
    let mut rng = Rng::keyed(1, &[]);
    let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
    // Albedo by uniform-sphere integration of f·cos: ∫ f cos dω = 1.
    let n = 400_000;
    let mut sum = 0.0f64;
    for _ in 0..n {
        let wi = uniform_sphere(rng.next_2d());
        sum += f64::from(
            m.eval(wo, wi, TransportMode::Radiance).x * wi.z.max(0.0) * 4.0 * std::f32::consts::PI,
        );
        let wi2 = uniform_sphere(rng.next_2d());
        assert_eq!(
            m.eval(wi, wi2, TransportMode::Radiance),
            m.eval(wi2, wi, TransportMode::Radiance),
            "reciprocity"
        );
    }
    assert!(
        (sum / f64::from(n) - 1.0).abs() < 0.01,
        "albedo {}",
        sum / f64::from(n)
    );
    // Sampling gives weight = albedo and a pdf that agrees with pdf().
    for _ in 0..1000 {
        let s = m
            .sample(wo, rng.next_f32(), rng.next_2d(), TransportMode::Radiance)
            .expect("sample");
        assert_eq!(s.weight, Rgb::ONE);
        assert!((s.pdf - m.pdf(wo, s.wi)).abs() < 1e-5);
        assert!(s.wi.z >= 0.0 && !s.is_specular());
    }
}

#[test]
fn mirror_reflects_about_the_normal() {
    let m = Material::Mirror(Mirror {
        reflectance: Rgb::new(0.9, 0.8, 0.7),
    });
    let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
    let s = m
        .sample(wo, 0.5, glam::Vec2::ZERO, TransportMode::Radiance)
        .expect("sample");
    assert!((s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-6);
    assert_eq!(s.weight, Rgb::new(0.9, 0.8, 0.7));
    assert!(s.is_specular() && m.is_specular());
}

#[test]
fn dielectric_conserves_energy_and_picks_branches_by_fresnel() {
    let glass = Dielectric::new(1.5, Rgb::ONE);
    let m = Material::Dielectric(glass);
    let mut rng = Rng::keyed(2, &[]);
    for cos in [0.95f32, 0.5, 0.1, -0.95, -0.5, -0.3] {
        let sin = (1.0 - cos * cos).sqrt();
        let wo = Vec3::new(sin, 0.0, cos);
        let f = fresnel_dielectric(cos, 1.5);
        let (r, t) = glass.branches(wo, TransportMode::Importance);
        let total = r.weight.x + t.map_or(0.0, |t| t.weight.x);
        assert!(
            (total - 1.0).abs() < 1e-5,
            "flux is conserved at cos {cos}: {total}"
        );
        let n = 100_000;
        let mut reflected = 0;
        for _ in 0..n {
            let s = m
                .sample(wo, rng.next_f32(), rng.next_2d(), TransportMode::Importance)
                .expect("sample");
            if s.wi.z * wo.z > 0.0 {
                reflected += 1;
            }
        }
        let frac = reflected as f32 / n as f32;
        assert!(
            (frac - f).abs() < 0.01,
            "cos {cos}: reflected {frac} vs F {f}"
        );
    }
    // Radiance crossing into glass is scaled by 1/η² (and back out by η²).
    let wo = Vec3::new(0.0, 0.0, 1.0);
    let (_, t) = glass.branches(wo, TransportMode::Radiance);
    let t = t.expect("transmits");
    assert!((t.weight.x - 0.96 / 2.25).abs() < 1e-4);
}
