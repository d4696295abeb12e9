use super::{Aperture, LightSample, PhotonEmission};
use crate::math::{Rgb, Vec2, Vec3};
use crate::spectrum::{Lambda, Spectrum};

/// Light arriving from one direction (the sun): `irradiance` (W/m² per channel) on a surface
/// facing it. Its power is that irradiance over the disk the scene's bounding sphere casts,
/// Φ = E·πr² (pbrt-v4's convention), so the bounding sphere is set when the scene is built;
/// its photons enter through an [`Aperture`].
#[derive(Clone, Copy, Debug)]
pub struct DirectionalLight {
    /// Unit direction the light travels in.
    pub direction: Vec3,
    pub irradiance: Spectrum,
    /// Where its photons enter the scene (set at build).
    pub aperture: Aperture,
}

impl DirectionalLight {
    pub fn new(direction: Vec3, irradiance: Spectrum) -> Self {
        Self {
            direction: direction.normalize_or(-Vec3::Z),
            irradiance,
            aperture: Aperture::default(),
        }
    }

    pub fn power(&self) -> Rgb {
        self.irradiance.rgb() * self.aperture.area()
    }

    /// A photon entering through the aperture (see [`Aperture`]): flux E / density, which is
    /// the whole power E·πr² for the scene's own disc.
    pub fn emit(&self, u_pick: f32, u: Vec2, lambda: &Lambda) -> Option<PhotonEmission> {
        let (origin, density) = self.aperture.sample(self.direction, u_pick, u)?;
        Some(PhotonEmission {
            origin,
            dir: self.direction,
            normal: Vec3::ZERO,
            error: Vec3::ZERO,
            flux: lambda.spectrum(&self.irradiance) / density,
        })
    }

    /// The direction toward the light; the shadow ray ends outside the scene's sphere.
    pub fn sample_li(&self, p: Vec3, lambda: &Lambda) -> Option<LightSample> {
        let wi = -self.direction;
        Some(LightSample {
            wi,
            radiance: lambda.spectrum(&self.irradiance),
            pdf: 1.0,
            point: p + wi * (2.0 * self.aperture.radius + (p - self.aperture.center).length()),
            normal: Vec3::ZERO,
            error: Vec3::ZERO,
            is_delta: true,
        })
    }
}
