//! The Trowbridge–Reitz (GGX) microfacet distribution, anisotropic, with
//! Smith masking–shadowing and sampling of the normals visible from a
//! direction. Rough conductors and dielectrics are built on it.

use super::geometry::{abs_cos_theta, cos2_theta, cos_phi, sin_phi, tan2_theta};
use crate::math::{lerp, sqr};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Roughness along the local x and y axes; α is the slope spread, so the
/// lobe narrows to a mirror as α → 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitzDistribution {
    alpha_x: f32,
    alpha_y: f32,
}

/// Below this α (in either direction) the surface is treated as perfectly
/// smooth: microfacet evaluation would be numerically hopeless, and a
/// delta lobe renders the same.
const EFFECTIVELY_SMOOTH_ALPHA: f32 = 1e-3;

impl TrowbridgeReitzDistribution {
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        TrowbridgeReitzDistribution { alpha_x, alpha_y }
    }

    /// pbrt-v4's mapping from the user-facing "roughness" parameter (used
    /// when `remaproughness` is true) to α.
    pub fn roughness_to_alpha(roughness: f32) -> f32 {
        roughness.sqrt()
    }

    pub fn alpha_x(&self) -> f32 {
        self.alpha_x
    }

    pub fn alpha_y(&self) -> f32 {
        self.alpha_y
    }

    /// Whether BxDFs should use a specular (delta) lobe instead.
    pub fn effectively_smooth(&self) -> bool {
        self.alpha_x.min(self.alpha_y) < EFFECTIVELY_SMOOTH_ALPHA
    }

    /// Microfacet normal density D(ωm), normalised so that
    /// ∫ D(ωm) cos θm dωm = 1 over the upper hemisphere.
    pub fn d(&self, wm: Vec3) -> f32 {
        let tan2_theta = tan2_theta(wm);
        if tan2_theta.is_infinite() {
            return 0.0;
        }
        let cos4_theta = sqr(cos2_theta(wm));
        if cos4_theta < 1e-16 {
            return 0.0;
        }
        let e = tan2_theta * (sqr(cos_phi(wm) / self.alpha_x) + sqr(sin_phi(wm) / self.alpha_y));
        1.0 / (PI * self.alpha_x * self.alpha_y * cos4_theta * sqr(1.0 + e))
    }

    /// Smith's auxiliary function Λ(ω): the ratio of back-facing to
    /// front-facing projected microfacet area seen from ω.
    pub fn lambda(&self, w: Vec3) -> f32 {
        let tan2_theta = tan2_theta(w);
        if tan2_theta.is_infinite() {
            return 0.0;
        }
        let alpha2 = sqr(cos_phi(w) * self.alpha_x) + sqr(sin_phi(w) * self.alpha_y);
        ((1.0 + alpha2 * tan2_theta).sqrt() - 1.0) / 2.0
    }

    /// Masking G1(ω): the fraction of microfacets visible from ω.
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking–shadowing G(ωo, ωi).
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of normals visible from ω, D_ω(ωm) = G1(ω) max(0, ω·ωm)
    /// D(ωm) / |cos θ|, which integrates to 1 over the upper hemisphere of
    /// ωm (pbrt's `D(w, wm)`). It takes |ω·ωm| rather than max(0, ω·ωm) so
    /// that ω below the surface sees the distribution from −ω; callers only
    /// evaluate it for normals facing ω or −ω accordingly, and back-facing
    /// normals are rejected before it is called.
    pub fn d_visible(&self, w: Vec3, wm: Vec3) -> f32 {
        self.g1(w) / abs_cos_theta(w) * self.d(wm) * w.dot(wm).abs()
    }

    /// Density of [`Self::sample_wm`] with respect to solid angle of ωm.
    pub fn pdf(&self, w: Vec3, wm: Vec3) -> f32 {
        self.d_visible(w, wm)
    }

    /// Samples a microfacet normal (in the upper hemisphere) from the
    /// distribution of normals visible from `w`, by stretching the
    /// configuration to a unit-roughness hemisphere, sampling its projected
    /// area, and stretching back (Heitz 2018, as pbrt-v4 does it).
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        let mut wh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize();
        if wh.z < 0.0 {
            wh = -wh;
        }
        let t1 = if wh.z < 0.99999 {
            Vec3::Z.cross(wh).normalize()
        } else {
            Vec3::X
        };
        let t2 = wh.cross(t1);
        let mut p = sample_uniform_disk_polar(u);
        // Squash the half of the disk the hemisphere's projection does not
        // cover, so points fall uniformly on the visible projected area.
        let h = (1.0 - sqr(p.x)).sqrt();
        p.y = lerp((1.0 + wh.z) / 2.0, h, p.y);
        let pz = (1.0 - p.length_squared()).max(0.0).sqrt();
        let nh = p.x * t1 + p.y * t2 + pz * wh;
        Vec3::new(self.alpha_x * nh.x, self.alpha_y * nh.y, nh.z.max(1e-6)).normalize()
    }

    /// Widens near-specular lobes so paths that would otherwise need to hit
    /// a tiny light through a mirror can be found (pbrt-v4's
    /// `--regularize`): α below 0.3 is doubled and clamped to [0.1, 0.3].
    pub fn regularize(&mut self) {
        if self.alpha_x < 0.3 {
            self.alpha_x = (2.0 * self.alpha_x).clamp(0.1, 0.3);
        }
        if self.alpha_y < 0.3 {
            self.alpha_y = (2.0 * self.alpha_y).clamp(0.1, 0.3);
        }
    }
}

/// Uniform point on the unit disk by the polar mapping (r = √u0, φ = 2π u1).
/// Visible-normal sampling needs this mapping rather than the concentric
/// one: its warp is defined in terms of the point's x coordinate.
fn sample_uniform_disk_polar(u: Vec2) -> Vec2 {
    let r = u.x.sqrt();
    let theta = 2.0 * PI * u.y;
    Vec2::new(r * theta.cos(), r * theta.sin())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::test_support::{integrate_sphere, Pcg32Source};

    fn distributions() -> [TrowbridgeReitzDistribution; 4] {
        [
            TrowbridgeReitzDistribution::new(0.5, 0.5),
            TrowbridgeReitzDistribution::new(0.2, 0.2),
            TrowbridgeReitzDistribution::new(0.15, 0.6),
            TrowbridgeReitzDistribution::new(1.0, 0.8),
        ]
    }

    /// Whether microfacet normal `m` (upper hemisphere) is visible from
    /// `w`, or from −w when `w` is below the surface.
    fn faces(w: Vec3, m: Vec3) -> bool {
        m.z > 0.0 && w.dot(m) * w.z.signum() > 0.0
    }

    #[test]
    fn projected_normal_density_integrates_to_one() {
        // ∫ D(ωm) cos θm dωm = 1: the microfacets' projected area is the
        // macro surface's.
        for distribution in distributions() {
            let integral = integrate_sphere(|w| distribution.d(w) * w.z.max(0.0), 400, 800);
            assert!(
                (integral - 1.0).abs() < 2e-3,
                "{distribution:?}: {integral}"
            );
        }
    }

    #[test]
    fn visible_normal_density_integrates_to_one() {
        // ∫ D_ω(ωm) dωm = 1 for every ω, from above or below: this holds only
        // if Λ (hence G1) is consistent with D.
        for distribution in distributions() {
            for w in [
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(0.6, 0.0, 0.8),
                Vec3::new(-0.3, 0.9, 0.316_227_8),
                Vec3::new(0.2, -0.1, -0.974_679_4),
            ] {
                let w = w.normalize();
                let integral = integrate_sphere(
                    |m| {
                        if faces(w, m) {
                            distribution.d_visible(w, m)
                        } else {
                            0.0
                        }
                    },
                    400,
                    800,
                );
                assert!(
                    (integral - 1.0).abs() < 3e-3,
                    "{distribution:?} {w}: {integral}"
                );
            }
        }
    }

    #[test]
    fn sampled_normals_follow_the_visible_density() {
        // Mean of a test function under sample_wm vs its integral against
        // pdf(w, ·): catches a wrong warp or density.
        let mut rng = Pcg32Source::new(7);
        for distribution in distributions() {
            let w = Vec3::new(0.5, -0.4, 0.768_114_6).normalize();
            let test_function = |m: Vec3| m.x * m.x + 0.5 * m.y + m.z * m.z * m.z;
            let n = 200_000;
            let mut sum = 0.0f64;
            let mut sum_sq = 0.0f64;
            for _ in 0..n {
                let m = distribution.sample_wm(w, rng.next_vec2());
                assert!(m.z > 0.0 && (m.length() - 1.0).abs() < 1e-4);
                let v = test_function(m) as f64;
                sum += v;
                sum_sq += v * v;
            }
            let mean = sum / n as f64;
            let std_error = ((sum_sq / n as f64 - mean * mean) / n as f64).sqrt();
            let expected = integrate_sphere(
                |m| {
                    if faces(w, m) {
                        distribution.pdf(w, m) * test_function(m)
                    } else {
                        0.0
                    }
                },
                400,
                800,
            ) as f64;
            assert!(
                (mean - expected).abs() < 4.0 * std_error + 1e-3,
                "{distribution:?}: sampled {mean} ± {std_error}, integrated {expected}"
            );
        }
    }

    #[test]
    fn smoothness_threshold_and_regularisation() {
        assert!(TrowbridgeReitzDistribution::new(0.0009, 0.5).effectively_smooth());
        assert!(!TrowbridgeReitzDistribution::new(0.001, 0.001).effectively_smooth());
        assert_eq!(TrowbridgeReitzDistribution::roughness_to_alpha(0.25), 0.5);
        let mut d = TrowbridgeReitzDistribution::new(0.0, 0.12);
        d.regularize();
        assert_eq!((d.alpha_x(), d.alpha_y()), (0.1, 0.24));
        let mut d = TrowbridgeReitzDistribution::new(0.2, 0.5);
        d.regularize();
        assert_eq!((d.alpha_x(), d.alpha_y()), (0.3, 0.5));
    }
}
