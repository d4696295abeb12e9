//! How a path reads the scene's colours: [`Lambda`].

use super::{Spectrum, Wavelengths};
use crate::math::Rgb;

/// What a path's three values mean: the R, G and B channels of linear Rec. 709, or the
/// spectrum at the three wavelengths the path carries (hero-wavelength sampling, Wilkie et al.
/// 2014). Scene colours are stored in RGB; a path reads each through its `Lambda`, which
/// upsamples it (Jakob and Hanika 2019) at its wavelengths in spectral rendering and returns
/// it as it is in RGB rendering, so RGB renders take exactly the code they always did.
///
/// Where a dispersive interface separates the wavelengths, the path goes on with the hero
/// alone (as pbrt-v4 terminates the secondary wavelengths): the others' values become zero
/// and the hero's is tripled, so that [`Lambda::to_rgb`], which averages the three, stays
/// unbiased whatever happened on the way and whichever branch a value came down. `hero_only`
/// records it, for what weighs the channels against each other (media) and for products of
/// two such paths (a photon and a visible point), which must triple only once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lambda {
    Rgb,
    Sampled {
        wavelengths: Wavelengths,
        hero_only: bool,
    },
}

impl Lambda {
    /// The wavelengths of a spectral path, drawn from `sampler`, or RGB (drawing nothing, so
    /// RGB paths keep the random numbers they always had).
    pub fn draw(spectral: bool, sampler: &mut impl crate::sampling::Sampler) -> Self {
        if spectral {
            Lambda::sampled(Wavelengths::sample_visible(sampler.next_f32()))
        } else {
            Lambda::Rgb
        }
    }

    pub fn sampled(wavelengths: Wavelengths) -> Self {
        Lambda::Sampled {
            wavelengths,
            hero_only: false,
        }
    }

    pub fn is_spectral(&self) -> bool {
        matches!(self, Lambda::Sampled { .. })
    }

    pub fn is_hero_only(&self) -> bool {
        matches!(
            self,
            Lambda::Sampled {
                hero_only: true,
                ..
            }
        )
    }

    /// A reflectance (an albedo, a tint: each channel in [0, 1]) at the path's channels.
    #[inline]
    pub fn reflectance(&self, rgb: Rgb) -> Rgb {
        match self {
            Lambda::Rgb => rgb,
            Lambda::Sampled { wavelengths, .. } => Spectrum::reflectance(rgb).sample(wavelengths),
        }
    }

    /// A coefficient without bound (σa, σs, a conductor's η and k).
    #[inline]
    pub fn unbounded(&self, rgb: Rgb) -> Rgb {
        match self {
            Lambda::Rgb => rgb,
            Lambda::Sampled { wavelengths, .. } => Spectrum::unbounded(rgb).sample(wavelengths),
        }
    }

    /// Emitted light given in RGB (radiance, intensity, irradiance, a sky's texel).
    #[inline]
    pub fn illuminant(&self, rgb: Rgb) -> Rgb {
        match self {
            Lambda::Rgb => rgb,
            Lambda::Sampled { wavelengths, .. } => {
                Spectrum::illuminant(rgb.max(Rgb::ZERO)).sample(wavelengths)
            }
        }
    }

    /// A spectrum the scene holds (a light's emission): its RGB colour, or its values.
    #[inline]
    pub fn spectrum(&self, s: &Spectrum) -> Rgb {
        match self {
            Lambda::Rgb => s.rgb(),
            Lambda::Sampled { wavelengths, .. } => s.sample(wavelengths),
        }
    }

    /// The hero wavelength in nanometres of a spectral path.
    pub fn hero(&self) -> Option<f32> {
        match self {
            Lambda::Rgb => None,
            Lambda::Sampled { wavelengths, .. } => Some(wavelengths.lambda(0)),
        }
    }

    /// Go on with the hero wavelength alone; returns the factor the path's values must take
    /// here: (3, 0, 0) the first time, (1, 0, 0) after (see the type's note). RGB paths are
    /// not touched (factor 1).
    #[must_use]
    pub fn keep_hero_only(&mut self) -> Rgb {
        match self {
            Lambda::Rgb => Rgb::ONE,
            Lambda::Sampled { hero_only, .. } if *hero_only => Rgb::X,
            Lambda::Sampled { hero_only, .. } => {
                *hero_only = true;
                Rgb::new(3.0, 0.0, 0.0)
            }
        }
    }

    /// The path's values as linear Rec. 709 RGB (through CIE 1931 XYZ).
    #[inline]
    pub fn to_rgb(&self, values: Rgb) -> Rgb {
        match self {
            Lambda::Rgb => values,
            Lambda::Sampled { wavelengths, .. } => wavelengths.to_rgb(values),
        }
    }
}
