//! Density grids from the bytes of files: OpenVDB (`.vdb`, what Blender bakes smoke and
//! fluids to) and Mitsuba's binary volume format (`.vol`). Both are untrusted input: every
//! size is checked against the file before anything is allocated, and a grid may hold at most
//! [`MAX_VOXELS`] voxels. The scene description reads the files (through `io::input`).

use super::{DensityGrid, MAX_VOXELS};
use crate::error::{Diagnostic, Error, Result};
use glam::{Affine3A, Mat3A, Vec3, Vec3A};
use std::path::Path;

/// A grid read from a file, with the map from its unit cube (see [`super::GridMedium`]) to
/// the space the file places it in.
#[derive(Debug)]
pub struct GridFile {
    pub grid: DensityGrid,
    pub unit_to_world: Affine3A,
}

/// The formats grids are read from, by the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GridFormat {
    /// OpenVDB.
    Vdb,
    /// Mitsuba's binary volume.
    Vol,
}

impl GridFormat {
    pub fn of(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("vdb") => Ok(GridFormat::Vdb),
            Some("vol") => Ok(GridFormat::Vol),
            _ => Err(Error::SceneFile(Box::new(Diagnostic::whole_file(
                path,
                "unsupported grid format; expected .vdb (OpenVDB) or .vol (Mitsuba)",
            )))),
        }
    }
}

/// The float grid `name` of the `.vdb` file `path` whose content is `bytes`, or the
/// single-channel grid of a `.vol` file (which has no names: `name` is not used).
pub fn parse(path: &Path, format: GridFormat, bytes: &[u8], name: &str) -> Result<GridFile> {
    let fail = |message: String| Error::SceneFile(Box::new(Diagnostic::whole_file(path, message)));
    match format {
        GridFormat::Vdb => read_vdb(bytes, name).map_err(fail),
        GridFormat::Vol => read_vol(bytes).map_err(fail),
    }
}

/// An OpenVDB float grid, read densely over its active voxels' bounding box. OpenVDB puts
/// voxel centres at integer index coordinates, so the unit cube spans index_min − ½ to
/// index_max + ½; the file's transform takes index space to its world.
fn read_vdb(bytes: &[u8], name: &str) -> std::result::Result<GridFile, String> {
    let dense = super::vdb::read_float_grid(bytes, name, MAX_VOXELS).map_err(|e| e.to_string())?;
    let [nx, ny, nz] = dense.resolution;
    if nx * ny * nz == 0 {
        return Err(format!("the grid '{name}' has no active voxels"));
    }
    let m = dense.index_to_world;
    let column = |c: usize| Vec3A::new(m[0][c] as f32, m[1][c] as f32, m[2][c] as f32);
    let index_to_world = Affine3A {
        matrix3: Mat3A::from_cols(column(0), column(1), column(2)),
        translation: column(3),
    };
    let min = Vec3::new(
        dense.index_min[0] as f32,
        dense.index_min[1] as f32,
        dense.index_min[2] as f32,
    ) - 0.5;
    let unit_to_index = Affine3A::from_translation(min)
        * Affine3A::from_scale(Vec3::new(nx as f32, ny as f32, nz as f32));
    Ok(GridFile {
        grid: DensityGrid::new(dense.resolution, dense.values)?,
        unit_to_world: index_to_world * unit_to_index,
    })
}

/// Mitsuba's `.vol`: "VOL", version 3, encoding 1 (32-bit floats), the resolution, the
/// channel count (1 for a density), a bounding box, then the values with x fastest, all
/// little-endian. Like Mitsuba 3's `gridvolume`, the grid fills the unit cube and the
/// bounding box in the file is not used: the medium's `transform` places it.
fn read_vol(bytes: &[u8]) -> std::result::Result<GridFile, String> {
    const HEADER: usize = 48;
    if bytes.len() < HEADER || &bytes[..3] != b"VOL" {
        return Err("not a Mitsuba volume: expected the bytes 'VOL' and a 48-byte header".into());
    }
    if bytes[3] != 3 {
        return Err(format!("byte 3: version {}, expected 3", bytes[3]));
    }
    let int =
        |at: usize| i32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    if int(4) != 1 {
        return Err(format!(
            "byte 4: encoding {}, expected 1 (32-bit floats)",
            int(4)
        ));
    }
    let dims = [int(8), int(12), int(16)];
    if dims.iter().any(|&d| d <= 0) {
        return Err(format!(
            "byte 8: resolution {}×{}×{}; each must be at least 1",
            dims[0], dims[1], dims[2]
        ));
    }
    if int(20) != 1 {
        return Err(format!(
            "byte 20: {} channels, expected 1 (a density)",
            int(20)
        ));
    }
    let resolution = dims.map(|d| d as usize);
    let count = resolution
        .iter()
        .try_fold(1usize, |n, &r| n.checked_mul(r))
        .filter(|&n| n <= MAX_VOXELS)
        .ok_or_else(|| {
            format!(
                "a grid of {}×{}×{} voxels: at most {MAX_VOXELS} are read",
                dims[0], dims[1], dims[2]
            )
        })?;
    let data = &bytes[HEADER..];
    if data.len() != count * 4 {
        return Err(format!(
            "byte {HEADER}: {} bytes of values for {count} voxels, expected {}",
            data.len(),
            count * 4
        ));
    }
    let values = data
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    Ok(GridFile {
        grid: DensityGrid::new(resolution, values)?,
        unit_to_world: Affine3A::IDENTITY,
    })
}

/// The bytes of a `.vol` file of one channel, for tools and tests that make grids.
pub fn write_vol(resolution: [usize; 3], values: &[f32]) -> Vec<u8> {
    let mut out = Vec::with_capacity(48 + 4 * values.len());
    out.extend_from_slice(b"VOL\x03");
    for v in [1, resolution[0], resolution[1], resolution[2], 1] {
        out.extend_from_slice(&(v as i32).to_le_bytes());
    }
    for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vol_file_reads_back_and_bad_ones_are_refused() {
        let bytes = write_vol([2, 1, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
        let g = read_vol(&bytes).unwrap();
        assert_eq!(g.grid.resolution(), [2, 1, 3]);
        assert_eq!(g.grid.max(), 5.0);
        let short = read_vol(&bytes[..bytes.len() - 1]).unwrap_err();
        assert!(short.contains("expected 24"), "{short}");
        let mut huge = bytes.clone();
        huge[8..12].copy_from_slice(&i32::MAX.to_le_bytes());
        huge[12..16].copy_from_slice(&i32::MAX.to_le_bytes());
        assert!(read_vol(&huge).unwrap_err().contains("at most"));
        let mut rgb = bytes;
        rgb[20] = 3;
        assert!(read_vol(&rgb).unwrap_err().contains("channels"));
        assert!(read_vol(b"VOL").is_err());
    }
}
