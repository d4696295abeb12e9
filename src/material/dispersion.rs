//! How a dielectric's index of refraction varies with wavelength: the Cauchy and Sellmeier
//! equations, the Abbe number glTF's `KHR_materials_dispersion` is given in, and a few named
//! glasses from their makers' catalogues.
//!
//! Wavelengths are in nanometres at the interface; the coefficients, as catalogues give them,
//! in micrometres: Cauchy n(λ) = A + B / λ² (B in µm²), Sellmeier n²(λ) = 1 + Σᵢ Bᵢ λ² / (λ² − Cᵢ)
//! (Cᵢ in µm²).

/// The Fraunhofer lines the Abbe number is defined on: d (helium, 587.56 nm), F (hydrogen,
/// 486.13 nm) and C (hydrogen, 656.27 nm). V_d = (n_d − 1) / (n_F − n_C).
pub const LINE_D_NM: f32 = 587.56;
pub const LINE_F_NM: f32 = 486.13;
pub const LINE_C_NM: f32 = 656.27;

/// A glass's index as a function of wavelength. `None` is a constant index.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Dispersion {
    #[default]
    None,
    /// n(λ) = a + b / λ², λ in µm.
    Cauchy { a: f32, b: f32 },
    /// n²(λ) = 1 + Σ bᵢ λ² / (λ² − cᵢ), λ in µm (three terms; unused ones are zero).
    Sellmeier { b: [f32; 3], c: [f32; 3] },
}

/// Named glasses: Sellmeier coefficients from the makers' data sheets and the papers cited.
const NAMED: [(&str, Dispersion); 7] = [
    // Schott N-BK7, the common optical crown glass (Schott data sheet; n_d 1.5168, V_d 64.17).
    (
        "bk7",
        Dispersion::Sellmeier {
            b: [1.039_612, 0.231_792_34, 1.010_469_5],
            c: [0.006_000_699, 0.020_017_914, 103.560_65],
        },
    ),
    // Fused silica (Malitson 1965; n_d 1.4585, V_d 67.8).
    (
        "fused-silica",
        Dispersion::Sellmeier {
            b: [0.696_166_3, 0.407_942_6, 0.897_479_4],
            c: [0.004_679_148, 0.013_512_063, 97.934_0],
        },
    ),
    // Diamond (Peter 1923, two terms; n_d 2.417, V_d 55).
    (
        "diamond",
        Dispersion::Sellmeier {
            b: [0.330_6, 4.335_6, 0.0],
            c: [0.030_625, 0.011_236, 0.0],
        },
    ),
    // Sapphire, ordinary ray (Malitson 1962; n_d 1.768, V_d 72).
    (
        "sapphire",
        Dispersion::Sellmeier {
            b: [1.431_349_3, 0.650_547_1, 5.341_402],
            c: [0.005_279_93, 0.014_238_26, 325.017_8],
        },
    ),
    // Schott N-SF11, a dense flint (n_d 1.7847, V_d 25.7).
    (
        "sf11",
        Dispersion::Sellmeier {
            b: [1.737_596_9, 0.313_747_35, 1.898_781],
            c: [0.013_188_707, 0.062_306_814, 155.236_3],
        },
    ),
    // Schott F2, a flint (n_d 1.6200, V_d 36.4).
    (
        "f2",
        Dispersion::Sellmeier {
            b: [1.345_333_6, 0.209_073_18, 0.937_357_2],
            c: [0.009_977_439, 0.047_045_077, 111.886_76],
        },
    ),
    // Water at 20 °C, from its d-line index and Abbe number (n_d 1.3330, V_d 55.7; Daimon
    // and Masumura 2007) as a Cauchy fit.
    ("water", Dispersion::abbe_const(1.333, 55.7)),
];

impl Dispersion {
    /// The names [`Dispersion::named`] knows, for messages.
    pub fn names() -> impl Iterator<Item = &'static str> {
        NAMED.iter().map(|(n, _)| *n)
    }

    /// A named glass (case and `-`/`_`/space insensitive: `"BK7"`, `"fused silica"`).
    pub fn named(name: &str) -> Option<Dispersion> {
        let key: String = name
            .chars()
            .filter(|c| !matches!(c, '-' | '_' | ' ' | '.'))
            .flat_map(char::to_lowercase)
            .collect();
        let key = key
            .strip_prefix('n')
            .filter(|k| *k == "bk7" || *k == "sf11")
            .unwrap_or(&key);
        NAMED
            .iter()
            .find(|(n, _)| n.replace('-', "") == key)
            .map(|(_, d)| *d)
    }

    /// The Cauchy glass with index `n_d` at the d line and Abbe number `v_d`, as glTF's
    /// `KHR_materials_dispersion` (dispersion = 20 / V_d) defines it from the material's index.
    /// `v_d` ≤ 0 or not finite is no dispersion.
    pub fn from_abbe(n_d: f32, v_d: f32) -> Dispersion {
        if !(v_d.is_finite() && v_d > 0.0 && n_d.is_finite()) {
            return Dispersion::None;
        }
        Self::abbe_const(n_d, v_d)
    }

    const fn abbe_const(n_d: f32, v_d: f32) -> Dispersion {
        // n_F − n_C = b (1/λ_F² − 1/λ_C²) = (n_d − 1) / V_d; a from n(λ_d) = n_d.
        let (f, c, d) = (LINE_F_NM / 1000.0, LINE_C_NM / 1000.0, LINE_D_NM / 1000.0);
        let b = (n_d - 1.0) / v_d / (1.0 / (f * f) - 1.0 / (c * c));
        Dispersion::Cauchy {
            a: n_d - b / (d * d),
            b,
        }
    }

    pub fn is_dispersive(&self) -> bool {
        !matches!(self, Dispersion::None)
    }

    /// The index at `lambda_nm`, or `None` for a constant index.
    pub fn ior(&self, lambda_nm: f32) -> Option<f32> {
        let l = f64::from(lambda_nm) / 1000.0;
        let l2 = l * l;
        let n = match *self {
            Dispersion::None => return None,
            Dispersion::Cauchy { a, b } => f64::from(a) + f64::from(b) / l2,
            Dispersion::Sellmeier { b, c } => {
                let n2 = 1.0
                    + b.iter()
                        .zip(c)
                        .map(|(&b, c)| f64::from(b) * l2 / (l2 - f64::from(c)))
                        .sum::<f64>();
                n2.max(1.0).sqrt()
            }
        };
        Some(n as f32)
    }

    /// The index at the d line (what a constant-index renderer, and RGB rendering, uses).
    pub fn ior_d(&self) -> Option<f32> {
        self.ior(LINE_D_NM)
    }

    /// The Abbe number V_d = (n_d − 1) / (n_F − n_C); infinite without dispersion.
    pub fn abbe(&self) -> f32 {
        match (
            self.ior(LINE_D_NM),
            self.ior(LINE_F_NM),
            self.ior(LINE_C_NM),
        ) {
            (Some(d), Some(f), Some(c)) if f != c => (d - 1.0) / (f - c),
            _ => f32::INFINITY,
        }
    }

    /// Whether the index is a physical glass over the visible range: finite, at least 1 and
    /// at most 5 from 360 to 830 nm.
    pub fn is_valid(&self) -> bool {
        (0..=47).all(|i| {
            self.ior(360.0 + 10.0 * i as f32)
                .is_none_or(|n| n.is_finite() && (1.0..=5.0).contains(&n))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_glasses_match_their_catalogue_indices_and_abbe_numbers() {
        for (name, n_d, v_d) in [
            ("BK7", 1.5168, 64.17),
            ("fused silica", 1.4585, 67.8),
            ("diamond", 2.4175, 55.0),
            ("sapphire", 1.7682, 72.2),
            ("N-SF11", 1.7847, 25.68),
            ("F2", 1.6200, 36.37),
            ("water", 1.3330, 55.7),
        ] {
            let d = Dispersion::named(name).unwrap_or_else(|| panic!("{name} unknown"));
            let n = d.ior_d().expect("dispersive");
            assert!((n - n_d).abs() < 2e-3, "{name}: n_d {n}, catalogue {n_d}");
            assert!(
                (d.abbe() - v_d).abs() < 0.03 * v_d,
                "{name}: V_d {}, catalogue {v_d}",
                d.abbe()
            );
            assert!(d.is_valid(), "{name}");
        }
        assert!(Dispersion::named("unobtainium").is_none());
    }

    #[test]
    fn abbe_form_gives_back_its_index_and_abbe_number() {
        let d = Dispersion::from_abbe(1.5, 40.0);
        assert!((d.ior_d().expect("dispersive") - 1.5).abs() < 1e-5);
        assert!((d.abbe() - 40.0).abs() < 1e-2, "{}", d.abbe());
        // Blue bends more than red.
        assert!(d.ior(450.0) > d.ior(650.0));
        assert_eq!(Dispersion::from_abbe(1.5, 0.0), Dispersion::None);
        assert_eq!(Dispersion::from_abbe(1.5, f32::NAN), Dispersion::None);
    }
}
