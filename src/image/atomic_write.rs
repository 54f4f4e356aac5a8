//! Writing a file so that it appears whole or not at all.
//!
//! A render that fails (or is interrupted) while writing its image must not
//! leave a truncated file that looks like a result, nor destroy the previous
//! one. The contents go to a temporary file in the same directory (so the
//! final rename stays on one file system, where it is atomic), which is
//! flushed to disk and then renamed over the destination. On any error the
//! temporary file is removed.

use super::ImageError;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes temporary files of concurrent writes within one process.
static TEMPORARY_FILE_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `path` atomically with the bytes `write_contents` produces.
pub(crate) fn write_atomically(
    path: &Path,
    write_contents: impl FnOnce(&mut BufWriter<File>) -> Result<(), ImageError>,
) -> Result<(), ImageError> {
    let file_name = path.file_name().ok_or_else(|| ImageError::Unwritable {
        path: path.to_path_buf(),
        message: "the path does not name a file".into(),
    })?;
    let directory = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let mut temporary_name = std::ffi::OsString::from(".");
    temporary_name.push(file_name);
    temporary_name.push(format!(
        ".{}-{}.tmp",
        std::process::id(),
        TEMPORARY_FILE_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let temporary_path = directory.join(temporary_name);

    let io_error = |path: &Path| {
        let path = path.to_path_buf();
        move |source| ImageError::Io { path, source }
    };
    let file = File::options()
        .write(true)
        .create_new(true)
        .open(&temporary_path)
        .map_err(io_error(&temporary_path))?;
    let temporary = TemporaryFile {
        path: temporary_path,
        keep: false,
    };

    let mut writer = BufWriter::new(file);
    write_contents(&mut writer)?;
    let file = writer.into_inner().map_err(|error| ImageError::Io {
        path: temporary.path.clone(),
        source: error.into_error(),
    })?;
    file.sync_all().map_err(io_error(&temporary.path))?;
    drop(file);
    std::fs::rename(&temporary.path, path).map_err(io_error(path))?;
    temporary.keep();
    Ok(())
}

/// A temporary file that is deleted when dropped, unless kept.
struct TemporaryFile {
    path: PathBuf,
    keep: bool,
}

impl TemporaryFile {
    /// The file was renamed into place: nothing to clean up.
    fn keep(mut self) {
        self.keep = true;
    }
}

impl Drop for TemporaryFile {
    fn drop(&mut self) {
        if !self.keep {
            // Best effort: the original error is what the caller needs.
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Helpers for tests that write files: a fresh, empty directory per test.
#[cfg(test)]
pub(crate) mod test_directory {
    use std::path::PathBuf;

    /// A new empty directory under the system temporary directory, removed
    /// again when the returned guard is dropped.
    pub(crate) struct TestDirectory(pub PathBuf);

    impl TestDirectory {
        pub(crate) fn new(name: &str) -> TestDirectory {
            let path = std::env::temp_dir()
                .join(format!("rpbrt-image-test-{}-{name}", std::process::id()));
            let _ = std::fs::remove_dir_all(&path);
            std::fs::create_dir_all(&path).expect("create test directory");
            TestDirectory(path)
        }

        pub(crate) fn join(&self, name: &str) -> PathBuf {
            self.0.join(name)
        }

        /// Names of the files in the directory, sorted.
        pub(crate) fn file_names(&self) -> Vec<String> {
            let mut names: Vec<String> = std::fs::read_dir(&self.0)
                .expect("list test directory")
                .map(|entry| {
                    entry
                        .expect("directory entry")
                        .file_name()
                        .to_string_lossy()
                        .into_owned()
                })
                .collect();
            names.sort();
            names
        }
    }

    impl Drop for TestDirectory {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_directory::TestDirectory;
    use super::*;
    use std::io::Write;

    #[test]
    fn writes_whole_file_and_leaves_no_temporary() {
        let directory = TestDirectory::new("atomic-ok");
        let path = directory.join("out.bin");
        write_atomically(&path, |writer| {
            writer.write_all(b"hello").map_err(|source| ImageError::Io {
                path: path.clone(),
                source,
            })
        })
        .unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"hello");
        assert_eq!(directory.file_names(), ["out.bin"]);
    }

    #[test]
    fn failure_leaves_no_file_and_keeps_the_previous_one() {
        let directory = TestDirectory::new("atomic-fail");
        let path = directory.join("out.bin");
        let failing = |writer: &mut BufWriter<File>| {
            // Enough bytes that some reach the temporary file on disk.
            writer.write_all(&[7u8; 100_000]).unwrap();
            Err(ImageError::Invalid("failed halfway".into()))
        };
        assert!(matches!(
            write_atomically(&path, failing),
            Err(ImageError::Invalid(_))
        ));
        assert!(
            directory.file_names().is_empty(),
            "{:?}",
            directory.file_names()
        );

        std::fs::write(&path, b"previous").unwrap();
        assert!(write_atomically(&path, failing).is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"previous");
        assert_eq!(directory.file_names(), ["out.bin"]);
    }

    #[test]
    fn missing_directory_is_an_error_naming_the_file() {
        let directory = TestDirectory::new("atomic-missing");
        let path = directory.join("no/such/dir/out.bin");
        let error = write_atomically(&path, |_| Ok(())).unwrap_err();
        assert!(error.to_string().contains("out.bin"), "{error}");
    }
}
