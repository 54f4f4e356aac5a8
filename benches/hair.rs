//! Hair BSDF cost per call: pbrt-v4's circular fibre against the dual
//! model (elliptical fibre, logistic and spectral diffraction), for
//! value, sample and pdf over a fixed set of (h, ωo, ωi), and for what a
//! path vertex asks of it: make the BxDF for its ωo (each model computes
//! its ωo state then: A_p and angles for the circular one, the
//! cross-section trace for the dual), evaluate and weigh a light sample
//! (value and density in one call, as the path integrator does), sample
//! the next direction. "elliptical" is the fibre alone (d_diff = 0, Table
//! 2's elliptical row); the other two add a diffracting layer
//! (d_diff = 0.5).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::{Vec2, Vec3};
use rpbrt::bxdfs::dual_hair::{DualHairBxDF, DualHairParams};
use rpbrt::bxdfs::hair::{CircularHairBxDF, HairBxDF};
use rpbrt::bxdfs::hair_diffraction::Diffraction;
use rpbrt::bxdfs::hair_ellipse::{Ellipse, InternalFresnel, Optics, RayModel, Variant};
use rpbrt::bxdfs::{BxDF, BxDFInterface, BxDFReflTransFlags, TransportMode};
use rpbrt::spectrum::SampledSpectrum;
use std::hint::black_box;

const N: usize = 1024;

/// Deterministic inputs: (h, ωo, ωi, uc, u).
fn inputs() -> Vec<(f32, Vec3, Vec3, f32, Vec2)> {
    let mut s = 0x9e37_79b9u32;
    let mut f = move || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s as f32 / u32::MAX as f32
    };
    let dir = |f: &mut dyn FnMut() -> f32| {
        let z = 1.0 - 2.0 * f();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let p = std::f32::consts::TAU * f();
        Vec3::new(r * p.cos(), r * p.sin(), z)
    };
    (0..N)
        .map(|_| {
            let h = -1.0 + 2.0 * f();
            let wo = dir(&mut f);
            let wi = dir(&mut f);
            (h, wo, wi, f(), Vec2::new(f(), f()))
        })
        .collect()
}

fn make(kind: &str, h: f32) -> BxDF {
    make_for(kind, h, None)
}

/// The BxDF, with its per-ω_o state (for the dual model its
/// cross-section trace) computed for `wo` when given.
fn make_for(kind: &str, h: f32, wo: Option<Vec3>) -> BxDF {
    let sigma = SampledSpectrum([0.4, 0.6, 0.9, 1.3]);
    let base = HairBxDF::new(h, 1.55, sigma, 0.3, 0.3, 2.0);
    let params = |diffraction| DualHairParams {
        ellipse: Ellipse::new(30.0, 20.0),
        mean_radius_um: 25.0,
        d_diff: if kind == "elliptical" { 0.0 } else { 0.5 },
        diffraction,
        s_diff: None,
        variant: Variant::Exact,
        internal_fresnel: InternalFresnel::Pbrt,
        residual: rpbrt::bxdfs::hair_ellipse::Residual::Uniform,
    };
    let lambda = [430.0, 520.0, 600.0, 680.0];
    match kind {
        "circular pbrt" => {
            let circular = CircularHairBxDF::new(base);
            BxDF::Hair(match wo {
                Some(wo) => circular.with_outgoing(wo),
                None => circular,
            })
        }
        _ => {
            let diffraction = if kind == "elliptical spectral" {
                Diffraction::Spectral
            } else {
                Diffraction::Logistic
            };
            let axis = glam::Vec2::from_angle(0.4);
            let dual = DualHairBxDF::new(base, params(diffraction), axis, lambda);
            BxDF::DualHair(match wo {
                Some(wo) => dual.with_outgoing(wo),
                None => dual,
            })
        }
    }
}

fn hair(c: &mut Criterion) {
    let inputs = inputs();
    let mode = TransportMode::Radiance;
    let all = BxDFReflTransFlags::All;
    let mut g = c.benchmark_group("hair");
    g.throughput(Throughput::Elements(N as u64));
    for kind in [
        "circular pbrt",
        "elliptical",
        "elliptical logistic",
        "elliptical spectral",
    ] {
        let bxdfs: Vec<BxDF> = inputs.iter().map(|i| make(kind, i.0)).collect();
        g.bench_function(format!("{kind}/f"), |b| {
            b.iter(|| {
                for (x, i) in bxdfs.iter().zip(&inputs) {
                    black_box(x.f(i.1, i.2, mode));
                }
            })
        });
        g.bench_function(format!("{kind}/sample_f"), |b| {
            b.iter(|| {
                for (x, i) in bxdfs.iter().zip(&inputs) {
                    black_box(x.sample_f(i.1, i.3, i.4, mode, all));
                }
            })
        });
        g.bench_function(format!("{kind}/vertex: make + f_and_pdf + sample_f"), |b| {
            b.iter(|| {
                for i in &inputs {
                    let x = make_for(kind, i.0, Some(i.1));
                    black_box(x.f_and_pdf(i.1, i.2, mode));
                    black_box(x.sample_f(i.1, i.3, i.4, mode, all));
                }
            })
        });
        g.bench_function(format!("{kind}/pdf"), |b| {
            b.iter(|| {
                for (x, i) in bxdfs.iter().zip(&inputs) {
                    black_box(x.pdf(i.1, i.2, mode, all));
                }
            })
        });
    }
    // The dual model's own work at a vertex: the trace through the
    // cross-section for ω_o (a = 30, b = 20 µm), as the BxDF asks for it.
    let ellipse = Ellipse::new(30.0, 20.0);
    let axis = glam::DVec2::from_angle(0.4);
    g.bench_function("elliptical/trace", |b| {
        b.iter(|| {
            for i in &inputs {
                let optics = Optics::new(1.55, i.1.x);
                let toward =
                    glam::DVec2::new(i.1.y as f64, i.1.z as f64).normalize_or(glam::DVec2::X);
                black_box(ellipse.trace_into(
                    toward,
                    axis,
                    i.0,
                    &optics,
                    RayModel::PBRT,
                    |k, exit| {
                        black_box((k, exit));
                        1.0
                    },
                ));
            }
        })
    });
    g.finish();
}

criterion_group!(benches, hair);
criterion_main!(benches);
