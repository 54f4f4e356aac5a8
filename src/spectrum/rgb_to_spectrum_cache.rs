//! Keeps fitted RGB → spectrum tables on disk, so the fit runs once per
//! machine rather than once per render, and a render reads only the rows
//! of the table its colours fall in.
//!
//! Files live in `$RPBRT_CACHE_DIR`, else `$XDG_CACHE_HOME/rpbrt`, else
//! `$HOME/.cache/rpbrt`. A file's name carries a fingerprint of everything
//! the fit depends on (fitter version, resolution, the colour space's
//! matrix and illuminant-weighted matching functions), so changed inputs
//! never read a stale table; its contents carry a checksum, so a truncated
//! or corrupted file is ignored and refitted. Failing to read or write the
//! cache is never an error: the table is then just computed in memory.
//!
//! A file holds a header, the z nodes, then the coefficients row by row
//! (`[max component][z][y]`, each row the `resolution` x steps' three
//! coefficients), then the checksum. [`CachedRows::open`] checks the
//! checksum by reading the file through a small buffer, then keeps it open
//! and reads each row when it is first asked for: the whole table is 9 MB,
//! of which a scene's colours use a small part (pbrt-v4 compiles its tables
//! into its binary, where likewise only the pages touched become resident).

use std::fs::File;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Bump when the fit changes in a way the fingerprint cannot see.
pub const FIT_VERSION: u32 = 1;

const MAGIC: &[u8; 8] = b"RPBRTS2C";

/// Bytes before the z nodes: magic, version, resolution, fingerprint.
const HEADER_BYTES: u64 = 8 + 4 + 4 + 8;

/// The largest resolution a file may declare (the fit uses 64).
const MAX_RESOLUTION: usize = 1024;

/// The cache directory from the environment, if any is configured.
pub fn cache_directory() -> Option<PathBuf> {
    let from_env = |name: &str| {
        std::env::var_os(name)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    from_env("RPBRT_CACHE_DIR")
        .or_else(|| from_env("XDG_CACHE_HOME").map(|d| d.join("rpbrt")))
        .or_else(|| from_env("HOME").map(|d| d.join(".cache").join("rpbrt")))
}

/// 64-bit FNV-1a, for fingerprints and checksums (not security).
#[derive(Clone, Copy, Debug)]
pub struct Fnv1a(u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a {
    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    pub fn write_f64(&mut self, v: f64) {
        self.write(&v.to_le_bytes());
    }

    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// Where the table for `space_name` with `fingerprint` is stored in `dir`.
pub fn cache_file(dir: &Path, space_name: &str, fingerprint: u64) -> PathBuf {
    dir.join(format!(
        "rgb-to-spectrum-{space_name}-{fingerprint:016x}.bin"
    ))
}

/// The number of rows of a table of `resolution` steps (3 · resolution²)
/// and the bytes of one row.
fn row_shape(resolution: usize) -> (usize, usize) {
    (3 * resolution * resolution, resolution * 3 * 4)
}

/// A file's size for `resolution`: header, z nodes, rows, checksum.
fn file_bytes(resolution: usize) -> u64 {
    let (rows, row_bytes) = row_shape(resolution);
    HEADER_BYTES + 4 * resolution as u64 + (rows * row_bytes) as u64 + 8
}

/// A table file whose checksum and header have been checked, kept open to
/// read its rows as they are needed.
#[derive(Debug)]
pub struct CachedRows {
    /// The open file. Its contents cannot change under it: [`store`]
    /// replaces a file by renaming a new one over it, which leaves this
    /// one's contents as they were.
    file: Mutex<File>,
    resolution: usize,
    z_nodes: Vec<f32>,
}

impl CachedRows {
    /// The table at `path`, if it holds a valid one for `fingerprint`.
    /// Reads the whole file once (through a 64 kB buffer) to check its
    /// checksum; keeps none of it but the z nodes.
    pub fn open(path: &Path, fingerprint: u64) -> Option<Self> {
        let mut file = File::open(path).ok()?;
        let length = file.metadata().ok()?.len();
        let mut header = [0u8; HEADER_BYTES as usize];
        file.read_exact(&mut header).ok()?;
        let (magic, rest) = header.split_at(8);
        let (version, rest) = rest.split_at(4);
        let (resolution, stored_fingerprint) = rest.split_at(4);
        let resolution = u32::from_le_bytes(resolution.try_into().ok()?) as usize;
        if magic != MAGIC.as_slice()
            || u32::from_le_bytes(version.try_into().ok()?) != FIT_VERSION
            || u64::from_le_bytes(stored_fingerprint.try_into().ok()?) != fingerprint
            || !(2..=MAX_RESOLUTION).contains(&resolution)
            || length != file_bytes(resolution)
        {
            return None;
        }
        let mut checksum = Fnv1a::default();
        checksum.write(&header);
        let mut z_bytes = vec![0u8; 4 * resolution];
        file.read_exact(&mut z_bytes).ok()?;
        checksum.write(&z_bytes);
        let z_nodes: Vec<f32> = z_bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let mut remaining = length - HEADER_BYTES - 4 * resolution as u64 - 8;
        let mut buffer = vec![0u8; 1 << 16];
        while remaining > 0 {
            let n = remaining.min(buffer.len() as u64) as usize;
            file.read_exact(&mut buffer[..n]).ok()?;
            checksum.write(&buffer[..n]);
            remaining -= n as u64;
        }
        let mut stored_checksum = [0u8; 8];
        file.read_exact(&mut stored_checksum).ok()?;
        if checksum.finish().to_le_bytes() != stored_checksum {
            return None;
        }
        Some(CachedRows {
            file: Mutex::new(file),
            resolution,
            z_nodes,
        })
    }

    pub fn resolution(&self) -> usize {
        self.resolution
    }

    pub fn z_nodes(&self) -> &[f32] {
        &self.z_nodes
    }

    /// Row `index` (`[max component][z][y]` flattened): the three
    /// coefficients of each x step. `None` if it cannot be read or holds a
    /// value that is not finite.
    pub fn read_row(&self, index: usize) -> Option<Vec<[f32; 3]>> {
        let (rows, row_bytes) = row_shape(self.resolution);
        if index >= rows {
            return None;
        }
        let offset = HEADER_BYTES + 4 * self.resolution as u64 + (index * row_bytes) as u64;
        let mut bytes = vec![0u8; row_bytes];
        {
            let mut file = self.file.lock().unwrap_or_else(|e| e.into_inner());
            file.seek(SeekFrom::Start(offset)).ok()?;
            file.read_exact(&mut bytes).ok()?;
        }
        let row: Vec<[f32; 3]> = bytes
            .chunks_exact(12)
            .map(|c| {
                let f = |k: usize| f32::from_le_bytes([c[k], c[k + 1], c[k + 2], c[k + 3]]);
                [f(0), f(4), f(8)]
            })
            .collect();
        row.iter()
            .all(|c| c.iter().all(|v| v.is_finite()))
            .then_some(row)
    }
}

/// Writes a table (`rows` in the order of [`CachedRows::read_row`]) to
/// `file`, computing its checksum on the way.
fn write_table<'a>(
    file: &mut impl Write,
    resolution: usize,
    z_nodes: &[f32],
    rows: impl Iterator<Item = &'a [[f32; 3]]>,
    fingerprint: u64,
) -> std::io::Result<()> {
    let mut checksum = Fnv1a::default();
    let mut put = |file: &mut dyn Write, bytes: &[u8]| {
        checksum.write(bytes);
        file.write_all(bytes)
    };
    put(file, MAGIC)?;
    put(file, &FIT_VERSION.to_le_bytes())?;
    put(file, &(resolution as u32).to_le_bytes())?;
    put(file, &fingerprint.to_le_bytes())?;
    for v in z_nodes {
        put(file, &v.to_le_bytes())?;
    }
    for row in rows {
        for v in row.iter().flatten() {
            put(file, &v.to_le_bytes())?;
        }
    }
    file.write_all(&checksum.finish().to_le_bytes())
}

/// Stores a table (its `rows` in the order of [`CachedRows::read_row`]) at
/// `path`, creating its directory. Writes a temporary file and renames it
/// into place, so a concurrent reader (another render starting) sees
/// either no file or a whole one, and one that has a file open keeps
/// reading the old one.
pub fn store<'a>(
    path: &Path,
    resolution: usize,
    z_nodes: &[f32],
    rows: impl Iterator<Item = &'a [[f32; 3]]>,
    fingerprint: u64,
) -> std::io::Result<()> {
    let dir = path.parent().unwrap_or_else(|| Path::new("."));
    std::fs::create_dir_all(dir)?;
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "table".to_string());
    let temporary = dir.join(format!(".{file_name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut file = BufWriter::new(File::create(&temporary)?);
        write_table(&mut file, resolution, z_nodes, rows, fingerprint)?;
        file.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        std::fs::rename(&temporary, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3-step table's z nodes and rows (3 · 3² rows of 3 entries).
    fn small_table() -> (usize, Vec<f32>, Vec<Vec<[f32; 3]>>) {
        let res = 3;
        let rows = (0..3 * res * res)
            .map(|r| {
                (0..res)
                    .map(|x| {
                        let i = ((r * res + x) * 3) as f32;
                        [i * 1e-3, (i + 1.0) * 1e-3, (i + 2.0) * 1e-3]
                    })
                    .collect()
            })
            .collect();
        (res, vec![0.0, 0.4, 1.0], rows)
    }

    fn store_small(path: &Path, fingerprint: u64) -> std::io::Result<()> {
        let (res, z_nodes, rows) = small_table();
        store(
            path,
            res,
            &z_nodes,
            rows.iter().map(Vec::as_slice),
            fingerprint,
        )
    }

    fn scratch_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("rpbrt-test-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn stored_tables_read_back_identically() {
        let dir = scratch_dir("cache-roundtrip");
        let (res, z_nodes, rows) = small_table();
        let path = cache_file(&dir, "srgb", 42);
        store_small(&path, 42).unwrap();
        let cached = CachedRows::open(&path, 42).unwrap();
        assert_eq!(cached.resolution(), res);
        assert_eq!(cached.z_nodes(), z_nodes.as_slice());
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(cached.read_row(i).as_ref(), Some(row));
        }
        assert_eq!(cached.read_row(rows.len()), None);
        // Another fingerprint (changed inputs) does not match.
        assert!(CachedRows::open(&path, 43).is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn damaged_files_are_ignored() {
        let dir = scratch_dir("cache-damaged");
        let path = dir.join("table.bin");
        store_small(&path, 7).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let damaged = |bytes: &[u8]| {
            std::fs::write(&path, bytes).unwrap();
            CachedRows::open(&path, 7).is_none()
        };
        assert!(!damaged(&bytes));
        let mut flipped = bytes.clone();
        flipped[40] ^= 1;
        assert!(damaged(&flipped));
        assert!(damaged(&bytes[..bytes.len() - 3]));
        assert!(damaged(&[]));
        assert!(CachedRows::open(Path::new("/nonexistent/table.bin"), 7).is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn an_unwritable_directory_is_an_error_not_a_panic() {
        let path = Path::new("/proc/rpbrt-cannot-write/table.bin");
        assert!(store_small(path, 1).is_err());
    }
}
