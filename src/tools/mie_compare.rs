//! `rpbrt bcsdf --compare-mie`: the dual model's azimuthal scattering of a
//! circular fibre measured against the exact wave solution (Lorenz–Mie
//! theory for cylinders, [`super::mie`]).
//!
//! Both sides are densities over the scattering angle Θ ∈ [−π, π) (0 =
//! straight on) on one uniform grid, normalised to 1, averaged over
//! 380–780 nm with CIE ȳ weights. The model's side is the h-averaged ray
//! part (R, TT, TRT and the residual of [`h_averaged_row`], logistic scale
//! s) with weight 1/(1 + d_diff) plus N_diff with weight d_diff/(1 +
//! d_diff), as `rpbrt bcsdf`'s maps; with absorption (κ > 0) its ray part
//! is traced per wavelength with σ_a = 4πκ/λ · r (pbrt's absorption per
//! unit radius) and its albedo is compared with Q_sca/Q_ext.
//!
//! Figures per fibre and model: the energy within ±1° and ±5°, in the
//! backward half and in the primary rainbow's band (155° ≤ |Θ| ≤ 170°),
//! the forward peak's full width at half maximum, and the L1 distance
//! ∫|model − exact| dΘ over all Θ and over |Θ| > 1° (beyond the
//! diffraction peak's core).

use super::mie::cylinder::{Cylinder, Efficiencies};
use super::mie::spectral::{spectral_average, AngularDensity, SpectralOptions};
use super::plot::{log_log_plot, Series};
use crate::bxdfs::hair::trimmed_logistic;
use crate::bxdfs::hair_diffraction::{spectral_integral, ClosedFormLobe, Diffraction};
use crate::bxdfs::hair_ellipse::{
    h_averaged_row, Ellipse, HAveragedMaps, InternalFresnel, Optics, RayModel, Residual, Variant,
};
use crate::spectrum::cie_y;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// `rpbrt bcsdf --compare-mie`'s own options (flattened into
/// `BcsdfArgs`).
#[derive(clap::Args, Clone, Debug)]
pub struct CompareMieArgs {
    /// Instead of the maps: the model for a circular fibre against the
    /// exact Lorenz–Mie solution (`rpbrt mie`), a table of figures per
    /// diameter and model (and with `--out`, plots); the ray lobes'
    /// logistic scale defaults to 0.01 there.
    #[arg(long)]
    pub compare_mie: bool,
    /// With `--compare-mie`: fibre diameters, µm.
    #[arg(long, value_delimiter = ',', default_value = "50,75,100")]
    pub diameters: Vec<f32>,
    /// With `--compare-mie`: the models compared, each `logistic`,
    /// `closedform` or `spectral`, optionally `+polarized`.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "logistic,closedform,spectral"
    )]
    pub models: Vec<String>,
    /// With `--compare-mie`: the absorption index κ (complex index η + iκ).
    #[arg(long, default_value_t = 0.0)]
    pub kappa: f32,
    /// With `--compare-mie`: scattering angles on the circle.
    #[arg(long, default_value_t = 1 << 16)]
    pub angles: usize,
    /// With `--compare-mie`: the exact solution's wavelength step, nm
    /// (its interference ripples fade as the step shrinks: at D = 75 µm
    /// the L1 figures move by 0.0014 from 1 to 0.25 nm, by 0.0001 from
    /// 0.25 to 0.1 nm).
    #[arg(long, default_value_t = 0.25)]
    pub wavelength_step: f32,
    /// With `--compare-mie`: a folder for the table and the plots.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// What `rpbrt bcsdf` shares with the comparison: the index, the
/// incidence (degrees), and the model's d_diff and ray-lobe scale when
/// given.
pub struct Fibre {
    pub eta: f32,
    pub theta_i_deg: f32,
    pub d_diff: Option<f32>,
    pub ray_scale: Option<f32>,
}

/// One model configuration compared: `DIFFRACTION[+polarized][+trrt]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelChoice {
    pub diffraction: Diffraction,
    pub fresnel: InternalFresnel,
    pub residual: Residual,
    pub name: String,
}

/// Parses `--models`: names from `logistic`, `closedform`, `spectral`,
/// each optionally with `+polarized` and `+trrt`.
pub fn parse_models(list: &[String]) -> Result<Vec<ModelChoice>, String> {
    list.iter()
        .map(|name| {
            let mut parts = name.split('+');
            let diffraction = parts.next().unwrap_or_default();
            let (mut polarized, mut trrt) = (false, false);
            for option in parts {
                match option {
                    "polarized" => polarized = true,
                    "trrt" => trrt = true,
                    other => {
                        return Err(format!(
                            "--models: unknown option \"+{other}\" in \"{name}\" (expected +polarized or +trrt)"
                        ))
                    }
                }
            }
            let diffraction = match diffraction {
                "logistic" => Diffraction::Logistic,
                "closedform" => Diffraction::ClosedForm,
                "spectral" => Diffraction::Spectral,
                other => {
                    return Err(format!(
                        "--models: unknown diffraction \"{other}\" (expected logistic, closedform or spectral)"
                    ))
                }
            };
            Ok(ModelChoice {
                diffraction,
                fresnel: if polarized {
                    InternalFresnel::Polarized
                } else {
                    InternalFresnel::Pbrt
                },
                residual: if trrt {
                    Residual::Trrt
                } else {
                    Residual::Uniform
                },
                name: name.clone(),
            })
        })
        .collect()
}

/// What is compared: the fibre (index, absorption index, incidence) and
/// the model's settings shared by every row.
#[derive(Clone, Debug)]
pub struct Setup {
    pub eta: f64,
    pub kappa: f64,
    pub theta_i_rad: f64,
    /// Outer cylinder thickness relative to the fibre.
    pub d_diff: f32,
    /// The ray lobes' logistic scale s.
    pub ray_scale: f32,
    pub angle_count: usize,
    /// The exact side's wavelength step, nm.
    pub wavelength_step_nm: f64,
}

/// The figures of one density (the exact one, or a model's against it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Figures {
    pub within_1deg: f64,
    pub within_5deg: f64,
    pub backward: f64,
    pub rainbow: f64,
    pub fwhm_deg: f64,
    /// L1 against the exact density: all Θ, and |Θ| > 1°.
    pub l1: Option<(f64, f64)>,
    /// Scattered over extinguished energy: Q_sca/Q_ext for the exact
    /// solution, Σ A_p and the diffraction share for the model.
    pub albedo: f64,
}

fn figures(density: &AngularDensity, exact: Option<&AngularDensity>, albedo: f64) -> Figures {
    let degree = 1f64.to_radians();
    let spacing = density.spacing_rad();
    let rainbow: f64 = (0..density.density.len())
        .filter(|&j| (155.0..=170.0).contains(&density.angle_rad(j).abs().to_degrees()))
        .map(|j| density.density[j] * spacing)
        .sum();
    let l1 = exact.map(|exact| {
        let (mut all, mut beyond) = (0.0, 0.0);
        for (j, (m, e)) in density.density.iter().zip(&exact.density).enumerate() {
            let d = (m - e).abs() * spacing;
            all += d;
            if density.angle_rad(j).abs() > degree {
                beyond += d;
            }
        }
        (all, beyond)
    });
    Figures {
        within_1deg: density.energy_within(degree),
        within_5deg: density.energy_within(5.0 * degree),
        backward: density.backward_fraction(),
        rainbow,
        fwhm_deg: density.forward_fwhm_rad().to_degrees(),
        l1,
        albedo,
    }
}

/// The exact solution for a fibre D µm across (ȳ-weighted, 1 nm steps).
pub fn exact_density(setup: &Setup, diameter_um: f64) -> Result<AngularDensity, String> {
    let cylinder = Cylinder::new(diameter_um, setup.eta, setup.kappa).map_err(|e| e.to_string())?;
    let options = SpectralOptions {
        angle_count: setup.angle_count,
        step_nm: setup.wavelength_step_nm,
        ..SpectralOptions::default()
    };
    spectral_average(&cylinder, setup.theta_i_rad, &options, &|| {}).map_err(|e| e.to_string())
}

/// h offsets per wavelength for the model's ray part: the lobes' exit
/// azimuths move fast near grazing h, and s = 0.01 is narrow.
const MODEL_OFFSETS: usize = 8000;

/// The model's density on the exact solution's grid (Θ_j = −π + 2πj/M)
/// and its albedo.
pub fn model_density(
    setup: &Setup,
    model: &ModelChoice,
    diameter_um: f64,
) -> (AngularDensity, f64) {
    let m = setup.angle_count;
    let optics = Optics::new(setup.eta as f32, (setup.theta_i_rad as f32).sin());
    // N_diff's width as the renderer's (the exact variant's D cos θ).
    let d_um = crate::bxdfs::dual_hair::DualHairParams::circular(0.5 * diameter_um as f32)
        .diffraction_width_um(0.0, optics.cos_theta);
    let (ray_weight, diffraction_weight) = (
        1.0 / (1.0 + setup.d_diff as f64),
        setup.d_diff as f64 / (1.0 + setup.d_diff as f64),
    );
    let angle = |j: usize| -PI + 2.0 * PI * j as f64 / m as f64;
    // N_diff on the grid (wavelength-independent but for the spectral
    // lobe's ȳ-weighted integral, which is what the exact side averages).
    let closed = ClosedFormLobe::new(d_um);
    let logistic_scale = crate::bxdfs::hair_diffraction::fitted_scale(d_um);
    let n_diff: Vec<f64> = (0..m)
        .map(|j| {
            let delta = angle(j) as f32;
            (match model.diffraction {
                Diffraction::ClosedForm => closed.density(delta),
                Diffraction::Logistic => {
                    trimmed_logistic(delta, logistic_scale, -PI as f32, PI as f32)
                }
                Diffraction::Spectral => spectral_integral(delta, d_um, cie_y),
            }) as f64
        })
        .collect();
    // Without absorption the ray part is the same at every wavelength.
    let wavelengths: Vec<(f64, f64)> = if setup.kappa == 0.0 {
        vec![(555.0, 1.0)]
    } else {
        (0..=20)
            .map(|k| {
                let lambda = 380.0 + 20.0 * k as f64;
                (lambda, cie_y(lambda as f32) as f64)
            })
            .collect()
    };
    let weight_sum: f64 = wavelengths.iter().map(|w| w.1).sum();
    let mut density = vec![0.0f64; m];
    for &(lambda_nm, weight) in &wavelengths {
        // σ_a per unit radius: 4πκ/λ times the radius, both in µm.
        let sigma_a = 4.0 * PI * setup.kappa / (lambda_nm * 1e-3) * 0.5 * diameter_um;
        // φ_in = 0: the forward direction is φ_out = π, grid point j of
        // φ_out = 2πj/M is Θ_j = φ_out − π.
        let averaged = HAveragedMaps {
            ellipse: Ellipse::CIRCLE,
            optics,
            sigma_a: sigma_a as f32,
            scale: setup.ray_scale,
            model: RayModel {
                variant: Variant::Exact,
                fresnel: model.fresnel,
                residual: model.residual,
            },
            offsets: MODEL_OFFSETS,
            azimuths: m,
        };
        let rows = h_averaged_row(&averaged, 0.0);
        let w = weight / weight_sum;
        for (j, value) in density.iter_mut().enumerate() {
            let ray: f64 = rows.iter().map(|r| r[j] as f64).sum();
            *value += w * (ray_weight * ray + diffraction_weight * n_diff[j]);
        }
    }
    let albedo: f64 = density.iter().sum::<f64>() * 2.0 * PI / m as f64;
    for value in &mut density {
        *value /= albedo.max(1e-300);
    }
    (
        AngularDensity {
            density,
            efficiencies: Default::default(),
        },
        albedo,
    )
}

/// One fibre's comparison: the exact figures and each model's.
pub struct Comparison {
    pub diameter_um: f64,
    pub exact: Figures,
    pub efficiencies: Efficiencies,
    pub models: Vec<(String, Figures)>,
    /// The densities, for plots: exact first, then the models'.
    pub densities: Vec<(String, AngularDensity)>,
}

/// Compares each model with the exact solution for one fibre.
pub fn compare(
    setup: &Setup,
    models: &[ModelChoice],
    diameter_um: f64,
) -> Result<Comparison, String> {
    let exact = exact_density(setup, diameter_um)?;
    let q = exact.efficiencies.unpolarised;
    let exact_figures = figures(&exact, None, q.q_sca / q.q_ext);
    let mut rows = Vec::new();
    let mut densities = vec![("exact".to_string(), exact.clone())];
    for model in models {
        let (density, albedo) = model_density(setup, model, diameter_um);
        rows.push((model.name.clone(), figures(&density, Some(&exact), albedo)));
        densities.push((model.name.clone(), density));
    }
    Ok(Comparison {
        diameter_um,
        exact: exact_figures,
        efficiencies: q,
        models: rows,
        densities,
    })
}

/// The comparisons as a Markdown table.
pub fn table(setup: &Setup, comparisons: &[Comparison]) -> String {
    let mut s = format!(
        "η = {}, κ = {}, θ_i = {}°, d_diff = {}, ray lobes' logistic scale {}; ȳ-weighted 380–780 nm\n\n",
        setup.eta,
        setup.kappa,
        setup.theta_i_rad.to_degrees().round(),
        setup.d_diff,
        setup.ray_scale
    );
    s += "| D | model | within ±1° | ±5° | backward half | rainbow band 155–170° | L1 (all) | L1 (|Θ| > 1°) | forward FWHM | albedo |\n";
    s += "|---|---|---|---|---|---|---|---|---|---|\n";
    for c in comparisons {
        let mut row = |name: &str, f: &Figures| {
            let (l1, l1_beyond) = f.l1.map_or(("—".into(), "—".into()), |(a, b)| {
                (format!("{a:.4}"), format!("{b:.4}"))
            });
            let _ = writeln!(
                s,
                "| {} µm | {name} | {:.3} | {:.3} | {:.4} | {:.4} | {l1} | {l1_beyond} | {:.3}° | {:.4} |",
                c.diameter_um, f.within_1deg, f.within_5deg, f.backward, f.rainbow, f.fwhm_deg, f.albedo
            );
        };
        row("exact (Lorenz–Mie)", &c.exact);
        for (name, f) in &c.models {
            row(name, f);
        }
    }
    s
}

/// Colours for the plot's curves: exact black, models after.
const COLOURS: [[f32; 3]; 7] = [
    [0.0, 0.0, 0.0],
    super::plot::BLUE,
    super::plot::ORANGE,
    [0.1, 0.6, 0.2],
    [0.75, 0.1, 0.6],
    [0.5, 0.5, 0.5],
    [0.8, 0.1, 0.1],
];

/// Log–log plot of density against |Θ| (both sides averaged), each curve
/// averaged over bins of equal width in log |Θ| (the exact pattern's
/// interference ripples would fill the plot otherwise). `backward`
/// measures from Θ = 180° instead (the rainbows).
fn plot(c: &Comparison, backward: bool, title: &str, path: &Path) -> Result<(), String> {
    let bins = 120;
    let (lo, hi) = (0.01f64.log10(), 180f64.log10());
    let series: Vec<Series> = c
        .densities
        .iter()
        .enumerate()
        .map(|(k, (name, d))| {
            let mut sums = vec![(0.0f64, 0usize); bins];
            for (j, value) in d.density.iter().enumerate() {
                let theta = d.angle_rad(j).abs().to_degrees();
                let x = if backward { 180.0 - theta } else { theta };
                if x <= 0.0 {
                    continue;
                }
                let bin = ((x.log10() - lo) / (hi - lo) * bins as f64).floor();
                if (0.0..bins as f64).contains(&bin) {
                    let cell = &mut sums[bin as usize];
                    cell.0 += value;
                    cell.1 += 1;
                }
            }
            let points = sums
                .iter()
                .enumerate()
                .filter(|(_, (_, n))| *n > 0)
                .map(|(b, (sum, n))| {
                    let x = 10f64.powf(lo + (b as f64 + 0.5) / bins as f64 * (hi - lo));
                    (x, sum / *n as f64)
                })
                .collect();
            Series {
                label: name.replace("polarized", "polarised"),
                colour: COLOURS[k % COLOURS.len()],
                points,
            }
        })
        .collect();
    let x_name = if backward {
        "180 - |angle| (degrees)"
    } else {
        "|scattering angle| (degrees)"
    };
    log_log_plot(title, x_name, "density per radian", &series)
        .and_then(|image| image.write_png(path))
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Runs the comparison for `rpbrt bcsdf --compare-mie`.
pub fn run(args: &CompareMieArgs, fibre: &Fibre) -> Result<(), String> {
    let models = parse_models(&args.models)?;
    if !args.kappa.is_finite() || args.kappa < 0.0 {
        return Err(format!("--kappa must be ≥ 0, not {}", args.kappa));
    }
    if fibre.theta_i_deg.is_nan() || fibre.theta_i_deg.abs() >= 90.0 {
        return Err(format!(
            "--theta-i must lie in (−90°, 90°), not {}",
            fibre.theta_i_deg
        ));
    }
    let setup = Setup {
        eta: fibre.eta as f64,
        kappa: args.kappa as f64,
        theta_i_rad: (fibre.theta_i_deg as f64).to_radians(),
        d_diff: fibre.d_diff.unwrap_or(1.0),
        ray_scale: fibre.ray_scale.unwrap_or(0.01),
        angle_count: args.angles,
        wavelength_step_nm: args.wavelength_step as f64,
    };
    if !(0.0..=1.0).contains(&setup.d_diff) {
        return Err(format!("--d-diff must be in [0, 1], not {}", setup.d_diff));
    }
    let progress = super::progress_bar(
        args.diameters.len() as u64,
        "{bar:30} {pos}/{len} fibres, {elapsed}",
        std::io::IsTerminal::is_terminal(&std::io::stderr()),
    );
    let mut comparisons = Vec::new();
    for &d in &args.diameters {
        if !(d.is_finite() && d > 0.0) {
            return Err(format!("--diameters: {d} is not a positive width in µm"));
        }
        comparisons.push(compare(&setup, &models, d as f64)?);
        progress.inc(1);
    }
    progress.finish_and_clear();
    let text = table(&setup, &comparisons);
    print!("{text}");
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let name = format!("theta{}-kappa{}", fibre.theta_i_deg.round(), args.kappa);
        std::fs::write(dir.join(format!("{name}.md")), &text)
            .map_err(|e| format!("{}: {e}", dir.display()))?;
        for c in &comparisons {
            let stem = format!("{name}-d{}", c.diameter_um);
            let mut csv = String::from("theta_deg");
            for (label, _) in &c.densities {
                let _ = write!(csv, ",{label}");
            }
            csv.push('\n');
            let exact = &c.densities[0].1;
            for j in 0..exact.density.len() {
                let _ = write!(csv, "{}", exact.angle_rad(j).to_degrees());
                for (_, d) in &c.densities {
                    let _ = write!(csv, ",{:.6e}", d.density[j]);
                }
                csv.push('\n');
            }
            std::fs::write(dir.join(format!("{stem}.csv")), csv)
                .map_err(|e| format!("{}: {e}", dir.display()))?;
            let title = format!(
                "d {} um, theta {}",
                c.diameter_um,
                fibre.theta_i_deg.round()
            );
            plot(c, false, &title, &dir.join(format!("{stem}-forward.png")))?;
            plot(c, true, &title, &dir.join(format!("{stem}-backward.png")))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The model's density is normalised and its albedo is 1 without
    /// absorption; with d_diff = 1 half the energy is the diffraction
    /// lobe's, all of it within a few degrees of forward.
    #[test]
    fn model_density_is_normalised_and_splits_the_energy() {
        let setup = Setup {
            eta: 1.55,
            kappa: 0.0,
            theta_i_rad: 0.0,
            d_diff: 1.0,
            ray_scale: 0.01,
            angle_count: 1 << 14,
            wavelength_step_nm: 1.0,
        };
        let models = parse_models(&["closedform+polarized".to_string()]).unwrap();
        let (density, albedo) = model_density(&setup, &models[0], 75.0);
        let total: f64 = density.density.iter().sum::<f64>() * density.spacing_rad();
        assert!((total - 1.0).abs() < 1e-6, "{total}");
        assert!((albedo - 1.0).abs() < 2e-3, "{albedo}");
        let forward = density.energy_within(3f64.to_radians());
        assert!((0.5..0.56).contains(&forward), "{forward}");
        assert!(parse_models(&["spectral+x".to_string()]).is_err());
        assert!(parse_models(&["sinc".to_string()]).is_err());
    }
}
