//! Synthetic `.bsdf` files for the tests (no file of the RGL database
//! ships with the project): the tables a measurement of a GGX
//! (Trowbridge–Reitz) microsurface would give, computed as the format
//! defines them (Dupuy & Jakob 2018, §4–5), with a spectral table that is
//! constant or varies smoothly over the warped domain.
//!
//! On the unit square x ↔ θ = x²π/2, y ↔ φ = (2y − 1)π:
//! - `ndf`: D(θ, φ) = 1 / (π αx αy (cos²θ + sin²θ (cos²φ/αx² + sin²φ/αy²))²);
//! - `sigma`: σ(θ, φ) = ∫ D(ωm) ⟨ω · ωm⟩ dωm, for GGX in closed form
//!   (cos θ + √(cos²θ + α(φ)² sin²θ))/2 with α(φ)² = αx² cos²φ + αy² sin²φ;
//! - `vndf`: per incident (φi, θi), D(ωm) ⟨ωi · ωm⟩ times the Jacobian
//!   2π² x sin θm of the unit square (the table is normalised when read),
//!   the azimuth relative to φi in an isotropic file;
//! - `spectra`: the given spectrum, times a smooth positive factor of the
//!   warped-domain position and θi when `varying`;
//! - `luminance`: the mean of `spectra` over the wavelengths.
//!
//! With constant spectra R(λ) the BRDF is R D / (4 σ(ωo) cos θi), whose
//! directional albedo is R times the fraction of ωo's visible normals that
//! reflect it above the surface ([`Synthetic::visible_reflecting_fraction`]).

use super::tensor_file::{encode, f32_bytes, DType};
use super::MeasuredBxDFData;
use glam::Vec3;
use std::f64::consts::PI;

/// Grid sizes: the NDF and σ, the VNDF, the warped domain, the incident
/// elevations and (anisotropic) azimuths.
const N_NDF: usize = 33;
const N_VNDF: usize = 33;
const N_WARPED: usize = 17;
const N_THETA_I: usize = 10;
const N_PHI_I: usize = 9;

#[derive(Clone, Debug)]
pub struct Synthetic {
    pub alpha_x: f64,
    pub alpha_y: f64,
    pub wavelengths: Vec<f32>,
    /// The spectrum at `wavelengths`.
    pub values: Vec<f32>,
    /// Spectra vary over the warped domain (so does the luminance).
    pub varying: bool,
    /// Tables conditioned on the incident azimuth too (nine azimuths over
    /// the circle); else one azimuth, isotropic.
    pub anisotropic: bool,
}

impl Synthetic {
    /// An isotropic GGX surface of roughness α with a constant grey
    /// spectrum of 0.8.
    pub fn ggx(alpha: f64) -> Self {
        Synthetic {
            alpha_x: alpha,
            alpha_y: alpha,
            wavelengths: vec![400.0, 500.0, 600.0, 700.0],
            values: vec![0.8; 4],
            varying: false,
            anisotropic: false,
        }
    }

    pub fn d(&self, theta: f64, phi: f64) -> f64 {
        let (s2, c2) = (theta.sin().powi(2), theta.cos().powi(2));
        let e = phi.cos().powi(2) / self.alpha_x.powi(2) + phi.sin().powi(2) / self.alpha_y.powi(2);
        1.0 / (PI * self.alpha_x * self.alpha_y * (c2 + s2 * e).powi(2))
    }

    pub fn sigma(&self, theta: f64, phi: f64) -> f64 {
        let a2 = (self.alpha_x * phi.cos()).powi(2) + (self.alpha_y * phi.sin()).powi(2);
        let c = theta.cos().max(0.0);
        0.5 * (c + (c * c + a2 * theta.sin().powi(2)).sqrt())
    }

    fn theta_i(&self) -> Vec<f32> {
        (0..N_THETA_I)
            .map(|k| (k as f64 / (N_THETA_I - 1) as f64 * 85f64.to_radians()) as f32)
            .collect()
    }

    fn phi_i(&self) -> Vec<f32> {
        if self.anisotropic {
            (0..N_PHI_I)
                .map(|k| (-PI + 2.0 * PI * k as f64 / (N_PHI_I - 1) as f64) as f32)
                .collect()
        } else {
            vec![0.0]
        }
    }

    /// The factor of the spectra at a point of the warped domain.
    fn variation(&self, x: f64, y: f64, theta_i: f64) -> f64 {
        if self.varying {
            0.5 + 0.8 * x * (1.0 - y) + 0.2 * theta_i.sin()
        } else {
            1.0
        }
    }

    /// A table over the unit square at `n` × `n` grid points, y rows.
    fn grid(n: usize, f: impl Fn(f64, f64) -> f64) -> Vec<f32> {
        let at = move |k: usize| k as f64 / (n - 1) as f64;
        (0..n)
            .flat_map(|j| (0..n).map(move |i| (at(i), at(j))))
            .map(|(x, y)| f(x, y) as f32)
            .collect()
    }

    /// The tensor file's fields.
    pub fn fields(&self) -> Vec<(&'static str, DType, Vec<usize>, Vec<u8>)> {
        let (theta_i, phi_i) = (self.theta_i(), self.phi_i());
        let to_theta = |x: f64| x * x * PI / 2.0;
        let to_phi = |y: f64| (2.0 * y - 1.0) * PI;
        let ndf = Self::grid(N_NDF, |x, y| self.d(to_theta(x), to_phi(y)));
        let sigma = Self::grid(N_NDF, |x, y| self.sigma(to_theta(x), to_phi(y)));
        let (mut vndf, mut luminance, mut spectra) = (Vec::new(), Vec::new(), Vec::new());
        for &phi in &phi_i {
            for &theta in &theta_i {
                let (phi, theta) = (phi as f64, theta as f64);
                let wi = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    (theta.sin() * phi.sin()) as f32,
                    theta.cos() as f32,
                );
                vndf.extend(Self::grid(N_VNDF, |x, y| {
                    let (tm, mut pm) = (to_theta(x), to_phi(y));
                    if !self.anisotropic {
                        pm += phi;
                    }
                    let wm = Vec3::new(
                        (tm.sin() * pm.cos()) as f32,
                        (tm.sin() * pm.sin()) as f32,
                        tm.cos() as f32,
                    );
                    self.d(tm, pm) * (wi.dot(wm) as f64).max(0.0) * 2.0 * PI * PI * x * tm.sin()
                }));
                let mean =
                    self.values.iter().map(|&v| v as f64).sum::<f64>() / self.values.len() as f64;
                luminance.extend(Self::grid(N_WARPED, |x, y| {
                    mean * self.variation(x, y, theta)
                }));
                for &value in &self.values {
                    spectra.extend(Self::grid(N_WARPED, |x, y| {
                        value as f64 * self.variation(x, y, theta)
                    }));
                }
            }
        }
        let (np, nt, nl) = (phi_i.len(), theta_i.len(), self.wavelengths.len());
        vec![
            ("description", DType::U8, vec![9], b"synthetic".to_vec()),
            ("jacobian", DType::U8, vec![1], vec![1]),
            ("theta_i", DType::F32, vec![nt], f32_bytes(&theta_i)),
            ("phi_i", DType::F32, vec![np], f32_bytes(&phi_i)),
            (
                "wavelengths",
                DType::F32,
                vec![nl],
                f32_bytes(&self.wavelengths),
            ),
            ("ndf", DType::F32, vec![N_NDF, N_NDF], f32_bytes(&ndf)),
            ("sigma", DType::F32, vec![N_NDF, N_NDF], f32_bytes(&sigma)),
            (
                "vndf",
                DType::F32,
                vec![np, nt, N_VNDF, N_VNDF],
                f32_bytes(&vndf),
            ),
            (
                "luminance",
                DType::F32,
                vec![np, nt, N_WARPED, N_WARPED],
                f32_bytes(&luminance),
            ),
            (
                "spectra",
                DType::F32,
                vec![np, nt, nl, N_WARPED, N_WARPED],
                f32_bytes(&spectra),
            ),
        ]
    }

    pub fn bytes(&self) -> Vec<u8> {
        encode(&self.fields())
    }

    /// The file's tables, leaked (a BxDF holds them by `'static`
    /// reference, as the material's cache keeps them).
    pub fn data(&self) -> &'static MeasuredBxDFData {
        let file = super::tensor_file::TensorFile::parse(&self.bytes()).unwrap();
        Box::leak(Box::new(MeasuredBxDFData::from_tensor(&file).unwrap()))
    }

    /// (1/σ(ωo)) ∫ D(ωm) ⟨ωo · ωm⟩ [reflect(ωo, ωm) above] dωm, by the
    /// midpoint rule on a fine θ × φ grid.
    pub fn visible_reflecting_fraction(&self, wo: Vec3) -> f64 {
        let wo = wo.as_dvec3();
        let (nt, np) = (2000, 800);
        let (dt, dp) = (PI / 2.0 / nt as f64, 2.0 * PI / np as f64);
        let mut sum = 0.0;
        for i in 0..nt {
            let t = (i as f64 + 0.5) * dt;
            for j in 0..np {
                let p = (j as f64 + 0.5) * dp;
                let m = glam::DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
                let c = wo.dot(m);
                let wi_z = 2.0 * c * m.z - wo.z;
                if c > 0.0 && wi_z > 0.0 {
                    sum += self.d(t, p) * c * t.sin();
                }
            }
        }
        sum * dt * dp / self.sigma(wo.z.acos(), wo.y.atan2(wo.x))
    }
}
