//! A boundary between two dielectrics (glass, water, a varnish layer):
//! Fresnel-weighted reflection and refraction, smooth or rough.

use super::fresnel::fr_dielectric;
use super::geometry::{abs_cos_theta, cos_theta, face_forward, reflect, refract, same_hemisphere};
use super::microfacet::TrowbridgeReitzDistribution;
use super::{BSDFSample, BxDFFlags, BxDFInterface, BxDFReflTransFlags, TransportMode};
use crate::math::sqr;
use crate::spectrum::SampledSpectrum;
use glam::{Vec2, Vec3};

/// `eta` is η below the surface (the side −z points into) over η above.
/// An index-matched boundary (η = 1) only transmits, straight through.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricBxDF {
    eta: f32,
    distribution: TrowbridgeReitzDistribution,
}

impl DielectricBxDF {
    pub fn new(eta: f32, distribution: TrowbridgeReitzDistribution) -> Self {
        DielectricBxDF { eta, distribution }
    }

    pub fn eta(&self) -> f32 {
        self.eta
    }

    pub fn distribution(&self) -> TrowbridgeReitzDistribution {
        self.distribution
    }

    /// Whether to use the delta (specular) lobes: smooth, or index-matched
    /// (which refracts without bending, so roughness does not matter).
    fn is_specular(&self) -> bool {
        self.eta == 1.0 || self.distribution.effectively_smooth()
    }

    /// Lobe probabilities from the Fresnel reflectance, restricted to the
    /// requested hemispheres; `None` if nothing may be sampled.
    fn lobe_probabilities(
        reflectance: f32,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<(f32, f32)> {
        let pr = if sample_flags.includes_reflection() {
            reflectance
        } else {
            0.0
        };
        let pt = if sample_flags.includes_transmission() {
            1.0 - reflectance
        } else {
            0.0
        };
        if pr == 0.0 && pt == 0.0 {
            None
        } else {
            Some((pr, pt))
        }
    }

    /// Smooth boundary: choose reflection with probability F, else
    /// refraction, so each sample's weight is 1 in importance transport.
    fn sample_specular(
        &self,
        wo: Vec3,
        uc: f32,
        mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<BSDFSample> {
        let reflectance = fr_dielectric(cos_theta(wo), self.eta);
        let transmittance = 1.0 - reflectance;
        let (pr, pt) = Self::lobe_probabilities(reflectance, sample_flags)?;
        if uc < pr / (pr + pt) {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            let f = SampledSpectrum::splat(reflectance / abs_cos_theta(wi));
            Some(BSDFSample::new(
                f,
                wi,
                pr / (pr + pt),
                BxDFFlags::SPECULAR_REFLECTION,
            ))
        } else {
            let (wi, etap) = refract(wo, Vec3::Z, self.eta)?;
            let mut f = SampledSpectrum::splat(transmittance / abs_cos_theta(wi));
            if mode == TransportMode::Radiance {
                // Radiance is compressed into the denser medium: L ∝ η².
                f /= sqr(etap);
            }
            Some(
                BSDFSample::new(f, wi, pt / (pr + pt), BxDFFlags::SPECULAR_TRANSMISSION)
                    .with_eta(etap),
            )
        }
    }

    /// Rough boundary: sample a visible microfacet normal, then reflect or
    /// refract about it with probability given by its Fresnel reflectance.
    fn sample_rough(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<BSDFSample> {
        let wm = self.distribution.sample_wm(wo, u);
        let reflectance = fr_dielectric(wo.dot(wm), self.eta);
        let transmittance = 1.0 - reflectance;
        let (pr, pt) = Self::lobe_probabilities(reflectance, sample_flags)?;
        if uc < pr / (pr + pt) {
            let wi = reflect(wo, wm);
            if !same_hemisphere(wo, wi) {
                return None;
            }
            let pdf = self.distribution.pdf(wo, wm) / (4.0 * wo.dot(wm).abs()) * pr / (pr + pt);
            let f = self.distribution.d(wm) * self.distribution.g(wo, wi) * reflectance
                / (4.0 * cos_theta(wi) * cos_theta(wo));
            Some(BSDFSample::new(
                SampledSpectrum::splat(f),
                wi,
                pdf,
                BxDFFlags::GLOSSY_REFLECTION,
            ))
        } else {
            let (wi, etap) = refract(wo, wm, self.eta)?;
            if same_hemisphere(wo, wi) || wi.z == 0.0 {
                return None;
            }
            let denominator = sqr(wi.dot(wm) + wo.dot(wm) / etap);
            // Refraction Jacobian dωm/dωi = |ωi·ωm| / (ωi·ωm + ωo·ωm/η')².
            let dwm_dwi = wi.dot(wm).abs() / denominator;
            let pdf = self.distribution.pdf(wo, wm) * dwm_dwi * pt / (pr + pt);
            let mut f = transmittance
                * self.distribution.d(wm)
                * self.distribution.g(wo, wi)
                * (wi.dot(wm) * wo.dot(wm) / (cos_theta(wi) * cos_theta(wo) * denominator)).abs();
            if mode == TransportMode::Radiance {
                f /= sqr(etap);
            }
            Some(
                BSDFSample::new(
                    SampledSpectrum::splat(f),
                    wi,
                    pdf,
                    BxDFFlags::GLOSSY_TRANSMISSION,
                )
                .with_eta(etap),
            )
        }
    }

    /// The generalized half vector of (ωo, ωi) oriented to +z, the relative
    /// index across the pair, and whether it is a reflection; `None` for
    /// degenerate pairs and for pairs only back-facing microfacets could
    /// connect.
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32, bool)> {
        let cos_theta_o = cos_theta(wo);
        let cos_theta_i = cos_theta(wi);
        let reflect = cos_theta_i * cos_theta_o > 0.0;
        let etap = if reflect {
            1.0
        } else if cos_theta_o > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let wm = wi * etap + wo;
        if cos_theta_i == 0.0 || cos_theta_o == 0.0 || wm.length_squared() == 0.0 {
            return None;
        }
        let wm = face_forward(wm.normalize(), Vec3::Z);
        if wm.dot(wi) * cos_theta_i < 0.0 || wm.dot(wo) * cos_theta_o < 0.0 {
            return None;
        }
        Some((wm, etap, reflect))
    }
}

impl BxDFInterface for DielectricBxDF {
    fn flags(&self) -> BxDFFlags {
        let sides = if self.eta == 1.0 {
            BxDFFlags::TRANSMISSION
        } else {
            BxDFFlags::REFLECTION | BxDFFlags::TRANSMISSION
        };
        let lobe = if self.distribution.effectively_smooth() {
            BxDFFlags::SPECULAR
        } else {
            BxDFFlags::GLOSSY
        };
        sides | lobe
    }

    fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> Option<BSDFSample> {
        if self.is_specular() {
            self.sample_specular(wo, uc, mode, sample_flags)
        } else {
            self.sample_rough(wo, uc, u, mode, sample_flags)
        }
    }

    fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        if self.is_specular() {
            return SampledSpectrum::ZERO;
        }
        let Some((wm, etap, reflect)) = self.half_vector(wo, wi) else {
            return SampledSpectrum::ZERO;
        };
        let reflectance = fr_dielectric(wo.dot(wm), self.eta);
        let d = self.distribution.d(wm);
        let g = self.distribution.g(wo, wi);
        if reflect {
            SampledSpectrum::splat(
                d * g * reflectance / (4.0 * cos_theta(wi) * cos_theta(wo)).abs(),
            )
        } else {
            let denominator = sqr(wi.dot(wm) + wo.dot(wm) / etap) * cos_theta(wi) * cos_theta(wo);
            let mut f = d * (1.0 - reflectance) * g * (wi.dot(wm) * wo.dot(wm) / denominator).abs();
            if mode == TransportMode::Radiance {
                f /= sqr(etap);
            }
            SampledSpectrum::splat(f)
        }
    }

    fn pdf(
        &self,
        wo: Vec3,
        wi: Vec3,
        _mode: TransportMode,
        sample_flags: BxDFReflTransFlags,
    ) -> f32 {
        if self.is_specular() {
            return 0.0;
        }
        let Some((wm, etap, reflect)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let reflectance = fr_dielectric(wo.dot(wm), self.eta);
        let Some((pr, pt)) = Self::lobe_probabilities(reflectance, sample_flags) else {
            return 0.0;
        };
        if reflect {
            self.distribution.pdf(wo, wm) / (4.0 * wo.dot(wm).abs()) * pr / (pr + pt)
        } else {
            let denominator = sqr(wi.dot(wm) + wo.dot(wm) / etap);
            let dwm_dwi = wi.dot(wm).abs() / denominator;
            self.distribution.pdf(wo, wm) * dwm_dwi * pt / (pr + pt)
        }
    }

    fn regularize(&mut self) {
        self.distribution.regularize();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::test_support::*;
    use crate::bxdfs::BxDF;

    fn glass(eta: f32, alpha_x: f32, alpha_y: f32) -> BxDF {
        BxDF::Dielectric(DielectricBxDF::new(
            eta,
            TrowbridgeReitzDistribution::new(alpha_x, alpha_y),
        ))
    }

    /// Albedo ∫ f |cos θi| dωi by importance sampling, in importance
    /// transport (where a lossless boundary conserves energy exactly).
    fn albedo(
        bxdf: &BxDF,
        wo: Vec3,
        mode: TransportMode,
        n: usize,
        rng: &mut Pcg32Source,
    ) -> Estimate {
        let mut acc = Accumulator::default();
        for _ in 0..n {
            // Samples with zero density (microfacet normals in the tangent
            // plane) carry nothing; the BSDF drops them the same way.
            let weight = bxdf
                .sample_f(
                    wo,
                    rng.next_f32(),
                    rng.next_vec2(),
                    mode,
                    BxDFReflTransFlags::All,
                )
                .filter(|bs| bs.pdf > 0.0)
                .map_or(0.0, |bs| bs.f.average() * bs.wi.z.abs() / bs.pdf);
            acc.add(weight as f64);
        }
        acc.estimate()
    }

    #[test]
    fn smooth_white_furnace_reflection_plus_transmission_is_one() {
        // Every sample carries weight 1 in importance transport (R chosen
        // with probability R, T with probability T), from both sides and
        // beyond the critical angle; in radiance transport transmission
        // carries 1/η'² instead.
        let mut rng = Pcg32Source::new(41);
        for eta in [1.5, 1.0 / 1.5, 1.33] {
            let bxdf = glass(eta, 0.0, 0.0);
            for wo in test_directions(&mut rng, 10, true) {
                for _ in 0..2_000 {
                    let Some(bs) = bxdf.sample_f(
                        wo,
                        rng.next_f32(),
                        rng.next_vec2(),
                        TransportMode::Importance,
                        BxDFReflTransFlags::All,
                    ) else {
                        panic!("smooth dielectric sampling failed for {wo}");
                    };
                    let weight = bs.f.average() * bs.wi.z.abs() / bs.pdf;
                    assert!((weight - 1.0).abs() < 1e-5, "η {eta}, wo {wo}: {weight}");
                    assert!((bs.wi.length() - 1.0).abs() < 1e-5);
                    // The same sample in radiance transport.
                    let radiance = bxdf
                        .sample_f(
                            wo,
                            rng.next_f32(),
                            Vec2::ZERO,
                            TransportMode::Radiance,
                            BxDFReflTransFlags::All,
                        )
                        .unwrap();
                    let w = radiance.f.average() * radiance.wi.z.abs() / radiance.pdf;
                    let expected = if radiance.is_transmission() {
                        1.0 / (radiance.eta * radiance.eta)
                    } else {
                        1.0
                    };
                    assert!((w - expected).abs() < 1e-5, "{w} vs η' = {}", radiance.eta);
                }
            }
        }
    }

    #[test]
    fn index_matched_boundary_passes_light_straight_through() {
        let bxdf = glass(1.0, 0.3, 0.3);
        assert_eq!(bxdf.flags(), BxDFFlags::GLOSSY_TRANSMISSION);
        let wo = Vec3::new(0.3, 0.4, 0.866_025_4);
        let bs = bxdf
            .sample_f(
                wo,
                0.1,
                Vec2::splat(0.5),
                TransportMode::Radiance,
                BxDFReflTransFlags::All,
            )
            .unwrap();
        assert!((bs.wi + wo).length() < 1e-6);
        assert!(bs.is_specular() && bs.is_transmission());
        assert!((bs.f.average() * bs.wi.z.abs() / bs.pdf - 1.0).abs() < 1e-6);
    }

    #[test]
    fn rough_white_furnace_is_at_most_one_and_near_one_when_smooth() {
        // Energy lost only to single-scattering masking; measured figures
        // are printed (importance transport, η = 1.5, wo from above and below).
        let mut rng = Pcg32Source::new(42);
        for alpha in [0.05, 0.3, 0.7] {
            let bxdf = glass(1.5, alpha, alpha);
            for wo in [
                Vec3::new(0.5, 0.0, 0.866_025_4),
                Vec3::new(0.0, 0.3, -0.953_939_2),
            ] {
                let a = albedo(&bxdf, wo, TransportMode::Importance, 200_000, &mut rng);
                eprintln!(
                    "rough dielectric α = {alpha}, wo.z = {}: albedo {:.4} ± {:.4}",
                    wo.z, a.mean, a.std_error
                );
                assert!(a.mean <= 1.0 + 3.0 * a.std_error, "{a:?}");
                if alpha == 0.05 {
                    assert!(a.mean > 0.985, "{a:?}");
                }
                if alpha == 0.3 && wo.z > 0.0 {
                    assert!(a.mean > 0.97, "{a:?}");
                }
            }
        }
    }

    const ROUGH_CASES: [(f32, f32, f32); 7] = [
        (1.5, 0.3, 0.3),
        (1.5, 0.6, 0.6),
        (1.5, 1.0, 1.0),
        (1.5, 0.15, 0.6),
        (1.0 / 1.5, 0.5, 0.5),
        (1.0 / 1.5, 0.55, 0.39),
        (1.33, 0.2, 0.2),
    ];

    fn assert_sampling_consistent(cases: &[(f32, f32, f32)], seed: u64) {
        let mut rng = Pcg32Source::new(seed);
        for &(eta, ax, ay) in cases {
            let bxdf = glass(eta, ax, ay);
            for wo in test_directions(&mut rng, 4, true) {
                // Radiance and importance transport alternate over the
                // directions (they differ only by the 1/η'² of transmission).
                let mode = if wo.z > 0.0 {
                    TransportMode::Radiance
                } else {
                    TransportMode::Importance
                };
                let report = sampling_consistency(&bxdf, wo, mode, 30_000, 200_000, &mut rng);
                let case = format!("η {eta} α ({ax}, {ay}) wo {wo} {mode:?}");
                eprintln!(
                    "dielectric {case}: sampled {:.4} ± {:.4}, uniform {:.4} ± {:.4}, z = {:.2}, max pdf rel. err {:.1e} ({} > 1e-3), max f rel. err {:.1e}",
                    report.importance.mean, report.importance.std_error, report.uniform.mean, report.uniform.std_error,
                    report.z_score(), report.max_pdf_relative_error, report.pdf_mismatches, report.max_f_relative_error
                );
                assert!(report.z_score() < 4.5, "{case}: {report:?}");
                // Rough lobes never produce delta samples.
                assert_eq!(report.specular.mean, 0.0, "{case}");
                assert!(
                    report.pdf_mismatches * 1000 <= report.samples,
                    "{case}: {report:?}"
                );
            }
        }
    }

    #[test]
    fn sampling_is_consistent_with_f_and_pdf_entering_denser() {
        assert_sampling_consistent(&ROUGH_CASES[..4], 43);
    }

    #[test]
    fn sampling_is_consistent_with_f_and_pdf_other_indices() {
        assert_sampling_consistent(&ROUGH_CASES[4..], 49);
    }

    #[test]
    fn chi2_isotropic() {
        let bsdf = tilted_bsdf(glass(1.5, 0.7, 0.7));
        let mut rng = Pcg32Source::new(44);
        let wos = test_directions(&mut rng, 2, true);
        assert_chi2_passes("dielectric η 1.5 α 0.7", &bsdf, &wos, &mut rng);
    }

    #[test]
    fn chi2_anisotropic() {
        let bsdf = tilted_bsdf(glass(1.5, 0.55, 0.39));
        let mut rng = Pcg32Source::new(45);
        let wos = test_directions(&mut rng, 2, true);
        assert_chi2_passes("dielectric η 1.5 α (0.55, 0.39)", &bsdf, &wos, &mut rng);
    }

    #[test]
    fn chi2_inverted_index() {
        let bsdf = tilted_bsdf(glass(1.0 / 1.5, 0.7, 0.7));
        let mut rng = Pcg32Source::new(46);
        let wos = test_directions(&mut rng, 2, true);
        assert_chi2_passes("dielectric η 1/1.5 α 0.7", &bsdf, &wos, &mut rng);
    }

    #[test]
    fn chi2_inverted_index_anisotropic() {
        let bsdf = tilted_bsdf(glass(1.0 / 1.5, 0.55, 0.39));
        let mut rng = Pcg32Source::new(47);
        let wos = test_directions(&mut rng, 2, true);
        assert_chi2_passes("dielectric η 1/1.5 α (0.55, 0.39)", &bsdf, &wos, &mut rng);
    }

    #[test]
    fn reflection_is_reciprocal_and_transmission_is_adjoint() {
        // Reflection: f(a, b) = f(b, a). Transmission: the radiance BTDF
        // with swapped arguments is the importance BTDF,
        // f_rad(a, b) = f_imp(b, a) (the 1/η'² factors move to the other side).
        let mut rng = Pcg32Source::new(48);
        for (eta, ax, ay) in ROUGH_CASES {
            let bxdf = glass(eta, ax, ay);
            let ws = test_directions(&mut rng, 12, true);
            for &a in &ws {
                for &b in &ws {
                    let radiance_ab = bxdf.f(a, b, TransportMode::Radiance).average();
                    let importance_ba = bxdf.f(b, a, TransportMode::Importance).average();
                    let scale = radiance_ab.abs().max(importance_ba.abs()).max(1e-3);
                    assert!(
                        (radiance_ab - importance_ba).abs() / scale < 2e-3,
                        "η {eta} {a} {b}: {radiance_ab} vs {importance_ba}"
                    );
                    if same_hemisphere(a, b) {
                        let radiance_ba = bxdf.f(b, a, TransportMode::Radiance).average();
                        assert!(
                            (radiance_ab - radiance_ba).abs() / scale < 2e-3,
                            "η {eta} {a} {b}"
                        );
                    }
                }
            }
        }
    }
}
