//! Participating media: what fills the inside of a closed shape (fog in a box, water, smoke)
//! or the whole scene (an atmosphere). A medium absorbs (σa) and scatters (σs) per unit
//! length and per RGB channel; scattering picks a new direction by its phase function.
//!
//! Free-flight sampling follows the spectral approach of pbrt-v3 (Pharr, Jakob and
//! Humphreys 2016, §15.2): a channel is chosen uniformly, a distance is drawn from that
//! channel's exponential, and the throughput is divided by the average of the three channels'
//! densities, so a medium coloured in σt stays unbiased in every channel.

mod phase;

pub use phase::{HenyeyGreenstein, PhaseSample};

use crate::math::Rgb;

/// Index of a medium in the scene's list.
pub type MediumId = u32;

/// A homogeneous medium: the same coefficients everywhere, per scene unit of length.
#[derive(Clone, Debug, PartialEq)]
pub struct Homogeneous {
    pub sigma_a: Rgb,
    pub sigma_s: Rgb,
    pub phase: HenyeyGreenstein,
}

/// Where a ray's next event in a medium is: a scattering point at `t`, or the surface at
/// the end of the segment. `weight` is the throughput to multiply in: transmittance, times
/// σs at a scattering point, over the density of the choice.
#[derive(Clone, Copy, Debug)]
pub struct FreeFlight {
    pub t: f32,
    pub scattered: bool,
    pub weight: Rgb,
}

impl Homogeneous {
    pub fn sigma_t(&self) -> Rgb {
        self.sigma_a + self.sigma_s
    }

    /// Transmittance over `distance`: exp(−σt d) (Beer–Lambert).
    pub fn transmittance(&self, distance: f32) -> Rgb {
        let d = self.sigma_t() * distance;
        Rgb::new((-d.x).exp(), (-d.y).exp(), (-d.z).exp())
    }

    /// Sample the next event along a segment of length `t_max` (infinite when the ray
    /// escapes), with `u_channel` choosing the channel and `u_distance` the distance.
    pub fn sample_free_flight(&self, t_max: f32, u_channel: f32, u_distance: f32) -> FreeFlight {
        let sigma_t = self.sigma_t();
        let channel = ((u_channel * 3.0) as usize).min(2);
        let s = sigma_t.to_array()[channel];
        let t = if s > 0.0 {
            -(1.0 - u_distance).ln() / s
        } else {
            f32::INFINITY
        };
        let scattered = t < t_max;
        let t = t.min(t_max);
        let tr = self.transmittance(t);
        // The density of what happened, per channel, averaged over the channel choice:
        // σt·Tr for a scattering at t, Tr for passing the whole segment.
        let density = if scattered { sigma_t * tr } else { tr };
        let pdf = (density.x + density.y + density.z) / 3.0;
        let weight = if pdf > 0.0 {
            if scattered {
                tr * self.sigma_s / pdf
            } else {
                tr / pdf
            }
        } else {
            Rgb::ZERO
        };
        FreeFlight {
            t,
            scattered,
            weight,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_flight_is_unbiased_for_the_transmittance_of_a_coloured_slab() {
        // E[weight · 1(passed)] over u must be exp(−σt d) per channel.
        let m = Homogeneous {
            sigma_a: Rgb::new(0.2, 0.5, 1.5),
            sigma_s: Rgb::new(0.3, 0.1, 0.0),
            phase: HenyeyGreenstein::new(0.0),
        };
        let d = 1.3;
        let n = 3000;
        let mut sum = Rgb::ZERO;
        for i in 0..n {
            for c in 0..3 {
                let f =
                    m.sample_free_flight(d, (c as f32 + 0.5) / 3.0, (i as f32 + 0.5) / n as f32);
                if !f.scattered {
                    sum += f.weight;
                }
            }
        }
        let estimate = sum / (3 * n) as f32;
        let exact = m.transmittance(d);
        assert!(
            (estimate - exact).abs().max_element() < 2e-3,
            "{estimate:?} vs {exact:?}"
        );
    }
}
