//! What the viewer sends to draw a saved photon map (`photon view maps.phm`): the photons as
//! points and the scene's shapes as a wireframe, both as little-endian f32 arrays the page
//! hands to WebGL as they are.

use photon::geometry::Shape;
use photon::math::Vec3;
use photon::photon::PhotonMaps;
use photon::scene::Scene;

/// Floats per photon: position (3), power in watts (3), unit direction toward where it came
/// from (3), depth (bounces from the light, 1 = straight from it), map (0 global, 1 caustic).
pub const PHOTON_FLOATS: usize = 11;

/// The most photons sent; a larger map is thinned evenly (every k-th photon, its power
/// times k, so the picture's total stays the map's).
pub const MAX_PHOTONS: usize = 2_000_000;

/// Segments per circle drawn for a sphere or a disk.
const CIRCLE_SEGMENTS: usize = 48;

/// The most wireframe segments sent (about 7 MB); a larger scene's triangles are thinned.
const MAX_SEGMENTS: usize = 300_000;

/// The photons of both maps, and how many of each the file holds.
pub fn photon_floats(maps: &PhotonMaps) -> (Vec<f32>, [usize; 2]) {
    let counts = [maps.global.len(), maps.caustic.len()];
    let stride = (counts[0] + counts[1]).div_ceil(MAX_PHOTONS).max(1);
    let mut out = Vec::with_capacity((counts[0] + counts[1]) / stride * PHOTON_FLOATS);
    for (which, map) in [(0.0, &maps.global), (1.0, &maps.caustic)] {
        let scale = map.power_scale * stride as f32;
        for p in map.photons().iter().step_by(stride) {
            out.extend(p.position().to_array());
            out.extend((p.relative_power() * scale).to_array());
            out.extend(p.incoming().to_array());
            out.push(f32::from(p.depth()));
            out.push(which);
        }
    }
    (out, counts)
}

/// The scene's shapes as line segments (6 floats each): each triangle's edges, three great
/// circles of each sphere, each disk's rim.
pub fn wireframe(scene: &Scene) -> Vec<f32> {
    let n = scene.primitive_count();
    let stride = (n * 3).div_ceil(MAX_SEGMENTS).max(1);
    let mut out = Vec::new();
    let mut segment = |a: Vec3, b: Vec3| {
        out.extend(a.to_array());
        out.extend(b.to_array());
    };
    let circle = |centre: Vec3, u: Vec3, v: Vec3, segment: &mut dyn FnMut(Vec3, Vec3)| {
        let at = |k: usize| {
            let t = std::f32::consts::TAU * k as f32 / CIRCLE_SEGMENTS as f32;
            centre + u * t.cos() + v * t.sin()
        };
        for k in 0..CIRCLE_SEGMENTS {
            segment(at(k), at(k + 1));
        }
    };
    for prim in (0..n).step_by(stride) {
        match scene.shape(prim as u32) {
            Shape::Triangle(t) => {
                let [a, b, c] = t.vertices();
                segment(a, b);
                segment(b, c);
                segment(c, a);
            }
            Shape::Sphere(s) => {
                let r = s.radius;
                circle(s.center, Vec3::X * r, Vec3::Y * r, &mut segment);
                circle(s.center, Vec3::Y * r, Vec3::Z * r, &mut segment);
                circle(s.center, Vec3::Z * r, Vec3::X * r, &mut segment);
            }
            Shape::Disk(d) => {
                let f = photon::math::Frame::from_normal(d.normal);
                circle(d.center, f.s * d.radius, f.t * d.radius, &mut segment);
            }
        }
    }
    out
}

/// Floats as little-endian bytes.
pub fn to_bytes(floats: &[f32]) -> Vec<u8> {
    floats.iter().flat_map(|v| v.to_le_bytes()).collect()
}
