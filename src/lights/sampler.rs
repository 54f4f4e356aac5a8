//! Choosing which light to sample for direct lighting.
//!
//! pbrt-v4's `lightsampler` parameter: `uniform`, `power`, `bvh` (default,
//! [`BvhLightSampler`]: importance at the shading point through a BVH over
//! the lights' bounds).

use super::bvh_sampler::BvhLightSampler;
use super::{Light, LightSampleContext};
use crate::shapes::ShapeStorage;
use crate::spectrum::SampledWavelengths;

/// The light sampler of a scene.
pub enum LightSampler {
    /// Fixed probabilities (`uniform`, `power`).
    Table(TableLightSampler),
    Bvh(BvhLightSampler),
}

impl LightSampler {
    pub fn uniform(count: usize) -> Self {
        LightSampler::Table(TableLightSampler::uniform(count))
    }

    pub fn power(lights: &[Light], shapes: &ShapeStorage) -> Self {
        LightSampler::Table(TableLightSampler::power(lights, shapes))
    }

    pub fn bvh(lights: &[Light], shapes: &ShapeStorage) -> Self {
        LightSampler::Bvh(BvhLightSampler::new(lights, shapes))
    }

    /// A light index and the probability of choosing it at `ctx`.
    pub fn sample(&self, ctx: &LightSampleContext, u: f32) -> Option<(usize, f32)> {
        match self {
            LightSampler::Table(t) => t.sample(u),
            LightSampler::Bvh(b) => b.sample(ctx, u),
        }
    }

    /// The light `sample(_, u)` chooses wherever the shading point is, if
    /// that does not depend on it.
    pub fn sample_anywhere(&self, u: f32) -> Option<usize> {
        match self {
            LightSampler::Table(t) => t.sample(u).map(|(i, _)| i),
            LightSampler::Bvh(b) => b.sample_infinite(u).map(|(i, _)| i),
        }
    }

    /// The probability that `sample` chooses `light` at `ctx`.
    pub fn pmf(&self, ctx: &LightSampleContext, light: usize) -> f32 {
        match self {
            LightSampler::Table(t) => t.pmf(light),
            LightSampler::Bvh(b) => b.pmf(ctx, light),
        }
    }
}

/// Lights chosen with fixed probabilities, wherever the shading point is.
pub struct TableLightSampler {
    /// Cumulative probabilities (last = 1).
    cdf: Vec<f32>,
    pmf: Vec<f32>,
}

impl TableLightSampler {
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
        TableLightSampler { cdf, pmf }
    }

    /// A light index and its probability.
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
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

    pub fn pmf(&self, light: usize) -> f32 {
        self.pmf.get(light).copied().unwrap_or(0.0)
    }
}
