//! The stored photon: 24 bytes.
//!
//! | bytes | field |
//! |---|---|
//! | 12 | position, 3 × f32 |
//! | 6 | power, 3 × f16, relative to its map's `power_scale` (so small fluxes stay normal f16) |
//! | 2 | incoming direction, octahedral 2 × u8 (Cigolle et al., JCGT 2014), error < 1° |
//! | 2 | geometric normal on the lit side, octahedral 2 × u8, error < 1° |
//! | 1 | depth: number of surface hits, 1 for light arriving straight from a light |
//! | 1 | flags: bits 2–3 colour channel (0 RGB, 1 R, 2 G, 3 B); bit 4 the last scattering was by a smooth lobe; the rest reserved |
//!
//! Jensen's record was 20 bytes with RGBE power and a 2-byte direction; f16 power keeps three
//! independent channels exact to 0.05%, which the per-channel maps need, and the stored normal
//! lets estimates reject photons from other surfaces (corners, thin objects) and lets
//! irradiance be precomputed at photon positions.

use crate::math::{Rgb, Vec2, Vec3};
use crate::medium::MediumId;
use bytemuck::{Pod, Zeroable};
use half::f16;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Photon {
    pub position: [f32; 3],
    power: [u16; 3],
    direction: [u8; 2],
    normal: [u8; 2],
    pub depth: u8,
    flags: u8,
}

const _: () = assert!(std::mem::size_of::<Photon>() == 24);

/// Which colour a photon carries: all three (RGB mode) or one channel (per-channel mode).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    Rgb,
    Red,
    Green,
    Blue,
}

impl Channel {
    pub fn index(self) -> Option<usize> {
        match self {
            Channel::Rgb => None,
            Channel::Red => Some(0),
            Channel::Green => Some(1),
            Channel::Blue => Some(2),
        }
    }

    pub fn from_index(i: usize) -> Channel {
        [Channel::Red, Channel::Green, Channel::Blue][i]
    }

    fn bits(self) -> u8 {
        match self {
            Channel::Rgb => 0,
            Channel::Red => 1,
            Channel::Green => 2,
            Channel::Blue => 3,
        }
    }
}

/// A progressive pass's photon at a scattering point in a medium: where, from which way,
/// with what power, in which medium (an estimate counts only its own medium's photons).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VolumePhoton {
    pub position: Vec3,
    /// Unit direction toward where the photon came from.
    pub incoming: Vec3,
    /// Power relative to the pass's scale, over σs where it scattered (see `trace`): at
    /// the pass's wavelengths in a spectral pass, else in RGB.
    pub power: Rgb,
    pub medium: MediumId,
    /// Whether a dispersive glass on the way left the path its hero wavelength alone (see
    /// [`crate::spectrum::Lambda::keep_hero_only`]).
    pub hero_only: bool,
}

impl VolumePhoton {
    /// The photon with its power as the RGB colour of the values at the path's channels
    /// `lambda` (what the photon integrator keeps, each photon having wavelengths of its own).
    pub fn to_rgb(self, lambda: &crate::spectrum::Lambda) -> Self {
        Self {
            power: lambda.to_rgb(self.power),
            hero_only: false,
            ..self
        }
    }
}

/// A progressive pass's photon, at full precision for the pass's own gathers (48 bytes, never
/// saved): reading it needs no decoding, and glossy lobes see its exact direction. The stored
/// [`Photon`] halves that with octahedral directions and half-float power.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassPhoton {
    pub position: Vec3,
    /// Unit surface normal on the side the photon arrived from.
    pub normal: Vec3,
    /// Unit direction toward where the photon came from.
    pub incoming: Vec3,
    /// Power relative to the pass's scale, at the pass's channels.
    pub power: Rgb,
    /// Whether a dispersive glass left the photon its hero wavelength alone (see
    /// [`crate::spectrum::Lambda::keep_hero_only`]).
    pub hero_only: bool,
}

impl super::grid::Located for PassPhoton {
    #[inline]
    fn location(&self) -> Vec3 {
        self.position
    }
}

/// Octahedral encoding of a unit vector into two u8 (Cigolle et al. 2014).
pub fn encode_octahedral(d: Vec3) -> [u8; 2] {
    let n = d / (d.x.abs() + d.y.abs() + d.z.abs());
    let mut p = Vec2::new(n.x, n.y);
    if n.z < 0.0 {
        let sign = Vec2::new(1.0f32.copysign(p.x), 1.0f32.copysign(p.y));
        p = (Vec2::ONE - Vec2::new(p.y.abs(), p.x.abs())) * sign;
    }
    let q = |v: f32| ((v.clamp(-1.0, 1.0) * 0.5 + 0.5) * 255.0).round() as u8;
    [q(p.x), q(p.y)]
}

pub fn decode_octahedral(e: [u8; 2]) -> Vec3 {
    let p = Vec2::new(f32::from(e[0]), f32::from(e[1])) / 255.0 * 2.0 - Vec2::ONE;
    let z = 1.0 - p.x.abs() - p.y.abs();
    let t = (-z).max(0.0);
    let x = p.x - t.copysign(p.x);
    let y = p.y - t.copysign(p.y);
    Vec3::new(x, y, z).normalize()
}

impl Photon {
    /// A photon at `position` on a surface with normal `normal` (on the side the photon
    /// arrived from) that came from direction `incoming` (unit, pointing away from the surface
    /// toward where the light came from) with flux `relative_power` × the map's scale.
    pub fn new(
        position: Vec3,
        normal: Vec3,
        incoming: Vec3,
        relative_power: Rgb,
        depth: u32,
        channel: Channel,
    ) -> Self {
        Self {
            position: position.to_array(),
            power: relative_power
                .to_array()
                .map(|c| f16::from_f32(c).to_bits()),
            direction: encode_octahedral(incoming),
            normal: encode_octahedral(normal),
            depth: depth.min(255) as u8,
            flags: channel.bits() << 2,
        }
    }

    pub fn position(&self) -> Vec3 {
        Vec3::from_array(self.position)
    }

    /// How many bounces from the light it arrived after: 1 straight from the light (at most
    /// 255).
    pub fn depth(&self) -> u8 {
        self.depth
    }

    /// Power relative to the map's `power_scale`.
    pub fn relative_power(&self) -> Rgb {
        Rgb::from_array(self.power.map(|b| f16::from_bits(b).to_f32()))
    }

    /// Unit direction toward where the photon came from.
    pub fn incoming(&self) -> Vec3 {
        decode_octahedral(self.direction)
    }

    /// Unit surface normal on the side the photon arrived from.
    pub fn normal(&self) -> Vec3 {
        decode_octahedral(self.normal)
    }

    pub fn channel(&self) -> Channel {
        match (self.flags >> 2) & 3 {
            0 => Channel::Rgb,
            1 => Channel::Red,
            2 => Channel::Green,
            _ => Channel::Blue,
        }
    }

    /// Whether the photon came straight from a light (its first surface hit).
    pub fn is_direct(&self) -> bool {
        self.depth == 1
    }

    /// The same photon, marked as having been scattered last by a smooth lobe (mirror, glass,
    /// a near-specular coat) or not.
    #[must_use]
    pub fn with_smooth_last_scattering(mut self, smooth: bool) -> Self {
        self.flags = (self.flags & !SMOOTH_LAST) | if smooth { SMOOTH_LAST } else { 0 };
        self
    }

    /// Whether the photon's last scattering before this hit was by a smooth lobe: the light
    /// of the final gather's paths that leave a rough point by a smooth surface (see
    /// `integrator::photon`).
    pub fn smooth_last_scattering(&self) -> bool {
        self.flags & SMOOTH_LAST != 0
    }
}

/// Flag bit: the last scattering was by a smooth lobe.
const SMOOTH_LAST: u8 = 1 << 4;

impl Photon {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Rng, uniform_sphere};

    #[test]
    fn fields_round_trip() {
        let mut rng = Rng::keyed(1, &[]);
        for _ in 0..10_000 {
            let d = uniform_sphere(rng.next_2d());
            let power = Rgb::new(
                rng.next_f32() + 1e-3,
                (rng.next_f32() + 0.1) * 1e-3,
                3.0 * rng.next_f32() + 0.1,
            );
            let n = uniform_sphere(rng.next_2d());
            let p = Photon::new(Vec3::new(1.0, -2.0, 3.5), n, d, power, 7, Channel::Green);
            // Chord length ≈ angle in radians: under 1°.
            assert!(
                (p.incoming() - d).length() < 1f32.to_radians(),
                "direction error"
            );
            assert!(
                (p.normal() - n).length() < 1f32.to_radians(),
                "normal error"
            );
            let back = p.relative_power();
            assert!(((back - power).abs() / power.max(Rgb::splat(1e-6))).max_element() < 1e-3);
            assert_eq!((p.depth, p.channel()), (7, Channel::Green));
            assert_eq!(p.position(), Vec3::new(1.0, -2.0, 3.5));
        }
    }
}
