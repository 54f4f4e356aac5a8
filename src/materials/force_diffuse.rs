//! pbrt-v4's `Option "forcediffuse" true`: the BSDF of every surface is
//! replaced by a diffuse one whose reflectance is the BSDF's directional
//! albedo ρ(ωo) = ∫ f(ωo, ωi) |cos θi| dωi.
//!
//! pbrt-v4 (`SurfaceInteraction::GetBSDF`) makes the material's BSDF, then
//! a `DiffuseBxDF` of `bsdf.rho(wo, {Get1D()}, {Get2D()})` in the same
//! shading frame: reflection only (glass becomes an opaque surface), the
//! reflectance not clamped, `interface` left an interface (it has no BSDF).
//! `BxDF::rho` samples the BxDF with transport mode radiance and sums
//! f |cos θi| / pdf.
//!
//! One difference: pbrt-v4 estimates ρ with one sample drawn from the pixel
//! sampler. A material has no sampler here, so ρ is estimated from
//! [`SAMPLES`] stratified samples rotated by a hash of the hit point, ωo and
//! the wavelengths. Each sample is uniform, so the expected image is
//! pbrt-v4's; it is less noisy, and the pixel sampler's stream is not
//! advanced (pbrt-v4 draws three numbers at each hit).

use crate::bxdfs::{BxDF, BxDFInterface, BxDFReflTransFlags, DiffuseBxDF, TransportMode, BSDF};
use crate::interaction::SurfaceInteraction;
use crate::math::hash::hash_words;
use crate::math::ONE_MINUS_EPSILON;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// Samples per estimate of ρ: a 4 × 4 grid of directions, each with its own
/// stratum of the lobe choice.
pub const SAMPLES: u32 = 16;

/// The diffuse BSDF that stands for `bsdf` at `si` under `forcediffuse`.
pub fn diffuse_equivalent(
    bsdf: &BSDF,
    si: &SurfaceInteraction,
    lambda: &SampledWavelengths,
) -> BSDF {
    let reflectance = albedo(bsdf, si.wo, rotation(si, lambda));
    BSDF::new(
        si.shading.n,
        si.shading.dpdu,
        BxDF::Diffuse(DiffuseBxDF::new(reflectance)),
    )
}

/// ρ(ωo) of `bsdf` (ωo in render space) from [`SAMPLES`] stratified
/// samples shifted by `rotation` (each in [0, 1)), as pbrt-v4's
/// `BxDF::rho`: zero when ωo lies in the shading tangent plane.
pub fn albedo(bsdf: &BSDF, wo_render: Vec3, rotation: [f32; 3]) -> SampledSpectrum {
    let wo = bsdf.render_to_local(wo_render);
    if wo.z == 0.0 {
        return SampledSpectrum::ZERO;
    }
    let mut sum = SampledSpectrum::ZERO;
    for i in 0..SAMPLES {
        let (uc, u) = stratified(i, rotation);
        let sample =
            bsdf.bxdf()
                .sample_f(wo, uc, u, TransportMode::Radiance, BxDFReflTransFlags::All);
        if let Some(bs) = sample.filter(|bs| bs.pdf > 0.0) {
            sum += bs.f * (bs.wi.z.abs() / bs.pdf);
        }
    }
    sum / SAMPLES as f32
}

/// The `i`th sample: (lobe choice, direction). The directions fill a 4 × 4
/// grid; the lobe choices fill 16 strata in an order that pairs them with
/// cells across the grid. `rotation` shifts all three coordinates (modulo 1).
fn stratified(i: u32, rotation: [f32; 3]) -> (f32, Vec2) {
    let shift = |stratum: u32, count: u32, r: f32| {
        ((stratum as f32 + r) / count as f32).min(ONE_MINUS_EPSILON)
    };
    let uc = shift((i * 7) % SAMPLES, SAMPLES, rotation[0]);
    let u = Vec2::new(shift(i % 4, 4, rotation[1]), shift(i / 4, 4, rotation[2]));
    (uc, u)
}

/// A shift in [0, 1)³ that varies from hit to hit: a hash of the point, ωo
/// and the first wavelength (all random from sample to sample).
fn rotation(si: &SurfaceInteraction, lambda: &SampledWavelengths) -> [f32; 3] {
    let bits = hash_words(&[
        si.p.x.to_bits(),
        si.p.y.to_bits(),
        si.p.z.to_bits(),
        si.wo.x.to_bits(),
        si.wo.y.to_bits(),
        si.wo.z.to_bits(),
        lambda.lambda[0].to_bits(),
    ]);
    let unit = |shift: u32| ((bits >> shift) & 0x1f_ffff) as f32 / (1u32 << 21) as f32;
    [unit(0), unit(21), unit(42)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::{ConductorBxDF, DielectricBxDF, TrowbridgeReitzDistribution};
    use crate::math::pcg32::Pcg32;

    fn at_normal(bxdf: BxDF) -> BSDF {
        BSDF::new(Vec3::Z, Vec3::X, bxdf)
    }

    /// A diffuse BSDF's cosine samples each give its reflectance: ρ is it
    /// exactly, whatever the rotation.
    #[test]
    fn a_diffuse_bsdf_keeps_its_reflectance() {
        let bsdf = at_normal(BxDF::Diffuse(DiffuseBxDF::new(SampledSpectrum::splat(0.3))));
        let wo = Vec3::new(0.3, -0.2, 0.8).normalize();
        for rotation in [[0.01; 3], [0.5, 0.25, 0.75], [0.999, 0.999, 0.999]] {
            let r = albedo(&bsdf, wo, rotation);
            assert!(
                (r - SampledSpectrum::splat(0.3))
                    .map(f32::abs)
                    .max_component()
                    < 1e-5,
                "{r:?}"
            );
        }
    }

    /// A smooth conductor given by its reflectance r reflects r at normal
    /// incidence (pbrt-v4's η = 1, k = 2√r/√(1 − r)).
    #[test]
    fn a_mirror_becomes_diffuse_of_its_fresnel_reflectance() {
        let r: f32 = 0.7;
        let k = 2.0 * r.sqrt() / (1.0 - r).sqrt();
        let bsdf = at_normal(BxDF::Conductor(ConductorBxDF::new(
            TrowbridgeReitzDistribution::new(0.0, 0.0),
            SampledSpectrum::ONE,
            SampledSpectrum::splat(k),
        )));
        let rho = albedo(&bsdf, Vec3::Z, [0.1, 0.2, 0.3]);
        assert!(
            (rho - SampledSpectrum::splat(r))
                .map(f32::abs)
                .max_component()
                < 1e-4,
            "{rho:?}"
        );
    }

    /// Glass (η = 1.5) at normal incidence: ρ = R + T/η² in radiance mode
    /// (R = 0.04). One rotation's estimate is not exact, but its mean over
    /// rotations is.
    #[test]
    fn glass_albedo_is_right_on_average() {
        let bsdf = at_normal(BxDF::Dielectric(DielectricBxDF::new(
            1.5,
            TrowbridgeReitzDistribution::new(0.0, 0.0),
        )));
        let expected = 0.04 + 0.96 / 2.25;
        let mut rng = Pcg32::new(7);
        let n = 4000;
        let mean = (0..n)
            .map(|_| {
                let rotation = [rng.uniform_f32(), rng.uniform_f32(), rng.uniform_f32()];
                albedo(&bsdf, Vec3::Z, rotation)[0] as f64
            })
            .sum::<f64>()
            / n as f64;
        assert!((mean - expected).abs() < 0.002, "{mean} vs {expected}");
    }

    /// The stand-in reflects only, on the side ωo is, with the BSDF's frame.
    #[test]
    fn the_stand_in_only_reflects() {
        let glass = at_normal(BxDF::Dielectric(DielectricBxDF::new(
            1.5,
            TrowbridgeReitzDistribution::new(0.0, 0.0),
        )));
        let mut si = SurfaceInteraction::default();
        si.shading.n = Vec3::Z;
        si.shading.dpdu = Vec3::X;
        si.wo = Vec3::new(0.0, 0.6, 0.8);
        let lambda = SampledWavelengths::sample_visible(0.5);
        let bsdf = diffuse_equivalent(&glass, &si, &lambda);
        let BxDF::Diffuse(d) = bsdf.bxdf() else {
            panic!("{:?}", bsdf.bxdf());
        };
        assert!(
            d.reflectance().min_component() > 0.3,
            "{:?}",
            d.reflectance()
        );
        assert_eq!(bsdf.flags(), crate::bxdfs::BxDFFlags::DIFFUSE_REFLECTION);
        let through = Vec3::new(0.0, -0.6, -0.8);
        assert_eq!(
            bsdf.f(si.wo, through, TransportMode::Radiance)
                .max_component(),
            0.0
        );
    }

    /// The stratified samples are in [0, 1) and cover each stratum once.
    #[test]
    fn samples_are_stratified() {
        let rotation = [0.99, 0.5, 0.001];
        let mut lobes = vec![false; SAMPLES as usize];
        let mut cells = vec![false; SAMPLES as usize];
        for i in 0..SAMPLES {
            let (uc, u) = stratified(i, rotation);
            assert!(
                (0.0..1.0).contains(&uc) && (0.0..1.0).contains(&u.x) && (0.0..1.0).contains(&u.y)
            );
            lobes[(uc * SAMPLES as f32) as usize] = true;
            cells[(u.x * 4.0) as usize + 4 * (u.y * 4.0) as usize] = true;
        }
        assert!(lobes.iter().all(|&b| b) && cells.iter().all(|&b| b));
    }
}
