//! Equiangular sampling of a distance along a ray toward a point (Kulla and Fajardo 2012,
//! "Importance Sampling Techniques for Path Tracing in Participating Media", §3): the
//! density of the distance t is proportional to 1 / r(t)², r the distance to the point,
//! which cancels the inverse-square law of a point light seen from the ray. Seen from the
//! point, the samples are uniform in the angle they make along the ray, hence the name.

use crate::math::Vec3;

/// The largest f32 below π/2.
const BELOW_HALF_PI: f32 = f32::from_bits(std::f32::consts::FRAC_PI_2.to_bits() - 1);

/// The distribution of distances in [0, `t_max`] along a ray for one point.
///
/// With `foot` the distance along the ray to the point's projection on it and `height` the
/// point's distance from the ray's line, r(t)² = height² + (t − foot)², and
/// p(t) = height / ((θ_b − θ_a) · r(t)²), with θ = atan((t − foot) / height) the angle at
/// the point from the perpendicular.
#[derive(Clone, Copy, Debug)]
pub struct Equiangular {
    foot: f32,
    height: f32,
    theta_a: f32,
    theta_b: f32,
}

impl Equiangular {
    /// The distribution along the ray from `origin` in unit direction `dir` up to `t_max`
    /// (which may be infinite) toward `point`; `None` when the point lies on the ray's line
    /// (in numbers: within 10⁻⁴ of its distance), where the density would be a delta, or
    /// when the segment is empty.
    pub fn new(origin: Vec3, dir: Vec3, point: Vec3, t_max: f32) -> Option<Self> {
        let to_point = point - origin;
        let foot = to_point.dot(dir);
        let height = (to_point - foot * dir).length();
        // The segment must have length, and the point a height the angles can resolve.
        let usable = t_max > 0.0 && height > 1e-4 * to_point.length();
        if !usable || !height.is_finite() {
            return None;
        }
        // θ stays below π/2, whose f32 rounding lies above it (where tan turns negative).
        let theta_a = (-foot / height).atan();
        let theta_b = ((t_max - foot) / height).atan().min(BELOW_HALF_PI);
        (theta_b > theta_a).then_some(Self {
            foot,
            height,
            theta_a,
            theta_b,
        })
    }

    /// The distance for the uniform number `u` (inverting the cumulative distribution, which
    /// is linear in θ).
    pub fn sample(&self, u: f32) -> f32 {
        let theta = self.theta_a + u * (self.theta_b - self.theta_a);
        (self.foot + self.height * theta.tan()).max(0.0)
    }

    /// The density of distance `t` (per unit length; zero outside the segment).
    pub fn pdf(&self, t: f32) -> f32 {
        let theta = ((t - self.foot) / self.height).atan();
        if theta < self.theta_a || theta > self.theta_b {
            return 0.0;
        }
        let along = t - self.foot;
        self.height / ((self.theta_b - self.theta_a) * (self.height * self.height + along * along))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn distribution(t_max: f32) -> Equiangular {
        Equiangular::new(
            Vec3::new(0.1, 0.2, 0.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.4, 0.0, -0.7),
            t_max,
        )
        .expect("a point off the ray")
    }

    #[test]
    fn the_density_integrates_to_one_over_the_segment() {
        // Midpoint rule over [0, 3] with the density peaked near t = 0.7, and over [0, 40]
        // for an open ray, whose far tail (beyond 40, about 1% of the angle) is added in
        // closed form: ∫ h / (θ-range · r²) from 40 on is (π/2 − θ(40)) / θ-range.
        for (t_max, tail) in [(3.0f32, false), (f32::INFINITY, true)] {
            let d = distribution(t_max);
            let end = if tail { 40.0 } else { t_max };
            let n = 400_000;
            let dt = end / n as f32;
            let mut sum: f64 = (0..n)
                .map(|i| f64::from(d.pdf((i as f32 + 0.5) * dt) * dt))
                .sum();
            if tail {
                let theta_end = ((40.0 - d.foot) / d.height).atan();
                sum +=
                    f64::from((std::f32::consts::FRAC_PI_2 - theta_end) / (d.theta_b - d.theta_a));
            }
            assert!((sum - 1.0).abs() < 1e-3, "t_max {t_max}: {sum}");
        }
    }

    #[test]
    fn samples_follow_the_density() {
        // The fraction of samples in each of 12 bins against the density's integral there.
        let d = distribution(3.0);
        let bins = 12;
        let n = 120_000;
        let mut counts = vec![0u32; bins];
        for i in 0..n {
            let t = d.sample((i as f32 + 0.5) / n as f32);
            assert!((0.0..=3.0).contains(&t), "{t} outside the segment");
            counts[((t / 3.0 * bins as f32) as usize).min(bins - 1)] += 1;
        }
        for (b, &count) in counts.iter().enumerate() {
            let steps = 2000;
            let width = 3.0 / bins as f32;
            let expected: f32 = (0..steps)
                .map(|k| {
                    d.pdf((b as f32 + (k as f32 + 0.5) / steps as f32) * width) * width
                        / steps as f32
                })
                .sum();
            let got = count as f32 / n as f32;
            assert!(
                (got - expected).abs() < 2e-3,
                "bin {b}: {got} against {expected}"
            );
        }
    }

    #[test]
    fn a_point_on_the_line_or_an_empty_segment_has_no_distribution() {
        let o = Vec3::ZERO;
        let dir = Vec3::new(0.0, 1.0, 0.0);
        assert!(Equiangular::new(o, dir, Vec3::new(0.0, 2.0, 0.0), 5.0).is_none());
        assert!(Equiangular::new(o, dir, Vec3::new(1.0, 2.0, 0.0), 0.0).is_none());
        // Behind the origin: still a distribution, falling off from t = 0.
        let behind = Equiangular::new(o, dir, Vec3::new(0.5, -2.0, 0.0), 5.0).expect("usable");
        assert!(behind.pdf(0.0) > behind.pdf(1.0));
    }
}
