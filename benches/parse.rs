//! Parser throughput (MB/s) on a generated curve scene of the form pbrt-v4
//! was measured on (`../shared/refs/README.md`), and the cost of the scene
//! description on top of it.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use pbrt_parser::Parser;
use std::hint::black_box;
use std::path::Path;

fn parse(c: &mut Criterion) {
    // 100k curves ≈ 20 MB: large enough to stream through several windows.
    let text = rpbrt::tools::curvegen::curve_scene(100_000, 1);
    let dir = std::env::temp_dir().join(format!("rpbrt-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("curves.pbrt");
    std::fs::write(&path, &text).unwrap();

    let mut group = c.benchmark_group("parse");
    group.sample_size(10);
    group.throughput(Throughput::Bytes(text.len() as u64));
    group.bench_function("directives (file, streamed)", |b| {
        b.iter(|| {
            let mut n = 0;
            for d in Parser::open(&path).unwrap() {
                black_box(d.unwrap());
                n += 1;
            }
            assert_eq!(n, 100_007);
        })
    });
    group.bench_function("scene description (file)", |b| {
        b.iter(|| black_box(rpbrt::scene::load(Path::new(&path)).unwrap()))
    });
    group.finish();
    std::fs::remove_dir_all(&dir).ok();
}

criterion_group!(benches, parse);
criterion_main!(benches);
