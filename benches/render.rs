//! BVH build and traversal on a large triangle mesh, and ray–curve
//! intersections on generated hair, through the built scene.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec3;
use rpbrt::math::Ray;
use rpbrt::scene::build::{build, BuiltScene, RenderOverrides};
use std::hint::black_box;
use std::path::Path;

/// A bumpy grid of `n`×`n` quads (2n² triangles) in one trianglemesh.
fn mesh_scene(n: usize) -> String {
    let mut p = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (
                i as f32 / n as f32 * 2.0 - 1.0,
                j as f32 / n as f32 * 2.0 - 1.0,
            );
            let z = 0.05 * ((x * 40.0).sin() * (y * 37.0).cos());
            p.push_str(&format!("{x} {y} {z} "));
        }
    }
    let mut idx = String::new();
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            idx.push_str(&format!(
                "{} {} {} {} {} {} ",
                a,
                a + 1,
                a + n + 2,
                a,
                a + n + 2,
                a + n + 1
            ));
        }
    }
    format!(
        "LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\"\nFilm \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n\
         Shape \"trianglemesh\" \"point3 P\" [{p}] \"integer indices\" [{idx}]\n"
    )
}

fn built(text: &str) -> BuiltScene {
    let loaded = rpbrt::scene::load_text(Path::new("bench.pbrt"), text).unwrap();
    build(loaded.scene, &RenderOverrides::default()).unwrap()
}

/// Rays from a grid of origins above the scene towards it.
fn rays(count: usize, height: f32) -> Vec<Ray> {
    let mut state = 0x2545_f491u32;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32
    };
    (0..count)
        .map(|_| {
            let o = Vec3::new(rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0, height);
            let t = Vec3::new(rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0, 0.0);
            Ray::new(o, (t - o).normalize(), 0.0)
        })
        .collect()
}

fn triangles(c: &mut Criterion) {
    let text = mesh_scene(300); // 180,000 triangles
    let mut group = c.benchmark_group("bvh");
    group.sample_size(10);
    group.bench_function("build 180k triangles (parse + build)", |b| {
        b.iter(|| black_box(built(&text)))
    });
    let scene = built(&text);
    let rays = rays(100_000, 2.0);
    group.throughput(Throughput::Elements(rays.len() as u64));
    group.bench_function("closest hit, 180k triangles", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| scene.intersect(r, f32::INFINITY).is_some())
                .count()
        })
    });
    group.finish();
}

fn curves(c: &mut Criterion) {
    // 20,000 random cylinder curves in a 8³ box (the parse benchmark's form).
    let text = rpbrt::tools::curvegen::curve_scene(20_000, 3)
        .replace("Material \"hair\"", "Material \"diffuse\"");
    let scene = built(&text);
    let rays = rays(100_000, 6.0);
    let mut group = c.benchmark_group("curves");
    group.sample_size(10);
    group.throughput(Throughput::Elements(rays.len() as u64));
    group.bench_function("closest hit, 20k curves", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| scene.intersect(r, f32::INFINITY).is_some())
                .count()
        })
    });
    group.bench_function("any hit, 20k curves", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| scene.intersect_p(r, f32::INFINITY))
                .count()
        })
    });
    group.finish();
}

criterion_group!(benches, triangles, curves);
criterion_main!(benches);
