//! NURBS curves and surfaces (Piegl & Tiller, "The NURBS Book", 1997): rational B-splines of
//! any degree on non-uniform knot vectors, evaluated with derivatives, and tessellated.

use glam::{DVec3, DVec4};

/// Knot span index containing `u` (The NURBS Book, A2.1).
fn find_span(n: usize, p: usize, u: f64, knots: &[f64]) -> usize {
    if u >= knots[n + 1] {
        return n;
    }
    if u <= knots[p] {
        return p;
    }
    let (mut low, mut high) = (p, n + 1);
    let mut mid = (low + high) / 2;
    while u < knots[mid] || u >= knots[mid + 1] {
        if u < knots[mid] {
            high = mid;
        } else {
            low = mid;
        }
        mid = (low + high) / 2;
    }
    mid
}

/// Non-zero basis functions and their first derivatives at `u` (A2.3 with n = 1):
/// returns (N_{span−p..span}(u), N'_{span−p..span}(u)).
fn basis_with_derivative(span: usize, u: f64, p: usize, knots: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut ndu = vec![vec![0.0; p + 1]; p + 1];
    let mut left = vec![0.0; p + 1];
    let mut right = vec![0.0; p + 1];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let values: Vec<f64> = (0..=p).map(|j| ndu[j][p]).collect();
    let mut ders = vec![0.0; p + 1];
    if p > 0 {
        for (r, d) in ders.iter_mut().enumerate() {
            // N'_{i,p} = p (N_{i,p−1} / (u_{i+p} − u_i) − N_{i+1,p−1} / (u_{i+p+1} − u_{i+1})).
            let mut v = 0.0;
            if r >= 1 {
                v += ndu[r - 1][p - 1] / ndu[p][r - 1];
            }
            if r < p {
                v -= ndu[r][p - 1] / ndu[p][r];
            }
            *d = p as f64 * v;
        }
    }
    (values, ders)
}

/// A NURBS curve: degree, knots (clamped), and homogeneous control points (w·x, w·y, w·z, w).
#[derive(Clone, Debug)]
pub struct NurbsCurve {
    pub degree: usize,
    pub knots: Vec<f64>,
    pub points: Vec<DVec4>,
}

/// Homogeneous control point from a position and a weight.
pub fn weighted(p: DVec3, w: f64) -> DVec4 {
    DVec4::new(p.x * w, p.y * w, p.z * w, w)
}

impl NurbsCurve {
    /// The basis function values at `u` (all of them, zero outside the span), for tests.
    pub fn basis(&self, u: f64) -> Vec<f64> {
        let n = self.points.len() - 1;
        let span = find_span(n, self.degree, u, &self.knots);
        let (values, _) = basis_with_derivative(span, u, self.degree, &self.knots);
        let mut all = vec![0.0; self.points.len()];
        for (j, v) in values.into_iter().enumerate() {
            all[span - self.degree + j] = v;
        }
        all
    }

    pub fn point(&self, u: f64) -> DVec3 {
        let n = self.points.len() - 1;
        let span = find_span(n, self.degree, u, &self.knots);
        let (values, _) = basis_with_derivative(span, u, self.degree, &self.knots);
        let mut c = DVec4::ZERO;
        for (j, v) in values.iter().enumerate() {
            c += *v * self.points[span - self.degree + j];
        }
        c.truncate() / c.w
    }
}

/// A NURBS surface; control points indexed `[i * count_v + j]`.
#[derive(Clone, Debug)]
pub struct NurbsSurface {
    pub degree_u: usize,
    pub degree_v: usize,
    pub knots_u: Vec<f64>,
    pub knots_v: Vec<f64>,
    pub count_u: usize,
    pub count_v: usize,
    pub points: Vec<DVec4>,
}

/// A clamped uniform knot vector for `count` control points of degree `p` on [0, 1].
pub fn clamped_uniform_knots(count: usize, p: usize) -> Vec<f64> {
    let inner = count - p;
    let mut k = vec![0.0; p + 1];
    for i in 1..inner {
        k.push(i as f64 / inner as f64);
    }
    k.extend(std::iter::repeat_n(1.0, p + 1));
    k
}

impl NurbsSurface {
    /// Point and unnormalised partial derivatives (S, ∂S/∂u, ∂S/∂v) by the quotient rule on the
    /// homogeneous form.
    pub fn eval(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        let (pu, pv) = (self.degree_u, self.degree_v);
        let su = find_span(self.count_u - 1, pu, u, &self.knots_u);
        let sv = find_span(self.count_v - 1, pv, v, &self.knots_v);
        let (nu, du) = basis_with_derivative(su, u, pu, &self.knots_u);
        let (nv, dv) = basis_with_derivative(sv, v, pv, &self.knots_v);
        let (mut a, mut au, mut av) = (DVec4::ZERO, DVec4::ZERO, DVec4::ZERO);
        for i in 0..=pu {
            for j in 0..=pv {
                let p = self.points[(su - pu + i) * self.count_v + (sv - pv + j)];
                a += nu[i] * nv[j] * p;
                au += du[i] * nv[j] * p;
                av += nu[i] * dv[j] * p;
            }
        }
        let s = a.truncate() / a.w;
        let s_u = (au.truncate() - au.w * s) / a.w;
        let s_v = (av.truncate() - av.w * s) / a.w;
        (s, s_u, s_v)
    }

    /// Unit normal ∂S/∂u × ∂S/∂v.
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        let (_, su, sv) = self.eval(u, v);
        su.cross(sv).normalize_or_zero()
    }

    /// Tessellate on a (segments_u + 1) × (segments_v + 1) grid of parameters into quads.
    pub fn tessellate(&self, segments_u: usize, segments_v: usize) -> super::PolyMesh {
        let mut mesh = super::PolyMesh::default();
        for i in 0..=segments_u {
            for j in 0..=segments_v {
                let (u, v) = (i as f64 / segments_u as f64, j as f64 / segments_v as f64);
                mesh.positions.push(self.eval(u, v).0);
            }
        }
        let idx = |i: usize, j: usize| (i * (segments_v + 1) + j) as u32;
        for i in 0..segments_u {
            for j in 0..segments_v {
                mesh.faces.push(vec![
                    idx(i, j),
                    idx(i + 1, j),
                    idx(i + 1, j + 1),
                    idx(i, j + 1),
                ]);
            }
        }
        mesh
    }
}
