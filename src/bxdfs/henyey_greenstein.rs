//! The Henyey–Greenstein phase function: scattering inside a layered
//! BxDF's medium, forward (g > 0) or backward (g < 0) peaked.

use crate::math::{safe_sqrt, sqr, Frame};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// |g| is kept below this: the sampling formula becomes unstable as
/// |g| → 1 (and such a sharp lobe should be a delta anyway).
const MAX_ASYMMETRY: f32 = 0.99;

/// Density of scattering from ωo into ωi, where both point away from the
/// scattering point (pbrt's convention), so forward scattering is
/// ωo·ωi = −1. Normalised over the sphere.
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let g = g.clamp(-MAX_ASYMMETRY, MAX_ASYMMETRY);
    let denominator = 1.0 + sqr(g) + 2.0 * g * cos_theta;
    (1.0 - sqr(g)) / (4.0 * PI * denominator * safe_sqrt(denominator))
}

/// A sampled scattering direction with phase-function value and density
/// (equal, since sampling is exact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseFunctionSample {
    pub p: f32,
    pub wi: Vec3,
    pub pdf: f32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    g: f32,
}

impl HenyeyGreenstein {
    pub fn new(g: f32) -> Self {
        HenyeyGreenstein { g }
    }

    pub fn p(&self, wo: Vec3, wi: Vec3) -> f32 {
        henyey_greenstein(wo.dot(wi), self.g)
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.p(wo, wi)
    }

    /// Inverts the CDF of cos θ about ωo, then picks φ uniformly.
    pub fn sample_p(&self, wo: Vec3, u: Vec2) -> Option<PhaseFunctionSample> {
        let g = self.g.clamp(-MAX_ASYMMETRY, MAX_ASYMMETRY);
        let cos_theta = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            -1.0 / (2.0 * g) * (1.0 + sqr(g) - sqr((1.0 - sqr(g)) / (1.0 + g - 2.0 * g * u.x)))
        };
        let sin_theta = safe_sqrt(1.0 - sqr(cos_theta));
        let phi = 2.0 * PI * u.y;
        let local = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
        let wi = Frame::from_z(wo).from_local(local);
        let pdf = henyey_greenstein(cos_theta, g);
        Some(PhaseFunctionSample { p: pdf, wi, pdf })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::test_support::{integrate_sphere, Accumulator, Pcg32Source};

    #[test]
    fn normalised_and_sampled_consistently() {
        let mut rng = Pcg32Source::new(61);
        let wo = Vec3::new(0.3, -0.2, 0.932_737_9).normalize();
        for g in [-0.7, -0.2, 0.0, 0.4, 0.9] {
            let phase = HenyeyGreenstein::new(g);
            let integral = integrate_sphere(|wi| phase.p(wo, wi), 400, 800);
            assert!((integral - 1.0).abs() < 2e-3, "g {g}: {integral}");
            // Mean cosine between the incoming propagation direction (−ωo)
            // and ωi is g.
            let mut mean_cos = Accumulator::default();
            for _ in 0..100_000 {
                let s = phase.sample_p(wo, rng.next_vec2()).unwrap();
                assert!((s.pdf - phase.pdf(wo, s.wi)).abs() <= 1e-3 * s.pdf.max(1.0));
                mean_cos.add((-wo).dot(s.wi) as f64);
            }
            let e = mean_cos.estimate();
            assert!(
                (e.mean - g as f64).abs() < 4.0 * e.std_error + 1e-3,
                "g {g}: {e:?}"
            );
        }
    }
}
