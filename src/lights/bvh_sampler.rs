//! pbrt-v4's `BVHLightSampler` (`lightsampler "bvh"`, the default): lights
//! at infinity are chosen uniformly, each with probability 1 / (their count,
//! plus one if there are bounded lights); the rest are chosen by walking a BVH
//! over their [`LightBounds`], picking each child with probability
//! proportional to its importance at the shading point (p, ns).
//!
//! The tree is built top-down with pbrt-v4's cost (`EvaluateCost`: power ×
//! a measure of the emission cone × box surface area × an aspect factor)
//! over 12 buckets per axis. Each light's path from the root is kept as a
//! bit trail (bit d = took the second child at depth d), so its PMF is
//! found by walking down again.

use super::light_bounds::{light_bounds, LightBounds};
use super::{Light, LightSampleContext};
use crate::math::{safe_sqrt, sqr, Bounds3, ONE_MINUS_EPSILON};
use crate::shapes::ShapeStorage;
use glam::Vec3;
use std::f32::consts::PI;

const BUCKETS: usize = 12;

#[derive(Clone, Copy, Debug)]
struct Node {
    /// Quantised within the bounds of all lights, as pbrt-v4's
    /// `CompactLightBounds`.
    bounds: LightBounds,
    /// Leaf: the light's index; interior: the second child's node (the
    /// first is the next node).
    child_or_light: u32,
    is_leaf: bool,
}

/// How a light is reached.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    Infinite,
    /// In the BVH, with its bit trail.
    Tree(u64),
    /// Bounded but without power: never sampled.
    Dark,
}

pub struct BvhLightSampler {
    infinite: Vec<u32>,
    nodes: Vec<Node>,
    slots: Vec<Slot>,
}

/// pbrt-v4's `EvaluateCost` for a split candidate: power × M_Ω (the solid
/// angle measure of the normal and emission cones) × box area, times the
/// box's aspect ratio along the split axis.
fn evaluate_cost(b: &LightBounds, bounds: &Bounds3, dim: usize) -> f32 {
    let theta_o = b.cos_theta_o.clamp(-1.0, 1.0).acos();
    let theta_e = b.cos_theta_e.clamp(-1.0, 1.0).acos();
    let theta_w = (theta_o + theta_e).min(PI);
    let sin_o = safe_sqrt(1.0 - sqr(b.cos_theta_o));
    let m_omega = 2.0 * PI * (1.0 - b.cos_theta_o)
        + PI / 2.0
            * (2.0 * theta_w * sin_o - (theta_o - 2.0 * theta_w).cos() - 2.0 * theta_o * sin_o
                + b.cos_theta_o);
    let diagonal = bounds.diagonal();
    let kr = diagonal.max_element() / diagonal[dim];
    b.phi * m_omega * kr * b.bounds.surface_area()
}

/// Picks 0 or 1 with probabilities proportional to `w` and remaps `u`
/// (pbrt's `SampleDiscrete` for two weights).
fn sample_two(w: [f32; 2], u: f32) -> (usize, f32, f32) {
    let sum = w[0] + w[1];
    let mut up = u * sum;
    if up == sum {
        up = crate::math::ray::next_float_down(up);
    }
    if up < w[0] {
        (0, w[0] / sum, (up / w[0]).min(ONE_MINUS_EPSILON))
    } else {
        (1, w[1] / sum, ((up - w[0]) / w[1]).min(ONE_MINUS_EPSILON))
    }
}

impl BvhLightSampler {
    pub fn new(lights: &[Light], shapes: &ShapeStorage) -> Self {
        let mut infinite = Vec::new();
        let mut slots = vec![Slot::Dark; lights.len()];
        let mut bounded = Vec::new();
        let mut all = Bounds3::EMPTY;
        for (i, light) in lights.iter().enumerate() {
            match light_bounds(light, shapes) {
                None => {
                    infinite.push(i as u32);
                    slots[i] = Slot::Infinite;
                }
                Some(b) if b.phi > 0.0 => {
                    all = all.union(b.bounds);
                    bounded.push((i as u32, b));
                }
                Some(_) => {}
            }
        }
        let mut sampler = BvhLightSampler {
            infinite,
            nodes: Vec::new(),
            slots,
        };
        if !bounded.is_empty() {
            let len = bounded.len();
            sampler.build(&mut bounded, 0..len, 0, 0, &all);
        }
        sampler
    }

    /// Builds the subtree over `lights[range]`; returns its node and bounds.
    fn build(
        &mut self,
        lights: &mut [(u32, LightBounds)],
        range: std::ops::Range<usize>,
        bit_trail: u64,
        depth: u32,
        all: &Bounds3,
    ) -> (usize, LightBounds) {
        let (start, end) = (range.start, range.end);
        if end - start == 1 {
            let (light, b) = lights[start];
            self.nodes.push(Node {
                bounds: b.quantized(all),
                child_or_light: light,
                is_leaf: true,
            });
            self.slots[light as usize] = Slot::Tree(bit_trail);
            return (self.nodes.len() - 1, b);
        }
        let mut bounds = Bounds3::EMPTY;
        let mut centroids = Bounds3::EMPTY;
        for (_, b) in &lights[range.clone()] {
            bounds = bounds.union(b.bounds);
            centroids = centroids.with_point(b.centroid());
        }
        let bucket_of = |b: &LightBounds, dim: usize| {
            let extent = centroids.max[dim] - centroids.min[dim];
            let offset = if extent > 0.0 {
                (b.centroid()[dim] - centroids.min[dim]) / extent
            } else {
                0.0
            };
            ((BUCKETS as f32 * offset) as usize).min(BUCKETS - 1)
        };
        // The cheapest split over 12 buckets per axis (as pbrt-v4, the
        // split after the first bucket is not considered).
        let mut best: Option<(f32, usize, usize)> = None;
        for dim in 0..3 {
            if centroids.max[dim] == centroids.min[dim] {
                continue;
            }
            let mut buckets = [LightBounds::default(); BUCKETS];
            for (_, b) in &lights[range.clone()] {
                let k = bucket_of(b, dim);
                buckets[k] = buckets[k].union(*b);
            }
            for split in 1..BUCKETS - 1 {
                let below = buckets[..=split]
                    .iter()
                    .fold(LightBounds::default(), |acc, b| acc.union(*b));
                let above = buckets[split + 1..]
                    .iter()
                    .fold(LightBounds::default(), |acc, b| acc.union(*b));
                let cost =
                    evaluate_cost(&below, &bounds, dim) + evaluate_cost(&above, &bounds, dim);
                if cost > 0.0 && best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, split, dim));
                }
            }
        }
        let mut mid = (start + end) / 2;
        if let Some((_, split, dim)) = best {
            let slice = &mut lights[range.clone()];
            let mut below = 0;
            for i in 0..slice.len() {
                if bucket_of(&slice[i].1, dim) <= split {
                    slice.swap(i, below);
                    below += 1;
                }
            }
            if below > 0 && below < slice.len() {
                mid = start + below;
            }
        }
        let node = self.nodes.len();
        self.nodes.push(Node {
            bounds: LightBounds::default(),
            child_or_light: 0,
            is_leaf: false,
        });
        let (_, b0) = self.build(lights, start..mid, bit_trail, depth + 1, all);
        let (child1, b1) = self.build(
            lights,
            mid..end,
            bit_trail | (1u64 << depth),
            depth + 1,
            all,
        );
        let b = b0.union(b1);
        self.nodes[node] = Node {
            bounds: b.quantized(all),
            child_or_light: child1 as u32,
            is_leaf: false,
        };
        (node, b)
    }

    /// The importance at (p, n) of an interior node's two children, and
    /// the second child's index.
    fn children_importance(
        &self,
        index: usize,
        node: &Node,
        p: Vec3,
        n: Vec3,
    ) -> ([f32; 2], usize) {
        let second = node.child_or_light as usize;
        let importance = [
            self.nodes[index + 1].bounds.importance(p, n),
            self.nodes[second].bounds.importance(p, n),
        ];
        (importance, second)
    }

    fn p_infinite(&self) -> f32 {
        let n = self.infinite.len() as f32;
        n / (n + if self.nodes.is_empty() { 0.0 } else { 1.0 })
    }

    /// The infinite light `sample(_, u)` chooses, if it chooses one (that
    /// choice does not depend on the shading point).
    pub fn sample_infinite(&self, u: f32) -> Option<(usize, f32)> {
        let p_infinite = self.p_infinite();
        if u < p_infinite {
            let u = (u / p_infinite).min(ONE_MINUS_EPSILON);
            let n = self.infinite.len();
            let index = ((u * n as f32) as usize).min(n - 1);
            return Some((self.infinite[index] as usize, p_infinite / n as f32));
        }
        None
    }

    /// A light and the probability of choosing it at `ctx`.
    pub fn sample(&self, ctx: &LightSampleContext, u: f32) -> Option<(usize, f32)> {
        if let Some(chosen) = self.sample_infinite(u) {
            return Some(chosen);
        }
        let p_infinite = self.p_infinite();
        if self.nodes.is_empty() {
            return None;
        }
        let (p, n) = (ctx.p, ctx.ns);
        let mut u = ((u - p_infinite) / (1.0 - p_infinite)).min(ONE_MINUS_EPSILON);
        let mut node_index = 0;
        let mut pmf = 1.0 - p_infinite;
        loop {
            let node = &self.nodes[node_index];
            if node.is_leaf {
                // A lone root leaf may have no importance here.
                if node_index > 0 || node.bounds.importance(p, n) > 0.0 {
                    return Some((node.child_or_light as usize, pmf));
                }
                return None;
            }
            let (importance, second) = self.children_importance(node_index, node, p, n);
            if importance[0] == 0.0 && importance[1] == 0.0 {
                return None;
            }
            let (child, child_pmf, remapped) = sample_two(importance, u);
            pmf *= child_pmf;
            u = remapped;
            node_index = if child == 0 { node_index + 1 } else { second };
        }
    }

    /// The probability that [`BvhLightSampler::sample`] chooses `light` at
    /// `ctx`.
    pub fn pmf(&self, ctx: &LightSampleContext, light: usize) -> f32 {
        let mut trail = match self.slots.get(light) {
            Some(Slot::Infinite) => {
                let n = self.infinite.len() as f32;
                return 1.0 / (n + if self.nodes.is_empty() { 0.0 } else { 1.0 });
            }
            Some(Slot::Tree(trail)) => *trail,
            Some(Slot::Dark) | None => return 0.0,
        };
        let (p, n) = (ctx.p, ctx.ns);
        let mut pmf = 1.0;
        let mut node_index = 0;
        loop {
            let node = &self.nodes[node_index];
            if node.is_leaf {
                if node_index == 0 && node.bounds.importance(p, n) == 0.0 {
                    return 0.0;
                }
                break;
            }
            let (importance, second) = self.children_importance(node_index, node, p, n);
            let taken = (trail & 1) as usize;
            if importance[taken] == 0.0 {
                return 0.0;
            }
            pmf *= importance[taken] / (importance[0] + importance[1]);
            node_index = if taken == 1 { second } else { node_index + 1 };
            trail >>= 1;
        }
        pmf * (1.0 - self.p_infinite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::{DiffuseAreaLight, PointLight, SpotLight, UniformInfiniteLight};
    use crate::math::Transform;
    use crate::shapes::mesh::{MeshData, TriangleMesh};
    use crate::shapes::{Shape, Triangle};
    use crate::spectrum::Spectrum;
    use glam::Vec3;

    /// The crate's PCG32, with the draws these tests need.
    struct Rng(crate::math::pcg32::Pcg32);
    impl Rng {
        fn new(seed: u64) -> Self {
            Rng(crate::math::pcg32::Pcg32::new(seed))
        }
        fn next(&mut self) -> f32 {
            self.0.uniform_f32()
        }
        fn vec(&mut self, scale: f32) -> Vec3 {
            Vec3::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5) * scale
        }
    }

    /// Small emitting triangles facing all ways, one- and two-sided, of
    /// varied power; point and spot lights; optionally an infinite light.
    fn scene(with_infinite: bool) -> (Vec<Light>, ShapeStorage) {
        let mut rng = Rng::new(7);
        let mut storage = ShapeStorage::default();
        let mut positions = Vec::new();
        for _ in 0..40 {
            let c = rng.vec(10.0);
            positions.extend([c, c + rng.vec(1.0), c + rng.vec(1.0)]);
        }
        let data = MeshData {
            vertex_indices: (0..positions.len() as u32).collect(),
            positions,
            ..Default::default()
        };
        storage
            .triangle_meshes
            .push(TriangleMesh::new(&Transform::IDENTITY, false, data));
        let mut lights = Vec::new();
        for i in 0..40 {
            let shape = Shape::Triangle(Triangle::new(0, i));
            let area = shape.area(&storage);
            lights.push(Light::DiffuseArea(DiffuseAreaLight {
                shape,
                radiance: Spectrum::Constant(1.0 + 3.0 * rng.next()),
                scale: 1.0,
                two_sided: i % 3 == 0,
                area,
                image: None,
                alpha: None,
                invisible: false,
            }));
        }
        for _ in 0..5 {
            lights.push(Light::Point(PointLight {
                position: rng.vec(10.0),
                intensity: Spectrum::Constant(2.0),
                scale: 1.0,
            }));
            lights.push(Light::Spot(SpotLight {
                position: rng.vec(10.0),
                axis: rng.vec(1.0).normalize(),
                intensity: Spectrum::Constant(5.0),
                scale: 1.0,
                cos_falloff_start: 0.9,
                cos_falloff_end: 0.7,
            }));
        }
        if with_infinite {
            lights.push(Light::UniformInfinite(UniformInfiniteLight {
                radiance: Spectrum::Constant(1.0),
                scale: 1.0,
                scene_center: Vec3::ZERO,
                scene_radius: 10.0,
            }));
        }
        (lights, storage)
    }

    fn context(rng: &mut Rng, on_surface: bool) -> LightSampleContext {
        let n = if on_surface {
            rng.vec(1.0).normalize()
        } else {
            Vec3::ZERO
        };
        LightSampleContext {
            p: rng.vec(14.0),
            p_error: Vec3::ZERO,
            n,
            ns: n,
            time: 0.0,
        }
    }

    #[test]
    fn pmf_sums_to_one_and_matches_sampling() {
        for with_infinite in [false, true] {
            let (lights, storage) = scene(with_infinite);
            let sampler = BvhLightSampler::new(&lights, &storage);
            let mut rng = Rng::new(99);
            let mut worst_chi2 = 0.0f64;
            let mut sums_to_one = 0;
            for k in 0..40 {
                let ctx = context(&mut rng, k % 2 == 0);
                let pmf: Vec<f32> = (0..lights.len()).map(|i| sampler.pmf(&ctx, i)).collect();
                let total: f32 = pmf.iter().sum();
                // Sampling frequencies against the PMF (stratified u).
                let n = 100_000;
                let mut counts = vec![0u32; lights.len()];
                let mut failed = 0;
                for j in 0..n {
                    let u = (j as f32 + 0.5) / n as f32;
                    let Some((i, p)) = sampler.sample(&ctx, u) else {
                        failed += 1;
                        continue;
                    };
                    assert!(
                        (p - pmf[i]).abs() <= 1e-4 * pmf[i].max(1e-3),
                        "{p} vs {}",
                        pmf[i]
                    );
                    counts[i] += 1;
                }
                // The PMF sums to the probability that sampling finds a
                // light: 1, except where, as in pbrt-v4, the walk can reach
                // a node whose children both have zero importance.
                let found = 1.0 - failed as f32 / n as f32;
                assert!(total <= 1.0 + 1e-4, "PMF sums to {total}");
                assert!(
                    (total - found).abs() < 2e-3,
                    "PMF sums to {total}, sampling finds a light with probability {found}"
                );
                if failed == 0 {
                    assert!((total - 1.0).abs() < 1e-4, "PMF sums to {total}");
                    sums_to_one += 1;
                }
                if total == 0.0 {
                    continue;
                }
                let (mut chi2, mut dof) = (0.0f64, 0usize);
                let (mut pooled_expected, mut pooled_observed) = (0.0f64, 0.0f64);
                for (c, p) in counts.iter().zip(&pmf) {
                    let expected = *p as f64 * n as f64;
                    if expected >= 5.0 {
                        chi2 += (*c as f64 - expected).powi(2) / expected;
                        dof += 1;
                    } else {
                        pooled_expected += expected;
                        pooled_observed += *c as f64;
                    }
                }
                if pooled_expected >= 5.0 {
                    chi2 += (pooled_observed - pooled_expected).powi(2) / pooled_expected;
                    dof += 1;
                }
                // Stratified u makes the counts tighter than random ones;
                // a bound well above the 99.9% quantile for ≤ 60 bins.
                let bound = 2.0 * dof as f64 + 30.0;
                assert!(chi2 < bound, "chi2 {chi2} with {dof} bins");
                worst_chi2 = worst_chi2.max(chi2 / dof.max(1) as f64);
            }
            eprintln!("infinite light: {with_infinite}; worst chi²/bins {worst_chi2:.3}; PMF sums to 1 at {sums_to_one} of 40 points");
            assert!(sums_to_one >= 1);
        }
    }

    #[test]
    fn nearby_lights_are_favoured() {
        let (lights, storage) = scene(false);
        let sampler = BvhLightSampler::new(&lights, &storage);
        // Next to a point light, that light dominates.
        let Light::Point(point) = &lights[40] else {
            unreachable!()
        };
        let ctx = LightSampleContext {
            p: point.position + Vec3::new(0.01, 0.0, 0.0),
            p_error: Vec3::ZERO,
            n: Vec3::ZERO,
            ns: Vec3::ZERO,
            time: 0.0,
        };
        let power = crate::lights::LightSampler::power(&lights, &storage).pmf(&ctx, 40);
        let bvh = sampler.pmf(&ctx, 40);
        assert!(bvh > 2.5 * power, "bvh {bvh}, power {power}");
    }

    /// Isotropic lights are never unimportant: the PMF sums to 1 everywhere.
    #[test]
    fn pmf_of_point_lights_sums_to_one() {
        let (lights, storage) = scene(true);
        let lights: Vec<Light> = lights
            .into_iter()
            .filter(|l| matches!(l, Light::Point(_) | Light::UniformInfinite(_)))
            .collect();
        let sampler = BvhLightSampler::new(&lights, &storage);
        let mut rng = Rng::new(5);
        for k in 0..200 {
            let ctx = context(&mut rng, k % 2 == 0);
            let total: f32 = (0..lights.len()).map(|i| sampler.pmf(&ctx, i)).sum();
            assert!((total - 1.0).abs() < 1e-5, "PMF sums to {total}");
        }
    }
}
