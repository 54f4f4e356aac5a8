//! pbrt-v4's hair BSDF (Chiang et al. 2016, "A Practical and Controllable
//! Hair and Fur Model for Production Path Tracing"): a rough dielectric
//! cylinder, scattering split into lobes p = 0 (R), 1 (TT), 2 (TRT) and a
//! residual for p ≥ 3, each a product of a longitudinal term M_p, an
//! attenuation A_p and an azimuthal term N_p.
//!
//! Local frame: x along the fibre (so sin θ = ω.x), y across the fibre's
//! projected width, z the surface normal; azimuth φ = atan2(ω.z, ω.y).
//! `h` ∈ [−1, 1] is where the ray crossed the fibre's width.

use super::fresnel::fr_dielectric;
use super::{BSDFSample, BxDFFlags, BxDFInterface, BxDFReflTransFlags};
use crate::math::{safe_asin, safe_sqrt, sqr};
use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Lobes evaluated explicitly; higher orders form the residual lobe.
pub const P_MAX: usize = 3;

/// √(π/8), from the logistic's variance.
const SQRT_PI_OVER_8: f32 = 0.626_657_07;

/// What [`HairBxDF`] derives from β_m, β_n and α alone: the same at every
/// hit of a material whose roughness and tilt are constant (pbrt-v4
/// recomputes them per hit: two exponentials per logistic bound, a sinh or
/// a log per lobe, a sine; about a third of the BxDF's making).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairLobes {
    /// M_p of R, TT and TRT: the variance v_p and the terms that follow
    /// from it (the residual shares TRT's; see [`HairBxDF::m`]).
    longitudinal: [Longitudinal; P_MAX],
    /// N_p's trimmed logistic.
    pub(crate) azimuthal: TrimmedLogistic,
    /// sin and cos of 2^k α, k = 0, 1, 2 (cuticle tilt shifts).
    sin_2k_alpha: [f32; 3],
    cos_2k_alpha: [f32; 3],
}

impl HairLobes {
    /// `beta_m`, `beta_n`: longitudinal and azimuthal roughness in [0, 1];
    /// `alpha_degrees`: cuticle tilt.
    pub fn new(beta_m: f32, beta_n: f32, alpha_degrees: f32) -> Self {
        let v0 = sqr(0.726 * beta_m + 0.812 * sqr(beta_m) + 3.7 * beta_m.powi(20));
        // R, TT, TRT; the residual's is TRT's.
        let v = [v0, 0.25 * v0, 4.0 * v0];
        let s = SQRT_PI_OVER_8 * (0.265 * beta_n + 1.194 * sqr(beta_n) + 5.372 * beta_n.powi(22));
        let mut sin_2k_alpha = [0.0; 3];
        let mut cos_2k_alpha = [0.0; 3];
        sin_2k_alpha[0] = alpha_degrees.to_radians().sin();
        cos_2k_alpha[0] = safe_sqrt(1.0 - sqr(sin_2k_alpha[0]));
        for i in 1..3 {
            sin_2k_alpha[i] = 2.0 * cos_2k_alpha[i - 1] * sin_2k_alpha[i - 1];
            cos_2k_alpha[i] = sqr(cos_2k_alpha[i - 1]) - sqr(sin_2k_alpha[i - 1]);
        }
        HairLobes {
            longitudinal: v.map(Longitudinal::new),
            azimuthal: TrimmedLogistic::new(s),
            sin_2k_alpha,
            cos_2k_alpha,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairBxDF {
    /// Offset across the fibre, −1…1.
    pub h: f32,
    /// Index of refraction of the fibre interior.
    pub eta: f32,
    /// Absorption coefficient inside the fibre (per unit diameter).
    pub sigma_a: SampledSpectrum,
    /// The roughness and tilt terms.
    lobes: HairLobes,
}

/// A sampled direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairSample {
    pub f: SampledSpectrum,
    pub wi: Vec3,
    pub pdf: f32,
}

/// Modified Bessel function of the first kind, order 0 (series).
fn i0(x: f32) -> f32 {
    let mut val = 0.0;
    let mut x2i = 1.0;
    let mut ifact: i64 = 1;
    let mut i4 = 1.0f32;
    for i in 0..10 {
        if i > 1 {
            ifact *= i;
        }
        val += x2i / (i4 * sqr(ifact as f32));
        x2i *= x * x;
        i4 *= 4.0;
    }
    val
}

/// log I₀(x), with the asymptotic form for large x (I₀ overflows).
fn log_i0(x: f32) -> f32 {
    if x > 12.0 {
        x + 0.5 * (-(2.0 * PI).ln() + (1.0 / x).ln() + 1.0 / (8.0 * x))
    } else {
        i0(x).ln()
    }
}

/// Longitudinal scattering M_p (d'Eon et al. 2011) for one variance v,
/// with the log form for low variance where the direct one overflows.
/// The terms that depend on v alone are computed once per BxDF: pbrt-v4
/// evaluates sinh(1/v) (or ln(1/2v)) in every call, a fifth of a hair path
/// vertex. Values are bit-identical to the per-call form (the same
/// expressions in the same order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Longitudinal {
    pub(crate) v: f32,
    /// ln(1/(2v)) for the log form (v ≤ 0.1), else sinh(1/v)·2v.
    constant: f32,
}

impl Longitudinal {
    pub(crate) fn new(v: f32) -> Self {
        let constant = if v <= 0.1 {
            (1.0 / (2.0 * v)).ln()
        } else {
            (1.0 / v).sinh() * 2.0 * v
        };
        Longitudinal { v, constant }
    }

    #[inline]
    pub(crate) fn eval(
        &self,
        cos_theta_i: f32,
        cos_theta_o: f32,
        sin_theta_i: f32,
        sin_theta_o: f32,
    ) -> f32 {
        let v = self.v;
        let a = cos_theta_i * cos_theta_o / v;
        let b = sin_theta_i * sin_theta_o / v;
        if v <= 0.1 {
            (log_i0(a) - b - 1.0 / v + std::f32::consts::LN_2 + self.constant).exp()
        } else {
            ((-b).exp() * i0(a)) / self.constant
        }
    }
}

/// Attenuations A_0…A_pMax, the last being the residual of all higher
/// orders (a geometric series).
fn ap(cos_theta_o: f32, eta: f32, h: f32, t: SampledSpectrum) -> [SampledSpectrum; P_MAX + 1] {
    let cos_gamma_o = safe_sqrt(1.0 - h * h);
    let f = fr_dielectric(cos_theta_o * cos_gamma_o, eta);
    let mut a = [SampledSpectrum::ZERO; P_MAX + 1];
    a[0] = SampledSpectrum::splat(f);
    a[1] = t * sqr(1.0 - f);
    for p in 2..P_MAX {
        a[p] = a[p - 1] * t * f;
    }
    let denom = SampledSpectrum::ONE - t * f;
    a[P_MAX] = (a[P_MAX - 1] * t * f).safe_div(denom);
    a
}

/// Net azimuthal deflection of lobe p.
fn phi(p: usize, gamma_o: f32, gamma_t: f32) -> f32 {
    2.0 * p as f32 * gamma_t - 2.0 * gamma_o + p as f32 * PI
}

pub(crate) fn logistic(x: f32, s: f32) -> f32 {
    let x = x.abs();
    let e = (-x / s).exp();
    e / (s * sqr(1.0 + e))
}

fn logistic_cdf(x: f32, s: f32) -> f32 {
    1.0 / (1.0 + (-x / s).exp())
}

/// The logistic of scale s restricted to [−π, π] and renormalised, with its
/// normalisation (its mass there and its CDF at −π) computed once: pbrt-v4
/// recomputes it, two exponentials, in every evaluation and sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrimmedLogistic {
    pub(crate) s: f32,
    mass: f32,
    cdf_low: f32,
}

impl TrimmedLogistic {
    pub(crate) fn new(s: f32) -> Self {
        TrimmedLogistic {
            s,
            mass: logistic_cdf(PI, s) - logistic_cdf(-PI, s),
            cdf_low: logistic_cdf(-PI, s),
        }
    }

    /// The density at x ∈ [−π, π].
    pub(crate) fn density(&self, x: f32) -> f32 {
        logistic(x, self.s) / self.mass
    }

    /// Samples [`TrimmedLogistic::density`]: its CDF inverted.
    pub(crate) fn sample(&self, u: f32) -> f32 {
        let x = -self.s * (1.0 / (u * self.mass + self.cdf_low) - 1.0).ln();
        x.clamp(-PI, PI)
    }
}

/// The logistic restricted to [a, b] and renormalised.
pub(crate) fn trimmed_logistic(x: f32, s: f32, a: f32, b: f32) -> f32 {
    logistic(x, s) / (logistic_cdf(b, s) - logistic_cdf(a, s))
}

/// An angle into [−π, π] (a bounded loop: angles here come from atan2
/// differences and sums).
pub(crate) fn wrap_angle(mut x: f32) -> f32 {
    if !x.is_finite() || x.abs() > 64.0 {
        // Not a sum of a few angles (and ∞ would never leave the loop).
        return (x + PI).rem_euclid(2.0 * PI) - PI;
    }
    while x > PI {
        x -= 2.0 * PI;
    }
    while x < -PI {
        x += 2.0 * PI;
    }
    x
}

/// A hair BSDF's value divided by |cos θ_i| (ωi's z in the hair frame),
/// as pbrt-v4's is, so that the integrator's cosine cancels.
#[inline]
pub(crate) fn divide_by_cos(f: SampledSpectrum, wi: Vec3) -> SampledSpectrum {
    let cos_wi = wi.z.abs();
    if cos_wi > 0.0 {
        f / cos_wi
    } else {
        f
    }
}

/// Picks lobe p with probability `pdf[p]` and remaps `uc` to [0, 1)
/// within its interval (so it can drive the lobe's azimuth).
pub(crate) fn choose_lobe(pdf: &[f32; P_MAX + 1], uc: f32) -> (usize, f32) {
    let mut p = 0;
    let mut acc = 0.0;
    loop {
        if p == P_MAX || uc < acc + pdf[p] {
            let width = pdf[p].max(f32::MIN_POSITIVE);
            return (p, ((uc - acc) / width).clamp(0.0, 1.0 - f32::EPSILON / 2.0));
        }
        acc += pdf[p];
        p += 1;
    }
}

/// Samples θ_i from M_p of variance v around the (tilted) θ_o
/// (d'Eon et al. 2013's sampling, as pbrt): returns (sin θ_i, cos θ_i).
pub(crate) fn sample_longitudinal(u: Vec2, v: f32, sin_o: f32, cos_o: f32) -> (f32, f32) {
    let cos_theta = 1.0 + v * (u.x.max(1e-5) + (1.0 - u.x) * (-2.0 / v).exp()).ln();
    let sin_theta = safe_sqrt(1.0 - sqr(cos_theta));
    let cos_phi = (2.0 * PI * u.y).cos();
    let sin_theta_i = (-cos_theta * sin_o + sin_theta * cos_phi * cos_o).clamp(-1.0, 1.0);
    (sin_theta_i, safe_sqrt(1.0 - sqr(sin_theta_i)))
}

/// What f, pdf and sampling need that depends on ω_o alone: its angles,
/// the refracted azimuth, each lobe's tilted θ_o, the attenuations and the
/// lobe probabilities.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Outgoing {
    sin_theta_o: f32,
    cos_theta_o: f32,
    phi_o: f32,
    gamma_o: f32,
    gamma_t: f32,
    /// (sin θ_o, cos θ_o) tilted for lobe p (untilted for the residual).
    tilted: [(f32, f32); P_MAX + 1],
    /// A_0…A_pMax.
    a: [SampledSpectrum; P_MAX + 1],
    /// Probabilities of choosing each lobe.
    ap_pdf: [f32; P_MAX + 1],
}

/// Lobe probabilities: A_p averaged over wavelengths, normalised.
fn ap_pdf(a: &[SampledSpectrum; P_MAX + 1]) -> [f32; P_MAX + 1] {
    let y: [f32; P_MAX + 1] = std::array::from_fn(|i| a[i].average());
    let sum: f32 = y.iter().sum();
    if sum <= 0.0 {
        return [0.25; P_MAX + 1];
    }
    y.map(|v| v / sum)
}

impl HairBxDF {
    /// `beta_m`, `beta_n`: longitudinal and azimuthal roughness in [0, 1];
    /// `alpha_degrees`: cuticle tilt.
    pub fn new(
        h: f32,
        eta: f32,
        sigma_a: SampledSpectrum,
        beta_m: f32,
        beta_n: f32,
        alpha_degrees: f32,
    ) -> Self {
        Self::from_lobes(
            h,
            eta,
            sigma_a,
            &HairLobes::new(beta_m, beta_n, alpha_degrees),
        )
    }

    /// The BxDF at offset h with the roughness and tilt terms of `lobes`
    /// (which a material with constant roughness and tilt makes once).
    pub fn from_lobes(h: f32, eta: f32, sigma_a: SampledSpectrum, lobes: &HairLobes) -> Self {
        HairBxDF {
            h,
            eta,
            sigma_a,
            lobes: *lobes,
        }
    }

    /// M_p of lobe p (0…P_MAX; the residual's variance is TRT's).
    #[inline]
    pub(crate) fn m(&self, p: usize) -> &Longitudinal {
        &self.lobes.longitudinal[p.min(P_MAX - 1)]
    }

    /// pbrt-v4's trimmed logistic on [−π, π] with scale s, its
    /// normalisation computed once (the same value bit for bit).
    pub(crate) fn azimuthal_logistic(&self, x: f32) -> f32 {
        self.lobes.azimuthal.density(x)
    }

    /// Samples [`HairBxDF::azimuthal_logistic`].
    pub(crate) fn sample_azimuthal_logistic(&self, u: f32) -> f32 {
        self.lobes.azimuthal.sample(u)
    }

    /// Azimuthal scattering N_p around lobe p's deflection.
    fn np(&self, phi_: f32, p: usize, gamma_o: f32, gamma_t: f32) -> f32 {
        self.azimuthal_logistic(wrap_angle(phi_ - phi(p, gamma_o, gamma_t)))
    }

    fn outgoing(&self, wo: Vec3) -> Outgoing {
        let sin_theta_o = wo.x;
        let cos_theta_o = safe_sqrt(1.0 - sqr(sin_theta_o));
        let phi_o = wo.z.atan2(wo.y);
        let gamma_o = safe_asin(self.h);
        // The refracted ray, in the modified index η' (Bravais) of the
        // projection into the normal plane.
        let sin_theta_t = sin_theta_o / self.eta;
        let cos_theta_t = safe_sqrt(1.0 - sqr(sin_theta_t));
        let etap = safe_sqrt(sqr(self.eta) - sqr(sin_theta_o)) / cos_theta_o;
        let sin_gamma_t = self.h / etap;
        let cos_gamma_t = safe_sqrt(1.0 - sqr(sin_gamma_t));
        let gamma_t = safe_asin(sin_gamma_t);
        // Transmittance of one chord through the fibre.
        let t = (-self.sigma_a * (2.0 * cos_gamma_t / cos_theta_t)).exp();
        let a = ap(cos_theta_o, self.eta, self.h, t);
        Outgoing {
            sin_theta_o,
            cos_theta_o,
            phi_o,
            gamma_o,
            gamma_t,
            tilted: std::array::from_fn(|p| self.tilted(p, sin_theta_o, cos_theta_o)),
            a,
            ap_pdf: ap_pdf(&a),
        }
    }

    /// sin θ_o, cos θ_o rotated by the cuticle tilt for lobe p (R tilts by
    /// −2α, TT by α, TRT by 4α).
    pub(crate) fn tilted(&self, p: usize, sin_theta_o: f32, cos_theta_o: f32) -> (f32, f32) {
        let (s, c) = match p {
            0 => (
                sin_theta_o * self.lobes.cos_2k_alpha[1] - cos_theta_o * self.lobes.sin_2k_alpha[1],
                cos_theta_o * self.lobes.cos_2k_alpha[1] + sin_theta_o * self.lobes.sin_2k_alpha[1],
            ),
            1 => (
                sin_theta_o * self.lobes.cos_2k_alpha[0] + cos_theta_o * self.lobes.sin_2k_alpha[0],
                cos_theta_o * self.lobes.cos_2k_alpha[0] - sin_theta_o * self.lobes.sin_2k_alpha[0],
            ),
            2 => (
                sin_theta_o * self.lobes.cos_2k_alpha[2] + cos_theta_o * self.lobes.sin_2k_alpha[2],
                cos_theta_o * self.lobes.cos_2k_alpha[2] - sin_theta_o * self.lobes.sin_2k_alpha[2],
            ),
            _ => (sin_theta_o, cos_theta_o),
        };
        // The tilt can push cos θ below zero near grazing angles.
        (s, c.abs())
    }

    /// f(ωo, ωi): the BSDF value (already divided by |cos θ_i|, as pbrt-v4
    /// does, so that the integrator's cosine cancels).
    pub fn value(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        self.value_at(&self.outgoing(wo), wi)
    }

    fn value_at(&self, o: &Outgoing, wi: Vec3) -> SampledSpectrum {
        self.value_and_density_at(o, wi).0
    }

    fn value_and_density_at(&self, o: &Outgoing, wi: Vec3) -> (SampledSpectrum, f32) {
        let sin_theta_i = wi.x;
        let cos_theta_i = safe_sqrt(1.0 - sqr(sin_theta_i));
        let phi_i = wi.z.atan2(wi.y);
        let (f, pdf) = self.lobes_at(o, sin_theta_i, cos_theta_i, phi_i - o.phi_o);
        (divide_by_cos(f, wi), pdf)
    }

    /// The lobes at ωi (θ_i by its sine and cosine, Δφ = φ_i − φ_o): the
    /// value Σ_p A_p M_p N_p (before the division by |cos θ_i|) and the
    /// density Σ_p (A_p / Σ A) M_p N_p, sharing each lobe's M_p and N_p (a
    /// sample needs both).
    fn lobes_at(
        &self,
        o: &Outgoing,
        sin_theta_i: f32,
        cos_theta_i: f32,
        dphi: f32,
    ) -> (SampledSpectrum, f32) {
        let mut fsum = SampledSpectrum::ZERO;
        let mut pdf = 0.0;
        for p in 0..P_MAX {
            let (sin_o, cos_o) = o.tilted[p];
            let m = self.m(p).eval(cos_theta_i, cos_o, sin_theta_i, sin_o);
            let n = self.np(dphi, p, o.gamma_o, o.gamma_t);
            fsum += o.a[p] * (m * n);
            pdf += m * o.ap_pdf[p] * n;
        }
        let m = self
            .m(P_MAX)
            .eval(cos_theta_i, o.cos_theta_o, sin_theta_i, o.sin_theta_o);
        fsum += o.a[P_MAX] * (m / (2.0 * PI));
        pdf += m * o.ap_pdf[P_MAX] / (2.0 * PI);
        (fsum, pdf)
    }

    /// Samples ωi: a lobe by its attenuation, θ_i from M_p, Δφ from N_p.
    /// `uc` picks the lobe (and is reused, rescaled, for N_p); `u` drives
    /// M_p.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<HairSample> {
        self.sample_at(&self.outgoing(wo), uc, u)
    }

    fn sample_at(&self, o: &Outgoing, uc: f32, u: Vec2) -> Option<HairSample> {
        let (p, uc) = choose_lobe(&o.ap_pdf, uc);
        let (sin_o, cos_o) = o.tilted[p];
        let (sin_theta_i, cos_theta_i) = sample_longitudinal(u, self.m(p).v, sin_o, cos_o);
        let dphi = if p < P_MAX {
            phi(p, o.gamma_o, o.gamma_t) + self.sample_azimuthal_logistic(uc)
        } else {
            2.0 * PI * uc
        };
        let phi_i = o.phi_o + dphi;
        let wi = Vec3::new(
            sin_theta_i,
            cos_theta_i * phi_i.cos(),
            cos_theta_i * phi_i.sin(),
        );
        let (f, pdf) = self.lobes_at(o, sin_theta_i, cos_theta_i, dphi);
        if !(pdf > 0.0) || !pdf.is_finite() {
            return None;
        }
        Some(HairSample {
            f: divide_by_cos(f, wi),
            wi,
            pdf,
        })
    }

    /// Solid-angle density with which [`Self::sample`] picks ωi.
    pub fn density(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.density_at(&self.outgoing(wo), wi)
    }

    fn density_at(&self, o: &Outgoing, wi: Vec3) -> f32 {
        self.value_and_density_at(o, wi).1
    }

    /// σ_a from eumelanin and pheomelanin concentrations, in linear sRGB
    /// (pbrt-v4's per-unit-concentration absorption of the two pigments).
    pub fn sigma_a_from_concentration(eumelanin: f32, pheomelanin: f32) -> [f32; 3] {
        const EUMELANIN: [f32; 3] = [0.419, 0.697, 1.37];
        const PHEOMELANIN: [f32; 3] = [0.187, 0.4, 1.05];
        std::array::from_fn(|i| eumelanin * EUMELANIN[i] + pheomelanin * PHEOMELANIN[i])
    }

    /// σ_a that gives a fibre of the given multiple-scattering colour
    /// (Chiang et al.'s fitted inverse, per wavelength).
    pub fn sigma_a_from_reflectance(c: SampledSpectrum, beta_n: f32) -> SampledSpectrum {
        let denom = 5.969 - 0.215 * beta_n + 2.532 * sqr(beta_n) - 10.73 * beta_n.powi(3)
            + 5.574 * beta_n.powi(4)
            + 0.245 * beta_n.powi(5);
        c.map(|ci| sqr(ci.max(1e-6).ln() / denom))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::sampling::{sample_uniform_sphere, UNIFORM_SPHERE_PDF};

    /// The crate's PCG32, with the draws these tests need.
    struct Rng(crate::math::pcg32::Pcg32);
    impl Rng {
        fn new(seed: u64) -> Self {
            Rng(crate::math::pcg32::Pcg32::new(seed))
        }
        fn f(&mut self) -> f32 {
            self.0.uniform_f32()
        }
        fn v2(&mut self) -> Vec2 {
            Vec2::new(self.f(), self.f())
        }
    }

    fn lossless(h: f32, beta_m: f32, beta_n: f32) -> HairBxDF {
        HairBxDF::new(h, 1.55, SampledSpectrum::ZERO, beta_m, beta_n, 0.0)
    }

    /// White furnace with σa = 0 (pbrt-v4's test): ∫ f |cos θi| dωi over the
    /// sphere is 1, estimated with uniform directions, for a grid of
    /// roughnesses.
    #[test]
    fn white_furnace_uniform() {
        let mut rng = Rng::new(0x1234_5678);
        let mut worst: f32 = 0.0;
        for bm in [0.1f32, 0.3, 0.5, 0.7, 0.9, 1.0] {
            for bn in [0.1f32, 0.3, 0.5, 0.7, 0.9, 1.0] {
                let wo = sample_uniform_sphere(rng.v2());
                let n = 300_000;
                let mut sum = 0.0f64;
                for _ in 0..n {
                    let h = -1.0 + 2.0 * rng.f();
                    let bxdf = lossless(h, bm, bn);
                    let wi = sample_uniform_sphere(rng.v2());
                    sum += (bxdf.value(wo, wi)[0] * wi.z.abs() / UNIFORM_SPHERE_PDF) as f64;
                }
                let avg = (sum / n as f64) as f32;
                worst = worst.max((avg - 1.0).abs());
                assert!((0.95..=1.05).contains(&avg), "β_m {bm} β_n {bn}: {avg}");
            }
        }
        eprintln!("white furnace (uniform): worst |E − 1| = {worst:.4}");
    }

    /// The same with the BSDF's own sampling: within 1 %.
    #[test]
    fn white_furnace_sampled() {
        let mut rng = Rng::new(0xdead_beef);
        for bm in [0.1f32, 0.4, 0.7, 1.0] {
            for bn in [0.1f32, 0.4, 0.7, 1.0] {
                let wo = sample_uniform_sphere(rng.v2());
                let n = 100_000;
                let mut sum = 0.0f64;
                for _ in 0..n {
                    let h = -1.0 + 2.0 * rng.f();
                    let bxdf = lossless(h, bm, bn);
                    if let Some(s) = bxdf.sample(wo, rng.f(), rng.v2()) {
                        sum += (s.f[0] * s.wi.z.abs() / s.pdf) as f64;
                    }
                }
                let avg = sum / n as f64;
                assert!((0.99..=1.01).contains(&avg), "β_m {bm} β_n {bn}: {avg}");
            }
        }
    }

    /// With σa = 0 the sampling is exact: every sample's weight
    /// f |cos θi| / pdf is 1 (pbrt-v4's test), to within (0.99, 1.01).
    #[test]
    fn sampling_weights_are_one_when_lossless() {
        let mut rng = Rng::new(42);
        for bm in [0.1f32, 0.4, 0.7, 1.0] {
            for bn in [0.1f32, 0.4, 0.7, 1.0] {
                for _ in 0..2000 {
                    let bxdf = lossless(-1.0 + 2.0 * rng.f(), bm, bn);
                    let wo = sample_uniform_sphere(rng.v2());
                    if let Some(s) = bxdf.sample(wo, rng.f(), rng.v2()) {
                        let w = s.f[0] * s.wi.z.abs() / s.pdf;
                        assert!(w > 0.99 && w < 1.01, "β_m {bm} β_n {bn}: weight {w}");
                    }
                }
            }
        }
    }

    /// Importance-sampled and uniform estimates of ∫ f |cos| agree with
    /// absorption present (pbrt-v4's sampling-consistency test), and pdf()
    /// matches the density sample_f reports.
    #[test]
    fn sampling_consistency_and_pdf() {
        let mut rng = Rng::new(7);
        let sigma_a = SampledSpectrum([0.25, 0.5, 1.0, 2.0]);
        for bm in [0.2f32, 0.5, 0.9] {
            for bn in [0.2f32, 0.5, 0.9] {
                let wo = sample_uniform_sphere(rng.v2());
                let n = 200_000;
                let (mut importance, mut uniform) = (0.0f64, 0.0f64);
                for _ in 0..n {
                    let h = -1.0 + 2.0 * rng.f();
                    let bxdf = HairBxDF::new(h, 1.55, sigma_a, bm, bn, 2.0);
                    if let Some(s) = bxdf.sample(wo, rng.f(), rng.v2()) {
                        importance += (s.f.average() * s.wi.z.abs() / s.pdf) as f64;
                        // A sample rounded onto the fibre's axis (sin θ =
                        // ±1 in f32) has no azimuth: pdf() takes φ = 0 and
                        // the sample the φ it drew (pbrt-v4 alike).
                        let on_axis = s.wi.y == 0.0 && s.wi.z == 0.0;
                        let p = bxdf.density(wo, s.wi);
                        assert!(
                            on_axis || (p - s.pdf).abs() <= 1e-3 * s.pdf.max(1.0),
                            "pdf {p} vs {} at wi {}",
                            s.pdf,
                            s.wi
                        );
                    }
                    let wi = sample_uniform_sphere(rng.v2());
                    uniform +=
                        (bxdf.value(wo, wi).average() * wi.z.abs() / UNIFORM_SPHERE_PDF) as f64;
                }
                let (a, b) = (importance / n as f64, uniform / n as f64);
                assert!((a - b).abs() / b < 0.05, "β_m {bm} β_n {bn}: {a} vs {b}");
            }
        }
    }

    /// Chi-square goodness of fit of sample_f against pdf() over a θ × φ
    /// grid of the sphere.
    #[test]
    fn chi_square_sampling_matches_pdf() {
        let mut rng = Rng::new(99);
        let (n_theta, n_phi) = (16usize, 32usize);
        for (bm, bn, h) in [(0.3f32, 0.3f32, 0.2f32), (0.6, 0.8, -0.7), (0.15, 0.4, 0.9)] {
            let bxdf = HairBxDF::new(h, 1.55, SampledSpectrum([0.3, 0.5, 0.8, 1.2]), bm, bn, 2.0);
            let wo = Vec3::new(0.3, 0.5, (1.0f32 - 0.09 - 0.25).sqrt());
            let n = 400_000;
            let mut observed = vec![0.0f64; n_theta * n_phi];
            for _ in 0..n {
                if let Some(s) = bxdf.sample(wo, rng.f(), rng.v2()) {
                    let theta = s.wi.z.clamp(-1.0, 1.0).acos();
                    let mut ph = s.wi.y.atan2(s.wi.x);
                    if ph < 0.0 {
                        ph += 2.0 * PI;
                    }
                    let ti = ((theta / PI) * n_theta as f32).min(n_theta as f32 - 1.0) as usize;
                    let pi = ((ph / (2.0 * PI)) * n_phi as f32).min(n_phi as f32 - 1.0) as usize;
                    observed[ti * n_phi + pi] += 1.0;
                }
            }
            // Expected counts: integrate pdf over each cell (8×8 subcells).
            let mut expected = vec![0.0f64; n_theta * n_phi];
            let sub = 8;
            for ti in 0..n_theta {
                for pi in 0..n_phi {
                    let mut acc = 0.0f64;
                    for a in 0..sub {
                        for b in 0..sub {
                            let theta =
                                (ti as f32 + (a as f32 + 0.5) / sub as f32) * PI / n_theta as f32;
                            let ph = (pi as f32 + (b as f32 + 0.5) / sub as f32) * 2.0 * PI
                                / n_phi as f32;
                            let wi = Vec3::new(
                                theta.sin() * ph.cos(),
                                theta.sin() * ph.sin(),
                                theta.cos(),
                            );
                            let d_omega =
                                theta.sin() * (PI / n_theta as f32) * (2.0 * PI / n_phi as f32)
                                    / (sub * sub) as f32;
                            acc += (bxdf.density(wo, wi) * d_omega) as f64;
                        }
                    }
                    expected[ti * n_phi + pi] = acc * n as f64;
                }
            }
            // Pool cells with small expectations, then χ².
            let (mut chi2, mut dof, mut pool_o, mut pool_e) = (0.0f64, 0i64, 0.0f64, 0.0f64);
            for (o, e) in observed.iter().zip(&expected) {
                if *e < 5.0 {
                    pool_o += o;
                    pool_e += e;
                } else {
                    chi2 += (o - e) * (o - e) / e;
                    dof += 1;
                }
            }
            if pool_e > 0.0 {
                chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
                dof += 1;
            }
            dof -= 1;
            // Wilson–Hilferty: p < 1e-3 corresponds to z > 3.09.
            let k = dof as f64;
            let z =
                ((chi2 / k).powf(1.0 / 3.0) - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
            assert!(
                z < 3.09,
                "β_m {bm} β_n {bn} h {h}: χ² = {chi2:.1} with {dof} dof (z = {z:.2})"
            );
        }
    }

    #[test]
    fn extreme_h_and_angles_are_finite() {
        for h in [-1.0f32, -0.999_999, 0.0, 0.999_999, 1.0] {
            let b = HairBxDF::new(h, 1.55, SampledSpectrum::splat(0.5), 0.3, 0.3, 2.0);
            for wo in [
                Vec3::X,
                -Vec3::X,
                Vec3::new(0.999_999, 0.0, 0.001).normalize(),
                Vec3::Z,
                Vec3::Y,
            ] {
                for wi in [Vec3::X, -Vec3::Z, Vec3::new(0.3, 0.4, 0.866)] {
                    let f = b.value(wo, wi);
                    assert!(
                        f.0.iter().all(|v| v.is_finite() && *v >= 0.0),
                        "h {h} wo {wo} wi {wi}: {f:?}"
                    );
                    assert!(b.density(wo, wi).is_finite());
                }
                if let Some(s) = b.sample(wo, 0.5, Vec2::new(0.3, 0.7)) {
                    assert!(
                        s.f.0.iter().all(|v| v.is_finite())
                            && s.pdf.is_finite()
                            && s.wi.is_finite()
                    );
                }
            }
        }
    }

    /// The BxDF made for ω_o gives f, pdf and sample_f bit for bit equal
    /// to the uncached [`HairBxDF`], for its own ω_o (state stored) and for
    /// another ω_o (state recomputed).
    #[test]
    fn stored_outgoing_state_changes_nothing() {
        use super::super::{BxDF, BxDFReflTransFlags, TransportMode};
        let (mode, all) = (TransportMode::Radiance, BxDFReflTransFlags::All);
        let bits = |s: SampledSpectrum| s.0.map(f32::to_bits);
        let mut rng = Rng::new(0x5eed);
        let mut stored_samples = 0;
        for (bm, bn, sigma_a, alpha) in [
            (0.3, 0.3, SampledSpectrum([0.4, 0.6, 0.9, 1.3]), 2.0),
            (0.05, 0.8, SampledSpectrum::ZERO, 0.0),
            (0.9, 0.1, SampledSpectrum([3.0, 2.0, 1.0, 0.5]), -4.0),
            (0.6, 0.6, SampledSpectrum::splat(0.05), 10.0),
        ] {
            for _ in 0..2000 {
                let base = HairBxDF::new(-1.0 + 2.0 * rng.f(), 1.55, sigma_a, bm, bn, alpha);
                let wo = sample_uniform_sphere(rng.v2());
                let other = sample_uniform_sphere(rng.v2());
                let wi = sample_uniform_sphere(rng.v2());
                let (uc, u) = (rng.f(), rng.v2());
                let made = BxDF::Hair(CircularHairBxDF::new(base).with_outgoing(wo));
                for w in [wo, other] {
                    assert_eq!(bits(made.f(w, wi, mode)), bits(base.value(w, wi)));
                    assert_eq!(
                        made.pdf(w, wi, mode, all).to_bits(),
                        base.density(w, wi).to_bits()
                    );
                    let cached = made.sample_f(w, uc, u, mode, all);
                    let plain = base.sample(w, uc, u);
                    assert_eq!(cached.is_some(), plain.is_some());
                    if let (Some(c), Some(p)) = (cached, plain) {
                        assert_eq!(bits(c.f), bits(p.f));
                        assert_eq!(
                            c.wi.to_array().map(f32::to_bits),
                            p.wi.to_array().map(f32::to_bits)
                        );
                        assert_eq!(c.pdf.to_bits(), p.pdf.to_bits());
                        stored_samples += usize::from(w == wo);
                    }
                }
            }
        }
        // Most directions sample: the comparison above was not vacuous.
        eprintln!("{stored_samples} of 8000 samples compared with the stored state");
        assert!(stored_samples > 7000, "{stored_samples}");
    }

    #[test]
    fn sigma_a_from_reflectance_inverts_to_darker_for_darker_colours() {
        let s = HairBxDF::sigma_a_from_reflectance(SampledSpectrum([0.9, 0.5, 0.2, 0.05]), 0.3);
        assert!(s[0] < s[1] && s[1] < s[2] && s[2] < s[3]);
        let e = HairBxDF::sigma_a_from_concentration(1.3, 0.0);
        assert!((e[0] - 1.3 * 0.419).abs() < 1e-6);
    }
}

/// [`BxDFInterface::sample_f`] of a hair model (either) from its own
/// `sample`: nothing when the requested hemispheres exclude the model's
/// `flags`. Hair ignores the transport mode: its lobes are reciprocal.
pub(super) fn sample_f_within(
    flags: BxDFFlags,
    sample_flags: BxDFReflTransFlags,
    sample: impl FnOnce() -> Option<HairSample>,
) -> Option<BSDFSample> {
    if !flags.allows(sample_flags) {
        return None;
    }
    let s = sample()?;
    Some(BSDFSample::new(s.f, s.wi, s.pdf, flags))
}

/// [`BxDFInterface::pdf`] of a hair model (either) from its own `density`:
/// zero when the requested hemispheres exclude the model's `flags`.
pub(super) fn pdf_within(
    flags: BxDFFlags,
    sample_flags: BxDFReflTransFlags,
    density: impl FnOnce() -> f32,
) -> f32 {
    if !flags.allows(sample_flags) {
        return 0.0;
    }
    density()
}

/// pbrt-v4's hair BxDF as a hit holds it: a [`HairBxDF`] with its ω_o
/// state (A_p, angles, tilts, lobe probabilities) computed once for the ω_o
/// it was made for. A path vertex asks f, pdf and sample_f with that ω_o
/// (pbrt-v4 recomputes the state in each); any other ω_o is computed
/// afresh, so the values are those of [`HairBxDF`] bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircularHairBxDF {
    bxdf: HairBxDF,
    outgoing: Option<(Vec3, Outgoing)>,
}

impl CircularHairBxDF {
    pub fn new(bxdf: HairBxDF) -> Self {
        CircularHairBxDF {
            bxdf,
            outgoing: None,
        }
    }

    /// The same BxDF with its state for `wo` (local frame) computed now.
    pub fn with_outgoing(mut self, wo: Vec3) -> Self {
        self.outgoing = Some((wo, self.bxdf.outgoing(wo)));
        self
    }

    /// The state for `wo`: the stored one (borrowed, not copied) when `wo`
    /// is the BxDF's own.
    fn outgoing_for(&self, wo: Vec3) -> std::borrow::Cow<'_, Outgoing> {
        match &self.outgoing {
            Some((w, o)) if *w == wo => std::borrow::Cow::Borrowed(o),
            _ => std::borrow::Cow::Owned(self.bxdf.outgoing(wo)),
        }
    }

    /// f for the pair (the BxDF ignores the transport mode).
    pub fn value(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        self.bxdf.value_at(&self.outgoing_for(wo), wi)
    }

    /// A direction ωi sampled from the lobes, with f and its density.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<HairSample> {
        self.bxdf.sample_at(&self.outgoing_for(wo), uc, u)
    }

    /// Solid-angle density with which [`Self::sample`] picks ωi.
    pub fn density(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.bxdf.density_at(&self.outgoing_for(wo), wi)
    }

    /// [`Self::value`] and [`Self::density`] at once (bit for bit the
    /// same; they share their lobes' terms).
    pub fn value_and_density(&self, wo: Vec3, wi: Vec3) -> (SampledSpectrum, f32) {
        self.bxdf.value_and_density_at(&self.outgoing_for(wo), wi)
    }
}

/// The four [`BxDFInterface`] methods both hair models (pbrt-v4's circular
/// one and the dual model) forward to their own `value`, `sample`,
/// `density` and `value_and_density`; each impl adds its `flags` and
/// `regularize`.
macro_rules! hair_model_bxdf_methods {
    () => {
        fn f(
            &self,
            wo: glam::Vec3,
            wi: glam::Vec3,
            _mode: $crate::bxdfs::TransportMode,
        ) -> $crate::spectrum::SampledSpectrum {
            self.value(wo, wi)
        }

        fn sample_f(
            &self,
            wo: glam::Vec3,
            uc: f32,
            u: glam::Vec2,
            _mode: $crate::bxdfs::TransportMode,
            sample_flags: $crate::bxdfs::BxDFReflTransFlags,
        ) -> Option<$crate::bxdfs::BSDFSample> {
            $crate::bxdfs::hair::sample_f_within(self.flags(), sample_flags, || {
                self.sample(wo, uc, u)
            })
        }

        fn pdf(
            &self,
            wo: glam::Vec3,
            wi: glam::Vec3,
            _mode: $crate::bxdfs::TransportMode,
            sample_flags: $crate::bxdfs::BxDFReflTransFlags,
        ) -> f32 {
            $crate::bxdfs::hair::pdf_within(self.flags(), sample_flags, || self.density(wo, wi))
        }

        fn f_and_pdf(
            &self,
            wo: glam::Vec3,
            wi: glam::Vec3,
            _mode: $crate::bxdfs::TransportMode,
        ) -> ($crate::spectrum::SampledSpectrum, Option<f32>) {
            let (f, pdf) = self.value_and_density(wo, wi);
            (f, Some(pdf))
        }
    };
}
pub(crate) use hair_model_bxdf_methods;

impl BxDFInterface for CircularHairBxDF {
    hair_model_bxdf_methods!();

    /// pbrt-v4 flags hair as glossy reflection, though it also transmits
    /// (TT).
    fn flags(&self) -> BxDFFlags {
        BxDFFlags::GLOSSY_REFLECTION
    }

    /// Nothing to roughen: no hair lobe is a delta.
    fn regularize(&mut self) {}
}
