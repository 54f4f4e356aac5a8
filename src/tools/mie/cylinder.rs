//! The Lorenz–Mie series for a homogeneous infinite circular cylinder lit
//! by a plane wave at any angle to its axis (Bohren & Huffman 1983, "B&H",
//! §8.4 for oblique incidence, §8.3–8.4 for normal incidence as its special
//! case): the scattering coefficients a_n, b_n of both incident
//! polarisations and the efficiencies they give.
//!
//! Conventions. The incident direction makes the hair longitudinal angle
//! θ_i with the plane normal to the axis (θ_i = 0: normal incidence), so
//! B&H's angle to the axis is ζ = 90° − θ_i. Case I is the incident
//! electric field in the plane of the axis and the incident direction
//! (TM at normal incidence, E ∥ axis), case II perpendicular to it (TE).
//! Efficiencies are B&H's: cross-section per unit length over the diameter
//! (C/(2aL)), so for large x, Q_ext → 2 cos θ_i (the shadow of a length L
//! seen obliquely is 2aL cos θ_i).

use super::bessel::{bessel_j_sequence, bessel_y_sequence, log_derivative_sequence};
use num_complex::Complex64;
use thiserror::Error;

/// Invalid input to the cylinder series.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MieError {
    #[error("the diameter must be a positive number of micrometres, got {0}")]
    Diameter(f64),
    #[error("the refractive index eta must be positive, got {0}")]
    Eta(f64),
    #[error("the absorption index kappa must be zero or positive, got {0}")]
    Kappa(f64),
    #[error("the wavelength must be a positive number of nanometres, got {0}")]
    Wavelength(f64),
    #[error("theta_i must lie strictly between -90 and 90 degrees, got {0} degrees")]
    IncidenceAngle(f64),
    #[error(
        "{angle_count} angles cannot resolve the {order_count} orders of the series \
         (at least {minimum} even angles are needed)"
    )]
    TooFewAngles {
        angle_count: usize,
        order_count: usize,
        minimum: usize,
    },
    #[error(
        "the wavelength range {min_nm}–{max_nm} nm with step {step_nm} nm is empty or invalid"
    )]
    WavelengthRange {
        min_nm: f64,
        max_nm: f64,
        step_nm: f64,
    },
}

/// A homogeneous circular cylinder in vacuum (or air): its diameter and
/// complex refractive index m = η + iκ relative to the surroundings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    /// Diameter, µm.
    pub diameter_um: f64,
    /// Real part of the refractive index.
    pub eta: f64,
    /// Imaginary part of the refractive index (absorption index, ≥ 0).
    pub kappa: f64,
}

impl Cylinder {
    /// A cylinder after checking its values.
    pub fn new(diameter_um: f64, eta: f64, kappa: f64) -> Result<Self, MieError> {
        let cylinder = Self {
            diameter_um,
            eta,
            kappa,
        };
        cylinder.validate()?;
        Ok(cylinder)
    }

    /// Checks the values (the fields are public, so [`coefficients`]
    /// checks again).
    pub fn validate(&self) -> Result<(), MieError> {
        if !(self.diameter_um.is_finite() && self.diameter_um > 0.0) {
            return Err(MieError::Diameter(self.diameter_um));
        }
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return Err(MieError::Eta(self.eta));
        }
        if !(self.kappa.is_finite() && self.kappa >= 0.0) {
            return Err(MieError::Kappa(self.kappa));
        }
        Ok(())
    }

    /// m = η + iκ.
    pub fn refractive_index(&self) -> Complex64 {
        Complex64::new(self.eta, self.kappa)
    }

    /// The size parameter x = ka = πD/λ.
    pub fn size_parameter(&self, wavelength_nm: f64) -> f64 {
        std::f64::consts::PI * self.diameter_um * 1000.0 / wavelength_nm
    }
}

/// Extinction, scattering and absorption efficiencies (B&H's, per 2aL).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Efficiencies {
    pub q_ext: f64,
    pub q_sca: f64,
    pub q_abs: f64,
}

impl Efficiencies {
    /// The mean of two (unpolarised light is the mean of cases I and II).
    pub fn mean(&self, other: &Self) -> Self {
        Self {
            q_ext: 0.5 * (self.q_ext + other.q_ext),
            q_sca: 0.5 * (self.q_sca + other.q_sca),
            q_abs: 0.5 * (self.q_abs + other.q_abs),
        }
    }

    /// `self + weight · other`, for weighted averages.
    pub fn add_weighted(&self, other: &Self, weight: f64) -> Self {
        Self {
            q_ext: self.q_ext + weight * other.q_ext,
            q_sca: self.q_sca + weight * other.q_sca,
            q_abs: self.q_abs + weight * other.q_abs,
        }
    }

    /// Every efficiency times `factor`.
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            q_ext: self.q_ext * factor,
            q_sca: self.q_sca * factor,
            q_abs: self.q_abs * factor,
        }
    }
}

/// Efficiencies of both incident polarisations and of unpolarised light.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PolarisedEfficiencies {
    /// Incident E in the plane of the axis and the incident direction.
    pub case_i: Efficiencies,
    /// Incident E perpendicular to that plane.
    pub case_ii: Efficiencies,
    /// The mean of the two.
    pub unpolarised: Efficiencies,
}

/// The scattering coefficients for orders n = 0..=n_max (those of negative
/// order follow by parity: b_{−n,I} = b_{n,I}, a_{−n,II} = a_{n,II},
/// a_{−n,I} = −a_{n,I}, b_{−n,II} = −b_{n,II}, since D_n and C_n below are
/// odd in n and every other factor even).
#[derive(Debug, Clone, PartialEq)]
pub struct Coefficients {
    /// x = ka.
    pub size_parameter: f64,
    /// θ_i, radians.
    pub theta_i_rad: f64,
    /// a_{n,I}: case I scattered into the cross polarisation (0 at normal
    /// incidence).
    pub a_case_i: Vec<Complex64>,
    /// b_{n,I}: case I, co-polarised.
    pub b_case_i: Vec<Complex64>,
    /// a_{n,II}: case II, co-polarised.
    pub a_case_ii: Vec<Complex64>,
    /// b_{n,II}: case II scattered into the cross polarisation (0 at
    /// normal incidence).
    pub b_case_ii: Vec<Complex64>,
}

/// The highest order kept for the argument ξ = x cos θ_i of the outer
/// Bessel functions: Wiscombe's/B&H's n_max = ξ + 4ξ^{1/3} + 2,
/// beyond which the coefficients fall off faster than exponentially
/// (J_n(x)/Y_n(x) in the evanescent region n > x); the test
/// `series_tail_is_negligible` checks the last order's size.
pub fn highest_order(size_parameter: f64) -> usize {
    (size_parameter + 4.0 * size_parameter.cbrt() + 2.0).ceil() as usize
}

/// The scattering coefficients of `cylinder` at `wavelength_nm` for
/// incidence at longitudinal angle `theta_i_rad` (0 = normal incidence).
///
/// B&H (8.30)–(8.31) with ξ = x sin ζ = x cos θ_i and
/// η = x (m² − cos²ζ)^{1/2} = x (m² − sin²θ_i)^{1/2}; every term there is
/// linear in J_n(η) or J_n'(η), so dividing through by J_n(η) leaves only
/// D_n(η) = J_n'(η)/J_n(η), which stays finite where J_n(η) of a complex
/// argument would overflow.
pub fn coefficients(
    cylinder: &Cylinder,
    wavelength_nm: f64,
    theta_i_rad: f64,
) -> Result<Coefficients, MieError> {
    cylinder.validate()?;
    if !(wavelength_nm.is_finite() && wavelength_nm > 0.0) {
        return Err(MieError::Wavelength(wavelength_nm));
    }
    if !(theta_i_rad.is_finite() && theta_i_rad.abs() < std::f64::consts::FRAC_PI_2) {
        return Err(MieError::IncidenceAngle(theta_i_rad.to_degrees()));
    }
    let x = cylinder.size_parameter(wavelength_nm);
    let m = cylinder.refractive_index();
    let cos_zeta = theta_i_rad.sin();
    let sin_zeta = theta_i_rad.cos();
    let xi = x * sin_zeta;
    // Principal square root: Re ≥ 0, Im ≥ 0 for κ ≥ 0, the wave inside
    // decaying away from the surface.
    let eta = x * (m * m - cos_zeta * cos_zeta).sqrt();
    // The series converges once J_n(ξ)/Y_n(ξ) dies off, past n ≈ ξ: near
    // grazing incidence ξ ≪ x, and orders up to x would overflow Y_n(ξ).
    let n_max = highest_order(xi);
    let bessel_j = bessel_j_sequence(xi, n_max + 1);
    let bessel_y = bessel_y_sequence(xi, &bessel_j, n_max);
    let log_derivative = log_derivative_sequence(eta, n_max);
    let i = Complex64::i();
    let m_squared = m * m;
    let radial_mismatch = xi * xi / (eta * eta) - 1.0;
    let mut result = Coefficients {
        size_parameter: x,
        theta_i_rad,
        a_case_i: Vec::with_capacity(n_max + 1),
        b_case_i: Vec::with_capacity(n_max + 1),
        a_case_ii: Vec::with_capacity(n_max + 1),
        b_case_ii: Vec::with_capacity(n_max + 1),
    };
    for n in 0..=n_max {
        let order = n as f64;
        let j = bessel_j[n];
        let y = bessel_y[n];
        // J_n' = J_{n−1} − (n/ξ)J_n, and J_{−1} = −J_1 (A&S 9.1.27, 9.1.5);
        // the same for Y.
        let j_previous = if n == 0 {
            -bessel_j[1]
        } else {
            bessel_j[n - 1]
        };
        let j_derivative = j_previous - order / xi * j;
        let y_derivative = if n == 0 {
            -bessel_y[1]
        } else {
            bessel_y[n - 1] - order / xi * y
        };
        let hankel = Complex64::new(j, y);
        let hankel_derivative = Complex64::new(j_derivative, y_derivative);
        let d_eta = log_derivative[n];
        // B&H (8.30)'s A_n … W_n, each over J_n(η).
        let coupling = order * cos_zeta * eta * radial_mismatch;
        let d_n = coupling * hankel;
        let c_n = coupling * j;
        let b_n = xi * (m_squared * xi * d_eta * j - eta * j_derivative);
        let v_n = xi * (m_squared * xi * d_eta * hankel - eta * hankel_derivative);
        let w_n = i * xi * (eta * hankel_derivative - xi * d_eta * hankel);
        let a_n = i * xi * (xi * d_eta * j - eta * j_derivative);
        let denominator = w_n * v_n + i * d_n * d_n;
        result.a_case_i.push((c_n * v_n - b_n * d_n) / denominator);
        result
            .b_case_i
            .push((w_n * b_n + i * d_n * c_n) / denominator);
        result
            .a_case_ii
            .push(-(a_n * v_n - i * c_n * d_n) / denominator);
        result
            .b_case_ii
            .push(-i * (c_n * w_n + a_n * d_n) / denominator);
    }
    Ok(result)
}

impl Coefficients {
    /// n_max + 1.
    pub fn order_count(&self) -> usize {
        self.b_case_i.len()
    }

    /// B&H (8.38)–(8.39): Q_ext from the forward amplitude (the optical
    /// theorem), Q_sca from the sum of squares (Parseval over the
    /// scattering azimuth), Q_abs their difference.
    pub fn efficiencies(&self) -> PolarisedEfficiencies {
        let two_over_x = 2.0 / self.size_parameter;
        let sum_over_all_orders = |values: &[Complex64]| -> Complex64 {
            values[0] + 2.0 * values[1..].iter().sum::<Complex64>()
        };
        let squares_over_all_orders = |values: &[Complex64]| -> f64 {
            values[0].norm_sqr() + 2.0 * values[1..].iter().map(|c| c.norm_sqr()).sum::<f64>()
        };
        let efficiencies = |co: &[Complex64], cross: &[Complex64]| {
            let q_ext = two_over_x * sum_over_all_orders(co).re;
            let q_sca = two_over_x * (squares_over_all_orders(co) + squares_over_all_orders(cross));
            Efficiencies {
                q_ext,
                q_sca,
                q_abs: q_ext - q_sca,
            }
        };
        let case_i = efficiencies(&self.b_case_i, &self.a_case_i);
        let case_ii = efficiencies(&self.a_case_ii, &self.b_case_ii);
        PolarisedEfficiencies {
            case_i,
            case_ii,
            unpolarised: case_i.mean(&case_ii),
        }
    }
}

#[cfg(test)]
mod tests;
