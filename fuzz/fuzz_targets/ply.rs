//! The PLY reader (`rpbrt::shapes::ply::read_ply_bytes`, the code
//! `read_ply` runs on a file): any bytes, read as a plain `.ply` and, when
//! they start with gzip's magic, as a `.ply.gz`, either give a mesh or an
//! error; never a panic, a hang or an unbounded allocation. A mesh read is
//! then turned into triangle and bilinear patch meshes (index checks).
#![no_main]

use libfuzzer_sys::fuzz_target;
use pbrt_parser::Location;
use rpbrt::math::Transform;
use rpbrt::shapes::ply::read_ply_bytes;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let location = Location::nowhere();
    let name = if data.starts_with(&[0x1f, 0x8b]) {
        "fuzz.ply.gz"
    } else {
        "fuzz.ply"
    };
    match read_ply_bytes(data, Path::new(name), &location) {
        Ok(mesh) => {
            let _ = mesh.into_meshes(&Transform::IDENTITY, false);
        }
        Err(e) => {
            let _ = e.to_string();
        }
    }
});
