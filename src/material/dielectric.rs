use super::{BsdfSample, Lobes, SpecularBranch, TransportMode};
use crate::math::{Rgb, Vec3};

/// Smooth dielectric boundary (glass): Fresnel reflection and refraction, total internal
/// reflection. The local `z` axis is the outward normal; `ior` is inside over outside.
#[derive(Clone, Copy, Debug)]
pub struct Dielectric {
    pub ior: f32,
    /// Multiplies transmitted light (1 for clear glass).
    pub transmittance: Rgb,
    /// The Beer–Lambert transmittance of the segment a path travelled inside the volume to
    /// reach this hit, scaling both branches (1 unless set by
    /// [`super::Material::attenuated`]).
    pub segment: Rgb,
}

/// Unpolarised Fresnel reflectance of a dielectric boundary for light arriving with cosine
/// `cos_i` (positive on the outside) and relative index `eta` = inside / outside.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta)
    } else {
        (cos_i, eta)
    };
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_par * r_par + r_perp * r_perp)
}

impl Dielectric {
    /// Clear glass of index `ior` (inside over outside) whose refraction is scaled by
    /// `transmittance`.
    pub fn new(ior: f32, transmittance: Rgb) -> Self {
        Self {
            ior,
            transmittance,
            segment: Rgb::ONE,
        }
    }

    /// Both branches with their weights; refraction is `None` under total internal reflection.
    pub fn branches(
        &self,
        wo: Vec3,
        mode: TransportMode,
    ) -> (SpecularBranch, Option<SpecularBranch>) {
        let f = fresnel_dielectric(wo.z, self.ior);
        let reflected = SpecularBranch {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: self.segment * f,
        };
        if f >= 1.0 {
            return (reflected, None);
        }
        // eta: ratio of the index on the transmitted side to the index on the incident side.
        let entering = wo.z > 0.0;
        let eta = if entering { self.ior } else { 1.0 / self.ior };
        let cos_o = wo.z.abs();
        let sin2_t = (1.0 - cos_o * cos_o).max(0.0) / (eta * eta);
        let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
        let n_side = if entering { 1.0 } else { -1.0 };
        let wi = (-wo / eta + (cos_o / eta - cos_t) * Vec3::new(0.0, 0.0, n_side)).normalize();
        let radiance_scale = match mode {
            TransportMode::Radiance => 1.0 / (eta * eta),
            TransportMode::Importance => 1.0,
        };
        let refracted = SpecularBranch {
            wi,
            weight: self.transmittance * self.segment * ((1.0 - f) * radiance_scale),
        };
        (reflected, Some(refracted))
    }

    /// Pick reflection or refraction with probability F and 1 − F.
    pub fn sample(&self, wo: Vec3, u_lobe: f32, mode: TransportMode) -> Option<BsdfSample> {
        let (reflected, refracted) = self.branches(wo, mode);
        let f = fresnel_dielectric(wo.z, self.ior);
        match refracted {
            Some(t) if u_lobe >= f => Some(BsdfSample {
                wi: t.wi,
                weight: t.weight / (1.0 - f),
                pdf: 1.0 - f,
                lobe: Lobes::SPECULAR_TRANSMISSION,
                eta: if wo.z > 0.0 { self.ior } else { 1.0 / self.ior },
            }),
            _ => Some(BsdfSample {
                wi: reflected.wi,
                weight: self.segment,
                pdf: f,
                lobe: Lobes::SPECULAR_REFLECTION,
                eta: 1.0,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_matches_known_values() {
        // Normal incidence: ((n−1)/(n+1))².
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_dielectric(-1.0, 1.5) - 0.04).abs() < 1e-6);
        // Grazing incidence reflects everything.
        assert!(fresnel_dielectric(1e-6, 1.5) > 0.999);
        // Beyond the critical angle inside glass: total internal reflection.
        let cos_inside = -(1.0f32 - 0.8 * 0.8).sqrt(); // sin θ = 0.8 > 1/1.5
        assert_eq!(fresnel_dielectric(cos_inside, 1.5), 1.0);
    }

    #[test]
    fn refraction_obeys_snell_and_goes_through() {
        let glass = Dielectric::new(1.5, Rgb::ONE);
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let (_, t) = glass.branches(wo, TransportMode::Importance);
        let t = t.expect("no TIR from outside");
        assert!(t.wi.z < 0.0, "refracted ray goes inside");
        let sin_o = 0.6f32;
        let sin_t = (t.wi.x * t.wi.x + t.wi.y * t.wi.y).sqrt();
        assert!((sin_o - 1.5 * sin_t).abs() < 1e-5);
        assert!(
            t.wi.x < 0.0,
            "refracted ray continues to the other side of the normal"
        );
        // Reversed: light inside arriving from `t.wi` leaves along the original `wo`.
        let (_, back) = glass.branches(t.wi, TransportMode::Importance);
        let back = back.expect("reverse path cannot be TIR");
        assert!((back.wi - wo).length() < 1e-5, "{} vs {wo}", back.wi);
    }
}
