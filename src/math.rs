//! Vectors, rays, orthonormal frames and the small numeric helpers everything else uses.
//!
//! Conventions stated once for the whole crate:
//! - world space is right-handed; lengths are in scene units (metres for the built-in scenes);
//! - `wo` and `wi` always point *away* from the surface;
//! - a [`Frame`] maps world directions into a local frame whose `z` axis is the normal.

pub use glam::{Vec2, Vec3};

/// A ray `origin + t * dir`; `dir` is unit length everywhere in the renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// An orthonormal basis around a unit normal `n`.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// Branchless basis construction of Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017).
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0_f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Self { s, t, n }
    }

    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// The rounding a photon estimate's plane test allows for points near `p` (see
/// `photon::estimate::disc_distance2`): about 170 float ulps of its largest coordinate, far
/// above the error of computed hit points. No floor in scene units: near the origin, where
/// this vanishes, the test's allowance for the normals' error (a share of the distance)
/// covers the coordinates' rounding, which shrinks with them.
pub fn plane_tolerance(p: Vec3) -> f32 {
    2e-5 * p.abs().max_element()
}

/// γₙ = nε / (1 − nε) with ε = 2⁻²⁴, the unit roundoff: a bound on the relative error of n
/// rounded operations (Higham 2002, §3.1; pbrt-v4 §6.8.1).
pub const fn gamma(n: u32) -> f32 {
    let e = n as f32 * (f32::EPSILON * 0.5);
    e / (1.0 - e)
}

/// Origin for a ray leaving the surface point `p` (each coordinate within `error` of the true
/// surface, geometric normal `ng`) in direction `dir`: moved along the normal, to the side
/// `dir` goes to, past the box of the point's error (pbrt-v4 §6.8.6) and then γ₄ of its
/// largest coordinate, which covers the rounding of the move and of a ray test started there
/// (a point of the plane y = 0 is exact across it, and would otherwise leave from the plane
/// itself, where Embree's test may find it again). The true surface then lies behind the
/// origin, so the ray cannot meet it again at its start, and no scene unit or position makes
/// the offset large: it is a few ulps of the hit point's own coordinates. This keeps reflected
/// rays outside and refracted rays inside a sphere, which the original project got wrong.
#[inline]
pub fn offset_origin(p: Vec3, error: Vec3, ng: Vec3, dir: Vec3) -> Vec3 {
    let d = ng.abs().dot(error) + gamma(4) * p.abs().max_element();
    if dir.dot(ng) >= 0.0 {
        p + d * ng
    } else {
        p - d * ng
    }
}

/// How far along a segment from `from` to `to` (its length `dist`) a surface counts as in
/// the way: all but its last 10⁻⁴ (pbrt-v4's `ShadowEpsilon`) and 32 ulps of the ends'
/// coordinates. A segment often ends on a surface (a light, a vertex it connects to), offset
/// from it by that point's error alone, which can be zero (a point of the plane y = 0 is
/// exact across it); the distance at which the segment then meets its own end's surface
/// rounds with the segment's coordinates and length, and must not count as a blocker.
#[inline]
pub fn segment_reach(from: Vec3, to: Vec3, dist: f32) -> f32 {
    dist * (1.0 - 1e-4) - gamma(64) * (from.abs().max_element() + to.abs().max_element())
}

/// Reflect `w` (pointing away from the surface) about the normal `n`.
pub fn reflect(w: Vec3, n: Vec3) -> Vec3 {
    2.0 * w.dot(n) * n - w
}

/// Linear RGB in the renderer's working space (Rec. 709 primaries). Radiance, power and
/// reflectance all use it; the unit depends on the quantity.
pub type Rgb = Vec3;

/// Luminance of a linear Rec. 709 colour.
pub fn luminance(c: Rgb) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// Square of `x`.
pub fn sqr(x: f32) -> f32 {
    x * x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_and_round_trips() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.5, 0.8).normalize(),
            Vec3::new(0.0, 0.0, -0.99999).normalize(),
        ] {
            let f = Frame::from_normal(n);
            assert!(f.s.dot(f.t).abs() < 1e-5);
            assert!(f.s.dot(f.n).abs() < 1e-5);
            assert!(f.t.dot(f.n).abs() < 1e-5);
            assert!((f.s.length() - 1.0).abs() < 1e-5);
            assert!((f.t.length() - 1.0).abs() < 1e-5);
            let v = Vec3::new(0.2, 0.7, -0.4);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-5);
            assert!((f.to_local(n) - Vec3::Z).length() < 1e-5);
        }
    }

    #[test]
    fn offset_origin_goes_to_the_side_of_the_direction_past_the_error() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let n = Vec3::Z;
        let error = Vec3::splat(1e-6);
        assert!(offset_origin(p, error, n, Vec3::new(0.0, 0.3, 1.0)).z > p.z + 1e-6);
        assert!(offset_origin(p, error, n, Vec3::new(0.0, 0.3, -1.0)).z < p.z - 1e-6);
        // With no error the origin still moves past the rounding of the move, along the
        // normal alone.
        let o = offset_origin(p, Vec3::ZERO, n, Vec3::Z);
        assert!(o.z > p.z && o.z < p.z + 1e-6, "{o}");
        assert_eq!((o.x, o.y), (p.x, p.y));
    }
}
