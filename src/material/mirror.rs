use super::{BsdfSample, Lobes};
use crate::math::{Rgb, Vec3};

/// Perfect specular reflector with a constant reflectance (no Fresnel), as in the Cornell
/// validation scene's mirror sphere.
#[derive(Clone, Copy, Debug)]
pub struct Mirror {
    pub reflectance: Rgb,
}

impl Mirror {
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: self.reflectance,
            pdf: 1.0,
            lobe: Lobes::SPECULAR_REFLECTION,
            eta: 1.0,
        })
    }
}
