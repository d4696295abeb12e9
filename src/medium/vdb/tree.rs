//! The tree of an OpenVDB float grid: the root's tiles and children, internal nodes of 32³
//! and 16³ entries and leaves of 8³ voxels (`tree/RootNode.h`, `tree/InternalNode.h`,
//! `tree/LeafNode.h`), their compressed values, and the dense copy of the active box.

use super::{
    BLOSC_MINIMUM_BYTES, BLOSC_PAD_BYTES, COMPRESS_ACTIVE_MASK, COMPRESS_BLOSC, COMPRESS_ZIP,
    Cursor, LEAF_LOG2, ROOT_CHILD_SPAN, Result, VdbError,
};

/// How node values are stored.
#[derive(Clone, Copy)]
struct Codec {
    compression: u32,
    half: bool,
    background: f32,
}

/// A node mask: bit `n` of the node's linear offset `n`, in little-endian u64 words.
struct Mask(Vec<u64>);

impl Mask {
    fn read(c: &mut Cursor, bits: usize, what: &str) -> Result<Mask> {
        let raw = c.take(bits / 8, what)?;
        Ok(Mask(
            raw.chunks_exact(8)
                .map(|w| u64::from_le_bytes(w.try_into().unwrap_or_default()))
                .collect(),
        ))
    }

    fn get(&self, n: usize) -> bool {
        self.0.get(n / 64).is_some_and(|w| w >> (n % 64) & 1 == 1)
    }

    fn count(&self) -> usize {
        self.0.iter().map(|w| w.count_ones() as usize).sum()
    }
}

/// An internal node (log2 width 5 or 4) or a leaf (3): `child_log2` is the log2 span in
/// voxels of one table entry (7 and 3 for internal nodes, 0 for leaves).
struct Node {
    origin: [i64; 3],
    log2: u32,
    child_log2: u32,
    children: Mask,
    active: Mask,
    values: Vec<f32>,
}

impl Node {
    /// Index coordinates of table entry `n`; x varies slowest (`offsetToLocalCoord`).
    fn entry_origin(&self, n: usize) -> [i64; 3] {
        let n = n as i64;
        let (l, w) = (i64::from(self.log2), (1i64 << self.log2) - 1);
        let local = [n >> (2 * l), (n >> l) & w, n & w];
        [0, 1, 2].map(|a| self.origin[a] + (local[a] << self.child_log2))
    }
}

pub(super) struct Tree {
    background: f32,
    /// Root tiles: origin, value, active; each spans 4096 voxels per axis.
    tiles: Vec<([i64; 3], f32, bool)>,
    internal: Vec<Node>,
    leaves: Vec<Node>,
    codec: Codec,
}

/// The tree topology (`RootNode::readTopology`): a buffer count, the background, tile and
/// child counts, the tiles (origin, value, active byte), then each root child depth first.
pub(super) fn read_topology(c: &mut Cursor, compression: u32, half: bool) -> Result<Tree> {
    c.i32("the tree buffer count")?;
    let background = c.f32("the background value")?;
    let tiles = c.u32("the root tile count")? as usize;
    let children = c.u32("the root child count")?;
    if tiles.checked_mul(17).is_none_or(|n| n > c.remaining()) {
        return Err(c.error(format!(
            "{tiles} root tiles of 17 bytes do not fit in the file"
        )));
    }
    let codec = Codec {
        compression,
        half,
        background,
    };
    let mut tree = Tree {
        background,
        tiles: Vec::with_capacity(tiles),
        internal: vec![],
        leaves: vec![],
        codec,
    };
    // The root is a map from origin to entry (OpenVDB's `RootNode`): an origin given twice
    // is an error, which also keeps the dense fills disjoint (bounded work).
    let mut origins = std::collections::HashSet::new();
    for _ in 0..tiles {
        let origin = read_root_origin(c, &mut origins)?;
        let value = c.f32("a root tile value")?;
        let active = c.array::<1>("a root tile active flag")?[0] != 0;
        tree.tiles.push((origin, value, active));
    }
    for _ in 0..children {
        let origin = read_root_origin(c, &mut origins)?;
        read_internal(c, &mut tree, origin, 5)?;
    }
    Ok(tree)
}

fn read_root_origin(
    c: &mut Cursor,
    seen: &mut std::collections::HashSet<[i64; 3]>,
) -> Result<[i64; 3]> {
    let mut origin = [0i64; 3];
    for v in &mut origin {
        let x = c.i32("a root entry origin")?;
        if x & ((1 << ROOT_CHILD_SPAN) - 1) != 0 {
            return Err(c.error(format!("root entry origin {x} is not a multiple of 4096")));
        }
        *v = i64::from(x);
    }
    if !seen.insert(origin) {
        return Err(c.error(format!("root entry origin {origin:?} appears twice")));
    }
    Ok(origin)
}

/// An internal node (`InternalNode::readTopology`): child mask, value mask, the compressed
/// table values, then its children (leaves store only their value mask here).
fn read_internal(c: &mut Cursor, tree: &mut Tree, origin: [i64; 3], log2: u32) -> Result<()> {
    let size = 1usize << (3 * log2);
    let children = Mask::read(c, size, "an internal node child mask")?;
    let active = Mask::read(c, size, "an internal node value mask")?;
    let values = read_values(c, size, &active, tree.codec)?;
    let child_log2 = if log2 == 5 { 7 } else { LEAF_LOG2 };
    let node = Node {
        origin,
        log2,
        child_log2,
        children,
        active,
        values,
    };
    let child_origins: Vec<[i64; 3]> = (0..size)
        .filter(|&n| node.children.get(n))
        .map(|n| node.entry_origin(n))
        .collect();
    tree.internal.push(node);
    for child in child_origins {
        if log2 == 5 {
            read_internal(c, tree, child, 4)?;
        } else {
            let active = Mask::read(c, 512, "a leaf value mask")?;
            let (children, values) = (Mask(vec![0; 8]), Vec::new());
            tree.leaves.push(Node {
                origin: child,
                log2: LEAF_LOG2,
                child_log2: 0,
                children,
                active,
                values,
            });
        }
    }
    Ok(())
}

/// The leaf buffers, in topology order (`LeafNode::readBuffers`): the value mask again,
/// then the 512 compressed values.
pub(super) fn read_leaf_buffers(c: &mut Cursor, tree: &mut Tree) -> Result<()> {
    let codec = tree.codec;
    for leaf in &mut tree.leaves {
        leaf.active = Mask::read(c, 512, "a leaf value mask")?;
        leaf.values = read_values(c, 512, &leaf.active, codec)?;
    }
    Ok(())
}

/// A node's values (`io::readCompressedValues`). A metadata byte says which inactive
/// values were left out under active-mask compression:
/// 0 none, or all +background; 1 all -background; 2 all one stored value;
/// 3 a selection mask picks -background (0) or +background (1);
/// 4 the mask picks a stored value (0) or +background (1);
/// 5 the mask picks between two stored values; 6 all values are stored.
/// Stored inactive values are full `f32`s even in half-float grids; then comes the
/// selection mask (for 3..5), then the active values (all values if nothing was left out).
fn read_values(c: &mut Cursor, size: usize, active: &Mask, codec: Codec) -> Result<Vec<f32>> {
    let meta = c.array::<1>("the node metadata byte")?[0];
    if meta > 6 {
        return Err(c.error(format!("node metadata byte {meta} is not one of 0..6")));
    }
    let bg = codec.background;
    let mut inactive = [if meta == 0 { bg } else { -bg }, bg];
    if matches!(meta, 2 | 4 | 5) {
        inactive[0] = c.f32("an inactive value")?;
    }
    if meta == 5 {
        inactive[1] = c.f32("the second inactive value")?;
    }
    let selection = match meta {
        3..=5 => Mask::read(c, size, "the inactive value selection mask")?,
        _ => Mask(Vec::new()),
    };
    let masked = codec.compression & COMPRESS_ACTIVE_MASK != 0 && meta != 6;
    let stored = if masked { active.count() } else { size };
    let data = read_chunk(c, stored, codec)?;
    if stored == size {
        return Ok(data);
    }
    let mut next = data.into_iter();
    let values = (0..size)
        .map(|n| match active.get(n) {
            true => next.next().unwrap_or(bg),
            false => inactive[usize::from(selection.get(n))],
        })
        .collect();
    Ok(values)
}

/// `count` values, as `f16` or `f32`, through the grid's codec (`io::readData`): Blosc
/// and zlib chunks start with an `i64` byte count, negative for raw data.
fn read_chunk(c: &mut Cursor, count: usize, codec: Codec) -> Result<Vec<f32>> {
    let width = if codec.half { 2 } else { 4 };
    let nbytes = count * width;
    let raw = if codec.compression & (COMPRESS_BLOSC | COMPRESS_ZIP) == 0 {
        c.take(nbytes, "uncompressed node values")?.to_vec()
    } else {
        let start = c.pos;
        let size = c.i64("a compressed chunk size")?;
        if size <= 0 {
            let raw_len = size.unsigned_abs();
            if raw_len != nbytes as u64 {
                return Err(c.error(format!(
                    "expected a raw chunk of {nbytes} bytes, the file says {raw_len}"
                )));
            }
            c.take(nbytes, "raw node values")?.to_vec()
        } else {
            let len = usize::try_from(size).unwrap_or(usize::MAX);
            let packed = c.take(len, "compressed node values")?;
            let at = |message: String| VdbError {
                offset: start as u64,
                message,
            };
            match codec.compression & COMPRESS_BLOSC != 0 {
                true => unblosc(packed, nbytes).map_err(at)?,
                false => inflate(packed, nbytes).map_err(at)?,
            }
        }
    };
    Ok(match codec.half {
        true => raw
            .chunks_exact(2)
            .map(|b| half::f16::from_le_bytes([b[0], b[1]]).to_f32())
            .collect(),
        false => raw
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect(),
    })
}

/// A Blosc chunk of `nbytes`; OpenVDB pads inputs under 48 bytes to 128 bytes.
fn unblosc(packed: &[u8], nbytes: usize) -> std::result::Result<Vec<u8>, String> {
    let mut out = super::blosc::decompress(packed, nbytes.max(BLOSC_PAD_BYTES))?;
    let padded = nbytes < BLOSC_MINIMUM_BYTES && out.len() == BLOSC_PAD_BYTES;
    if out.len() != nbytes && !padded {
        return Err(format!(
            "expected {nbytes} bytes from a Blosc chunk, it holds {}",
            out.len()
        ));
    }
    out.truncate(nbytes);
    Ok(out)
}

/// A zlib stream that must inflate to exactly `nbytes`.
fn inflate(packed: &[u8], nbytes: usize) -> std::result::Result<Vec<u8>, String> {
    let mut out = vec![0u8; nbytes + 1];
    let mut z = flate2::Decompress::new(true);
    let status = z
        .decompress(packed, &mut out, flate2::FlushDecompress::Finish)
        .map_err(|e| format!("zlib chunk: {e}"))?;
    if status != flate2::Status::StreamEnd || z.total_out() != nbytes as u64 {
        return Err(format!(
            "expected {nbytes} bytes from a zlib chunk, it gives {} or more",
            z.total_out()
        ));
    }
    out.truncate(nbytes);
    Ok(out)
}

/// The dense box being filled: inclusive index bounds and x-fastest values.
struct Dense {
    min: [i64; 3],
    max: [i64; 3],
    res: [usize; 3],
    values: Vec<f32>,
}

impl Dense {
    /// Sets the voxels of the cube `[lo, lo + span)` that fall inside the box.
    fn fill(&mut self, lo: [i64; 3], span: i64, value: f32) {
        let a = [0, 1, 2].map(|i| lo[i].max(self.min[i]));
        let b = [0, 1, 2].map(|i| (lo[i] + span - 1).min(self.max[i]));
        if (0..3).any(|i| a[i] > b[i]) {
            return;
        }
        let len = (b[0] - a[0] + 1) as usize;
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                let row = self.index([a[0], y, z]);
                if let Some(run) = self.values.get_mut(row..row + len) {
                    run.fill(value);
                }
            }
        }
    }

    fn index(&self, p: [i64; 3]) -> usize {
        let d = [0, 1, 2].map(|i| (p[i] - self.min[i]) as usize);
        d[0] + self.res[0] * (d[1] + self.res[1] * d[2])
    }
}

/// The inclusive index bounds of all active voxels and active tiles, if any.
fn active_bounds(tree: &Tree) -> Option<([i64; 3], [i64; 3])> {
    let mut bounds: Option<([i64; 3], [i64; 3])> = None;
    let mut add = |lo: [i64; 3], span: i64| {
        let hi = lo.map(|v| v + span - 1);
        let (min, max) = bounds.get_or_insert((lo, hi));
        for a in 0..3 {
            min[a] = min[a].min(lo[a]);
            max[a] = max[a].max(hi[a]);
        }
    };
    for &(origin, _, active) in &tree.tiles {
        if active {
            add(origin, 1 << ROOT_CHILD_SPAN);
        }
    }
    for node in tree.internal.iter().chain(&tree.leaves) {
        let size = 1usize << (3 * node.log2);
        for n in (0..size).filter(|&n| node.active.get(n) && !node.children.get(n)) {
            add(node.entry_origin(n), 1 << node.child_log2);
        }
    }
    bounds
}

/// Copies the tree into a dense array over its active bounds (OpenVDB `copyToDense`:
/// tile and leaf values whether active or not, the background elsewhere).
pub(super) type DenseParts = ([usize; 3], Vec<f32>, [i32; 3]);

pub(super) fn densify(tree: &Tree, max_voxels: usize) -> std::result::Result<DenseParts, String> {
    let Some((min, max)) = active_bounds(tree) else {
        return Ok(([0; 3], Vec::new(), [0; 3]));
    };
    let res = [0, 1, 2].map(|a| usize::try_from(max[a] - min[a] + 1).unwrap_or(usize::MAX));
    let count = res.iter().try_fold(1usize, |n, &r| n.checked_mul(r));
    if count.is_none_or(|n| n > max_voxels) {
        let [nx, ny, nz] = res;
        return Err(format!(
            "the active voxels span {nx} x {ny} x {nz} voxels, more than the limit of {max_voxels}"
        ));
    }
    let index_min = min.map(|v| i32::try_from(v).unwrap_or(i32::MIN));
    if index_min.iter().zip(&min).any(|(&a, &b)| i64::from(a) != b) {
        return Err(format!(
            "the active bounds start at {min:?}, outside the 32-bit index range"
        ));
    }
    let values = vec![tree.background; count.unwrap_or(0)];
    let mut dense = Dense {
        min,
        max,
        res,
        values,
    };
    for &(origin, value, _) in &tree.tiles {
        dense.fill(origin, 1 << ROOT_CHILD_SPAN, value);
    }
    for node in tree.internal.iter().chain(&tree.leaves) {
        let size = 1usize << (3 * node.log2);
        for n in (0..size).filter(|&n| !node.children.get(n)) {
            let value = node.values.get(n).copied().unwrap_or(tree.background);
            dense.fill(node.entry_origin(n), 1 << node.child_log2, value);
        }
    }
    Ok((res, dense.values, index_min))
}
