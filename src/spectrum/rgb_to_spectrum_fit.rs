//! Fitting a sigmoid-polynomial spectrum to an RGB (Jakob & Hanika 2019,
//! "A Low-Dimensional Function Space for Efficient Spectral Upsampling").
//!
//! For a target RGB in a colour space, find c = (c0, c1, c2) such that the
//! reflectance s(λ) = sigmoid(c0 t² + c1 t + c2), t = (λ − 360)/470, seen
//! under the space's illuminant has that RGB. The mismatch is measured in
//! CIELab (perceptually even, so dark colours count as much as bright
//! ones) and minimised by Gauss–Newton with an analytic Jacobian.

use glam::{DMat3, DVec3};

use super::cie::{cie_xyz, CIE_Y_INTEGRAL};
use super::densely_sampled::DenselySampled;
use super::sampled::{LAMBDA_MAX, LAMBDA_MIN};
use super::sigmoid_polynomial::RgbSigmoidPolynomial;

/// Gauss–Newton iterations per fit at most (warm starts usually need 2–4).
const MAX_ITERATIONS: usize = 15;
/// Stop once the squared Lab error is below this (ΔE < 0.001).
const CONVERGED_SQUARED_LAB_ERROR: f64 = 1e-6;
/// Coefficients larger than this are scaled back, as pbrt-v4's fitter
/// does. Kept at pbrt's value so that tables (and so renders) agree with
/// pbrt's, although it leaves a few near-white yellows, whose exact fit
/// needs a slightly larger coefficient, off by up to ~4e-2 in blue.
const MAX_COEFFICIENT: f64 = 200.0;

/// Quadrature samples are processed this many at a time, in independent
/// lanes the compiler turns into SIMD. The per-sample work (a square root
/// and a division) runs in f32, which vectorises 4-wide and makes the whole
/// table about 4× faster to fit than f64; sums of a few hundred f32 terms
/// are accurate to ~1e-7, far below the ΔE 1e-3 the fit stops at, and the
/// lanes are totalled in f64.
const LANES: usize = 8;

/// What a fit needs to know about the colour space: how a reflectance
/// becomes XYZ under its illuminant, and how its RGBs become XYZ.
#[derive(Clone, Debug)]
pub struct FitProblem {
    /// Normalised wavelength t ∈ [0, 1] of each quadrature sample, in
    /// chunks of [`LANES`] (the last padded with zero weights).
    t: Vec<[f32; LANES]>,
    /// (x̄, ȳ, z̄)(λ) · illuminant(λ) · dλ / ∫ȳ at each sample, one array per
    /// component: XYZ of a reflectance is Σ weight · s(λ).
    weight_x: Vec<[f32; LANES]>,
    weight_y: Vec<[f32; LANES]>,
    weight_z: Vec<[f32; LANES]>,
    xyz_from_rgb: DMat3,
    /// XYZ of a perfect white reflector: the Lab reference white.
    white: DVec3,
}

impl FitProblem {
    /// The problem for a colour space with this illuminant and RGB → XYZ
    /// matrix. XYZ is computed exactly as the renderer does (1 nm sums of
    /// the nearest-nanometre tables, divided by ∫ȳ), so RGB (1, 1, 1) is
    /// the white of a constant-1 reflectance.
    pub fn new(illuminant: &DenselySampled, xyz_from_rgb: DMat3) -> Self {
        let mut t = Vec::new();
        let mut weights = Vec::new();
        let mut white = DVec3::ZERO;
        for l in LAMBDA_MIN as i32..=LAMBDA_MAX as i32 {
            let lambda = l as f32;
            let weight = cie_xyz(lambda).as_dvec3() * f64::from(illuminant.eval(lambda))
                / f64::from(CIE_Y_INTEGRAL);
            t.push(
                (f64::from(lambda) - f64::from(LAMBDA_MIN)) / f64::from(LAMBDA_MAX - LAMBDA_MIN),
            );
            weights.push(weight);
            white += weight;
        }
        let chunk = |values: Vec<f64>| -> Vec<[f32; LANES]> {
            values
                .chunks(LANES)
                .map(|c| std::array::from_fn(|i| c.get(i).map_or(0.0, |&v| v as f32)))
                .collect()
        };
        FitProblem {
            t: chunk(t),
            weight_x: chunk(weights.iter().map(|w| w.x).collect()),
            weight_y: chunk(weights.iter().map(|w| w.y).collect()),
            weight_z: chunk(weights.iter().map(|w| w.z).collect()),
            xyz_from_rgb,
            white,
        }
    }

    /// XYZ of the reflectance with normalised coefficients `c`, and its
    /// derivative with respect to them (columns: ∂/∂c0, ∂/∂c1, ∂/∂c2).
    fn xyz_and_jacobian(&self, c: DVec3) -> (DVec3, DMat3) {
        type Lanes = [f32; LANES];
        let c = c.as_vec3();
        let zero: Lanes = [0.0; LANES];
        // Per-lane sums: XYZ, and XYZ-weighted s'(x)·t², s'(x)·t, s'(x).
        let (mut sx, mut sy, mut sz) = (zero, zero, zero);
        let (mut ax, mut ay, mut az) = (zero, zero, zero);
        let (mut bx, mut by, mut bz) = (zero, zero, zero);
        let (mut dx, mut dy, mut dz) = (zero, zero, zero);
        let chunks = self
            .t
            .iter()
            .zip(&self.weight_x)
            .zip(&self.weight_y)
            .zip(&self.weight_z);
        for (((t, wx), wy), wz) in chunks {
            let mut s: Lanes = zero;
            let mut ds: Lanes = zero;
            for i in 0..LANES {
                let x = (c.x * t[i] + c.y) * t[i] + c.z;
                let inv_root = 1.0 / (1.0 + x * x).sqrt();
                s[i] = 0.5 + 0.5 * x * inv_root;
                // d sigmoid / dx = 1 / (2 (1 + x²)^{3/2}).
                ds[i] = 0.5 * inv_root * inv_root * inv_root;
            }
            for i in 0..LANES {
                let ds1 = ds[i] * t[i];
                let ds2 = ds1 * t[i];
                sx[i] += wx[i] * s[i];
                sy[i] += wy[i] * s[i];
                sz[i] += wz[i] * s[i];
                ax[i] += wx[i] * ds2;
                ay[i] += wy[i] * ds2;
                az[i] += wz[i] * ds2;
                bx[i] += wx[i] * ds1;
                by[i] += wy[i] * ds1;
                bz[i] += wz[i] * ds1;
                dx[i] += wx[i] * ds[i];
                dy[i] += wy[i] * ds[i];
                dz[i] += wz[i] * ds[i];
            }
        }
        let total = |l: Lanes| l.iter().map(|&v| f64::from(v)).sum::<f64>();
        let v = |x: Lanes, y: Lanes, z: Lanes| DVec3::new(total(x), total(y), total(z));
        (
            v(sx, sy, sz),
            DMat3::from_cols(v(ax, ay, az), v(bx, by, bz), v(dx, dy, dz)),
        )
    }

    /// CIELab of `xyz` against the reference white, with the derivative
    /// of Lab with respect to XYZ.
    fn lab_and_jacobian(&self, xyz: DVec3) -> (DVec3, DMat3) {
        let (fx, dfx) = lab_f(xyz.x / self.white.x);
        let (fy, dfy) = lab_f(xyz.y / self.white.y);
        let (fz, dfz) = lab_f(xyz.z / self.white.z);
        let lab = DVec3::new(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz));
        let (gx, gy, gz) = (dfx / self.white.x, dfy / self.white.y, dfz / self.white.z);
        // Rows: ∂L, ∂a, ∂b over (∂X, ∂Y, ∂Z); glam takes columns.
        let jacobian = DMat3::from_cols(
            DVec3::new(0.0, 500.0 * gx, 0.0),
            DVec3::new(116.0 * gy, -500.0 * gy, 200.0 * gy),
            DVec3::new(0.0, 0.0, -200.0 * gz),
        );
        (lab, jacobian)
    }

    /// CIELab of an RGB of this colour space.
    fn target_lab(&self, rgb: DVec3) -> DVec3 {
        self.lab_and_jacobian(self.xyz_from_rgb * rgb).0
    }

    /// Refines normalised coefficients `c` (the starting guess: a
    /// neighbouring solution, or zero) towards `rgb`. Returns the refined
    /// coefficients; a singular step leaves the best found so far.
    pub fn fit(&self, rgb: DVec3, mut c: DVec3) -> DVec3 {
        let target = self.target_lab(rgb);
        for _ in 0..MAX_ITERATIONS {
            let (xyz, d_xyz) = self.xyz_and_jacobian(c);
            let (lab, d_lab) = self.lab_and_jacobian(xyz);
            let residual = target - lab;
            if residual.length_squared() < CONVERGED_SQUARED_LAB_ERROR {
                break;
            }
            let jacobian = d_lab * d_xyz;
            let det = jacobian.determinant();
            if !(det.abs() > 1e-15) || !det.is_finite() {
                break;
            }
            let step = jacobian.inverse() * residual;
            if !step.is_finite() {
                break;
            }
            c += step;
            let largest = c.max_element();
            if largest > MAX_COEFFICIENT {
                c *= MAX_COEFFICIENT / largest;
            }
        }
        c
    }

    /// Lab distance between `rgb` and what coefficients `c` reproduce.
    pub fn lab_error(&self, rgb: DVec3, c: DVec3) -> f64 {
        let (xyz, _) = self.xyz_and_jacobian(c);
        (self.target_lab(rgb) - self.lab_and_jacobian(xyz).0).length()
    }
}

/// CIELab's companding function f(t) and its derivative.
fn lab_f(t: f64) -> (f64, f64) {
    const DELTA: f64 = 6.0 / 29.0;
    if t > DELTA * DELTA * DELTA {
        let cube_root = t.cbrt();
        (cube_root, 1.0 / (3.0 * cube_root * cube_root))
    } else {
        let slope = 1.0 / (3.0 * DELTA * DELTA);
        (t * slope + 4.0 / 29.0, slope)
    }
}

/// Converts coefficients over normalised t = (λ − 360)/470 into the
/// polynomial in λ (nm) that evaluation uses.
pub fn to_wavelength_polynomial(c: DVec3) -> RgbSigmoidPolynomial {
    let offset = f64::from(LAMBDA_MIN);
    let inv_span = 1.0 / f64::from(LAMBDA_MAX - LAMBDA_MIN);
    let (a, b, k) = (c.x, c.y, c.z);
    RgbSigmoidPolynomial::new(
        (a * inv_span * inv_span) as f32,
        (b * inv_span - 2.0 * a * offset * inv_span * inv_span) as f32,
        (k - b * offset * inv_span + a * (offset * inv_span).powi(2)) as f32,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::sigmoid_polynomial::sigmoid;

    fn srgb_problem() -> FitProblem {
        let cs = crate::spectrum::color_space::get(crate::scene_description::ColorSpaceName::Srgb);
        FitProblem::new(cs.illuminant_densely_sampled(), cs.xyz_from_rgb.as_dmat3())
    }

    #[test]
    fn analytic_jacobian_matches_finite_differences() {
        let p = srgb_problem();
        let c = DVec3::new(-3.0, 2.5, -0.4);
        let (_, jacobian) = p.xyz_and_jacobian(c);
        // The sums run in f32, so the step must be well above its noise.
        let h = 1e-3;
        for axis in 0..3 {
            let mut dc = DVec3::ZERO;
            dc[axis] = h;
            let numeric = (p.xyz_and_jacobian(c + dc).0 - p.xyz_and_jacobian(c - dc).0) / (2.0 * h);
            let analytic = jacobian.col(axis);
            let error = (numeric - analytic).abs().max_element() / analytic.abs().max_element();
            assert!(error < 1e-3, "{numeric} vs {analytic}");
        }
    }

    #[test]
    fn fits_reproduce_their_rgb() {
        let p = srgb_problem();
        for rgb in [
            DVec3::new(0.8, 0.2, 0.1),
            DVec3::new(0.1, 0.6, 0.3),
            DVec3::new(0.05, 0.1, 0.7),
            DVec3::new(0.5, 0.5, 0.4),
        ] {
            // Walk up from a dim version, as the table builder does.
            let mut c = DVec3::ZERO;
            for step in 1..=8 {
                c = p.fit(rgb * (f64::from(step) / 8.0), c);
            }
            let error = p.lab_error(rgb, c);
            assert!(error < 1e-2, "{rgb}: ΔE {error}");
        }
    }

    #[test]
    fn wavelength_polynomial_is_the_same_function() {
        let c = DVec3::new(-12.0, 9.0, -1.5);
        let poly = to_wavelength_polynomial(c);
        for lambda in [360.0_f32, 455.5, 600.0, 830.0] {
            let t = (f64::from(lambda) - 360.0) / 470.0;
            let expected = sigmoid(((c.x * t + c.y) * t + c.z) as f32);
            assert!((poly.eval(lambda) - expected).abs() < 1e-5, "{lambda}");
        }
    }
}
