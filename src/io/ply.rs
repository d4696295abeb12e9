//! Photon maps as PLY point clouds (binary little-endian by default, ASCII on request), for
//! MeshLab, Blender or CloudCompare: the original project's visualisation, for any map.
//!
//! Per vertex: `x y z` position; `nx ny nz` the photon's incoming direction (toward where it
//! came from), as the original stored it; `red green blue` the colour asked for; `power` the
//! flux in watts (of the selected channel, or summed over RGB); `depth`.

use super::atomic::write_atomically;
use super::image::linear_to_srgb;
use crate::error::{Error, Result};
use crate::math::Rgb;
use crate::photon::{Channel, MapKind, Photon, PhotonMap, PhotonMaps};
use std::io::{BufWriter, Write};
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlyEncoding {
    Binary,
    Ascii,
}

/// How points are coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlyColor {
    /// Incoming direction mapped to RGB (d · 0.5 + 0.5).
    Direction,
    /// Photon power, relative to the brightest exported photon, sRGB-encoded.
    Power,
    /// A palette by depth: 1 white, 2 yellow, 3 orange, 4 red, 5 magenta, 6 blue, 7+ cyan.
    Depth,
}

/// Which photons to export.
#[derive(Clone, Debug, PartialEq)]
pub struct PlyFilter {
    pub maps: Vec<MapKind>,
    pub depth: Option<u8>,
    /// Keep only photons that carry this channel (0 red, 1 green, 2 blue).
    pub channel: Option<usize>,
}

struct Point {
    photon: Photon,
    power: Rgb,
}

fn selected(maps: &PhotonMaps, f: &PlyFilter) -> Vec<Point> {
    let mut out = Vec::new();
    for &kind in &f.maps {
        let map: &PhotonMap = maps.map(kind);
        for (i, p) in map.photons().iter().enumerate() {
            if f.depth.is_some_and(|d| p.depth != d) {
                continue;
            }
            let mut power = map.power(i);
            if let Some(c) = f.channel {
                let carries = match p.channel() {
                    Channel::Rgb => power[c] > 0.0,
                    ch => ch.index() == Some(c),
                };
                if !carries {
                    continue;
                }
                let mut only = Rgb::ZERO;
                only[c] = power[c];
                power = only;
            }
            out.push(Point { photon: *p, power });
        }
    }
    out
}

fn depth_color(depth: u8) -> [u8; 3] {
    const PALETTE: [[u8; 3]; 7] = [
        [255, 255, 255],
        [255, 230, 0],
        [255, 140, 0],
        [230, 20, 20],
        [220, 0, 220],
        [40, 80, 255],
        [0, 220, 220],
    ];
    PALETTE[(depth.max(1) as usize - 1).min(PALETTE.len() - 1)]
}

fn to_byte(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// Write the selected photons; returns how many were written.
pub fn export(
    maps: &PhotonMaps,
    path: &Path,
    filter: &PlyFilter,
    color: PlyColor,
    encoding: PlyEncoding,
) -> Result<u64> {
    let points = selected(maps, filter);
    let brightest = points
        .iter()
        .map(|p| p.power.max_element())
        .fold(0.0f32, f32::max);
    let colour = |p: &Point| -> [u8; 3] {
        match color {
            PlyColor::Direction => (p.photon.incoming() * 0.5 + 0.5).to_array().map(to_byte),
            PlyColor::Power => {
                let rel = if brightest > 0.0 {
                    p.power / brightest
                } else {
                    Rgb::ZERO
                };
                rel.to_array().map(|c| to_byte(linear_to_srgb(c)))
            }
            PlyColor::Depth => depth_color(p.photon.depth),
        }
    };
    let format = match encoding {
        PlyEncoding::Binary => "binary_little_endian",
        PlyEncoding::Ascii => "ascii",
    };
    write_atomically(path, |tmp| {
        let io = |source| Error::Write {
            path: path.to_owned(),
            source,
        };
        let mut w = BufWriter::new(std::fs::File::create(tmp).map_err(io)?);
        let header = format!(
            "ply\nformat {format} 1.0\ncomment Photon photon map of scene '{}', maps {:?}\nelement vertex {}\n\
             property float x\nproperty float y\nproperty float z\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             property uchar red\nproperty uchar green\nproperty uchar blue\n\
             property float power\nproperty uchar depth\nend_header\n",
            maps.scene_name,
            filter.maps.iter().map(|m| m.name()).collect::<Vec<_>>(),
            points.len()
        );
        w.write_all(header.as_bytes()).map_err(io)?;
        for p in &points {
            let pos = p.photon.position;
            let d = p.photon.incoming();
            let c = colour(p);
            let power = p.power.x + p.power.y + p.power.z;
            match encoding {
                PlyEncoding::Ascii => writeln!(
                    w,
                    "{} {} {} {} {} {} {} {} {} {} {}",
                    pos[0], pos[1], pos[2], d.x, d.y, d.z, c[0], c[1], c[2], power, p.photon.depth
                )
                .map_err(io)?,
                PlyEncoding::Binary => {
                    let mut rec = Vec::with_capacity(32);
                    for v in [pos[0], pos[1], pos[2], d.x, d.y, d.z] {
                        rec.extend_from_slice(&v.to_le_bytes());
                    }
                    rec.extend_from_slice(&c);
                    rec.extend_from_slice(&power.to_le_bytes());
                    rec.push(p.photon.depth);
                    w.write_all(&rec).map_err(io)?;
                }
            }
        }
        w.flush().map_err(io)
    })?;
    Ok(points.len() as u64)
}
