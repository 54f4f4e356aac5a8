//! Scene text to built scene: any bytes are parsed, described and built
//! into the renderable scene (shapes, lights, textures, BVH) by
//! `rpbrt::scene::build::build`, and one ray is traced through the BVH.
//! Every step either succeeds or gives an error; none panics, hangs or
//! allocates without bound.
//!
//! Caps: includes are not followed, inputs naming absolute paths or `..`
//! are skipped (a fuzzed file name could name any file, `/dev/zero`
//! included), and relative file names resolve in a directory that does
//! not exist. Nothing is rendered. Run with `-rss_limit_mb=2048
//! -timeout=10` (see docs/robustness.md).
#![no_main]

use glam::Vec3;
use libfuzzer_sys::fuzz_target;
use pbrt_parser::Parser;
use rpbrt::math::ray::Ray;
use rpbrt::scene::build::{build, RenderOverrides};
use rpbrt::scene::{describe, SceneBuilder};

fuzz_target!(|data: &[u8]| {
    if data.windows(2).any(|w| w == b"\"/" || w == b"..") {
        return;
    }
    let parser = Parser::from_text("fuzz.pbrt", data.to_vec()).follow_includes(false);
    let builder = SceneBuilder::new("/nonexistent-rpbrt-fuzz".into());
    let loaded = match describe(parser, builder) {
        Ok(loaded) => loaded,
        Err(e) => {
            let _ = e.to_string();
            return;
        }
    };
    let overrides = RenderOverrides {
        outfile: Some("/nonexistent-rpbrt-fuzz/out.exr".into()),
        ..Default::default()
    };
    match build(loaded.scene, &overrides) {
        Ok(built) => {
            let ray = Ray::new(Vec3::new(0.1, 0.2, -10.0), Vec3::new(0.01, 0.02, 1.0), 0.5);
            let _ = built.intersect(&ray, f32::INFINITY);
            let _ = built.intersect_p(&ray, 1e6);
        }
        Err(e) => {
            let _ = e.to_string();
        }
    }
});
