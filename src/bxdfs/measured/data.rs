//! A measured BRDF's tables, made from a `.bsdf` tensor file of the RGL
//! material database (pbrt-v4's `MeasuredBxDFData`; Dupuy & Jakob 2018,
//! "An adaptive parameterization for efficient material acquisition and
//! rendering").
//!
//! The file's fields, as pbrt-v4 requires them (all f32 but where noted;
//! `nφ`, `nθ` the incident directions' grid, `nλ` the wavelengths):
//!
//! | field | shape | what |
//! |---|---|---|
//! | `description` | `[n]` u8 | text, unused |
//! | `jacobian` | `[1]` u8 | a flag; pbrt-v4 requires it and never uses it, nor does rpbrt |
//! | `theta_i`, `phi_i` | `[nθ]`, `[nφ]` | the incident elevations and azimuths (radians) of the conditioned tables |
//! | `wavelengths` | `[nλ]` | nm |
//! | `ndf` | `[ny, nx]` | the microfacet distribution D(ωm) over the unit square (x ↔ θm, y ↔ φm) |
//! | `sigma` | `[ny, nx]` | the projected area σ(ω) = ∫ D(ωm) ⟨ω · ωm⟩ dωm over the unit square |
//! | `vndf` | `[nφ, nθ, ny, nx]` | the visible normals' density, per incident direction |
//! | `luminance` | `[nφ, nθ, n, n]` | the sampling density of the warped domain, per incident direction |
//! | `spectra` | `[nφ, nθ, nλ, n, n]` | the BRDF's spectral factor over the warped domain |
//!
//! A file with at most two azimuths is isotropic (azimuths relative to the
//! incident one); otherwise its azimuths must span the whole circle (pbrt-v4
//! refuses a "reduction", a file holding a fraction of it).
//!
//! Beyond pbrt-v4's checks, rpbrt refuses tables that would make it divide
//! by zero or sample nothing (fewer than 2 × 2 values, a density slice of
//! no mass, incident grids that do not increase): pbrt-v4 would render
//! NaN or crash on those.

use super::tensor_file::{DType, TensorError, TensorFile};
use crate::samplers::piecewise_linear_2d::{PiecewiseLinear2D, TableError, Tabulation};
use std::fmt;

/// Why a tensor file is not a measured BRDF rpbrt can use.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    #[error("{0}")]
    Tensor(#[from] TensorError),
    #[error("field \"{field}\": {error}")]
    Table {
        field: &'static str,
        error: TableError,
    },
    #[error("field \"{field}\" must increase (it does not at index {index})")]
    NotIncreasing { field: &'static str, index: usize },
    #[error("its azimuths cover 1/{0} of the circle: only whole-circle (or isotropic) files are supported, as in pbrt-v4")]
    Reduction(i64),
}

/// The tables of one file.
pub struct MeasuredBxDFData {
    pub(super) wavelengths: Vec<f32>,
    /// Interpolated (not sampled): the spectral factor at (φi, θi, λ).
    pub(super) spectra: PiecewiseLinear2D<3>,
    pub(super) ndf: PiecewiseLinear2D<0>,
    pub(super) sigma: PiecewiseLinear2D<0>,
    /// Densities conditioned on (φi, θi).
    pub(super) vndf: PiecewiseLinear2D<2>,
    pub(super) luminance: PiecewiseLinear2D<2>,
    pub(super) isotropic: bool,
}

impl fmt::Debug for MeasuredBxDFData {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Not the tables: megabytes of numbers.
        f.debug_struct("MeasuredBxDFData")
            .field("wavelengths", &self.wavelengths.len())
            .field("isotropic", &self.isotropic)
            .finish_non_exhaustive()
    }
}

fn table_error(field: &'static str) -> impl Fn(TableError) -> DataError {
    move |error| DataError::Table { field, error }
}

fn shape_error(field: &str, got: &[usize], want: String) -> DataError {
    TensorError::WrongShape {
        field: field.to_string(),
        got: got.to_vec(),
        want,
    }
    .into()
}

/// Checks that a grid of parameter values strictly increases (the
/// interpolation brackets a value by bisection); NaN does not.
fn increasing(field: &'static str, values: &[f32]) -> Result<(), DataError> {
    let increases = |w: &[f32]| w[0].partial_cmp(&w[1]) == Some(std::cmp::Ordering::Less);
    match values.windows(2).position(|w| !increases(w)) {
        Some(i) => Err(DataError::NotIncreasing {
            field,
            index: i + 1,
        }),
        None => Ok(()),
    }
}

impl MeasuredBxDFData {
    /// The tables of a tensor file, checked as pbrt-v4 checks them (and as
    /// the module's documentation adds).
    pub fn from_tensor(file: &TensorFile) -> Result<Self, DataError> {
        file.field_of("description", DType::U8, 1)?;
        let jacobian = file.field_of("jacobian", DType::U8, 1)?;
        if jacobian.shape != [1] {
            return Err(shape_error(
                "jacobian",
                &jacobian.shape,
                "expected [1]".into(),
            ));
        }
        let theta_i = file.field_of("theta_i", DType::F32, 1)?.f32s();
        let phi_i = file.field_of("phi_i", DType::F32, 1)?.f32s();
        let wavelengths = file.field_of("wavelengths", DType::F32, 1)?.f32s();
        let ndf = file.field_of("ndf", DType::F32, 2)?;
        let sigma = file.field_of("sigma", DType::F32, 2)?;
        let vndf = file.field_of("vndf", DType::F32, 4)?;
        let luminance = file.field_of("luminance", DType::F32, 4)?;
        let spectra = file.field_of("spectra", DType::F32, 5)?;

        let (n_phi, n_theta, n_lambda) = (phi_i.len(), theta_i.len(), wavelengths.len());
        let conditioned = |field: &str, shape: &[usize]| {
            if shape[0] != n_phi || shape[1] != n_theta {
                return Err(shape_error(
                    field,
                    shape,
                    format!("expected [{n_phi} (phi_i), {n_theta} (theta_i), ...]"),
                ));
            }
            Ok(())
        };
        conditioned("vndf", &vndf.shape)?;
        conditioned("luminance", &luminance.shape)?;
        conditioned("spectra", &spectra.shape)?;
        if luminance.shape[2] != luminance.shape[3] {
            return Err(shape_error(
                "luminance",
                &luminance.shape,
                "its last two sizes must be equal".into(),
            ));
        }
        let (n, m) = (luminance.shape[2], luminance.shape[3]);
        if spectra.shape[2..] != [n_lambda, n, m] {
            return Err(shape_error(
                "spectra",
                &spectra.shape,
                format!("expected [{n_phi}, {n_theta}, {n_lambda} (wavelengths), {n}, {m} (as luminance)]"),
            ));
        }

        increasing("theta_i", &theta_i)?;
        increasing("phi_i", &phi_i)?;
        increasing("wavelengths", &wavelengths)?;
        let isotropic = n_phi <= 2;
        if !isotropic {
            let span = phi_i[n_phi - 1] - phi_i[0];
            let reduction = (2.0 * std::f32::consts::PI / span).round() as i64;
            if reduction != 1 {
                return Err(DataError::Reduction(reduction));
            }
        }

        let params2 = [phi_i.as_slice(), theta_i.as_slice()];
        Ok(MeasuredBxDFData {
            ndf: PiecewiseLinear2D::new(
                &ndf.f32s(),
                ndf.shape[1],
                ndf.shape[0],
                [],
                Tabulation::Values,
            )
            .map_err(table_error("ndf"))?,
            sigma: PiecewiseLinear2D::new(
                &sigma.f32s(),
                sigma.shape[1],
                sigma.shape[0],
                [],
                Tabulation::Values,
            )
            .map_err(table_error("sigma"))?,
            vndf: PiecewiseLinear2D::new(
                &vndf.f32s(),
                vndf.shape[3],
                vndf.shape[2],
                params2,
                Tabulation::Density,
            )
            .map_err(table_error("vndf"))?,
            luminance: PiecewiseLinear2D::new(
                &luminance.f32s(),
                m,
                n,
                params2,
                Tabulation::Density,
            )
            .map_err(table_error("luminance"))?,
            spectra: PiecewiseLinear2D::new(
                &spectra.f32s(),
                m,
                n,
                [&phi_i, &theta_i, &wavelengths],
                Tabulation::Values,
            )
            .map_err(table_error("spectra"))?,
            wavelengths,
            isotropic,
        })
    }
}
