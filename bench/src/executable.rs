//! The `rpbrt` executable the harness runs as child processes (peak
//! memory, the dual-model pairs): the one beside this program, as Cargo
//! builds the workspace's binaries into one folder.

use crate::error::{io_error, Error};
use std::path::{Path, PathBuf};

/// The `rpbrt` executable beside the running `rpbrt-bench`.
pub fn rpbrt_executable() -> Result<PathBuf, Error> {
    let me = std::env::current_exe().map_err(io_error(Path::new("<rpbrt-bench executable>")))?;
    let path = me.with_file_name(format!("rpbrt{}", std::env::consts::EXE_SUFFIX));
    if path.is_file() {
        Ok(path)
    } else {
        Err(Error::Usage(format!(
            "{} is not there: the harness renders through the rpbrt executable beside it; \
             build both with `cargo build --release --workspace`",
            path.display()
        )))
    }
}
