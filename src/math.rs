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

/// Offset for a ray leaving a surface at `p`, large enough to clear the float error of the hit
/// point (which grows with the magnitude of the coordinates), small enough to be invisible.
/// About 170 float ulps of the largest coordinate: well above the error of our intersection
/// routines (a few ulps), far below any feature size.
pub fn surface_epsilon(p: Vec3) -> f32 {
    2e-5 * (p.abs().max_element() + 1e-2)
}

/// Origin for a ray leaving the surface at `p` (geometric normal `ng`) in direction `dir`:
/// pushed to the side of the surface that `dir` goes to. This keeps reflected rays outside and
/// refracted rays inside a sphere, which the original project got wrong.
pub fn offset_origin(p: Vec3, ng: Vec3, dir: Vec3) -> Vec3 {
    let eps = surface_epsilon(p);
    if dir.dot(ng) >= 0.0 {
        p + eps * ng
    } else {
        p - eps * ng
    }
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
    fn offset_origin_goes_to_the_side_of_the_direction() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let n = Vec3::Z;
        assert!(offset_origin(p, n, Vec3::new(0.0, 0.3, 1.0)).z > p.z);
        assert!(offset_origin(p, n, Vec3::new(0.0, 0.3, -1.0)).z < p.z);
    }
}
