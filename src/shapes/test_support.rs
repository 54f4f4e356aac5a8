//! Helpers for the shape tests: a small deterministic random generator and
//! random directions.

use crate::math::pcg32::Pcg32;
use glam::{Vec2, Vec3};

/// The stream the shape tests draw from: pcg-basic's default increment
/// (not one of pbrt's `SetSequence` streams), kept so the tests' numbers
/// do not change.
const TEST_STREAM_INCREMENT: u64 = 1_442_695_040_888_963_407;

/// The crate's PCG32 on a fixed stream, seeded by a scrambled `seed`, with
/// 24-bit floats: deterministic, good enough for tests.
pub struct TestRng(Pcg32);

impl TestRng {
    pub fn new(seed: u64) -> Self {
        let state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x853c_49e6_748f_ea9b;
        let mut rng = TestRng(Pcg32::from_state_and_increment(
            state,
            TEST_STREAM_INCREMENT,
        ));
        rng.next_u32();
        rng
    }

    pub fn next_u32(&mut self) -> u32 {
        self.0.uniform_u32()
    }

    /// Uniform in [0, 1): the top 24 bits scaled by 2^-24 (unlike
    /// [`Pcg32::uniform_f32`], which scales all 32).
    pub fn uniform(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    pub fn uniform2(&mut self) -> Vec2 {
        Vec2::new(self.uniform(), self.uniform())
    }

    /// Uniform in [low, high).
    pub fn range(&mut self, low: f32, high: f32) -> f32 {
        low + (high - low) * self.uniform()
    }

    /// A uniformly distributed unit vector.
    pub fn direction(&mut self) -> Vec3 {
        crate::math::sampling::sample_uniform_sphere(self.uniform2())
    }

    /// A unit vector in the hemisphere around `n`.
    pub fn direction_around(&mut self, n: Vec3) -> Vec3 {
        let d = self.direction();
        if d.dot(n) < 0.0 {
            -d
        } else {
            d
        }
    }
}

use crate::math::Frame;
use crate::shapes::{Shape, ShapeSampleContext, ShapeStorage};

/// Mean and standard error of a list of values.
pub fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// The cone from `ctx.p` bounding a shape (its bounds' bounding sphere),
/// or the whole sphere of directions when `ctx.p` is inside that.
pub struct BoundingCone {
    pub axis: Vec3,
    pub cos_theta_max: f32,
    frame: Frame,
}

impl BoundingCone {
    pub fn new(shape: &Shape, storage: &ShapeStorage, ctx: &ShapeSampleContext) -> Self {
        let (center, radius) = shape.bounds(storage).bounding_sphere();
        let to_center = center - ctx.p;
        let distance = to_center.length();
        let (axis, cos_theta_max) = if distance <= radius * 1.0001 {
            (Vec3::Z, -1.0)
        } else {
            let sin = radius / distance;
            (to_center / distance, (1.0 - sin * sin).max(0.0).sqrt())
        };
        BoundingCone {
            axis,
            cos_theta_max,
            frame: Frame::from_z(axis),
        }
    }

    pub fn solid_angle(&self) -> f64 {
        2.0 * std::f64::consts::PI * (1.0 - self.cos_theta_max as f64)
    }

    /// A uniformly distributed direction in the cone.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let cos_theta = 1.0 - u.x * (1.0 - self.cos_theta_max);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * u.y;
        self.frame.from_local(Vec3::new(
            sin_theta * phi.cos(),
            sin_theta * phi.sin(),
            cos_theta,
        ))
    }

    /// A positive test function that varies across the cone by O(1), both
    /// radially and sideways: 1 + r + ½s, r ∈ [0, 1] the normalised angle
    /// from the axis, s ∈ [−1, 1] the normalised offset along the frame's x.
    pub fn test_function(&self, w: Vec3) -> f64 {
        let radial = (1.0 - w.dot(self.axis)) / (1.0 - self.cos_theta_max);
        let sin_theta_max = (1.0 - self.cos_theta_max * self.cos_theta_max)
            .max(0.0)
            .sqrt();
        let sideways = if self.cos_theta_max > 0.0 {
            w.dot(self.frame.x) / sin_theta_max
        } else {
            w.dot(self.frame.x)
        };
        1.0 + radial as f64 + 0.5 * sideways as f64
    }
}

/// Checks that every direction `sample_from` gives from `ctx` hits the
/// shape (bar a few through silhouettes and edges, which may miss by
/// rounding) and that, where the first hit is the sampled point,
/// `pdf_from` gives the sample's density. Returns 1/pdf and f(ω)/pdf per
/// sample (0 for failed samples).
pub fn check_sample_densities(
    shape: &Shape,
    storage: &ShapeStorage,
    ctx: &ShapeSampleContext,
    samples: usize,
    rng: &mut TestRng,
    f: impl Fn(Vec3) -> f64,
) -> (Vec<f64>, Vec<f64>) {
    let mut inverse_pdfs = Vec::with_capacity(samples);
    let mut weighted = Vec::with_capacity(samples);
    let mut compared = 0;
    let mut misses = 0;
    for i in 0..samples {
        let Some(sample) = shape.sample_from(storage, ctx, rng.uniform2()) else {
            inverse_pdfs.push(0.0);
            weighted.push(0.0);
            continue;
        };
        assert!(
            sample.pdf > 0.0 && sample.pdf.is_finite(),
            "sample {i}: pdf {}",
            sample.pdf
        );
        let wi = (sample.p - ctx.p).normalize();
        inverse_pdfs.push(1.0 / sample.pdf as f64);
        weighted.push(f(wi) / sample.pdf as f64);
        let Some(hit) = shape.intersect(storage, &ctx.spawn_ray(wi), f32::INFINITY) else {
            misses += 1;
            continue;
        };
        let scale = 1e-3 * (1.0 + sample.p.distance(ctx.p));
        if hit.interaction.p.distance(sample.p) < scale {
            let pdf = shape.pdf_from(storage, ctx, wi);
            assert!(
                (pdf - sample.pdf).abs() <= 2e-2 * sample.pdf,
                "sample {i}: pdf_from {pdf} vs sample pdf {}",
                sample.pdf
            );
            compared += 1;
        }
    }
    assert!(
        misses <= samples / 1000,
        "{misses} sampled directions miss the shape"
    );
    assert!(
        compared > samples / 2,
        "only {compared} samples were first hits"
    );
    (inverse_pdfs, weighted)
}

/// Checks `sample_from`/`pdf_from` of a shape seen from `ctx`:
/// - [`check_sample_densities`];
/// - E[1/pdf] (the Monte Carlo estimate of ∫ 1 dω) matches the analytic
///   solid angle `expected_solid_angle` within noise;
/// - the estimate of ∫ f dω for a test function f varying strongly across
///   the shape matches an estimate from directions uniform in a cone
///   bounding the shape (so the samples have the density they claim, not
///   just the right normalisation).
pub fn check_solid_angle_sampling(
    shape: &Shape,
    storage: &ShapeStorage,
    ctx: &ShapeSampleContext,
    expected_solid_angle: f32,
    seed: u64,
) {
    let mut rng = TestRng::new(seed);
    let cone = BoundingCone::new(shape, storage, ctx);
    let f = |w: Vec3| cone.test_function(w);
    let (inverse_pdfs, weighted) = check_sample_densities(shape, storage, ctx, 40_000, &mut rng, f);
    let (mean, error) = mean_and_error(&inverse_pdfs);
    let expected = expected_solid_angle as f64;
    assert!(
        (mean - expected).abs() <= 4.0 * error + 2e-3 * expected,
        "∫1 dω: {mean} ± {error}, expected {expected}"
    );

    // Reference ∫ f dω over the directions that hit the shape.
    let reference: Vec<f64> = (0..400_000)
        .map(|_| {
            let w = cone.sample(rng.uniform2());
            let hits = shape.intersect_p(storage, &ctx.spawn_ray(w), f32::INFINITY);
            if hits {
                cone.solid_angle() * f(w)
            } else {
                0.0
            }
        })
        .collect();
    let (reference_mean, reference_error) = mean_and_error(&reference);
    let (estimate, estimate_error) = mean_and_error(&weighted);
    let tolerance = 4.0 * (reference_error.hypot(estimate_error)) + 1e-3 * reference_mean;
    assert!(
        (estimate - reference_mean).abs() <= tolerance,
        "∫f dω: sampled {estimate} ± {estimate_error}, uniform {reference_mean} ± {reference_error}"
    );
}
