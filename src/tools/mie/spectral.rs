//! The angular distribution of the light a cylinder scatters, at one
//! wavelength or averaged over the visible spectrum weighted by CIE ȳ.
//!
//! The far-field amplitudes are Fourier series in the scattering azimuth Θ
//! around the cone of scattered directions (B&H (8.34)–(8.37) for normal
//! incidence, §8.4 for oblique):
//!   T_1(Θ) = Σ_n b_{n,I} e^{inΘ},  T_3(Θ) = Σ_n a_{n,I} e^{inΘ},
//!   T_2(Θ) = Σ_n a_{n,II} e^{inΘ}, T_4(Θ) = Σ_n b_{n,II} e^{inΘ},
//! over all integers n (negative orders by the parities of
//! [`Coefficients`]); Θ = 0 is forward (straight on, along the cone; hair's
//! φ_o − φ_i − π = 0). Unpolarised light scatters
//! I(Θ) = (|T_1|² + |T_2|² + |T_3|² + |T_4|²)/2 per unit Θ, with
//! Q_sca = (1/πx)∫ I dΘ. Each series is summed on a uniform grid by one
//! inverse FFT: the Fourier coefficients of |T|² would need a convolution
//! per wavelength, the FFT of T is O(M log M).

use super::cylinder::{
    coefficients, Coefficients, Cylinder, Efficiencies, MieError, PolarisedEfficiencies,
};
use num_complex::Complex64;
use rayon::prelude::*;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::PI;
use std::sync::Arc;

/// Default number of scattering angles: 2^16, a spacing of 0.0055°, so a
/// forward peak of FWHM 0.28° (D = 100 µm) spans ~50 samples.
pub const DEFAULT_ANGLE_COUNT: usize = 1 << 16;

/// A normalised density over the scattering azimuth Θ ∈ [−π, π) on the
/// uniform grid Θ_j = −π + 2πj/M, with the efficiencies it came with.
#[derive(Debug, Clone, PartialEq)]
pub struct AngularDensity {
    /// Density per radian at Θ_j; Σ_j density_j · 2π/M = 1.
    pub density: Vec<f64>,
    /// Efficiencies (at one wavelength, or ȳ-weighted means).
    pub efficiencies: PolarisedEfficiencies,
}

impl AngularDensity {
    /// Θ_j, radians.
    pub fn angle_rad(&self, index: usize) -> f64 {
        -PI + 2.0 * PI * index as f64 / self.density.len() as f64
    }

    /// The grid spacing, radians.
    pub fn spacing_rad(&self) -> f64 {
        2.0 * PI / self.density.len() as f64
    }

    /// The fraction of the scattered energy with |Θ| ≤ `half_width_rad`.
    pub fn energy_within(&self, half_width_rad: f64) -> f64 {
        self.energy_where(|theta| theta.abs() <= half_width_rad)
    }

    /// The fraction scattered into the backward half, |Θ| > 90°.
    pub fn backward_fraction(&self) -> f64 {
        self.energy_where(|theta| theta.abs() > 0.5 * PI)
    }

    fn energy_where(&self, inside: impl Fn(f64) -> bool) -> f64 {
        let spacing = self.spacing_rad();
        (0..self.density.len())
            .filter(|&j| inside(self.angle_rad(j)))
            .map(|j| self.density[j] * spacing)
            .sum()
    }

    /// Full width at half maximum of the forward peak, radians: where the
    /// density first falls below half its value at Θ = 0 on each side
    /// (linear interpolation between grid points).
    pub fn forward_fwhm_rad(&self) -> f64 {
        let count = self.density.len();
        let centre = count / 2; // Θ = 0 (the count is even)
        let half = 0.5 * self.density[centre];
        let mut width = 0.0;
        for direction in [1_isize, -1] {
            let mut step = 1;
            while step < count / 2 {
                let index = (centre as isize + direction * step as isize) as usize;
                let previous = (centre as isize + direction * (step as isize - 1)) as usize;
                if self.density[index] < half {
                    let fraction = (self.density[previous] - half)
                        / (self.density[previous] - self.density[index]);
                    width += (step as f64 - 1.0 + fraction) * self.spacing_rad();
                    break;
                }
                step += 1;
            }
        }
        width
    }
}

/// The smallest (even) angle count that resolves a series of `order_count`
/// orders: T has harmonics −n_max..=n_max, which M ≥ 2n_max + 1 points
/// carry without aliasing; |T|² has harmonics up to 2n_max < M, so the
/// discrete sum of the density is also its exact integral.
pub fn minimum_angle_count(order_count: usize) -> usize {
    2 * order_count
}

fn check_angle_count(angle_count: usize, order_count: usize) -> Result<(), MieError> {
    let minimum = minimum_angle_count(order_count);
    if angle_count < minimum || angle_count % 2 == 1 {
        return Err(MieError::TooFewAngles {
            angle_count,
            order_count,
            minimum,
        });
    }
    Ok(())
}

/// Work buffers for summing the series by FFT on one thread.
struct SeriesSummer {
    fft: Arc<dyn Fft<f64>>,
    buffer: Vec<Complex64>,
    scratch: Vec<Complex64>,
}

impl SeriesSummer {
    fn new(fft: Arc<dyn Fft<f64>>) -> Self {
        let length = fft.len();
        Self {
            scratch: vec![Complex64::new(0.0, 0.0); fft.get_inplace_scratch_len()],
            buffer: vec![Complex64::new(0.0, 0.0); length],
            fft,
        }
    }

    /// Adds `weight` · |Σ_n c_n e^{inΘ_j}|² to `intensity`, with c_n for
    /// n ≥ 0 given and c_{−n} = `parity` · c_n. Θ_j = −π + 2πj/M, so the
    /// series is Σ_n c_n (−1)^n e^{2πinj/M}: an inverse DFT.
    fn add_squared_series(
        &mut self,
        values: &[Complex64],
        parity: f64,
        weight: f64,
        intensity: &mut [f64],
    ) {
        if values.iter().all(|c| c.norm_sqr() == 0.0) {
            return;
        }
        let length = self.buffer.len();
        self.buffer.fill(Complex64::new(0.0, 0.0));
        for (n, &c) in values.iter().enumerate() {
            let shifted = if n % 2 == 0 { c } else { -c };
            self.buffer[n % length] += shifted;
            if n > 0 {
                self.buffer[(length - n % length) % length] += parity * shifted;
            }
        }
        self.fft
            .process_with_scratch(&mut self.buffer, &mut self.scratch);
        for (total, value) in intensity.iter_mut().zip(&self.buffer) {
            *total += weight * value.norm_sqr();
        }
    }

    /// Adds `weight` · I(Θ_j), the unpolarised intensity (module doc).
    fn add_unpolarised(&mut self, coefficients: &Coefficients, weight: f64, intensity: &mut [f64]) {
        let half = 0.5 * weight;
        self.add_squared_series(&coefficients.b_case_i, 1.0, half, intensity);
        self.add_squared_series(&coefficients.a_case_i, -1.0, half, intensity);
        self.add_squared_series(&coefficients.a_case_ii, 1.0, half, intensity);
        self.add_squared_series(&coefficients.b_case_ii, -1.0, half, intensity);
    }
}

fn inverse_fft(angle_count: usize) -> Arc<dyn Fft<f64>> {
    FftPlanner::<f64>::new().plan_fft_inverse(angle_count)
}

/// The unpolarised intensity I(Θ_j) = (|T_1|² + |T_2|² + |T_3|² + |T_4|²)/2
/// on `angle_count` angles (not normalised: its integral is πx·Q_sca).
pub fn angular_intensity(
    coefficients: &Coefficients,
    angle_count: usize,
) -> Result<Vec<f64>, MieError> {
    check_angle_count(angle_count, coefficients.order_count())?;
    let mut intensity = vec![0.0; angle_count];
    SeriesSummer::new(inverse_fft(angle_count)).add_unpolarised(coefficients, 1.0, &mut intensity);
    Ok(intensity)
}

fn normalised(mut values: Vec<f64>) -> Vec<f64> {
    let integral: f64 = values.iter().sum::<f64>() * 2.0 * PI / values.len() as f64;
    if integral > 0.0 {
        for value in &mut values {
            *value /= integral;
        }
    }
    values
}

/// The normalised density of unpolarised light scattered at one
/// wavelength, θ_i from the plane normal to the axis (0 = normal incidence).
pub fn angular_density(
    cylinder: &Cylinder,
    wavelength_nm: f64,
    theta_i_rad: f64,
    angle_count: usize,
) -> Result<AngularDensity, MieError> {
    let coefficients = coefficients(cylinder, wavelength_nm, theta_i_rad)?;
    let intensity = angular_intensity(&coefficients, angle_count)?;
    Ok(AngularDensity {
        density: normalised(intensity),
        efficiencies: coefficients.efficiencies(),
    })
}

/// The wavelengths and grid of a spectral average.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpectralOptions {
    pub min_nm: f64,
    pub max_nm: f64,
    pub step_nm: f64,
    pub angle_count: usize,
}

impl Default for SpectralOptions {
    /// 380–780 nm in 1 nm steps (401 wavelengths), 2^16 angles.
    fn default() -> Self {
        Self {
            min_nm: 380.0,
            max_nm: 780.0,
            step_nm: 1.0,
            angle_count: DEFAULT_ANGLE_COUNT,
        }
    }
}

impl SpectralOptions {
    /// The wavelengths min, min + step, … ≤ max (within rounding).
    pub fn wavelengths_nm(&self) -> Result<Vec<f64>, MieError> {
        let valid = self.min_nm.is_finite()
            && self.max_nm.is_finite()
            && self.step_nm.is_finite()
            && self.min_nm > 0.0
            && self.step_nm > 0.0
            && self.max_nm >= self.min_nm
            && (self.max_nm - self.min_nm) / self.step_nm < 1e6;
        if !valid {
            return Err(MieError::WavelengthRange {
                min_nm: self.min_nm,
                max_nm: self.max_nm,
                step_nm: self.step_nm,
            });
        }
        let count = ((self.max_nm - self.min_nm) / self.step_nm + 1e-9).floor() as usize + 1;
        Ok((0..count)
            .map(|k| self.min_nm + k as f64 * self.step_nm)
            .collect())
    }
}

/// The density of the total scattered light over the spectrum: the
/// intensities C_sca(λ)·density_λ(Θ) (power per unit incident intensity,
/// equal-energy illuminant) summed with weights ȳ(λ), then normalised; and
/// the ȳ-weighted mean efficiencies Σ ȳ Q / Σ ȳ. Wavelengths run in
/// parallel; `on_wavelength_done` is called after each (for a progress bar).
pub fn spectral_average(
    cylinder: &Cylinder,
    theta_i_rad: f64,
    options: &SpectralOptions,
    on_wavelength_done: &(dyn Fn() + Sync),
) -> Result<AngularDensity, MieError> {
    cylinder.validate()?;
    let wavelengths = options.wavelengths_nm()?;
    // The shortest wavelength has the most orders.
    let longest_series = coefficients(cylinder, wavelengths[0], theta_i_rad)?;
    check_angle_count(options.angle_count, longest_series.order_count())?;
    let fft = inverse_fft(options.angle_count);
    let angle_count = options.angle_count;
    struct Partial {
        intensity: Vec<f64>,
        efficiencies: PolarisedEfficiencies,
        weight: f64,
    }
    let empty = || Partial {
        intensity: vec![0.0; angle_count],
        efficiencies: PolarisedEfficiencies::default(),
        weight: 0.0,
    };
    let total = wavelengths
        .par_iter()
        .map_init(
            || SeriesSummer::new(Arc::clone(&fft)),
            |summer, &wavelength_nm| -> Result<Partial, MieError> {
                let mut partial = empty();
                let y_bar = f64::from(crate::spectrum::cie_y(wavelength_nm as f32));
                if y_bar > 0.0 {
                    let coefficients = coefficients(cylinder, wavelength_nm, theta_i_rad)?;
                    let efficiencies = coefficients.efficiencies();
                    // I(Θ) integrates to πx·Q_sca and C_sca = Q_sca·D, so
                    // C_sca·density = D·I/(πx) = λ·I/π² (D cancels).
                    let weight = y_bar * wavelength_nm / (PI * PI);
                    summer.add_unpolarised(&coefficients, weight, &mut partial.intensity);
                    partial.efficiencies =
                        weighted(&PolarisedEfficiencies::default(), &efficiencies, y_bar);
                    partial.weight = y_bar;
                }
                on_wavelength_done();
                Ok(partial)
            },
        )
        .try_reduce(empty, |mut left, right| {
            for (a, b) in left.intensity.iter_mut().zip(&right.intensity) {
                *a += b;
            }
            left.efficiencies = weighted(&left.efficiencies, &right.efficiencies, 1.0);
            left.weight += right.weight;
            Ok(left)
        })?;
    let mean = if total.weight > 0.0 {
        1.0 / total.weight
    } else {
        0.0
    };
    Ok(AngularDensity {
        density: normalised(total.intensity),
        efficiencies: weighted(&PolarisedEfficiencies::default(), &total.efficiencies, mean),
    })
}

/// `base + weight · other`, field by field.
fn weighted(
    base: &PolarisedEfficiencies,
    other: &PolarisedEfficiencies,
    weight: f64,
) -> PolarisedEfficiencies {
    let add = |a: &Efficiencies, b: &Efficiencies| a.add_weighted(b, weight);
    PolarisedEfficiencies {
        case_i: add(&base.case_i, &other.case_i),
        case_ii: add(&base.case_ii, &other.case_ii),
        unpolarised: add(&base.unpolarised, &other.unpolarised),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cylinder(diameter_um: f64, kappa: f64) -> Cylinder {
        Cylinder {
            diameter_um,
            eta: 1.55,
            kappa,
        }
    }

    /// The FFT sum against the series summed term by term at a few
    /// angles, oblique incidence (all four series present).
    #[test]
    fn fft_matches_direct_summation() {
        let theta_i = 40f64.to_radians();
        let c = coefficients(&cylinder(3.0, 0.01), 550.0, theta_i).expect("valid");
        let angle_count = 4096;
        let intensity = angular_intensity(&c, angle_count).expect("enough angles");
        for j in [0, 17, 1000, 2048, 3001] {
            let theta = -PI + 2.0 * PI * j as f64 / angle_count as f64;
            // Σ over all integers n of c_n e^{inΘ} with c_{−n} = ±c_n.
            let series = |values: &[Complex64], parity: f64| -> Complex64 {
                values
                    .iter()
                    .enumerate()
                    .fold(Complex64::new(0.0, 0.0), |sum, (n, &v)| {
                        let positive = Complex64::from_polar(1.0, n as f64 * theta);
                        if n == 0 {
                            sum + v
                        } else {
                            sum + v * (positive + parity * positive.conj())
                        }
                    })
            };
            let expected = 0.5
                * (series(&c.b_case_i, 1.0).norm_sqr()
                    + series(&c.a_case_i, -1.0).norm_sqr()
                    + series(&c.a_case_ii, 1.0).norm_sqr()
                    + series(&c.b_case_ii, -1.0).norm_sqr());
            assert!(
                (intensity[j] - expected).abs() < 1e-9 * expected.max(1.0),
                "Θ = {theta}: {} against {expected}",
                intensity[j]
            );
        }
    }

    /// ∫ I dΘ = πx·Q_sca (Parseval), so the FFT grid carries the whole
    /// series; and the density integrates to 1.
    #[test]
    fn intensity_integrates_to_scattering_efficiency() {
        for theta_i_deg in [0.0_f64, 50.0] {
            let c = coefficients(&cylinder(20.0, 0.002), 600.0, theta_i_deg.to_radians())
                .expect("valid");
            let intensity = angular_intensity(&c, 8192).expect("enough angles");
            let integral: f64 = intensity.iter().sum::<f64>() * 2.0 * PI / 8192.0;
            let expected = PI * c.size_parameter * c.efficiencies().unpolarised.q_sca;
            assert!(
                (integral - expected).abs() < 1e-10 * expected,
                "{integral} against {expected}"
            );
            let density = angular_density(
                &cylinder(20.0, 0.002),
                600.0,
                theta_i_deg.to_radians(),
                8192,
            )
            .expect("valid");
            let total: f64 = density.density.iter().sum::<f64>() * density.spacing_rad();
            assert!((total - 1.0).abs() < 1e-12);
        }
    }

    /// x ≫ 1 without absorption: Q_ext = 2, of which 1 (half the scattered
    /// energy) is the Fraunhofer diffraction peak of angular width ~λ/D;
    /// the rest, refracted and reflected light, goes everywhere. For
    /// D = 60 µm at 550 nm (x ≈ 343) the diffraction lobe's first zero is at
    /// λ/D = 0.5°, so within ±3° there is half the energy plus the small
    /// share of the ray part near forward.
    #[test]
    fn half_the_energy_is_diffracted_forward() {
        let density = angular_density(&cylinder(60.0, 0.0), 550.0, 0.0, 1 << 14).expect("valid");
        let within = density.energy_within(3f64.to_radians());
        assert!((0.5..0.6).contains(&within), "energy within ±3°: {within}");
        let q = density.efficiencies.unpolarised;
        assert!((q.q_sca / q.q_ext - 1.0).abs() < 1e-10);
        // A single slit of width D: the FWHM of sinc² is 0.886 λ/D.
        let fwhm = density.forward_fwhm_rad();
        let fraunhofer = 0.886 * 0.55 / 60.0;
        assert!(
            (fwhm / fraunhofer - 1.0).abs() < 0.05,
            "FWHM {fwhm} against {fraunhofer}"
        );
    }

    #[test]
    fn too_few_angles_are_rejected() {
        let c = coefficients(&cylinder(20.0, 0.0), 500.0, 0.0).expect("valid");
        assert!(matches!(
            angular_intensity(&c, 64),
            Err(MieError::TooFewAngles { .. })
        ));
        assert!(matches!(
            angular_intensity(&c, 100_001),
            Err(MieError::TooFewAngles { .. })
        ));
    }

    /// The spectral average over a single wavelength is that wavelength's
    /// density, and its efficiencies are that wavelength's.
    #[test]
    fn one_wavelength_average_is_the_single_wavelength_density() {
        let cyl = cylinder(5.0, 0.01);
        let options = SpectralOptions {
            min_nm: 550.0,
            max_nm: 550.0,
            step_nm: 1.0,
            angle_count: 4096,
        };
        let average = spectral_average(&cyl, 0.2, &options, &|| {}).expect("valid");
        let single = angular_density(&cyl, 550.0, 0.2, 4096).expect("valid");
        for (a, b) in average.density.iter().zip(&single.density) {
            assert!((a - b).abs() < 1e-12 * b.max(1.0));
        }
        assert!(
            (average.efficiencies.unpolarised.q_ext - single.efficiencies.unpolarised.q_ext).abs()
                < 1e-12
        );
    }
}
