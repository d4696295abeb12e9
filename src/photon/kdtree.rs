//! A balanced kd-tree over points kept in one array (after Jensen, "Realistic Image Synthesis
//! Using Photon Mapping", 2001, ch. 6), with bucket leaves.
//!
//! The build orders the points in place: every range longer than [`LEAF`] is split at its
//! median along the longest axis of its bounds, the left half holding the smaller coordinates.
//! Only leaves hold points, contiguous in memory; the split planes live in a small
//! breadth-first array ([`KdIndex`]) whose top levels share a few cache lines, so a query
//! touches point memory only in the leaves it scans. The split of a range depends only on the
//! set of points in it (its bounds and its smallest right-half coordinate), so a saved point
//! order rebuilds its index in O(N log N) without sorting.
//!
//! Median splits never degenerate on points that share a coordinate (flat walls), unlike
//! bucket-splitting trees. Queries return squared distances computed exactly as brute force.

use crate::math::Vec3;

/// What the tree needs of a point.
pub trait KdPoint: Send + Sync {
    fn position(&self) -> Vec3;
}

impl KdPoint for super::Photon {
    fn position(&self) -> Vec3 {
        super::Photon::position(self)
    }
}

fn longest_axis<T: KdPoint>(points: &[T]) -> usize {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in points {
        let q = p.position();
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let e = hi - lo;
    if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    }
}

/// Ranges this short are leaves, scanned linearly (measured: 32 is 40% faster than 8).
pub const LEAF: usize = 32;
/// Ranges this long are ordered on two threads.
const PARALLEL: usize = 32_768;

/// One split plane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Split {
    value: f32,
    axis: u32,
}

/// The split planes of a kd-tree, breadth first: node k's children are 2k+1 and 2k+2.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KdIndex {
    splits: Vec<Split>,
}

/// Order `points` into a kd-tree and return its index.
pub fn build<T: KdPoint>(points: &mut [T]) -> KdIndex {
    order(points);
    KdIndex::from_order(points)
}

fn order<T: KdPoint>(points: &mut [T]) {
    if points.len() <= LEAF {
        return;
    }
    let axis = longest_axis(points);
    let mid = points.len() / 2;
    points.select_nth_unstable_by(mid, |a, b| {
        a.position()[axis].total_cmp(&b.position()[axis])
    });
    let (left, right) = points.split_at_mut(mid);
    if left.len() >= PARALLEL {
        rayon::join(|| order(left), || order(right));
    } else {
        order(left);
        order(right);
    }
}

impl KdIndex {
    /// The index of points already in kd-tree order (as [`build`] left them, or as saved).
    pub fn from_order<T: KdPoint>(points: &[T]) -> Self {
        let mut splits = Vec::new();
        fill(points, 0, 0, points.len(), &mut splits);
        Self { splits }
    }

    /// Call `f(index, squared distance)` for every point within `sqrt(r2)` of `q` (inclusive).
    #[inline]
    pub fn for_each_within<T: KdPoint>(
        &self,
        points: &[T],
        q: Vec3,
        r2: f32,
        f: &mut impl FnMut(usize, f32),
    ) {
        let mut v = WithinRadius { r2, f };
        self.search(points, 0, 0, points.len(), q, &mut v);
    }

    /// Indices and squared distances of all points within `sqrt(r2)` of `q`, nearest first.
    pub fn within<T: KdPoint>(&self, points: &[T], q: Vec3, r2: f32) -> Vec<(usize, f32)> {
        let mut out = Vec::new();
        self.for_each_within(points, q, r2, &mut |i, d2| out.push((i, d2)));
        out.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        out
    }

    /// The `k` nearest points to `q` within `sqrt(max_r2)`, nearest first.
    pub fn nearest<T: KdPoint>(
        &self,
        points: &[T],
        q: Vec3,
        k: usize,
        max_r2: f32,
    ) -> Vec<(usize, f32)> {
        self.nearest_by(points, q, k, max_r2, &|_, _, d2| Some(d2))
            .into_sorted()
    }
}

impl KdIndex {
    /// The `k` nearest points under a custom metric: `metric(index, point, euclidean d²)` returns the
    /// point's distance² (which must be ≥ the Euclidean one, so pruning stays exact) or `None`
    /// to skip it. Used for disc-shaped searches and normal filters.
    pub fn nearest_by<T: KdPoint>(
        &self,
        points: &[T],
        q: Vec3,
        k: usize,
        max_r2: f32,
        metric: &impl Fn(usize, &T, f32) -> Option<f32>,
    ) -> Nearest {
        let mut v = NearestBy {
            best: Nearest::new(k, max_r2),
            metric,
        };
        self.search(points, 0, 0, points.len(), q, &mut v);
        v.best
    }

    /// The one traversal: visits every point whose Euclidean distance² is within the
    /// visitor's current radius², nearer subtrees first.
    fn search<T: KdPoint, V: Visitor<T>>(
        &self,
        points: &[T],
        node: usize,
        lo: usize,
        hi: usize,
        q: Vec3,
        v: &mut V,
    ) {
        if hi - lo <= LEAF {
            for (i, p) in points[lo..hi].iter().enumerate() {
                let d2 = (p.position() - q).length_squared();
                if d2 <= v.r2() {
                    v.visit(lo + i, p, d2);
                }
            }
            return;
        }
        let mid = lo + (hi - lo) / 2;
        let s = self.splits[node];
        let delta = q[s.axis as usize] - s.value;
        let (left, right) = ((2 * node + 1, lo, mid), (2 * node + 2, mid, hi));
        let (near, far) = if delta < 0.0 {
            (left, right)
        } else {
            (right, left)
        };
        self.search(points, near.0, near.1, near.2, q, v);
        if delta * delta <= v.r2() {
            self.search(points, far.0, far.1, far.2, q, v);
        }
    }
}

/// What a search does with the points it reaches, and how far it still looks.
trait Visitor<T> {
    fn r2(&self) -> f32;
    fn visit(&mut self, i: usize, point: &T, d2: f32);
}

struct WithinRadius<'f, F> {
    r2: f32,
    f: &'f mut F,
}

impl<T, F: FnMut(usize, f32)> Visitor<T> for WithinRadius<'_, F> {
    fn r2(&self) -> f32 {
        self.r2
    }
    fn visit(&mut self, i: usize, _: &T, d2: f32) {
        (self.f)(i, d2);
    }
}

struct NearestBy<'m, M> {
    best: Nearest,
    metric: &'m M,
}

impl<T, M: Fn(usize, &T, f32) -> Option<f32>> Visitor<T> for NearestBy<'_, M> {
    fn r2(&self) -> f32 {
        self.best.r2()
    }
    fn visit(&mut self, i: usize, point: &T, d2: f32) {
        if let Some(m) = (self.metric)(i, point, d2) {
            self.best.offer(m, i);
        }
    }
}

fn fill<T: KdPoint>(points: &[T], node: usize, lo: usize, hi: usize, splits: &mut Vec<Split>) {
    if hi - lo <= LEAF {
        return;
    }
    let mid = lo + (hi - lo) / 2;
    let axis = longest_axis(&points[lo..hi]);
    // Every left point is ≤ the median ≤ every right point, so the smallest right coordinate
    // separates the halves whatever order the deeper levels left them in.
    let value = points[mid..hi]
        .iter()
        .map(|p| p.position()[axis])
        .fold(f32::INFINITY, f32::min);
    if splits.len() <= node {
        splits.resize(node + 1, Split::default());
    }
    splits[node] = Split {
        value,
        axis: axis as u32,
    };
    fill(points, 2 * node + 1, lo, mid, splits);
    fill(points, 2 * node + 2, mid, hi, splits);
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
    pub fn r2(&self) -> f32 {
        if self.heap.len() == self.k && self.k > 0 {
            self.heap[0].0
        } else {
            self.max_r2
        }
    }

    #[inline]
    pub fn offer(&mut self, d2: f32, i: usize) {
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

    /// Found so far, in heap order: (squared distance, index).
    pub fn found(&self) -> &[(f32, usize)] {
        &self.heap
    }

    /// Whether all k were found (so `r2()` is the k-th distance).
    pub fn is_full(&self) -> bool {
        self.heap.len() == self.k
    }

    /// Found points as (index, squared distance), nearest first.
    pub fn into_sorted(mut self) -> Vec<(usize, f32)> {
        self.heap
            .sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        self.heap.into_iter().map(|(d2, i)| (i, d2)).collect()
    }
}
