//! A reader for float grids in OpenVDB files (`.vdb`), such as Blender's smoke caches.
//!
//! VDB files are untrusted input: every size read from the file is checked against the
//! bytes that remain (or, for decompressed data, against what the node holds) before
//! anything is allocated, all arithmetic on file values is checked, and malformed input
//! gives a [`VdbError`] naming the byte offset, never a panic.
//!
//! Supported: file format versions 222 and newer (Blender 4.5 writes 224), grids of type
//! `Tree_float_5_4_3` stored as 32-bit or half floats, uncompressed, zlib (`ZIP`) or Blosc
//! (LZ4, byte shuffle) compressed, with or without active-mask compression, and the linear
//! transform maps (uniform scale, scale, translation, their combinations, affine).
//! Not supported: older files, other value types, instanced grids, frustum and other
//! non-linear maps, files without grid offsets. The layout follows the OpenVDB sources
//! (`io/Archive.cc`, `io/GridDescriptor.cc`, `io/Compression.h`, `tree/RootNode.h`,
//! `tree/InternalNode.h`, `tree/LeafNode.h`, `math/Maps.h`); all numbers are little endian.

mod blosc;
mod tree;

use tree::{densify, read_leaf_buffers, read_topology};

use std::fmt;

/// A float grid read into a dense array over its active voxels' bounding box.
///
/// Values are what OpenVDB's `tools::copyToDense` gives: every voxel of the box holds the
/// tree's value there, active or not (inactive voxels keep their stored value, voxels
/// outside any tile or leaf hold the background). A grid without active voxels gives
/// `resolution == [0, 0, 0]` and no values.
#[derive(Debug, Clone, PartialEq)]
pub struct DenseGrid {
    /// nx, ny, nz.
    pub resolution: [usize; 3],
    /// x fastest, then y, then z: `values[x + nx * (y + ny * z)]`.
    pub values: Vec<f32>,
    /// Index coordinate of `values[0]`.
    pub index_min: [i32; 3],
    /// Row-major 3x4 affine map, `world = M * (i, j, k, 1)`; voxel centres are at integer
    /// index coordinates (the OpenVDB convention).
    pub index_to_world: [[f64; 4]; 3],
}

/// What went wrong, and at which byte of the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VdbError {
    pub offset: u64,
    pub message: String,
}

impl fmt::Display for VdbError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "byte {}: {}", self.offset, self.message)
    }
}

impl std::error::Error for VdbError {}

/// The file starts with the 64-bit magic number 0x56444220 ("VDB " little endian).
const MAGIC: [u8; 8] = [0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0];
/// Format 222 (`OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION`) moved the compression flags
/// into each grid and added the per-node metadata byte; older layouts are not read.
const MIN_VERSION: u32 = 222;
/// Grid compression flags (`io::COMPRESS_*`).
const COMPRESS_ZIP: u32 = 0x1;
const COMPRESS_ACTIVE_MASK: u32 = 0x2;
const COMPRESS_BLOSC: u32 = 0x4;
const FLOAT_TREE: &str = "Tree_float_5_4_3";
/// A grid type name ending in this suffix was saved with 16-bit floats.
const HALF_SUFFIX: &str = "_HalfFloat";
/// Unique grid names are `name` or `name\x1eN` for repeated names.
const NAME_SEPARATOR: char = '\u{1e}';
/// OpenVDB pads Blosc input shorter than 48 bytes to 128 bytes before compressing.
const BLOSC_MINIMUM_BYTES: usize = 48;
const BLOSC_PAD_BYTES: usize = 128;
/// Log2 of the node widths of a 5-4-3 tree: a root child spans 2^12 voxels per axis.
const LEAF_LOG2: u32 = 3;
const ROOT_CHILD_SPAN: u32 = 12;

type Result<T> = std::result::Result<T, VdbError>;

/// A bounds-checked position in the file.
struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Cursor<'a> {
    fn at(bytes: &'a [u8], pos: u64, what: &str) -> Result<Self> {
        match usize::try_from(pos) {
            Ok(p) if p <= bytes.len() => Ok(Cursor { bytes, pos: p }),
            _ => Err(VdbError {
                offset: pos,
                message: format!(
                    "{what} at byte {pos} is past the end of the {}-byte file",
                    bytes.len()
                ),
            }),
        }
    }

    fn error(&self, message: impl Into<String>) -> VdbError {
        VdbError {
            offset: self.pos as u64,
            message: message.into(),
        }
    }

    fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        if n > self.remaining() {
            let left = self.remaining();
            return Err(self.error(format!(
                "expected {what} ({n} bytes), the file has {left} bytes left"
            )));
        }
        let slice = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(slice)
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let mut out = [0u8; N];
        out.copy_from_slice(self.take(N, what)?);
        Ok(out)
    }

    fn u32(&mut self, what: &str) -> Result<u32> {
        self.array(what).map(u32::from_le_bytes)
    }

    fn i32(&mut self, what: &str) -> Result<i32> {
        self.array(what).map(i32::from_le_bytes)
    }

    fn i64(&mut self, what: &str) -> Result<i64> {
        self.array(what).map(i64::from_le_bytes)
    }

    fn f32(&mut self, what: &str) -> Result<f32> {
        self.array(what).map(f32::from_le_bytes)
    }

    fn f64s<const N: usize>(&mut self, what: &str) -> Result<[f64; N]> {
        let mut out = [0.0; N];
        for v in &mut out {
            *v = self.array(what).map(f64::from_le_bytes)?;
        }
        Ok(out)
    }

    /// A string: u32 length, then that many bytes (not NUL terminated).
    fn string(&mut self, what: &str) -> Result<String> {
        let len = self.u32(what)? as usize;
        Ok(String::from_utf8_lossy(self.take(len, what)?).into_owned())
    }

    /// An `i64` file position, which must lie inside the file.
    fn position(&mut self, what: &str) -> Result<u64> {
        let value = self.i64(what)?;
        match u64::try_from(value) {
            Ok(p) if p <= self.bytes.len() as u64 => Ok(p),
            _ => Err(self.error(format!(
                "{what} {value} is outside the {}-byte file",
                self.bytes.len()
            ))),
        }
    }
}

/// One entry of the grid table (`GridDescriptor`).
struct GridEntry {
    name: String,
    type_name: String,
    half_suffix: bool,
    instance_parent: String,
    grid_pos: u64,
    block_pos: u64,
}

/// The names of the grids in the file, in file order.
pub fn grid_names(bytes: &[u8]) -> std::result::Result<Vec<String>, VdbError> {
    Ok(read_grid_table(bytes)?
        .1
        .into_iter()
        .map(|g| g.name)
        .collect())
}

/// Reads the float grid called `name` into a dense array over its active bounding box,
/// refusing boxes of more than `max_voxels` voxels.
pub fn read_float_grid(
    bytes: &[u8],
    name: &str,
    max_voxels: usize,
) -> std::result::Result<DenseGrid, VdbError> {
    let (table_pos, grids) = read_grid_table(bytes)?;
    let Some(entry) = grids.iter().find(|g| g.name == name) else {
        let names: Vec<&str> = grids.iter().map(|g| g.name.as_str()).collect();
        let message = format!(
            "expected the grid '{name}', the file has: {}",
            names.join(", ")
        );
        return Err(VdbError {
            offset: table_pos,
            message,
        });
    };
    let mut c = Cursor::at(bytes, entry.grid_pos, "the grid")?;
    if entry.type_name != FLOAT_TREE {
        let message = format!(
            "unsupported grid type '{}': only float grids ({FLOAT_TREE}) are read",
            entry.type_name
        );
        return Err(c.error(message));
    }
    if !entry.instance_parent.is_empty() {
        return Err(c.error(format!(
            "grid '{name}' is an instance of '{}': instanced grids are not supported",
            entry.instance_parent
        )));
    }
    let compression = c.u32("the grid compression flags")?;
    if compression & !(COMPRESS_ZIP | COMPRESS_ACTIVE_MASK | COMPRESS_BLOSC) != 0 {
        return Err(c.error(format!("unknown grid compression flags {compression:#x}")));
    }
    let half = read_metadata(&mut c)?.unwrap_or(entry.half_suffix);
    let index_to_world = read_transform(&mut c)?;
    let mut tree = read_topology(&mut c, compression, half)?;
    let mut c = Cursor::at(bytes, entry.block_pos, "the grid's leaf buffers")?;
    read_leaf_buffers(&mut c, &mut tree)?;
    let (resolution, values, index_min) =
        densify(&tree, max_voxels).map_err(|message| VdbError {
            offset: entry.grid_pos,
            message: format!("grid '{name}': {message}"),
        })?;
    Ok(DenseGrid {
        resolution,
        values,
        index_min,
        index_to_world,
    })
}

/// Reads the file header and grid table; returns the table's offset and its entries.
fn read_grid_table(bytes: &[u8]) -> Result<(u64, Vec<GridEntry>)> {
    let mut c = Cursor { bytes, pos: 0 };
    if c.array::<8>("the 8-byte OpenVDB magic number")? != MAGIC {
        return Err(VdbError {
            offset: 0,
            message: "not an OpenVDB file: the magic number is not 'VDB '".into(),
        });
    }
    let version = c.u32("the file format version")?;
    if version < MIN_VERSION {
        return Err(c.error(format!(
            "OpenVDB file format version {version} is not supported: need {MIN_VERSION} or newer"
        )));
    }
    c.take(8, "the library version")?;
    if c.array::<1>("the grid offsets flag")?[0] == 0 {
        return Err(
            c.error("the file has no grid offsets (a streamed archive), which is not supported")
        );
    }
    c.take(36, "the 36-character file UUID")?;
    read_metadata(&mut c)?;
    let table_pos = c.pos as u64;
    let count = c.i32("the grid count")?;
    let mut grids = Vec::new();
    for _ in 0..count.max(0) {
        grids.push(read_grid_entry(&mut c)?);
    }
    Ok((table_pos, grids))
}

/// A grid descriptor: unique name, type, instance parent, then the grid, leaf-buffer and
/// end positions. The grid's own header sits between its descriptor and the next one.
fn read_grid_entry(c: &mut Cursor) -> Result<GridEntry> {
    let unique_name = c.string("a grid name")?;
    let name = unique_name
        .split(NAME_SEPARATOR)
        .next()
        .unwrap_or_default()
        .to_string();
    let mut type_name = c.string("a grid type")?;
    let half_suffix = type_name.ends_with(HALF_SUFFIX);
    if half_suffix {
        type_name.truncate(type_name.len() - HALF_SUFFIX.len());
    }
    let instance_parent = c.string("the instance parent name")?;
    let grid_pos = c.position("the grid position")?;
    let block_pos = c.position("the leaf buffer position")?;
    let end_pos = c.position("the grid end position")?;
    if grid_pos < c.pos as u64 || block_pos < grid_pos || end_pos < block_pos {
        return Err(c.error(format!(
            "grid '{name}' positions must increase: grid {grid_pos}, buffers {block_pos}, end {end_pos}"
        )));
    }
    *c = Cursor::at(c.bytes, end_pos, "the grid end")?;
    Ok(GridEntry {
        name,
        type_name,
        half_suffix,
        instance_parent,
        grid_pos,
        block_pos,
    })
}

/// Skips a metadata map (u32 count, then name, type name, u32 size and value bytes each);
/// returns the `is_saved_as_half_float` flag if the map has it.
fn read_metadata(c: &mut Cursor) -> Result<Option<bool>> {
    let count = c.u32("the metadata count")?;
    let mut half = None;
    for _ in 0..count {
        let key = c.string("a metadata name")?;
        let kind = c.string("a metadata type")?;
        let size = c.u32("a metadata size")? as usize;
        let value = c.take(size, "a metadata value")?;
        if key == "is_saved_as_half_float" && kind == "bool" {
            half = value.first().map(|&b| b != 0);
        }
    }
    Ok(half)
}

/// The transform: a map type name, then the map's fields as `f64`s (`math/Maps.h`).
/// Scale maps store scale, voxel size and three derived vectors, translate variants
/// put the translation first; the affine map stores a row-vector 4x4 matrix.
fn read_transform(c: &mut Cursor) -> Result<[[f64; 4]; 3]> {
    let kind = c.string("the transform map type")?;
    let (linear, translation) = match kind.as_str() {
        "UniformScaleMap" | "ScaleMap" => {
            let [sx, sy, sz, ..] = c.f64s::<15>("the scale map")?;
            (diagonal([sx, sy, sz]), [0.0; 3])
        }
        "UniformScaleTranslateMap" | "ScaleTranslateMap" => {
            let [tx, ty, tz, sx, sy, sz, ..] = c.f64s::<18>("the scale-translate map")?;
            (diagonal([sx, sy, sz]), [tx, ty, tz])
        }
        "TranslationMap" => (diagonal([1.0; 3]), c.f64s::<3>("the translation map")?),
        "AffineMap" => {
            let m = c.f64s::<16>("the affine map matrix")?;
            let linear = [0, 1, 2].map(|row| [0, 1, 2].map(|col| m[col * 4 + row]));
            (linear, [m[12], m[13], m[14]])
        }
        other => {
            return Err(c.error(format!(
                "unsupported transform map '{other}': expected UniformScaleMap, ScaleMap, \
                 UniformScaleTranslateMap, ScaleTranslateMap, TranslationMap or AffineMap"
            )));
        }
    };
    let m = [0, 1, 2].map(|r| [linear[r][0], linear[r][1], linear[r][2], translation[r]]);
    if m.iter().flatten().any(|v| !v.is_finite()) {
        return Err(c.error(format!("the {kind} transform has non-finite entries")));
    }
    Ok(m)
}

fn diagonal(s: [f64; 3]) -> [[f64; 3]; 3] {
    [[s[0], 0.0, 0.0], [0.0, s[1], 0.0], [0.0, 0.0, s[2]]]
}
