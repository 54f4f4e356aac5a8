//! Shared machinery for the BxDF tests: a seeded generator, quadrature
//! over the sphere, Monte Carlo estimates with standard errors, the
//! sampling-consistency check, and pbrt-v4's χ² goodness-of-fit test of a
//! sampling routine against its density.

use super::{BxDF, BxDFInterface, BxDFReflTransFlags, TransportMode, BSDF};
use crate::math::pcg32::Pcg32;
use crate::math::sampling::{sample_cosine_hemisphere, sample_uniform_sphere, UNIFORM_SPHERE_PDF};
use glam::{Vec2, Vec3};
use std::f64::consts::PI;

/// A seeded uniform source for tests (deterministic, so test outcomes are
/// reproducible).
pub struct Pcg32Source(Pcg32);

impl Pcg32Source {
    pub fn new(seed: u64) -> Self {
        Pcg32Source(Pcg32::new_with_seed(seed, 0x9e37_79b9_7f4a_7c15 ^ seed))
    }

    pub fn next_f32(&mut self) -> f32 {
        self.0.uniform_f32()
    }

    pub fn next_vec2(&mut self) -> Vec2 {
        let x = self.next_f32();
        Vec2::new(x, self.next_f32())
    }
}

/// Direction from spherical coordinates about +z.
pub fn spherical_direction(theta: f64, phi: f64) -> Vec3 {
    Vec3::new(
        (theta.sin() * phi.cos()) as f32,
        (theta.sin() * phi.sin()) as f32,
        theta.cos() as f32,
    )
}

/// ∫ f dω over the sphere by the midpoint rule on a θ×φ grid.
pub fn integrate_sphere(f: impl Fn(Vec3) -> f32, theta_res: usize, phi_res: usize) -> f32 {
    let d_theta = PI / theta_res as f64;
    let d_phi = 2.0 * PI / phi_res as f64;
    let mut sum = 0.0f64;
    for i in 0..theta_res {
        let theta = (i as f64 + 0.5) * d_theta;
        let mut ring = 0.0f64;
        for j in 0..phi_res {
            let phi = (j as f64 + 0.5) * d_phi;
            ring += f(spherical_direction(theta, phi)) as f64;
        }
        sum += ring * theta.sin();
    }
    (sum * d_theta * d_phi) as f32
}

/// A Monte Carlo mean with its standard error.
#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    pub mean: f64,
    pub std_error: f64,
}

/// Accumulates i.i.d. values into an [`Estimate`].
#[derive(Default)]
pub struct Accumulator {
    count: u64,
    sum: f64,
    sum_sq: f64,
}

impl Accumulator {
    pub fn add(&mut self, v: f64) {
        self.count += 1;
        self.sum += v;
        self.sum_sq += v * v;
    }

    pub fn estimate(&self) -> Estimate {
        let n = self.count as f64;
        let mean = self.sum / n;
        let variance = (self.sum_sq / n - mean * mean).max(0.0);
        Estimate {
            mean,
            std_error: (variance / n).sqrt(),
        }
    }
}

/// A render-space BSDF around a tilted frame whose tangent is not
/// orthogonal to the normal, so tests also exercise the frame handling.
pub fn tilted_bsdf(bxdf: BxDF) -> BSDF {
    let normal = Vec3::new(0.3, -0.5, 0.8).normalize();
    let tangent = Vec3::new(1.0, 0.2, 0.1);
    BSDF::new(normal, tangent, bxdf)
}

/// Outgoing directions for tests: cosine-distributed above the surface,
/// as pbrt's tests draw them, and optionally mirrored below it.
pub fn test_directions(rng: &mut Pcg32Source, count: usize, include_below: bool) -> Vec<Vec3> {
    (0..count)
        .map(|i| {
            let mut w = sample_cosine_hemisphere(rng.next_vec2());
            if include_below && i % 2 == 1 {
                w.z = -w.z;
            }
            w
        })
        .collect()
}

/// What [`sampling_consistency`] measured for one outgoing direction.
#[derive(Clone, Copy, Debug)]
pub struct ConsistencyReport {
    /// E[f |cos θi| / pdf] over `sample_f`, non-specular samples only
    /// (the part `f` can see).
    pub importance: Estimate,
    /// The same over specular samples only (zero for other samples).
    pub specular: Estimate,
    /// E[f |cos θi| / p_uniform] over uniformly distributed directions.
    pub uniform: Estimate,
    /// Largest |pdf() − sample pdf| / sample pdf over the samples.
    pub max_pdf_relative_error: f64,
    /// Largest |f() − sample f| / sample f over the samples.
    pub max_f_relative_error: f64,
    /// Samples whose pdf() disagreed with the sample's pdf by more than
    /// 1e-3 (relative).
    pub pdf_mismatches: usize,
    pub samples: usize,
}

impl ConsistencyReport {
    /// Difference of the two estimates in units of their combined
    /// standard error.
    pub fn z_score(&self) -> f64 {
        let se = (self.importance.std_error.powi(2) + self.uniform.std_error.powi(2)).sqrt();
        (self.importance.mean - self.uniform.mean).abs() / se.max(1e-12)
    }
}

/// Estimates ∫ f(ωo, ωi) |cos θi| dωi two ways — by importance sampling
/// with `sample_f` and by uniform sphere sampling with `f` — and compares
/// `pdf()` and `f()` with what each sample reported. Works on the average
/// over wavelengths.
pub fn sampling_consistency(
    bxdf: &impl BxDFInterface,
    wo: Vec3,
    mode: TransportMode,
    importance_samples: usize,
    uniform_samples: usize,
    rng: &mut Pcg32Source,
) -> ConsistencyReport {
    let mut importance = Accumulator::default();
    let mut specular = Accumulator::default();
    let mut max_pdf_relative_error = 0.0f64;
    let mut max_f_relative_error = 0.0f64;
    let mut pdf_mismatches = 0;
    for _ in 0..importance_samples {
        let uc = rng.next_f32();
        let u = rng.next_vec2();
        let sample = bxdf
            .sample_f(wo, uc, u, mode, BxDFReflTransFlags::All)
            .filter(|bs| bs.f.is_nonzero() && bs.pdf > 0.0);
        let Some(bs) = sample else {
            importance.add(0.0);
            specular.add(0.0);
            continue;
        };
        let weight = (bs.f.average() * bs.wi.z.abs() / bs.pdf) as f64;
        if bs.is_specular() {
            importance.add(0.0);
            specular.add(weight);
        } else {
            importance.add(weight);
            specular.add(0.0);
        }
        if !bs.pdf_is_proportional && !bs.is_specular() {
            let pdf = bxdf.pdf(wo, bs.wi, mode, BxDFReflTransFlags::All) as f64;
            let relative = (pdf - bs.pdf as f64).abs() / bs.pdf as f64;
            max_pdf_relative_error = max_pdf_relative_error.max(relative);
            if relative > 1e-3 {
                pdf_mismatches += 1;
            }
            let f = bxdf.f(wo, bs.wi, mode).average() as f64;
            let reference = bs.f.average() as f64;
            if reference > 0.0 {
                max_f_relative_error = max_f_relative_error.max((f - reference).abs() / reference);
            }
        }
    }
    let mut uniform = Accumulator::default();
    for _ in 0..uniform_samples {
        let wi = sample_uniform_sphere(rng.next_vec2());
        let f = bxdf.f(wo, wi, mode).average();
        uniform.add((f * wi.z.abs() / UNIFORM_SPHERE_PDF) as f64);
    }
    ConsistencyReport {
        importance: importance.estimate(),
        specular: specular.estimate(),
        uniform: uniform.estimate(),
        max_pdf_relative_error,
        max_f_relative_error,
        pdf_mismatches,
        samples: importance_samples,
    }
}

// ---------------------------------------------------------------------
// χ² goodness of fit (pbrt-v4's bsdfs_test.cpp, after Mitsuba's test).

/// θ bins of the frequency table; φ gets twice as many.
pub const CHI2_THETA_RES: usize = 80;
pub const CHI2_PHI_RES: usize = 2 * CHI2_THETA_RES;
/// Samples per table.
pub const CHI2_SAMPLE_COUNT: usize = 1_000_000;
/// Cells expecting fewer samples than this are pooled: the χ² statistic's
/// normal approximation fails for small expected counts.
pub const CHI2_MIN_EXPECTED: f64 = 5.0;
/// Rejection threshold before the Šidák correction.
pub const CHI2_SIGNIFICANCE: f64 = 0.01;

fn cell_index(w: Vec3) -> usize {
    let theta = (w.z.clamp(-1.0, 1.0) as f64).acos();
    let mut phi = (w.y as f64).atan2(w.x as f64);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let i = ((theta * CHI2_THETA_RES as f64 / PI) as usize).min(CHI2_THETA_RES - 1);
    let j = ((phi * CHI2_PHI_RES as f64 / (2.0 * PI)) as usize).min(CHI2_PHI_RES - 1);
    i * CHI2_PHI_RES + j
}

/// Histogram of non-specular sampled directions (local frame) over θ×φ
/// cells. `sample` gets (uc, u) and returns the direction, if any.
pub fn frequency_table(
    mut sample: impl FnMut(f32, Vec2) -> Option<Vec3>,
    rng: &mut Pcg32Source,
) -> Vec<f64> {
    let mut table = vec![0.0; CHI2_THETA_RES * CHI2_PHI_RES];
    for _ in 0..CHI2_SAMPLE_COUNT {
        let uc = rng.next_f32();
        let u = rng.next_vec2();
        if let Some(w) = sample(uc, u) {
            table[cell_index(w)] += 1.0;
        }
    }
    table
}

/// Expected counts per cell: the sample count times ∫cell pdf sin θ dθ dφ.
/// Densities have kinks and cliffs (e.g. where refraction stops being
/// possible), so each cell is integrated adaptively: 4×4-point
/// Gauss–Legendre on the cell, then on 2×2, 4×4, 8×8 sub-cells until two
/// successive refinements agree.
pub fn expected_table(pdf: impl Fn(Vec3) -> f32) -> Vec<f64> {
    let d_theta = PI / CHI2_THETA_RES as f64;
    let d_phi = 2.0 * PI / CHI2_PHI_RES as f64;
    let mut table = vec![0.0; CHI2_THETA_RES * CHI2_PHI_RES];
    for i in 0..CHI2_THETA_RES {
        for j in 0..CHI2_PHI_RES {
            let theta_range = (i as f64 * d_theta, (i + 1) as f64 * d_theta);
            let phi_range = (j as f64 * d_phi, (j + 1) as f64 * d_phi);
            let mut previous = integrate_cell(&pdf, theta_range, phi_range, 1);
            let mut splits = 2;
            let integral = loop {
                let refined = integrate_cell(&pdf, theta_range, phi_range, splits);
                let tolerance = 1e-4 * refined.abs().max(1.0 / CHI2_SAMPLE_COUNT as f64);
                if (refined - previous).abs() <= tolerance || splits >= 8 {
                    break refined;
                }
                previous = refined;
                splits *= 2;
            };
            table[i * CHI2_PHI_RES + j] = integral * CHI2_SAMPLE_COUNT as f64;
        }
    }
    table
}

/// ∫ pdf sin θ dθ dφ over a θ×φ rectangle split into `splits`² sub-cells,
/// each by 4×4-point Gauss–Legendre quadrature.
fn integrate_cell(
    pdf: &impl Fn(Vec3) -> f32,
    (theta0, theta1): (f64, f64),
    (phi0, phi1): (f64, f64),
    splits: usize,
) -> f64 {
    const NODES: [f64; 4] = [
        -0.861_136_311_594_052_6,
        -0.339_981_043_584_856_3,
        0.339_981_043_584_856_3,
        0.861_136_311_594_052_6,
    ];
    const WEIGHTS: [f64; 4] = [
        0.347_854_845_137_453_9,
        0.652_145_154_862_546_1,
        0.652_145_154_862_546_1,
        0.347_854_845_137_453_9,
    ];
    let h_theta = (theta1 - theta0) / splits as f64;
    let h_phi = (phi1 - phi0) / splits as f64;
    let mut sum = 0.0;
    for si in 0..splits {
        for sj in 0..splits {
            let theta_mid = theta0 + (si as f64 + 0.5) * h_theta;
            let phi_mid = phi0 + (sj as f64 + 0.5) * h_phi;
            for (a, wa) in NODES.iter().zip(WEIGHTS) {
                let theta = theta_mid + 0.5 * a * h_theta;
                for (b, wb) in NODES.iter().zip(WEIGHTS) {
                    let phi = phi_mid + 0.5 * b * h_phi;
                    sum += wa * wb * pdf(spherical_direction(theta, phi)) as f64 * theta.sin();
                }
            }
        }
    }
    sum * 0.25 * h_theta * h_phi
}

/// Outcome of a χ² test that did not reject.
#[derive(Clone, Copy, Debug)]
pub struct Chi2Outcome {
    pub statistic: f64,
    pub degrees_of_freedom: usize,
    pub p_value: f64,
    /// Per-test significance after the Šidák correction.
    pub threshold: f64,
}

/// Pearson's χ² test of observed against expected cell counts, pooling
/// low-expectation cells, with the significance level Šidák-corrected for
/// `test_count` tests. Err explains a rejection.
pub fn chi2_test(
    observed: &[f64],
    expected: &[f64],
    test_count: usize,
) -> Result<Chi2Outcome, String> {
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut pooled_observed, mut pooled_expected) = (0.0, 0.0);
    let mut statistic = 0.0;
    let mut cells = 0usize;
    for &c in &order {
        if expected[c] == 0.0 {
            // Samples where the density is zero. Rounding can put a few
            // there legitimately, so allow a tiny fraction.
            if observed[c] > CHI2_SAMPLE_COUNT as f64 * 1e-5 {
                return Err(format!(
                    "{} samples in a cell with expected frequency 0",
                    observed[c]
                ));
            }
        } else if expected[c] < CHI2_MIN_EXPECTED
            || (pooled_expected > 0.0 && pooled_expected < CHI2_MIN_EXPECTED)
        {
            pooled_observed += observed[c];
            pooled_expected += expected[c];
        } else {
            statistic += (observed[c] - expected[c]).powi(2) / expected[c];
            cells += 1;
        }
    }
    if pooled_expected > 0.0 || pooled_observed > 0.0 {
        statistic += (pooled_observed - pooled_expected).powi(2) / pooled_expected;
        cells += 1;
    }
    if cells < 2 {
        return Err(format!("too few degrees of freedom ({cells} cells)"));
    }
    let degrees_of_freedom = cells - 1;
    let p_value = chi2_survival(statistic, degrees_of_freedom);
    let threshold = 1.0 - (1.0 - CHI2_SIGNIFICANCE).powf(1.0 / test_count as f64);
    if !p_value.is_finite() || p_value < threshold {
        return Err(format!(
            "rejected: χ² = {statistic:.1}, dof = {degrees_of_freedom}, p = {p_value:.3e} < {threshold:.3e}"
        ));
    }
    Ok(Chi2Outcome {
        statistic,
        degrees_of_freedom,
        p_value,
        threshold,
    })
}

/// Runs the χ² test of a BSDF's non-specular sampling against its `pdf()`
/// for each outgoing direction (local frame), Šidák-corrected over them.
pub fn chi2_test_bsdf(
    bsdf: &BSDF,
    wos: &[Vec3],
    rng: &mut Pcg32Source,
) -> Result<Vec<Chi2Outcome>, String> {
    let mode = TransportMode::Radiance;
    let mut outcomes = Vec::new();
    for &wo_local in wos {
        let wo = bsdf.local_to_render(wo_local);
        let observed = frequency_table(
            |uc, u| {
                bsdf.sample_f(wo, uc, u, mode, BxDFReflTransFlags::All)
                    .filter(|bs| !bs.is_specular())
                    .map(|bs| bsdf.render_to_local(bs.wi))
            },
            rng,
        );
        let expected = expected_table(|wi| {
            bsdf.pdf(wo, bsdf.local_to_render(wi), mode, BxDFReflTransFlags::All)
        });
        let outcome = chi2_test(&observed, &expected, wos.len())
            .map_err(|e| format!("wo = {wo_local}: {e}"))?;
        outcomes.push(outcome);
    }
    Ok(outcomes)
}

/// Runs [`chi2_test_bsdf`], panicking with the reason on rejection, and
/// prints the statistics (visible with `--nocapture`).
pub fn assert_chi2_passes(name: &str, bsdf: &BSDF, wos: &[Vec3], rng: &mut Pcg32Source) {
    let outcomes = chi2_test_bsdf(bsdf, wos, rng).unwrap_or_else(|e| panic!("{name}: {e}"));
    for (wo, o) in wos.iter().zip(outcomes) {
        eprintln!(
            "χ² {name}, wo.z = {:.3}: χ² = {:.0}, dof = {}, p = {:.3} (reject below {:.4})",
            wo.z, o.statistic, o.degrees_of_freedom, o.p_value, o.threshold
        );
    }
}

/// P(X ≥ x) for X ~ χ² with `dof` degrees of freedom: the regularised
/// upper incomplete gamma function Q(dof/2, x/2).
pub fn chi2_survival(x: f64, dof: usize) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    regularized_upper_gamma(0.5 * dof as f64, 0.5 * x)
}

/// Q(a, x) = Γ(a, x)/Γ(a): by its power series for x < a + 1 and by a
/// continued fraction (modified Lentz) otherwise, both standard.
fn regularized_upper_gamma(a: f64, x: f64) -> f64 {
    let log_prefactor = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let mut term = 1.0 / a;
        let mut sum = term;
        let mut ap = a;
        for _ in 0..100_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        log_prefactor.exp() * h
    }
}

/// ln Γ(x) for x > 0 (Lanczos approximation, g = 7, n = 9).
fn ln_gamma(x: f64) -> f64 {
    const COEFFICIENTS: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection formula.
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut sum = COEFFICIENTS[0];
    for (i, c) in COEFFICIENTS.iter().enumerate().skip(1) {
        sum += c / (x + i as f64);
    }
    let t = x + 7.5;
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chi2_survival_matches_known_values() {
        // dof 2 has the closed form exp(−x/2).
        for x in [0.1, 1.0, 5.0, 20.0] {
            assert!((chi2_survival(x, 2) - (-0.5 * x).exp()).abs() < 1e-12);
        }
        // Table values: the 0.05 critical points.
        assert!((chi2_survival(3.841_458_8, 1) - 0.05).abs() < 1e-6);
        assert!((chi2_survival(18.307_038, 10) - 0.05).abs() < 1e-6);
        assert!((chi2_survival(124.342_11, 100) - 0.05).abs() < 1e-6);
        // Large dof: the mean is the median-ish; Q(dof) ≈ 0.5 − small.
        let q = chi2_survival(5000.0, 5000);
        assert!((q - 0.4973).abs() < 1e-3, "{q}");
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-12);
        assert!((ln_gamma(10.0) - 362_880f64.ln()).abs() < 1e-10);
    }

    #[test]
    fn chi2_rejects_a_sampler_that_does_not_match_its_density() {
        // Negative control: cosine-hemisphere samples tested against a
        // cos^1.1 density (renormalised) must be rejected; against the
        // right density they must pass.
        let mut rng = Pcg32Source::new(3);
        let sample = |_: f32, u: Vec2| Some(sample_cosine_hemisphere(u));
        let observed = frequency_table(sample, &mut rng);
        let right = expected_table(|w| w.z.max(0.0) / std::f32::consts::PI);
        assert!(chi2_test(&observed, &right, 1).is_ok());
        let normalisation = 2.1 / (2.0 * std::f32::consts::PI);
        let wrong = expected_table(|w| w.z.max(0.0).powf(1.1) * normalisation);
        let outcome = chi2_test(&observed, &wrong, 1);
        assert!(outcome.is_err(), "{outcome:?}");
    }
}
