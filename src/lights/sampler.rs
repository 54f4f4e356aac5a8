//! Choosing which light to sample for direct lighting.
//!
//! pbrt-v4's `lightsampler` parameter: `uniform`, `power`, `bvh` (default).
//! For `bvh`, lights without bounds (distant and infinite) are chosen as
//! pbrt-v4's BVH sampler chooses them — each with probability
//! 1 / (their count + 1 if there are bounded lights) — and bounded lights
//! share the rest by power; the BVH's spatial importance among bounded
//! lights is not built yet (unbiased either way: only the noise differs
//! where many lights are spread over the scene).

use super::{Light, LightSampleContext};
use crate::shapes::ShapeStorage;
use crate::spectrum::SampledWavelengths;

pub struct LightSampler {
    /// Cumulative probabilities (last = 1).
    cdf: Vec<f32>,
    pmf: Vec<f32>,
}

impl LightSampler {
    pub fn uniform(count: usize) -> Self {
        Self::from_weights(&vec![1.0; count])
    }

    /// Probabilities proportional to each light's power (its average over
    /// four stratified wavelengths), as pbrt-v4's PowerLightSampler.
    pub fn power(lights: &[Light], shapes: &ShapeStorage) -> Self {
        let lambda = SampledWavelengths::sample_uniform(
            0.5,
            crate::spectrum::LAMBDA_MIN,
            crate::spectrum::LAMBDA_MAX,
        );
        let weights: Vec<f32> = lights
            .iter()
            .map(|l| {
                l.phi(&lambda, shapes)
                    .safe_div(lambda.pdf())
                    .average()
                    .max(0.0)
            })
            .collect();
        if weights.iter().sum::<f32>() > 0.0 {
            Self::from_weights(&weights)
        } else {
            Self::uniform(lights.len())
        }
    }

    /// pbrt-v4's BVH light sampler's treatment of unbounded lights, with
    /// bounded lights by power.
    pub fn bvh(lights: &[Light], shapes: &ShapeStorage) -> Self {
        let unbounded = |l: &Light| {
            matches!(
                l.kind(),
                super::LightKind::Infinite | super::LightKind::DeltaDirection
            )
        };
        let n_unbounded = lights.iter().filter(|l| unbounded(l)).count();
        let n_bounded = lights.len() - n_unbounded;
        if n_unbounded == 0 {
            return Self::power(lights, shapes);
        }
        let p_unbounded = n_unbounded as f32 / (n_unbounded + usize::from(n_bounded > 0)) as f32;
        let power = Self::power(lights, shapes);
        let bounded_total: f32 = lights
            .iter()
            .zip(&power.pmf)
            .filter(|(l, _)| !unbounded(l))
            .map(|(_, p)| p)
            .sum();
        let weights: Vec<f32> = lights
            .iter()
            .zip(&power.pmf)
            .map(|(l, &p)| {
                if unbounded(l) {
                    p_unbounded / n_unbounded as f32
                } else if bounded_total > 0.0 {
                    (1.0 - p_unbounded) * p / bounded_total
                } else {
                    (1.0 - p_unbounded) / n_bounded as f32
                }
            })
            .collect();
        Self::from_weights(&weights)
    }

    fn from_weights(weights: &[f32]) -> Self {
        let total: f64 = weights.iter().map(|&w| w as f64).sum();
        let pmf: Vec<f32> = weights
            .iter()
            .map(|&w| {
                if total > 0.0 {
                    (w as f64 / total) as f32
                } else {
                    0.0
                }
            })
            .collect();
        let mut cdf = Vec::with_capacity(pmf.len());
        let mut acc = 0.0f64;
        for &w in weights {
            acc += w as f64;
            cdf.push((acc / total) as f32);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        LightSampler { cdf, pmf }
    }

    /// A light index and its probability.
    pub fn sample(&self, _ctx: &LightSampleContext, u: f32) -> Option<(usize, f32)> {
        if self.cdf.is_empty() {
            return None;
        }
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.cdf.len() - 1);
        let p = self.pmf[i];
        (p > 0.0).then_some((i, p))
    }

    pub fn pmf(&self, _ctx: &LightSampleContext, light: usize) -> f32 {
        self.pmf.get(light).copied().unwrap_or(0.0)
    }
}
