//! Reading float grids from NanoVDB `.nvdb` files, for the `nanovdb`
//! medium.
//!
//! A file is one or more segments. Each segment is a 16-byte header
//! (magic `NanoVDB0`, a packed version number, the grid count, the codec),
//! then per grid a metadata record and its name, then the grids' data, one
//! after another. Codecs: `NONE` (the grid's bytes as they are in memory)
//! and `ZIP` (a u64 byte count, then a zlib stream of the grid's bytes);
//! `BLOSC` is refused. All numbers are little-endian.
//!
//! Two layouts are read, told apart by the header's version: NanoVDB
//! 32.x (what pbrt-v4 is built with and reads; it refuses other majors)
//! and the layout before NanoVDB 29 (version 0.0.x, as in the Houdini
//! exporter's test volume `sphere.nvdb`, 0.0.19, which pbrt-v4 refuses as
//! "an older version"). Other versions are refused with the version
//! named. In a file's metadata record (176 bytes in 32.x, 144 before) the
//! grid's in-memory and stored sizes, type and name size are used; grids
//! are found by name.
//!
//! The grid itself is NanoVDB's in-memory tree, which this reader decodes
//! into plain arrays (every offset and count checked against the buffer,
//! so a corrupt file is an error, never a panic). Byte sizes, 32.x / old:
//!
//! | part | bytes | what is used |
//! |------|-------|--------------|
//! | grid | 672 / 608 | magic, world bbox (6 f64), the index↔world map (f32 3×3 inverse matrix and translation), class, type; old: blind-metadata count (288 bytes each before the tree) |
//! | tree | 64 | byte offsets (from the tree) of the first leaf, lower and upper internal node and the root; node counts |
//! | root | 64 + 32 per tile | tile count, background; tiles: key (21 bits per axis of the coordinate ≫ 12), value, child (32.x: a byte offset from the root, 0 for none; old: an index after the tiles, negative for none) |
//! | upper internal | 270 400 / 139 328 | 32³ child mask and table (32.x: 8-byte entries, an f32 value or a byte offset from the node; old: 4-byte entries, an f32 value or a child index from the node offset) |
//! | lower internal | 33 856 / 17 472 | 16³ of the same |
//! | leaf | 2 144 | 8³ f32 values (x slowest, z fastest), from byte 96 / 64 |
//!
//! In the old layout an internal node's child lies at the node's address
//! plus its node offset times the node's size, plus the child index times
//! the child's size. Nodes of a level must lie one after another from the
//! tree's offset for that level (as NanoVDB writes them).
//!
//! Values are looked up as NanoVDB's `ReadAccessor::getValue` does (a
//! voxel's value at integer index coordinates, active or not), and
//! [`FloatGrid::sample`] interpolates them trilinearly as
//! `SampleFromVoxels<_, 1>` does: voxel (i, j, k) has its value at the
//! index-space point (i, j, k).

use glam::Vec3;
use std::io::Read;

/// Why a `.nvdb` file could not be read.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum NvdbError {
    #[error("not a NanoVDB file (no \"NanoVDB0\" magic number at byte {0})")]
    Magic(usize),
    #[error("the file ends early (reading {0})")]
    Truncated(&'static str),
    #[error("NanoVDB file version {0} is not supported (files of 32.x, as pbrt-v4 reads, and of 0.0.x are)")]
    Version(String),
    #[error("the {0} codec is not supported (NONE and ZIP are)")]
    Codec(String),
    #[error("grid \"{name}\": ZIP data could not be decompressed: {reason}")]
    Zip { name: String, reason: String },
    #[error("grid \"{name}\" is a {kind} grid; only float grids are supported")]
    NotFloat { name: String, kind: String },
    #[error("grid \"{name}\" is corrupt: {what}")]
    Corrupt { name: String, what: String },
}

/// NanoVDB's grid type names, by number.
fn grid_type_name(t: u32, layout: &Layout) -> String {
    const OLD_NAMES: [&str; 11] = [
        "Unknown", "Float", "Double", "Int16", "Int32", "Int64", "Vec3f", "Vec3d", "Mask", "FP16",
        "UInt32",
    ];
    const V32_NAMES: [&str; 19] = [
        "Unknown", "Float", "Double", "Int16", "Int32", "Int64", "Vec3f", "Vec3d", "Mask", "Half",
        "UInt32", "Boolean", "RGBA8", "Fp4", "Fp8", "Fp16", "FpN", "Vec4f", "Vec4d",
    ];
    let names: &[&str] = if layout.v32 { &V32_NAMES } else { &OLD_NAMES };
    names
        .get(t as usize)
        .map_or_else(|| format!("type {t}"), |s| s.to_string())
}

/// NanoVDB's grid class names, by number.
pub fn grid_class_name(c: u32) -> String {
    const NAMES: [&str; 6] = [
        "Unknown",
        "LevelSet",
        "FogVolume",
        "Staggered",
        "PointIndex",
        "PointData",
    ];
    NAMES
        .get(c as usize)
        .map_or_else(|| format!("class {c}"), |s| s.to_string())
}

const MAGIC: &[u8; 8] = b"NanoVDB0";
const HEADER_SIZE: usize = 16;
const LEAF_SIZE: usize = 2_144;
/// The bit of the packed version where the major number starts.
const MAJOR_SHIFT: u32 = 21;

/// Where things are in one of the two layouts read.
#[derive(Clone, Copy, Debug)]
struct Layout {
    /// Bytes of a grid's metadata record in the file, and where in it the
    /// grid name's size is.
    meta_size: usize,
    meta_name_size: usize,
    /// Bytes of the grid header (the tree follows it, after any blind
    /// metadata in the old layout).
    grid_size: usize,
    world_bbox: usize,
    map: usize,
    class: usize,
    grid_type: usize,
    /// The root's tile count and background.
    root_tiles: usize,
    root_background: usize,
    /// In a root tile: the value and the child.
    tile_value: usize,
    tile_child: usize,
    /// Node sizes: leaf, lower, upper.
    sizes: [usize; 3],
    /// Offset of the leaf values.
    leaf_values: usize,
    /// NanoVDB 32: masks after a 32-byte bbox and flags, 8-byte table
    /// entries holding byte offsets; before 29: masks first, 4-byte
    /// entries holding child indices.
    v32: bool,
}

/// Files before NanoVDB 29 (version 0.0.x).
const OLD: Layout = Layout {
    meta_size: 144,
    meta_name_size: 40,
    grid_size: 608,
    world_bbox: 264,
    map: 312,
    class: 584,
    grid_type: 588,
    root_tiles: 32,
    root_background: 48,
    tile_value: 8,
    tile_child: 12,
    sizes: [LEAF_SIZE, 17_472, 139_328],
    leaf_values: 64,
    v32: false,
};

/// NanoVDB 32.x files (what pbrt-v4 reads).
const V32: Layout = Layout {
    meta_size: 176,
    meta_name_size: 136,
    grid_size: 672,
    world_bbox: 560,
    map: 296,
    class: 632,
    grid_type: 636,
    root_tiles: 24,
    root_background: 28,
    tile_value: 20,
    tile_child: 8,
    sizes: [LEAF_SIZE, 33_856, 270_400],
    leaf_values: 96,
    v32: true,
};

const BLIND_META_SIZE: usize = 288;
const TREE_SIZE: usize = 64;
const ROOT_SIZE: usize = 64;
const ROOT_TILE_SIZE: usize = 32;

impl Layout {
    /// Bytes of an internal node's mask of `log2dim`.
    fn mask_bytes(log2dim: u32) -> usize {
        (1usize << (3 * log2dim)) / 8
    }
    /// Where an internal node's child mask and table start.
    fn child_mask(&self, log2dim: u32) -> usize {
        let m = Self::mask_bytes(log2dim);
        if self.v32 {
            32 + m
        } else {
            m
        }
    }
    fn table(&self, log2dim: u32) -> usize {
        let m = Self::mask_bytes(log2dim);
        if self.v32 {
            (32 + 2 * m + 16).div_ceil(32) * 32
        } else {
            2 * m
        }
    }
}

/// A little-endian reader over a byte slice whose every read is checked.
struct Bytes<'a> {
    data: &'a [u8],
}

impl<'a> Bytes<'a> {
    fn slice(&self, at: usize, len: usize) -> Option<&'a [u8]> {
        self.data.get(at..at.checked_add(len)?)
    }
    fn array<const N: usize>(&self, at: usize) -> Option<[u8; N]> {
        self.slice(at, N)?.try_into().ok()
    }
    fn u16(&self, at: usize) -> Option<u16> {
        self.array(at).map(u16::from_le_bytes)
    }
    fn u32(&self, at: usize) -> Option<u32> {
        self.array(at).map(u32::from_le_bytes)
    }
    fn i32(&self, at: usize) -> Option<i32> {
        self.array(at).map(i32::from_le_bytes)
    }
    fn u64(&self, at: usize) -> Option<u64> {
        self.array(at).map(u64::from_le_bytes)
    }
    fn f32(&self, at: usize) -> Option<f32> {
        self.array(at).map(f32::from_le_bytes)
    }
    fn f64(&self, at: usize) -> Option<f64> {
        self.array(at).map(f64::from_le_bytes)
    }
}

/// A node's table entry: a value, or the index of a child node.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    Value(f32),
    Child(u32),
}

/// An internal node: `1 << (3·log2dim)` slots, x slowest.
#[derive(Clone, Debug)]
struct Internal {
    slots: Vec<Slot>,
}

/// One float grid of a NanoVDB file, decoded.
#[derive(Clone, Debug)]
pub struct FloatGrid {
    /// NanoVDB's grid class (2: fog volume, 0: unknown).
    pub class: u32,
    /// The world-space box of the active values, as stored.
    pub world_min: [f64; 3],
    pub world_max: [f64; 3],
    /// World → index: index = inv · (world − vec), in single precision
    /// (NanoVDB's `worldToIndexF`).
    inv_mat: [f32; 9],
    vec: [f32; 3],
    background: f32,
    /// Root tiles: key and what they hold.
    root: Vec<(u64, Slot)>,
    uppers: Vec<Internal>,
    lowers: Vec<Internal>,
    leaves: Vec<[f32; 512]>,
}

/// The root key of index coordinate (i, j, k): each coordinate shifted
/// right by 12 (the upper node's span), 21 bits each, x highest.
fn root_key(i: i32, j: i32, k: i32) -> u64 {
    let part = |c: i32| u64::from((c as u32) >> 12);
    part(k) | (part(j) << 21) | (part(i) << 42)
}

impl FloatGrid {
    /// The value of voxel (i, j, k), active or not.
    pub fn value(&self, i: i32, j: i32, k: i32) -> f32 {
        let key = root_key(i, j, k);
        let Some(&(_, slot)) = self.root.iter().find(|(k2, _)| *k2 == key) else {
            return self.background;
        };
        let upper = match slot {
            Slot::Value(v) => return v,
            Slot::Child(c) => &self.uppers[c as usize],
        };
        let n = (((i & 4095) >> 7) << 10) | (((j & 4095) >> 7) << 5) | ((k & 4095) >> 7);
        let lower = match upper.slots[n as usize] {
            Slot::Value(v) => return v,
            Slot::Child(c) => &self.lowers[c as usize],
        };
        let n = (((i & 127) >> 3) << 8) | (((j & 127) >> 3) << 4) | ((k & 127) >> 3);
        let leaf = match lower.slots[n as usize] {
            Slot::Value(v) => return v,
            Slot::Child(c) => &self.leaves[c as usize],
        };
        leaf[(((i & 7) << 6) | ((j & 7) << 3) | (k & 7)) as usize]
    }

    /// World-space (the medium's space) `p` in index space.
    pub fn world_to_index(&self, p: Vec3) -> Vec3 {
        let d = [p.x - self.vec[0], p.y - self.vec[1], p.z - self.vec[2]];
        let m = &self.inv_mat;
        Vec3::new(
            m[0] * d[0] + m[1] * d[1] + m[2] * d[2],
            m[3] * d[0] + m[4] * d[1] + m[5] * d[2],
            m[6] * d[0] + m[7] * d[1] + m[8] * d[2],
        )
    }

    /// The trilinear interpolation of the voxel values at index-space
    /// point `q`.
    pub fn sample_index(&self, q: Vec3) -> f32 {
        let f = q.floor();
        let w = q - f;
        if !f.is_finite() || f.abs().max_element() > (i32::MAX - 1) as f32 {
            return self.background;
        }
        let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
        let v = |di: i32, dj: i32, dk: i32| self.value(i + di, j + dj, k + dk);
        let lerp = |a: f32, b: f32, t: f32| a + t * (b - a);
        let x0 = lerp(
            lerp(v(0, 0, 0), v(0, 0, 1), w.z),
            lerp(v(0, 1, 0), v(0, 1, 1), w.z),
            w.y,
        );
        let x1 = lerp(
            lerp(v(1, 0, 0), v(1, 0, 1), w.z),
            lerp(v(1, 1, 0), v(1, 1, 1), w.z),
            w.y,
        );
        lerp(x0, x1, w.x)
    }

    /// The interpolated value at world-space (medium-space) `p`.
    pub fn sample(&self, p: Vec3) -> f32 {
        self.sample_index(self.world_to_index(p))
    }

    /// The largest value any lookup can give (at least 0).
    pub fn max_value(&self) -> f32 {
        let slots = |nodes: &[Internal]| {
            nodes
                .iter()
                .flat_map(|n| n.slots.iter())
                .filter_map(|s| match s {
                    Slot::Value(v) => Some(*v),
                    Slot::Child(_) => None,
                })
                .fold(f32::MIN, f32::max)
        };
        let root = self
            .root
            .iter()
            .filter_map(|(_, s)| match s {
                Slot::Value(v) => Some(*v),
                Slot::Child(_) => None,
            })
            .fold(self.background, f32::max);
        let leaves = self
            .leaves
            .iter()
            .flat_map(|l| l.iter())
            .fold(f32::MIN, |a, &b| a.max(b));
        root.max(slots(&self.uppers))
            .max(slots(&self.lowers))
            .max(leaves)
            .max(0.0)
    }
}

/// A grid's metadata record in a segment.
struct Meta {
    grid_size: u64,
    file_size: u64,
    grid_type: u32,
    name: String,
}

/// Reads the float grid named `name` from the bytes of a `.nvdb` file;
/// `Ok(None)` when no grid has that name.
pub fn read_grid(file: &[u8], name: &str) -> Result<Option<FloatGrid>, NvdbError> {
    let b = Bytes { data: file };
    let mut at = 0usize;
    while at < file.len() {
        let header = b
            .slice(at, HEADER_SIZE)
            .ok_or(NvdbError::Truncated("a segment header"))?;
        if &header[..8] != MAGIC {
            return Err(NvdbError::Magic(at));
        }
        let version = b
            .u32(at + 8)
            .ok_or(NvdbError::Truncated("a segment header"))?;
        let layout = match version >> MAJOR_SHIFT {
            0 => OLD,
            32 => V32,
            major => {
                return Err(NvdbError::Version(format!(
                    "{major}.{}.{}",
                    (version >> 10) & 0x7ff,
                    version & 0x3ff
                )))
            }
        };
        let count = b
            .u16(at + 12)
            .ok_or(NvdbError::Truncated("a segment header"))?;
        let codec = b
            .u16(at + 14)
            .ok_or(NvdbError::Truncated("a segment header"))?;
        at += HEADER_SIZE;
        let mut metas = Vec::new();
        for _ in 0..count {
            let trunc = || NvdbError::Truncated("grid metadata");
            let grid_size = b.u64(at).ok_or_else(trunc)?;
            let file_size = b.u64(at + 8).ok_or_else(trunc)?;
            let grid_type = b.u32(at + 32).ok_or_else(trunc)?;
            let name_size = b.u32(at + layout.meta_name_size).ok_or_else(trunc)? as usize;
            at += layout.meta_size;
            let raw = b
                .slice(at, name_size)
                .ok_or(NvdbError::Truncated("a grid name"))?;
            let end = raw.iter().position(|&c| c == 0).unwrap_or(raw.len());
            let grid_name = String::from_utf8_lossy(&raw[..end]).into_owned();
            at += name_size;
            metas.push(Meta {
                grid_size,
                file_size,
                grid_type,
                name: grid_name,
            });
        }
        for meta in metas {
            let stored = usize::try_from(meta.file_size)
                .ok()
                .and_then(|n| b.slice(at, n))
                .ok_or(NvdbError::Truncated("grid data"))?;
            at += stored.len();
            if meta.name != name {
                continue;
            }
            if meta.grid_type != 1 {
                return Err(NvdbError::NotFloat {
                    name: meta.name,
                    kind: grid_type_name(meta.grid_type, &layout),
                });
            }
            let data = decode(stored, codec, &meta)?;
            return parse_grid(&data, meta.name, &layout).map(Some);
        }
    }
    Ok(None)
}

/// The grid's bytes from its stored form.
fn decode(stored: &[u8], codec: u16, meta: &Meta) -> Result<Vec<u8>, NvdbError> {
    let corrupt = |what: &str| NvdbError::Corrupt {
        name: meta.name.clone(),
        what: what.to_string(),
    };
    let size = usize::try_from(meta.grid_size).map_err(|_| corrupt("its size is too large"))?;
    match codec {
        0 => {
            if stored.len() != size {
                return Err(corrupt("its stored size differs from its size"));
            }
            Ok(stored.to_vec())
        }
        1 => {
            let b = Bytes { data: stored };
            let n = b.u64(0).ok_or(NvdbError::Truncated("ZIP data"))?;
            let zipped = usize::try_from(n)
                .ok()
                .and_then(|n| b.slice(8, n))
                .ok_or(NvdbError::Truncated("ZIP data"))?;
            let mut out = Vec::new();
            // One byte more than expected tells a longer stream apart.
            flate2::read::ZlibDecoder::new(zipped)
                .take(meta.grid_size.saturating_add(1))
                .read_to_end(&mut out)
                .map_err(|e| NvdbError::Zip {
                    name: meta.name.clone(),
                    reason: e.to_string(),
                })?;
            if out.len() != size {
                return Err(NvdbError::Zip {
                    name: meta.name.clone(),
                    reason: format!("{} bytes instead of {size}", out.len()),
                });
            }
            Ok(out)
        }
        2 => Err(NvdbError::Codec("BLOSC".into())),
        other => Err(NvdbError::Codec(format!("unknown ({other})"))),
    }
}

/// Decodes a grid's in-memory bytes.
fn parse_grid(data: &[u8], name: String, layout: &Layout) -> Result<FloatGrid, NvdbError> {
    let b = Bytes { data };
    let corrupt = |what: String| NvdbError::Corrupt {
        name: name.clone(),
        what,
    };
    let short = || corrupt("it ends early".into());
    if b.slice(0, 8) != Some(&MAGIC[..]) {
        return Err(corrupt("no magic number".into()));
    }
    let f64s =
        |at: usize| -> Option<[f64; 3]> { Some([b.f64(at)?, b.f64(at + 8)?, b.f64(at + 16)?]) };
    let world_min = f64s(layout.world_bbox).ok_or_else(short)?;
    let world_max = f64s(layout.world_bbox + 24).ok_or_else(short)?;
    // The map: 9 f32 matrix, 9 f32 inverse, 3 f32 translation, f32 taper,
    // then the same in f64.
    let mut inv_mat = [0.0f32; 9];
    for (n, m) in inv_mat.iter_mut().enumerate() {
        *m = b.f32(layout.map + 36 + 4 * n).ok_or_else(short)?;
    }
    let mut vec = [0.0f32; 3];
    for (n, v) in vec.iter_mut().enumerate() {
        *v = b.f32(layout.map + 72 + 4 * n).ok_or_else(short)?;
    }
    let class = b.u32(layout.class).ok_or_else(short)?;
    let grid_type = b.u32(layout.grid_type).ok_or_else(short)?;
    if grid_type != 1 {
        return Err(NvdbError::NotFloat {
            name,
            kind: grid_type_name(grid_type, layout),
        });
    }
    let tree = if layout.v32 {
        layout.grid_size
    } else {
        let blind = b.u32(592).ok_or_else(short)? as usize;
        blind
            .checked_mul(BLIND_META_SIZE)
            .and_then(|n| n.checked_add(layout.grid_size))
            .ok_or_else(short)?
    };
    b.slice(tree, TREE_SIZE).ok_or_else(short)?;
    // Offsets (from the tree) and counts of leaves, lower, upper, root.
    let mut offset = [0usize; 4];
    let mut count = [1usize; 4];
    for level in 0..4 {
        let o = b.u64(tree + 8 * level).ok_or_else(short)?;
        offset[level] = usize::try_from(o)
            .ok()
            .and_then(|o| o.checked_add(tree))
            .ok_or_else(short)?;
        if level < 3 || !layout.v32 {
            count[level] = b.u32(tree + 32 + 4 * level).ok_or_else(short)? as usize;
        }
    }
    let sizes = layout.sizes;
    for level in 0..3 {
        let end = count[level]
            .checked_mul(sizes[level])
            .and_then(|n| n.checked_add(offset[level]));
        if end.is_none_or(|e| e > data.len()) {
            return Err(corrupt(format!("its level-{level} nodes lie outside it")));
        }
    }
    let root = offset[3];
    let tile_count = b.u32(root + layout.root_tiles).ok_or_else(short)? as usize;
    let background = b.f32(root + layout.root_background).ok_or_else(short)?;
    let tiles_at = root + ROOT_SIZE;
    // A child at byte `addr` of level `level`, as an index.
    let child_index = |addr: i128, level: usize| -> Result<u32, NvdbError> {
        let rel = addr - offset[level] as i128;
        let size = sizes[level] as i128;
        if rel < 0 || rel % size != 0 || rel / size >= count[level] as i128 {
            return Err(corrupt(format!(
                "a child pointer misses the level-{level} nodes"
            )));
        }
        Ok((rel / size) as u32)
    };
    let mut root_tiles = Vec::with_capacity(tile_count.min(data.len() / ROOT_TILE_SIZE));
    for t in 0..tile_count {
        let at = tiles_at + t * ROOT_TILE_SIZE;
        let key = b.u64(at).ok_or_else(short)?;
        let value = b.f32(at + layout.tile_value).ok_or_else(short)?;
        let child = if layout.v32 {
            // A byte offset from the root; 0: a value tile.
            let off = b.u64(at + layout.tile_child).ok_or_else(short)? as i64;
            (off != 0).then(|| root as i128 + i128::from(off))
        } else {
            // An index after the tiles; negative: a value tile.
            let id = b.i32(at + layout.tile_child).ok_or_else(short)?;
            let children_at = tiles_at as i128 + (tile_count * ROOT_TILE_SIZE) as i128;
            (id >= 0).then(|| children_at + i128::from(id) * sizes[2] as i128)
        };
        let slot = match child {
            None => Slot::Value(value),
            Some(addr) => Slot::Child(child_index(addr, 2)?),
        };
        root_tiles.push((key, slot));
    }
    let internal = |level: usize, log2dim: u32| -> Result<Vec<Internal>, NvdbError> {
        let n_slots = 1usize << (3 * log2dim);
        let size = sizes[level];
        let child_mask = layout.child_mask(log2dim);
        let table = layout.table(log2dim);
        (0..count[level])
            .map(|node| {
                let at = offset[level] + node * size;
                // Before 29, children are counted from a node offset
                // after the table, min/max and bbox.
                let base = if layout.v32 {
                    at as i128
                } else {
                    let node_offset = b.i32(at + table + 4 * n_slots + 32).ok_or_else(short)?;
                    at as i128 + i128::from(node_offset) * size as i128
                };
                let slots = (0..n_slots)
                    .map(|n| {
                        let word = b.u64(at + child_mask + 8 * (n / 64)).ok_or_else(short)?;
                        let is_child = word >> (n % 64) & 1 == 1;
                        let addr = if layout.v32 {
                            let entry = at + table + 8 * n;
                            if !is_child {
                                return Ok(Slot::Value(b.f32(entry).ok_or_else(short)?));
                            }
                            base + i128::from(b.u64(entry).ok_or_else(short)? as i64)
                        } else {
                            let entry = at + table + 4 * n;
                            if !is_child {
                                return Ok(Slot::Value(b.f32(entry).ok_or_else(short)?));
                            }
                            let id = b.u32(entry).ok_or_else(short)?;
                            base + i128::from(id) * sizes[level - 1] as i128
                        };
                        Ok(Slot::Child(child_index(addr, level - 1)?))
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(Internal { slots })
            })
            .collect()
    };
    let uppers = internal(2, 5)?;
    let lowers = internal(1, 4)?;
    let leaves = (0..count[0])
        .map(|leaf| {
            let at = offset[0] + leaf * LEAF_SIZE + layout.leaf_values;
            let mut values = [0.0f32; 512];
            for (n, v) in values.iter_mut().enumerate() {
                *v = b.f32(at + 4 * n).ok_or_else(short)?;
            }
            Ok(values)
        })
        .collect::<Result<Vec<_>, NvdbError>>()?;
    Ok(FloatGrid {
        class,
        world_min,
        world_max,
        inv_mat,
        vec,
        background,
        root: root_tiles,
        uppers,
        lowers,
        leaves,
    })
}

/// Writes NanoVDB files in the layout [`read_grid`] reads, for tests.
#[cfg(test)]
pub(crate) mod test_writer {
    use super::*;

    /// A float grid of one root tile, one upper and one lower node and
    /// the leaves at `leaves` (origins, multiples of 8 in 0..128, with
    /// their 512 values, x slowest); every other voxel of the first 128³
    /// block has `tile` (a lower-node tile value). Index (i, j, k) is at
    /// world `voxel · (i, j, k) + translation`; the world box is given.
    pub struct GridSpec {
        pub name: String,
        pub grid_type: u32,
        pub class: u32,
        pub voxel: f32,
        pub translation: [f32; 3],
        pub world_min: [f64; 3],
        pub world_max: [f64; 3],
        pub background: f32,
        pub tile: f32,
        pub leaves: Vec<([i32; 3], Vec<f32>)>,
    }

    fn put(buf: &mut [u8], at: usize, bytes: &[u8]) {
        buf[at..at + bytes.len()].copy_from_slice(bytes);
    }

    /// The grid's in-memory bytes in `layout`.
    fn grid_bytes(spec: &GridSpec, layout: &Layout) -> Vec<u8> {
        let [leaf_size, lower_size, upper_size] = layout.sizes;
        let tree = layout.grid_size;
        let root = tree + TREE_SIZE;
        let upper = root + ROOT_SIZE + ROOT_TILE_SIZE;
        let lower = upper + upper_size;
        let leaf0 = lower + lower_size;
        let total = leaf0 + spec.leaves.len() * leaf_size;
        let mut g = vec![0u8; total];
        put(&mut g, 0, MAGIC);
        let name_at = if layout.v32 { 40 } else { 8 };
        put(&mut g, name_at, spec.name.as_bytes());
        if layout.v32 {
            put(&mut g, 16, &((32u32 << 21) | (3 << 10) | 3).to_le_bytes());
            put(&mut g, 28, &1u32.to_le_bytes());
            put(&mut g, 32, &(total as u64).to_le_bytes());
        }
        for a in 0..3 {
            put(
                &mut g,
                layout.world_bbox + 8 * a,
                &spec.world_min[a].to_le_bytes(),
            );
            put(
                &mut g,
                layout.world_bbox + 24 + 8 * a,
                &spec.world_max[a].to_le_bytes(),
            );
        }
        let map = layout.map;
        for a in 0..3 {
            let (v, t) = (spec.voxel, spec.translation[a]);
            put(&mut g, map + 16 * a, &v.to_le_bytes());
            put(&mut g, map + 36 + 16 * a, &(1.0 / v).to_le_bytes());
            put(&mut g, map + 72 + 4 * a, &t.to_le_bytes());
            put(&mut g, map + 88 + 32 * a, &f64::from(v).to_le_bytes());
            put(
                &mut g,
                map + 160 + 32 * a,
                &(1.0 / f64::from(v)).to_le_bytes(),
            );
            put(&mut g, map + 232 + 8 * a, &f64::from(t).to_le_bytes());
        }
        put(&mut g, map + 84, &1.0f32.to_le_bytes());
        put(&mut g, map + 256, &1.0f64.to_le_bytes());
        put(&mut g, layout.class, &spec.class.to_le_bytes());
        put(&mut g, layout.grid_type, &spec.grid_type.to_le_bytes());
        if layout.v32 {
            for a in 0..3 {
                put(&mut g, 608 + 8 * a, &f64::from(spec.voxel).to_le_bytes());
            }
        } else {
            put(&mut g, 576, &f64::from(spec.voxel).to_le_bytes());
        }
        let offsets = [leaf0, lower, upper, root].map(|o| (o - tree) as u64);
        let counts = [spec.leaves.len() as u32, 1, 1, 1];
        for l in 0..4 {
            put(&mut g, tree + 8 * l, &offsets[l].to_le_bytes());
            if l < 3 || !layout.v32 {
                put(&mut g, tree + 32 + 4 * l, &counts[l].to_le_bytes());
            }
        }
        // The root: one tile holding the upper node, the index box
        // 0…127 (the lower node's span).
        for a in 0..3 {
            put(&mut g, root + 12 + 4 * a, &127i32.to_le_bytes());
        }
        put(&mut g, root + layout.root_tiles, &1u32.to_le_bytes());
        put(
            &mut g,
            root + layout.root_background,
            &spec.background.to_le_bytes(),
        );
        let tile = root + ROOT_SIZE;
        if layout.v32 {
            put(&mut g, tile + 8, &((upper - root) as i64).to_le_bytes());
        }
        // Upper: slot 0 holds the lower node.
        put(&mut g, upper + layout.child_mask(5), &1u64.to_le_bytes());
        if layout.v32 {
            let at = upper + layout.table(5);
            put(&mut g, at, &((lower - upper) as i64).to_le_bytes());
        } else {
            // Node offset 1: the children start right after this node.
            put(
                &mut g,
                upper + layout.table(5) + 4 * 32768 + 32,
                &1i32.to_le_bytes(),
            );
        }
        // Lower: tiles of `tile`, children for the leaves.
        let table = lower + layout.table(4);
        let entry = if layout.v32 { 8 } else { 4 };
        for n in 0..4096 {
            put(&mut g, table + entry * n, &spec.tile.to_le_bytes());
        }
        if !layout.v32 {
            put(&mut g, table + 4 * 4096 + 32, &1i32.to_le_bytes());
        }
        for (id, (origin, values)) in spec.leaves.iter().enumerate() {
            let [i, j, k] = origin.map(|c| (c >> 3) as usize);
            let n = (i << 8) | (j << 4) | k;
            let w = lower + layout.child_mask(4) + 8 * (n / 64);
            let word = u64::from_le_bytes(g[w..w + 8].try_into().unwrap()) | (1 << (n % 64));
            put(&mut g, w, &word.to_le_bytes());
            let at = leaf0 + id * leaf_size;
            if layout.v32 {
                put(&mut g, table + 8 * n, &((at - lower) as i64).to_le_bytes());
                put(&mut g, at, &origin.map(|c| c.to_le_bytes()).concat());
            } else {
                put(&mut g, table + 4 * n, &(id as u32).to_le_bytes());
                let bbox = at + layout.leaf_values + 4 * 512 + 8;
                put(&mut g, bbox, &origin.map(|c| c.to_le_bytes()).concat());
            }
            for (m, v) in values.iter().enumerate() {
                put(&mut g, at + layout.leaf_values + 4 * m, &v.to_le_bytes());
            }
        }
        g
    }

    /// NanoVDB's hash of a grid name (its readers match names by it).
    fn name_key(name: &str) -> u64 {
        name.bytes().fold(0u64, |h, c| {
            (h.wrapping_mul(67))
                .wrapping_add(u64::from(c))
                .wrapping_add(h >> 56)
        })
    }

    /// A one-segment file of `grids` with codec NONE (0) or ZIP (1), in
    /// NanoVDB 32.3.3's layout when `v32`, else in version 0.0.19's.
    pub fn file_bytes(grids: &[GridSpec], codec: u16, v32: bool) -> Vec<u8> {
        let layout = if v32 { V32 } else { OLD };
        let version: u32 = if v32 { (32 << 21) | (3 << 10) | 3 } else { 19 };
        let mut out = Vec::new();
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&version.to_le_bytes());
        out.extend_from_slice(&(grids.len() as u16).to_le_bytes());
        out.extend_from_slice(&codec.to_le_bytes());
        let mut datas = Vec::new();
        for spec in grids {
            let raw = grid_bytes(spec, &layout);
            let stored = if codec == 1 {
                use std::io::Write;
                let mut z = flate2::write::ZlibEncoder::new(Vec::new(), Default::default());
                z.write_all(&raw).unwrap();
                let zipped = z.finish().unwrap();
                let mut s = (zipped.len() as u64).to_le_bytes().to_vec();
                s.extend_from_slice(&zipped);
                s
            } else {
                raw.clone()
            };
            let mut meta = vec![0u8; layout.meta_size];
            put(&mut meta, 0, &(raw.len() as u64).to_le_bytes());
            put(&mut meta, 8, &(stored.len() as u64).to_le_bytes());
            put(&mut meta, 16, &name_key(&spec.name).to_le_bytes());
            put(&mut meta, 32, &spec.grid_type.to_le_bytes());
            put(&mut meta, 36, &spec.class.to_le_bytes());
            let name_size = spec.name.len() as u32 + 1;
            put(&mut meta, layout.meta_name_size, &name_size.to_le_bytes());
            if v32 {
                put(&mut meta, 168, &codec.to_le_bytes());
                put(&mut meta, 172, &version.to_le_bytes());
            }
            out.extend_from_slice(&meta);
            out.extend_from_slice(spec.name.as_bytes());
            out.push(0);
            datas.push(stored);
        }
        for d in datas {
            out.extend_from_slice(&d);
        }
        out
    }

    /// A density grid: one leaf at the origin with value f(i, j, k),
    /// tiles of `tile` elsewhere, voxel size 1, no translation.
    pub fn ramp(name: &str, tile: f32, f: impl Fn(i32, i32, i32) -> f32) -> GridSpec {
        let values = (0..512)
            .map(|n| f(n >> 6, (n >> 3) & 7, n & 7))
            .collect::<Vec<_>>();
        GridSpec {
            name: name.into(),
            grid_type: 1,
            class: 2,
            voxel: 1.0,
            translation: [0.0; 3],
            world_min: [0.0; 3],
            world_max: [7.0; 3],
            background: 0.0,
            tile,
            leaves: vec![([0, 0, 0], values)],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_writer::*;
    use super::*;

    fn linear(i: i32, j: i32, k: i32) -> f32 {
        1.0 + i as f32 + 10.0 * j as f32 + 100.0 * k as f32
    }

    /// Both layouts: before NanoVDB 29 and 32.x.
    const LAYOUTS: [bool; 2] = [false, true];

    #[test]
    fn voxel_values_and_trilinear_interpolation_read_back() {
        for v32 in LAYOUTS {
            let mut spec = ramp("density", 0.5, linear);
            // A second leaf next to the first along z.
            spec.leaves.push(([0, 0, 8], vec![7.0; 512]));
            let file = file_bytes(&[spec], 0, v32);
            let g = read_grid(&file, "density").unwrap().unwrap();
            assert_eq!(g.class, 2);
            for &(i, j, k) in &[(0, 0, 0), (3, 5, 7), (7, 7, 7), (1, 0, 6)] {
                assert_eq!(g.value(i, j, k), linear(i, j, k), "v32 {v32}");
                let p = Vec3::new(i as f32, j as f32, k as f32);
                assert!((g.sample(p) - linear(i, j, k)).abs() < 1e-4);
            }
            // The second leaf, a lower-node tile and the background beyond
            // the root tile.
            assert_eq!(g.value(2, 3, 9), 7.0);
            assert_eq!(g.value(20, 3, 3), 0.5);
            assert_eq!(g.value(-1, 0, 0), 0.0);
            assert_eq!(g.value(5000, 0, 0), 0.0);
            // A linear field is reproduced between the voxels.
            let p = Vec3::new(2.25, 4.5, 3.75);
            let expected = 1.0 + 2.25 + 45.0 + 375.0;
            assert!((g.sample(p) - expected).abs() < 1e-3, "{}", g.sample(p));
            // Half-way to the neighbour tile value along x.
            let p = Vec3::new(7.5, 0.0, 0.0);
            assert!((g.sample(p) - (linear(7, 0, 0) + 0.5) / 2.0).abs() < 1e-5);
            assert_eq!(g.max_value(), 7.0f32.max(linear(7, 7, 7)));
        }
    }

    #[test]
    fn zip_files_read_as_uncompressed_ones_and_names_select_grids() {
        for v32 in LAYOUTS {
            let grids = [
                ramp("density", 0.0, linear),
                ramp("temperature", 0.0, |_, _, _| 3.0),
            ];
            let zipped = file_bytes(&grids, 1, v32);
            let plain = file_bytes(&grids, 0, v32);
            assert!(zipped.len() < plain.len());
            for file in [&zipped, &plain] {
                let d = read_grid(file, "density").unwrap().unwrap();
                assert_eq!(d.value(4, 2, 1), linear(4, 2, 1));
                let t = read_grid(file, "temperature").unwrap().unwrap();
                assert_eq!(t.value(4, 2, 1), 3.0);
                assert!(read_grid(file, "velocity").unwrap().is_none());
            }
        }
    }

    #[test]
    fn world_to_index_applies_the_inverse_map() {
        for v32 in LAYOUTS {
            let mut spec = ramp("density", 0.0, linear);
            spec.voxel = 0.25;
            spec.translation = [1.0, -2.0, 3.0];
            let g = read_grid(&file_bytes(&[spec], 0, v32), "density")
                .unwrap()
                .unwrap();
            let q = g.world_to_index(Vec3::new(1.5, -1.0, 3.25));
            assert!((q - Vec3::new(2.0, 4.0, 1.0)).length() < 1e-5, "{q}");
            assert!((g.sample(Vec3::new(1.5, -1.0, 3.25)) - linear(2, 4, 1)).abs() < 1e-4);
        }
    }

    #[test]
    fn truncated_and_corrupt_files_are_errors_not_panics() {
        for (v32, layout) in [(false, OLD), (true, V32)] {
            for codec in [0, 1] {
                let file = file_bytes(&[ramp("density", 0.0, linear)], codec, v32);
                for len in (0..file.len()).step_by(97).chain([file.len() - 1]) {
                    let r = read_grid(&file[..len], "density");
                    assert!(r.is_err() || len == 0, "{len} bytes: {r:?}");
                }
            }
            // Bytes flipped in the grid header, tree, root and the start
            // of the upper node: an error or a value, never a panic.
            let file = file_bytes(&[ramp("density", 0.0, linear)], 0, v32);
            let start = HEADER_SIZE + layout.meta_size + 8;
            let end = start + layout.grid_size + TREE_SIZE + ROOT_SIZE + ROOT_TILE_SIZE + 64;
            for at in (start..end).step_by(3) {
                let mut bad = file.clone();
                bad[at] ^= 0xa5;
                if let Ok(Some(g)) = read_grid(&bad, "density") {
                    g.sample(Vec3::splat(3.5));
                }
            }
            let mut bad = file.clone();
            bad[0] = b'X';
            assert_eq!(read_grid(&bad, "density").unwrap_err(), NvdbError::Magic(0));
        }
    }

    #[test]
    fn other_versions_codecs_and_types_are_named() {
        let mut file = file_bytes(&[ramp("density", 0.0, linear)], 0, false);
        file[8..12].copy_from_slice(&((31u32 << 21) | (2 << 10) | 1).to_le_bytes());
        let e = read_grid(&file, "density").unwrap_err().to_string();
        assert!(e.contains("31.2.1"), "{e}");
        for v32 in LAYOUTS {
            let mut file = file_bytes(&[ramp("density", 0.0, linear)], 0, v32);
            file[14] = 2;
            let e = read_grid(&file, "density").unwrap_err().to_string();
            assert!(e.contains("BLOSC"), "{e}");
            let mut spec = ramp("density", 0.0, linear);
            spec.grid_type = 6;
            let e = read_grid(&file_bytes(&[spec], 0, v32), "density")
                .unwrap_err()
                .to_string();
            assert!(e.contains("Vec3f"), "{e}");
        }
    }

    /// The shared Houdini test volume: a ZIP-compressed density sphere.
    #[test]
    fn shared_sphere_volume_reads() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/scenes/houdini-pbrt-v4/tests/resources/sphere.nvdb");
        let Ok(file) = std::fs::read(&path) else {
            eprintln!("skipping: {} is not present", path.display());
            return;
        };
        let g = read_grid(&file, "density").unwrap().unwrap();
        assert_eq!(g.class, 2);
        // About ±1.09 on each axis.
        for a in 0..3 {
            assert!((g.world_min[a] + 1.09).abs() < 0.01, "{:?}", g.world_min);
            assert!((g.world_max[a] - 1.09).abs() < 0.01, "{:?}", g.world_max);
        }
        assert!(g.sample(Vec3::ZERO) > 0.5, "{}", g.sample(Vec3::ZERO));
        assert_eq!(g.sample(Vec3::new(1.05, 1.05, 1.05)), 0.0);
        assert_eq!(g.sample(Vec3::new(3.0, 0.0, 0.0)), 0.0);
        let m = g.max_value();
        assert!(m > 0.5 && m <= 1.0, "{m}");
    }
}
