//! Photon maps: photons in a kd-tree, with the scale that turns their stored power into watts.

use super::kdtree;
use super::record::Photon;
use crate::geometry::Bounds;
use crate::math::{Rgb, Vec3};

/// The two maps of Jensen's method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MapKind {
    /// Photons that reached a diffuse surface through specular surfaces only (L S+ D).
    Caustic,
    /// Every other stored photon, including direct ones (depth 1), which integrators that
    /// compute direct light themselves skip.
    Global,
}

impl MapKind {
    pub fn name(self) -> &'static str {
        match self {
            MapKind::Caustic => "caustic",
            MapKind::Global => "global",
        }
    }
}

/// Photons arranged as a kd-tree. Photon `i`'s flux in watts is
/// `photons[i].relative_power() * power_scale`; the 1/N of the emitted count is already in it.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonMap {
    pub kind: MapKind,
    photons: Vec<Photon>,
    index: kdtree::KdIndex,
    pub power_scale: f32,
}

impl PhotonMap {
    /// Build the kd-tree over `photons` (in parallel for large maps).
    pub fn build(kind: MapKind, mut photons: Vec<Photon>, power_scale: f32) -> Self {
        let index = kdtree::build(&mut photons);
        Self {
            kind,
            photons,
            index,
            power_scale,
        }
    }

    /// Photons already in kd-tree order (as saved to a file).
    pub fn from_tree_order(kind: MapKind, photons: Vec<Photon>, power_scale: f32) -> Self {
        let index = kdtree::KdIndex::from_order(&photons);
        Self {
            kind,
            photons,
            index,
            power_scale,
        }
    }

    pub fn index(&self) -> &kdtree::KdIndex {
        &self.index
    }

    pub fn photons(&self) -> &[Photon] {
        &self.photons
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// Flux of photon `i` in watts per channel.
    pub fn power(&self, i: usize) -> Rgb {
        self.photons[i].relative_power() * self.power_scale
    }

    /// Sum of all photons' flux.
    pub fn total_power(&self) -> Rgb {
        let mut s = glam::DVec3::ZERO;
        for p in &self.photons {
            s += p.relative_power().as_dvec3();
        }
        (s * f64::from(self.power_scale)).as_vec3()
    }

    pub fn bounds(&self) -> Bounds {
        self.photons.iter().fold(Bounds::EMPTY, |b, p| {
            let q = p.position();
            Bounds {
                min: b.min.min(q),
                max: b.max.max(q),
            }
        })
    }

    /// Photons within radius `r` of `q`: (index, squared distance), nearest first.
    pub fn within(&self, q: Vec3, r: f32) -> Vec<(usize, f32)> {
        self.index.within(&self.photons, q, r * r)
    }

    /// Visit photons within radius `r` of `q` without allocating.
    #[inline]
    pub fn for_each_within(&self, q: Vec3, r: f32, f: &mut impl FnMut(usize, f32)) {
        self.index.for_each_within(&self.photons, q, r * r, f);
    }

    /// The `k` nearest photons within `max_r` of `q`: (index, squared distance), nearest first.
    pub fn nearest(&self, q: Vec3, k: usize, max_r: f32) -> Vec<(usize, f32)> {
        self.index.nearest(&self.photons, q, k, max_r * max_r)
    }
}
