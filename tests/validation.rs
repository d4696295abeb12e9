//! The validation suite (validation/README.md): every scene, rendered by every integrator at
//! the quick budget, against its converged Mitsuba 3 reference. Per-channel means within 1%
//! (path) or 2% (the photon-mapping integrators), and relMSE within a bound per scene (about
//! twice what was measured when the suite was made, so that noise does not fail it and a
//! regression does).

use photon::validate::{Budget, Method, find_cases, load_case, run};
use std::path::Path;

/// relMSE bounds per scene for (path, photon, sppm, ppm) at `Budget::QUICK`.
const BOUNDS: &[(&str, [f64; 4])] = &[
    ("absorbing-glass", [0.0018, 0.012, 0.03, 0.027]),
    ("absorbing-water", [0.0004, 0.005, 0.015, 0.015]),
    ("alpha-fence", [0.0026, 0.006, 0.033, 0.03]),
    ("coloured-fog", [0.02, 0.01, 0.09, 0.1]),
    ("curved-ceiling", [0.0004, 0.005, 0.015, 0.015]),
    ("directional", [0.0002, 0.0035, 0.009, 0.01]),
    ("door-ajar", [0.003, 0.018, 0.09, 0.13]),
    ("env-spheres", [0.0008, 0.016, 0.022, 0.028]),
    ("flush-light", [0.012, 0.029, 0.09, 0.094]),
    ("fog-box", [0.0003, 0.006, 0.022, 0.022]),
    // `path` samples distances toward the spot light too (equiangular sampling): 0.0025 here,
    // and 0.0020–0.0028 over four other seeds at 32² and 4096 spp. A fifth read 0.036: a
    // bounce that passed a millimetre from the light, whose in-scattered light grows as 1/h
    // with that distance h. Free flight alone reads 0.030 here.
    ("fog-spot", [0.012, 0.006, 0.04, 0.04]),
    ("glass-caustics", [0.025, 0.045, 0.065, 0.06]),
    ("glossy-cornell", [0.0022, 0.018, 0.016, 0.015]),
    ("glossy-floor-spot", [0.0016, 0.011, 0.019, 0.018]),
    ("grazing-area", [0.0012, 0.014, 0.022, 0.022]),
    ("indirect-only", [0.0025, 0.024, 0.04, 0.04]),
    ("lamp-shade", [0.012, 0.044, 0.06, 0.055]),
    ("light-strip", [0.013, 0.011, 0.033, 0.035]),
    ("millimetres", [0.0005, 0.0055, 0.027, 0.026]),
    ("mirror-caustic", [0.01, 0.027, 0.083, 0.073]),
    ("normal-mapped", [0.001, 0.006, 0.025, 0.02]),
    ("point-light", [0.002, 0.022, 0.037, 0.035]),
    ("rough-glass", [0.005, 0.012, 0.022, 0.021]),
    ("smoke-grid", [0.0001, 0.0045, 0.017, 0.016]),
    ("smooth-box", [0.0033, 0.025, 0.19, 0.26]),
    ("spot-light", [0.0015, 0.017, 0.025, 0.021]),
    ("textured-mesh", [0.0004, 0.007, 0.018, 0.02]),
    ("thick-medium", [0.0002, 0.0045, 0.019, 0.019]),
];

/// Where a photon-mapping method's mean lies further from the reference than 2% at the quick
/// budget, the bias measured (per channel, the largest), its cause, and the tolerance that
/// keeps it from growing.
///
/// `coloured-fog` (dense blue fog, σs 1.6; the camera 2 cm from the front wall):
/// - `sppm` and `ppm` read blue 4.4% dark (0.9% at the full budget, 64² and 256 passes). The
///   suite's fixed radius makes volume balls 0.07 wide next to the camera, and a ball half
///   behind the wall finds half the photons: blue's in-scattering comes mostly from its first
///   mean free path (0.6). With the camera 0.6 from the wall the same renders read 0.3%. The
///   command line's radius grows with the distance from the camera and spares that wall.
/// - `photon` reads red 2.7% bright and blue 2.8% dark at both budgets: its beam estimate's
///   bias in a medium whose colours scatter this differently.
const KNOWN_BIASES: &[(&str, Method, f64)] = &[
    ("coloured-fog", Method::Sppm, 0.055),
    ("coloured-fog", Method::Ppm, 0.055),
    ("coloured-fog", Method::Photon, 0.035),
];

#[test]
fn every_scene_matches_its_reference_with_every_integrator() {
    check_suite(Budget::QUICK, BOUNDS);
}

/// relMSE bounds per scene for (path, photon, sppm, ppm) at `Budget::QUICK.spectral()`,
/// against the references Mitsuba 3's `llvm_ad_spectral` made (`reference-spectral.exr`).
const SPECTRAL_BOUNDS: &[(&str, [f64; 4])] = &[
    ("absorbing-glass", [0.003, 0.052, 0.042, 0.053]),
    ("absorbing-water", [0.0008, 0.032, 0.021, 0.028]),
    ("directional", [0.0006, 0.031, 0.011, 0.017]),
    ("env-spheres", [0.0017, 0.07, 0.02, 0.042]),
    ("fog-box", [0.0005, 0.035, 0.033, 0.043]),
    ("glass-caustics", [0.028, 0.097, 0.097, 0.13]),
    ("glossy-cornell", [0.005, 0.038, 0.025, 0.033]),
    ("indirect-only", [0.0035, 0.051, 0.05, 0.07]),
    ("point-light", [0.0032, 0.064, 0.06, 0.081]),
    ("smoke-grid", [0.0002, 0.035, 0.023, 0.031]),
    ("spot-light", [0.0021, 0.035, 0.036, 0.044]),
    ("textured-mesh", [0.0008, 0.03, 0.023, 0.037]),
];

#[test]
fn every_spectral_scene_matches_its_spectral_reference_with_every_integrator() {
    check_suite(Budget::QUICK.spectral(), SPECTRAL_BOUNDS);
}

/// Every scene with a reference for `budget` (RGB or spectral), each integrator within its
/// bound in `bounds` and its means within 1% (path) or 2% (the others).
fn check_suite(budget: Budget, bounds: &[(&str, [f64; 4])]) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("validation");
    let cases = find_cases(&dir, budget.spectral).expect("reads validation/");
    let loaded: Vec<_> = cases
        .iter()
        .map(|c| load_case(c, budget.size).expect("loads"))
        .collect();
    let names: Vec<&str> = cases.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        bounds.iter().map(|b| b.0).collect::<Vec<_>>(),
        "every scene has bounds here, and every bound a scene"
    );
    let mut failures = Vec::new();
    for ((case, loaded), (_, bounds)) in cases.iter().zip(&loaded).zip(bounds) {
        for (method, bound) in Method::ALL.into_iter().zip(bounds) {
            let o = run(case, loaded, method, &budget).expect("renders");
            let c = &o.comparison;
            let known = KNOWN_BIASES
                .iter()
                .find(|k| k.0 == case.name && k.1 == method && !budget.spectral);
            let tolerance = match (method, known) {
                (_, Some(k)) => k.2,
                (Method::Path, None) => 0.01,
                _ => 0.02,
            };
            let ratios = [c.red.mean_ratio, c.green.mean_ratio, c.blue.mean_ratio];
            eprintln!(
                "{:<16} {:<6} relMSE {:.5} (bound {bound}) mean ratios {:.4} {:.4} {:.4}",
                case.name,
                method.name(),
                c.overall.rel_mse,
                ratios[0],
                ratios[1],
                ratios[2]
            );
            // Written so that a NaN fails too.
            let means_ok = ratios.iter().all(|r| (r - 1.0).abs() <= tolerance);
            let error_ok = c.overall.rel_mse.is_finite() && c.overall.rel_mse <= *bound;
            if !means_ok || !error_ok {
                failures.push(format!(
                    "{} {}: mean ratios {ratios:?} (±{tolerance}), relMSE {} (bound {bound})",
                    case.name,
                    method.name(),
                    c.overall.rel_mse
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
