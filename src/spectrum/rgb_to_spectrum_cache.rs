//! Keeps fitted RGB → spectrum tables on disk, so the fit runs once per
//! machine rather than once per render.
//!
//! Files live in `$RPBRT_CACHE_DIR`, else `$XDG_CACHE_HOME/rpbrt`, else
//! `$HOME/.cache/rpbrt`. A file's name carries a fingerprint of everything
//! the fit depends on (fitter version, resolution, the colour space's
//! matrix and illuminant-weighted matching functions), so changed inputs
//! never read a stale table; its contents carry a checksum, so a truncated
//! or corrupted file is ignored and refitted. Failing to read or write the
//! cache is never an error: the table is then just computed in memory.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::rgb_to_spectrum::RgbToSpectrumTable;

/// Bump when the fit changes in a way the fingerprint cannot see.
pub const FIT_VERSION: u32 = 1;

const MAGIC: &[u8; 8] = b"RPBRTS2C";

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

fn encode(table: &RgbToSpectrumTable, fingerprint: u64) -> Vec<u8> {
    let mut bytes =
        Vec::with_capacity(32 + 4 * (table.z_nodes().len() + table.coefficients().len()));
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&FIT_VERSION.to_le_bytes());
    bytes.extend_from_slice(&(table.resolution() as u32).to_le_bytes());
    bytes.extend_from_slice(&fingerprint.to_le_bytes());
    for v in table.z_nodes().iter().chain(table.coefficients()) {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let mut checksum = Fnv1a::default();
    checksum.write(&bytes);
    bytes.extend_from_slice(&checksum.finish().to_le_bytes());
    bytes
}

fn decode(bytes: &[u8], fingerprint: u64) -> Option<RgbToSpectrumTable> {
    let (body, checksum_bytes) = bytes.split_at_checked(bytes.len().checked_sub(8)?)?;
    let mut checksum = Fnv1a::default();
    checksum.write(body);
    if checksum.finish().to_le_bytes() != checksum_bytes {
        return None;
    }
    let rest = body.strip_prefix(MAGIC.as_slice())?;
    let (version, rest) = rest.split_at_checked(4)?;
    let (resolution, rest) = rest.split_at_checked(4)?;
    let (stored_fingerprint, rest) = rest.split_at_checked(8)?;
    if u32::from_le_bytes(version.try_into().ok()?) != FIT_VERSION
        || u64::from_le_bytes(stored_fingerprint.try_into().ok()?) != fingerprint
    {
        return None;
    }
    let resolution = u32::from_le_bytes(resolution.try_into().ok()?) as usize;
    if !(2..=1024).contains(&resolution) {
        return None;
    }
    let floats: Vec<f32> = rest
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    if rest.len() % 4 != 0 || floats.len() < resolution {
        return None;
    }
    let (z_nodes, coefficients) = floats.split_at(resolution);
    RgbToSpectrumTable::from_parts(resolution, z_nodes.to_vec(), coefficients.to_vec())
}

/// The cached table, if `path` holds a valid one for `fingerprint`.
pub fn load(path: &Path, fingerprint: u64) -> Option<RgbToSpectrumTable> {
    let bytes = std::fs::read(path).ok()?;
    decode(&bytes, fingerprint)
}

/// Stores `table` at `path`, creating its directory. Writes a temporary
/// file and renames it into place, so a concurrent reader (another render
/// starting) sees either no file or a whole one.
pub fn store(path: &Path, table: &RgbToSpectrumTable, fingerprint: u64) -> std::io::Result<()> {
    let dir = path.parent().unwrap_or_else(|| Path::new("."));
    std::fs::create_dir_all(dir)?;
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "table".to_string());
    let temporary = dir.join(format!(".{file_name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(&encode(table, fingerprint))?;
        file.sync_all()?;
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
    use glam::Vec3;

    fn small_table() -> RgbToSpectrumTable {
        let res = 3;
        let coefficients = (0..3 * res * res * res * 3)
            .map(|i| i as f32 * 1e-3)
            .collect();
        RgbToSpectrumTable::from_parts(res, vec![0.0, 0.4, 1.0], coefficients).unwrap()
    }

    fn scratch_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("rpbrt-test-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn stored_tables_load_back_identically() {
        let dir = scratch_dir("cache-roundtrip");
        let table = small_table();
        let path = cache_file(&dir, "srgb", 42);
        store(&path, &table, 42).unwrap();
        assert_eq!(load(&path, 42), Some(table.clone()));
        // Another fingerprint (changed inputs) does not match.
        assert_eq!(load(&path, 43), None);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn damaged_files_are_ignored() {
        let table = small_table();
        let bytes = encode(&table, 7);
        assert!(decode(&bytes, 7).is_some());
        let mut flipped = bytes.clone();
        flipped[40] ^= 1;
        assert!(decode(&flipped, 7).is_none());
        assert!(decode(&bytes[..bytes.len() - 3], 7).is_none());
        assert!(decode(&[], 7).is_none());
        assert!(load(Path::new("/nonexistent/table.bin"), 7).is_none());
        assert_eq!(table.lookup(Vec3::ONE).eval(500.0), 1.0);
    }

    #[test]
    fn an_unwritable_directory_is_an_error_not_a_panic() {
        let table = small_table();
        let path = Path::new("/proc/rpbrt-cannot-write/table.bin");
        assert!(store(path, &table, 1).is_err());
    }
}
