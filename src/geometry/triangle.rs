use super::{Bounds, ShapeHit, SurfacePoint};
use crate::math::{Ray, Vec2, Vec3, gamma};
use crate::sampling::uniform_triangle;
use glam::{Vec3A, Vec3Swizzles};

/// A triangle as its three vertices, exactly as the mesh gives them: two triangles sharing an
/// edge then share its floats, which the watertight test needs.
#[derive(Clone, Copy, Debug)]
pub struct Triangle {
    pub p0: Vec3,
    pub p1: Vec3,
    pub p2: Vec3,
}

impl Triangle {
    pub fn new(p0: Vec3, p1: Vec3, p2: Vec3) -> Self {
        Self { p0, p1, p2 }
    }

    /// The edge from the first vertex to the second.
    #[inline]
    pub fn e1(&self) -> Vec3 {
        self.p1 - self.p0
    }

    /// The edge from the first vertex to the third.
    #[inline]
    pub fn e2(&self) -> Vec3 {
        self.p2 - self.p0
    }

    /// Barycentric coordinates (b1, b2) of a point of the triangle's plane: p = p0 + b1 e1 + b2 e2.
    pub fn barycentrics(&self, p: Vec3) -> Vec2 {
        let (e1, e2) = (self.e1(), self.e2());
        let d = p - self.p0;
        let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (d1, d2) = (d.dot(e1), d.dot(e2));
        let det = d11 * d22 - d12 * d12;
        if det == 0.0 {
            return Vec2::ZERO;
        }
        Vec2::new((d22 * d1 - d12 * d2) / det, (d11 * d2 - d12 * d1) / det)
    }

    pub fn vertices(&self) -> [Vec3; 3] {
        [self.p0, self.p1, self.p2]
    }

    pub fn bounds(&self) -> Bounds {
        let [a, b, c] = self.vertices();
        Bounds {
            min: a.min(b).min(c),
            max: a.max(b).max(c),
        }
    }

    /// The hit with `t` in (`t_min`, `t_max`), by the watertight test ([`watertight_hit`]).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        watertight_hit(
            &ShearedRay::new(ray),
            &transposed(self.vertices()),
            t_min,
            t_max,
        )
    }

    /// Geometric normal following the winding (p0, p1, p2), counter-clockwise seen from the front.
    pub fn normal(&self) -> Vec3 {
        self.e1().cross(self.e2()).normalize()
    }

    pub fn surface(&self, hit: &ShapeHit) -> SurfacePoint {
        // From barycentrics rather than the ray: the point then lies on the triangle's plane.
        self.point_at(hit.uv.x, hit.uv.y)
    }

    /// The point p0 + b1 (p1 − p0) + b2 (p2 − p0), with the bound of its rounding: the exact
    /// value for any b1, b2 lies on the triangle's plane, and the two differences, two products
    /// and two sums round each coordinate by at most γ₇ of the terms' magnitudes (pbrt-v4
    /// §6.8.5 bounds the same interpolation).
    fn point_at(&self, b1: f32, b2: f32) -> SurfacePoint {
        let (a, b) = (b1 * self.e1(), b2 * self.e2());
        SurfacePoint {
            p: self.p0 + a + b,
            n: self.normal(),
            error: gamma(7) * (self.p0.abs() + a.abs() + b.abs()),
        }
    }

    /// Half the edges' cross product's length, in f64: its squared components overflow f32
    /// for edges past about 1e10, well inside the coordinates a scene may have.
    pub fn area(&self) -> f32 {
        let (a, b) = (self.e1().as_dvec3(), self.e2().as_dvec3());
        (0.5 * a.cross(b).length()) as f32
    }

    pub fn sample_area(&self, u: Vec2) -> SurfacePoint {
        let b = uniform_triangle(u);
        self.point_at(b.y, b.z)
    }
}

/// A ray made ready for [`watertight_hit`] (Woop, Benthin & Wald, "Watertight Ray/Triangle
/// Intersection", JCGT 2013): the permutation and shear that turn its direction into +z. Made
/// once per ray and used for every triangle it is tested against.
#[derive(Clone, Copy, Debug)]
pub struct ShearedRay {
    /// k_x, k_y, k_z: k_z the axis along which the direction is largest, the others after it
    /// in cyclic order.
    axes: [usize; 3],
    /// The origin's coordinates along k_x, k_y and k_z, each in every lane.
    origin: [Vec3A; 3],
    /// s_x = −d_kx/d_kz and s_y = −d_ky/d_kz, in every lane.
    shear: [Vec3A; 2],
    /// 1/d_kz: the ray's frame's z over distance along the ray.
    inv_dz: f32,
}

impl ShearedRay {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let a = ray.dir.abs();
        let kz = if a.x > a.y && a.x > a.z {
            0
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let axes = [(kz + 1) % 3, (kz + 2) % 3, kz];
        let (d, o) = (ray.dir.to_array(), ray.origin.to_array());
        let dz = d[kz];
        Self {
            axes,
            origin: axes.map(|k| Vec3A::splat(o[k])),
            shear: [
                Vec3A::splat(-d[axes[0]] / dz),
                Vec3A::splat(-d[axes[1]] / dz),
            ],
            inv_dz: 1.0 / dz,
        }
    }
}

/// A triangle's vertices by coordinate: `[xs, ys, zs]`, each holding that coordinate of the
/// three vertices in its lanes, as [`watertight_hit`] reads them.
#[inline]
pub fn transposed([a, b, c]: [Vec3; 3]) -> [Vec3A; 3] {
    [
        Vec3A::new(a.x, b.x, c.x),
        Vec3A::new(a.y, b.y, c.y),
        Vec3A::new(a.z, b.z, c.z),
    ]
}

/// The watertight ray–triangle test (Woop, Benthin & Wald 2013; pbrt-v4 §6.5.3) on the three
/// vertices at once, a lane each ([`transposed`]). The vertices are moved into the ray's frame,
/// where the ray is the +z axis through the origin, and the signs of the three 2D edge
/// functions decide. An edge's function is computed from that edge's two vertices alone (the
/// same products, negated for the other winding), so two triangles sharing an edge agree on
/// which side of it the ray passes: no ray slips between them, as rays aimed at shared edges
/// and vertices did with Möller–Trumbore. A function that rounds to zero is computed again in
/// double precision, whose products are exact. Returns the hit with `t` in (`t_min`,
/// `t_max`) and its barycentrics (b1, b2) of the second and third vertices.
#[inline(always)]
pub fn watertight_hit(
    ray: &ShearedRay,
    vertices: &[Vec3A; 3],
    t_min: f32,
    t_max: f32,
) -> Option<ShapeHit> {
    let [kx, ky, kz] = ray.axes;
    let z = vertices[kz] - ray.origin[2];
    let x = (vertices[kx] - ray.origin[0]) + ray.shear[0] * z;
    let y = (vertices[ky] - ray.origin[1]) + ray.shear[1] * z;
    // Lane i: the edge opposite vertex i, from vertex i+1 to vertex i+2.
    let (x1, y1, x2, y2) = (x.yzx(), y.yzx(), x.zxy(), y.zxy());
    let mut e = x1 * y2 - y1 * x2;
    if e.cmpeq(Vec3A::ZERO).any() {
        let exact = |i: usize| {
            (f64::from(x1[i]) * f64::from(y2[i]) - f64::from(y1[i]) * f64::from(x2[i])) as f32
        };
        e = Vec3A::new(exact(0), exact(1), exact(2));
    }
    if e.cmplt(Vec3A::ZERO).any() && e.cmpgt(Vec3A::ZERO).any() {
        return None;
    }
    let det = e.x + e.y + e.z;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let t_scaled = (e.x * z.x + e.y * z.y + e.z * z.z) * ray.inv_dz;
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    (t > t_min && t < t_max && t > rounding_of_t(&x, &y, &(z * ray.inv_dz), &e, inv_det)).then(
        || ShapeHit {
            t,
            uv: Vec2::new(e.y * inv_det, e.z * inv_det),
        },
    )
}

/// A bound on the rounding error of the distance [`watertight_hit`] computes, from the
/// sheared vertices `x`, `y`, the scaled depths `z` and the edge functions `e` (pbrt-v4
/// §6.8.4, "Robust Triangle Intersections"). A hit closer than this may lie behind the
/// origin: a ray leaving a surface by [`crate::math::offset_origin`] would otherwise find the
/// surface it left.
#[inline]
fn rounding_of_t(x: &Vec3A, y: &Vec3A, z: &Vec3A, e: &Vec3A, inv_det: f32) -> f32 {
    let max_x = x.abs().max_element();
    let max_y = y.abs().max_element();
    let max_z = z.abs().max_element();
    let delta_z = gamma(3) * max_z;
    let delta_x = gamma(5) * (max_x + max_z);
    let delta_y = gamma(5) * (max_y + max_z);
    let delta_e = 2.0 * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e = e.abs().max_element();
    3.0 * (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv_det.abs()
}
