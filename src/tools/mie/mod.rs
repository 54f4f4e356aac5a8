//! `rpbrt mie`: exact scattering of a plane wave by a homogeneous circular
//! cylinder (Lorenz–Mie theory for cylinders; Bohren & Huffman 1983, ch. 8,
//! with §8.4's oblique incidence), the wave-optics reference the dual hair
//! model is measured against (issue 30).
//!
//! The library side ([`Cylinder`], [`coefficients`], [`angular_density`],
//! [`spectral_average`]) is what `rpbrt bcsdf --compare-mie` calls; this
//! file is the command: it writes the density over the scattering angle
//! (`theta_deg,density`, 0 = forward, per radian, integrating to 1) and
//! prints the efficiencies.

pub mod bessel;
pub mod cylinder;
pub mod spectral;

pub use cylinder::{
    coefficients, highest_order, Coefficients, Cylinder, Efficiencies, MieError,
    PolarisedEfficiencies,
};
pub use spectral::{
    angular_density, angular_intensity, minimum_angle_count, spectral_average, AngularDensity,
    SpectralOptions, DEFAULT_ANGLE_COUNT,
};

use std::fmt::Write as _;
use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};

/// Options of `rpbrt mie`.
#[derive(clap::Args, Clone, Debug)]
pub struct MieArgs {
    /// Fibre diameter, µm.
    #[arg(long, allow_hyphen_values = true, default_value_t = 75.0)]
    pub diameter: f64,
    /// Real part of the refractive index.
    #[arg(long, allow_hyphen_values = true, default_value_t = 1.55)]
    pub eta: f64,
    /// Absorption index: the imaginary part of the refractive index.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub kappa: f64,
    /// Longitudinal angle of the light from the plane normal to the axis,
    /// degrees (0 = normal incidence).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub theta_i: f64,
    /// One wavelength (nm) instead of the CIE ȳ-weighted average over
    /// 380–780 nm.
    #[arg(long, allow_hyphen_values = true)]
    pub wavelength: Option<f64>,
    /// Wavelength step of the spectral average, nm.
    #[arg(long, allow_hyphen_values = true, default_value_t = 1.0)]
    pub wavelength_step: f64,
    /// Number of scattering angles over the full circle (even; at least
    /// twice the number of orders of the series).
    #[arg(long, default_value_t = DEFAULT_ANGLE_COUNT)]
    pub angles: usize,
    /// Writes the density: columns theta_deg,density.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Writes the efficiencies (Q_ext, Q_sca, Q_abs per polarisation).
    #[arg(long)]
    pub efficiencies: Option<PathBuf>,
}

/// Runs the tool.
pub fn run(args: &MieArgs) -> Result<(), String> {
    let cylinder = Cylinder::new(args.diameter, args.eta, args.kappa).map_err(|e| e.to_string())?;
    if !(args.theta_i.is_finite() && args.theta_i.abs() < 90.0) {
        return Err(MieError::IncidenceAngle(args.theta_i).to_string());
    }
    let theta_i_rad = args.theta_i.to_radians();
    let started = std::time::Instant::now();
    let (density, description) = match args.wavelength {
        Some(wavelength_nm) => (
            angular_density(&cylinder, wavelength_nm, theta_i_rad, args.angles)
                .map_err(|e| e.to_string())?,
            format!("λ = {wavelength_nm} nm"),
        ),
        None => {
            let options = SpectralOptions {
                step_nm: args.wavelength_step,
                angle_count: args.angles,
                ..SpectralOptions::default()
            };
            let count = options.wavelengths_nm().map_err(|e| e.to_string())?.len();
            let bar = super::progress_bar(
                count as u64,
                "{bar:30} {pos}/{len} wavelengths, {elapsed}",
                std::io::stderr().is_terminal(),
            );
            let density = spectral_average(&cylinder, theta_i_rad, &options, &|| bar.inc(1))
                .map_err(|e| e.to_string())?;
            bar.finish_and_clear();
            (
                density,
                format!(
                    "CIE ȳ-weighted over {}–{} nm, {} wavelengths",
                    options.min_nm, options.max_nm, count
                ),
            )
        }
    };
    let q = density.efficiencies;
    eprintln!(
        "D = {} µm, m = {} + {}i, θ_i = {}°, {description} ({:.2} s)",
        args.diameter,
        args.eta,
        args.kappa,
        args.theta_i,
        started.elapsed().as_secs_f64()
    );
    for (name, e) in [
        ("case I", q.case_i),
        ("case II", q.case_ii),
        ("unpolarised", q.unpolarised),
    ] {
        eprintln!(
            "  {name:<12} Q_ext {:.6}  Q_sca {:.6}  Q_abs {:.6}",
            e.q_ext, e.q_sca, e.q_abs
        );
    }
    eprintln!(
        "  energy within ±1° {:.4}, ±5° {:.4}, backward half {:.4}, forward FWHM {:.4}°",
        density.energy_within(1f64.to_radians()),
        density.energy_within(5f64.to_radians()),
        density.backward_fraction(),
        density.forward_fwhm_rad().to_degrees()
    );
    if let Some(path) = &args.csv {
        write_file(path, &density_csv(&density))?;
    }
    if let Some(path) = &args.efficiencies {
        write_file(path, &efficiencies_csv(&q))?;
    }
    Ok(())
}

/// `theta_deg,density`, one row per grid angle from −180° upwards.
pub fn density_csv(density: &AngularDensity) -> String {
    let mut text = String::with_capacity(32 * density.density.len());
    text.push_str("theta_deg,density\n");
    for (index, value) in density.density.iter().enumerate() {
        // Writing to a String cannot fail.
        let _ = writeln!(
            text,
            "{:.6},{:.9e}",
            density.angle_rad(index).to_degrees(),
            value
        );
    }
    text
}

/// `polarisation,q_ext,q_sca,q_abs` for case I, case II and unpolarised.
pub fn efficiencies_csv(q: &PolarisedEfficiencies) -> String {
    let mut text = String::from("polarisation,q_ext,q_sca,q_abs\n");
    for (name, e) in [
        ("I", q.case_i),
        ("II", q.case_ii),
        ("unpolarised", q.unpolarised),
    ] {
        let _ = writeln!(
            text,
            "{name},{:.12},{:.12},{:.12}",
            e.q_ext, e.q_sca, e.q_abs
        );
    }
    text
}

fn write_file(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}
