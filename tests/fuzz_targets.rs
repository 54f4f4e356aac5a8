//! The fuzz targets (`fuzz/`, run with cargo-fuzz on a nightly toolchain;
//! docs/robustness.md) still compile against the library as it is today.
//! Their crate is not a workspace member (libFuzzer links only under
//! cargo-fuzz's flags), so nothing else builds them: the `scene` target
//! went uncompiled for weeks after `build` came to take the scene
//! description by value. `cargo check` of that crate, on the toolchain
//! running these tests, into its own target folder; skipped with a message
//! where no C++ compiler is found (libfuzzer-sys builds libFuzzer's C++
//! sources even to check).

use std::path::Path;
use std::process::Command;

#[test]
fn the_fuzz_targets_compile() {
    if Command::new("c++").arg("--version").output().is_err() {
        eprintln!("skipped: no C++ compiler (`c++`), which libfuzzer-sys needs to build");
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = Command::new(cargo)
        .args(["check", "--bins", "--quiet", "--manifest-path"])
        .arg(root.join("fuzz/Cargo.toml"))
        .arg("--target-dir")
        .arg(root.join("target/fuzz-check"))
        .output()
        .expect("cargo runs");
    assert!(
        output.status.success(),
        "the fuzz targets do not compile:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
}
