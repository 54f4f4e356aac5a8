//! The CyHair reader (`rpbrt::shapes::cyhair::read_hair_bytes`, the code
//! `read_hair` runs on a file): any bytes either give a hair file or an
//! error (naming the byte offset); never a panic, a hang or an unbounded
//! allocation (the header's counts are checked against the length before
//! any array is allocated). A file read is then walked segment by segment.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pbrt_parser::Location;
use rpbrt::shapes::cyhair::read_hair_bytes;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let location = Location::nowhere();
    match read_hair_bytes(data, Path::new("fuzz.hair"), &location) {
        Ok(hair) => {
            for i in 0..hair.points.len() {
                let _ = hair.thickness_at(i);
            }
        }
        Err(e) => {
            let _ = e.to_string();
        }
    }
});
