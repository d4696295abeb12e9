//! A balanced kd-tree stored implicitly in one array (Jensen, "Realistic Image Synthesis Using
//! Photon Mapping", 2001, ch. 6): the median of every range is its node, so the tree costs no
//! memory beyond the points themselves plus two bits for the split axis.
//!
//! Built in bulk after all points are known, in parallel; answers k-nearest (within a maximum
//! radius) and fixed-radius queries with squared distances, exactly as brute force would.
//! Median splits never degenerate on points that share a coordinate (flat walls), unlike
//! bucket-splitting trees.

use crate::math::Vec3;

/// What the tree needs of a point: its position and a place to keep the split axis.
pub trait KdPoint: Send {
    fn position(&self) -> Vec3;
    fn split_axis(&self) -> usize;
    fn set_split_axis(&mut self, axis: usize);
}

impl KdPoint for super::Photon {
    fn position(&self) -> Vec3 {
        super::Photon::position(self)
    }
    fn split_axis(&self) -> usize {
        super::Photon::split_axis(self)
    }
    fn set_split_axis(&mut self, axis: usize) {
        super::Photon::set_split_axis(self, axis);
    }
}

/// Ranges this short are scanned linearly rather than split.
const LEAF: usize = 8;
/// Ranges this long are built on two threads.
const PARALLEL: usize = 32_768;

/// Arrange `points` into a balanced kd-tree in place.
pub fn build<T: KdPoint>(points: &mut [T]) {
    if points.len() <= LEAF {
        return;
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in points.iter() {
        let q = p.position();
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let extent = hi - lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = points.len() / 2;
    points.select_nth_unstable_by(mid, |a, b| {
        a.position()[axis].total_cmp(&b.position()[axis])
    });
    points[mid].set_split_axis(axis);
    let (left, rest) = points.split_at_mut(mid);
    let right = &mut rest[1..];
    if left.len() >= PARALLEL {
        rayon::join(|| build(left), || build(right));
    } else {
        build(left);
        build(right);
    }
}

/// Call `f(index, squared distance)` for every point within `sqrt(r2)` of `q` (inclusive).
#[inline]
pub fn for_each_within<T: KdPoint>(points: &[T], q: Vec3, r2: f32, f: &mut impl FnMut(usize, f32)) {
    within_range(points, 0, points.len(), q, r2, f);
}

fn within_range<T: KdPoint>(
    points: &[T],
    lo: usize,
    hi: usize,
    q: Vec3,
    r2: f32,
    f: &mut impl FnMut(usize, f32),
) {
    if hi - lo <= LEAF {
        for (i, p) in points[lo..hi].iter().enumerate() {
            let d2 = (p.position() - q).length_squared();
            if d2 <= r2 {
                f(lo + i, d2);
            }
        }
        return;
    }
    let mid = lo + (hi - lo) / 2;
    let node = &points[mid];
    let p = node.position();
    let axis = node.split_axis();
    let delta = q[axis] - p[axis];
    let d2 = (p - q).length_squared();
    if d2 <= r2 {
        f(mid, d2);
    }
    let (near, far) = if delta <= 0.0 {
        ((lo, mid), (mid + 1, hi))
    } else {
        ((mid + 1, hi), (lo, mid))
    };
    within_range(points, near.0, near.1, q, r2, f);
    if delta * delta <= r2 {
        within_range(points, far.0, far.1, q, r2, f);
    }
}

/// Indices and squared distances of all points within `sqrt(r2)` of `q`, nearest first.
pub fn within<T: KdPoint>(points: &[T], q: Vec3, r2: f32) -> Vec<(usize, f32)> {
    let mut out = Vec::new();
    for_each_within(points, q, r2, &mut |i, d2| out.push((i, d2)));
    out.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    out
}

/// A bounded max-heap of the k nearest candidates found so far.
pub struct Nearest {
    k: usize,
    heap: Vec<(f32, usize)>,
    max_r2: f32,
}

impl Nearest {
    pub fn new(k: usize, max_r2: f32) -> Self {
        Self {
            k,
            heap: Vec::with_capacity(k + 1),
            max_r2,
        }
    }

    /// Current search radius²: the k-th distance once k are found, else the maximum.
    #[inline]
    fn r2(&self) -> f32 {
        if self.heap.len() == self.k {
            self.heap[0].0
        } else {
            self.max_r2
        }
    }

    #[inline]
    fn offer(&mut self, d2: f32, i: usize) {
        if d2 > self.r2() || self.k == 0 {
            return;
        }
        if self.heap.len() == self.k {
            // Replace the farthest, then sift down.
            self.heap[0] = (d2, i);
            let mut j = 0;
            loop {
                let (l, r) = (2 * j + 1, 2 * j + 2);
                let mut m = j;
                if l < self.heap.len() && self.heap[l].0 > self.heap[m].0 {
                    m = l;
                }
                if r < self.heap.len() && self.heap[r].0 > self.heap[m].0 {
                    m = r;
                }
                if m == j {
                    break;
                }
                self.heap.swap(j, m);
                j = m;
            }
        } else {
            self.heap.push((d2, i));
            let mut j = self.heap.len() - 1;
            while j > 0 {
                let parent = (j - 1) / 2;
                if self.heap[parent].0 >= self.heap[j].0 {
                    break;
                }
                self.heap.swap(j, parent);
                j = parent;
            }
        }
    }

    /// Found points as (index, squared distance), nearest first.
    pub fn into_sorted(mut self) -> Vec<(usize, f32)> {
        self.heap
            .sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        self.heap.into_iter().map(|(d2, i)| (i, d2)).collect()
    }
}

/// The `k` nearest points to `q` within `sqrt(max_r2)`, nearest first.
pub fn nearest<T: KdPoint>(points: &[T], q: Vec3, k: usize, max_r2: f32) -> Vec<(usize, f32)> {
    let mut best = Nearest::new(k, max_r2);
    nearest_range(points, 0, points.len(), q, &mut best);
    best.into_sorted()
}

fn nearest_range<T: KdPoint>(points: &[T], lo: usize, hi: usize, q: Vec3, best: &mut Nearest) {
    if hi - lo <= LEAF {
        for (i, p) in points[lo..hi].iter().enumerate() {
            best.offer((p.position() - q).length_squared(), lo + i);
        }
        return;
    }
    let mid = lo + (hi - lo) / 2;
    let node = &points[mid];
    let p = node.position();
    let axis = node.split_axis();
    let delta = q[axis] - p[axis];
    let (near, far) = if delta <= 0.0 {
        ((lo, mid), (mid + 1, hi))
    } else {
        ((mid + 1, hi), (lo, mid))
    };
    nearest_range(points, near.0, near.1, q, best);
    best.offer((p - q).length_squared(), mid);
    if delta * delta <= best.r2() {
        nearest_range(points, far.0, far.1, q, best);
    }
}
