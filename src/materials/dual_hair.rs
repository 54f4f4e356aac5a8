//! The dual hair model's parameters on `Material "hair"` (Benamira &
//! Pattanaik 2021; see [`crate::bxdfs::dual_hair`]). With none of them
//! given the material is pbrt-v4's hair, unchanged.
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `float ellipse_a`, `float ellipse_b` | — (circular) | semi-major and semi-minor axes in µm, given together, a ≥ b > 0 |
//! | `float d_diff` | 0 | outer (diffracting) cylinder thickness relative to the fibre, [0, 1] |
//! | `float ellipse_orientation` | 0 | major axis angle (degrees) about the fibre, from the strand's reference direction across it (below) |
//! | `vector3 ellipse_reference` | — | for cylinder and flat curves: the reference is this world-space direction projected onto the fibre's cross-section plane at each point |
//! | `bool ellipse_random` | false | for cylinder and flat curves: each strand's reference is turned by its own angle, drawn from the strand (deterministic), as real hair's fibres are not lined up |
//! | `string diffraction` | `"closedform"` (`"logistic"` with `s_diff` or `variant "paper"`) | `"closedform"` (the ȳ-weighted Fraunhofer pattern in closed form: parabolic core and 1/Δ² tail, sampled exactly), `"logistic"` (N_diff, Eq. 35) or `"spectral"` (exact sinc² per wavelength) |
//! | `float s_diff` | fitted to the width (κ/D; Eq. 36 with `variant "paper"`) | the logistic N_diff's scale in radians, > 0 (the paper's artistic control); with `"closedform"` or `"spectral"` an error |
//! | `string variant` | `"exact"` | `"exact"` or `"paper"` (Eq. 7, 22, 36 as printed) |
//! | `string fresnel` | `"averaged"` | `"averaged"` (the two polarisations' reflectances averaged at each interface, as pbrt-v4) or `"polarized"` (carried apart along each path and averaged at the exit: closer to the exact wave solution, docs/dual-model.md); `"polarized"` takes each interface from its own side, so it cannot be combined with `internal_fresnel "paper"` |
//! | `string residual` | `"uniform"` | the light leaving after TRT: `"uniform"` in azimuth (pbrt-v4's residual) or `"trrt"` (TRRT, p = 3, as a lobe about its own traced exit azimuth, the secondary rainbow; p ≥ 4 uniform); `"trrt"` needs `variant "exact"` (the paper's has no residual) |
//! | `string internal_fresnel` | `"pbrt"` (`"paper"` with `variant "paper"`) | inner interfaces' Fresnel: `"pbrt"` (each interface from its own side; pbrt's f0 for a circle) or `"paper"` (Eq. 22/24's f_p = air → hair Fresnel at the internal angle) |
//!
//! The reference across the fibre: on a ribbon its normal; on a cylinder
//! or flat curve `ellipse_reference` projected, or without it a frame
//! carried along the strand without twist from a start that the strand's
//! first tangent fixes (turned by a per-strand angle with `ellipse_random`;
//! without either, the start has no meaning a scene can use).
//!
//! Normalisation (paper §7.2): σ_a (or melanin) is absorption per mean
//! semi-axis (a + b)/2, so an a = 30, b = 20 µm fibre absorbs like a
//! circular fibre 50 µm thick, as in the paper's comparisons; only a/b
//! shapes the ray part, and the size sets the diffraction width D. Without
//! `ellipse_a`/`ellipse_b` the fibre is circular with radius 25 µm (the
//! paper's 50 µm reference fibre) for diffraction.
//!
//! Geometry: the written curve width is the fibre's; the scene build widens
//! the curve to (1 + d_diff) × that, the outer diffracting cylinder, so the
//! fibre occupies the middle 1/(1 + d_diff) of h (with d_diff = 0, all of it).

use crate::bxdfs::dual_hair::DualHairParams;
use crate::bxdfs::hair_diffraction::Diffraction;
use crate::bxdfs::hair_ellipse::{Ellipse, InternalFresnel, Residual, Variant};
use crate::error::{scene_error, Result};
use crate::scene_description::params::ParamSet;
use glam::{Vec2, Vec3};
use pbrt_parser::ParamType;

/// Where a cylinder or flat strand's reference across the fibre comes
/// from (ribbons use their normal).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AxisFrame {
    /// `vector3 ellipse_reference`, world space.
    pub reference: Option<Vec3>,
    /// `bool ellipse_random`.
    pub random: bool,
}

/// The fibre's [`AxisFrame`] parameters.
pub fn read_axis_frame(p: &ParamSet) -> Result<AxisFrame> {
    let random_param = p.find("ellipse_random", &[ParamType::Bool])?;
    let random = p.bool("ellipse_random", false)?;
    let reference = match p.find("ellipse_reference", &[ParamType::Vector3])? {
        None => None,
        Some(param) => match param.numbers() {
            [x, y, z] => {
                let v = Vec3::new(*x as f32, *y as f32, *z as f32);
                if !v.is_finite() || v.length_squared() == 0.0 {
                    return scene_error(
                        "\"ellipse_reference\" must be a finite, non-zero direction",
                        &param.location,
                    );
                }
                if random {
                    let at = random_param.map_or(&param.location, |r| &r.location);
                    return scene_error(
                        "\"ellipse_random\" and \"ellipse_reference\" exclude each other: the reference fixes every strand's axis",
                        at,
                    );
                }
                Some(v)
            }
            _ => return scene_error("\"ellipse_reference\" takes one direction", &param.location),
        },
    };
    Ok(AxisFrame { reference, random })
}

/// Radius of the circular fibre when no ellipse is given, µm.
const DEFAULT_RADIUS_UM: f32 = 25.0;

/// The dual model's parameters and the ellipse orientation (its cos, sin),
/// or `None` when none of its parameters is given (pbrt's hair).
pub fn read(p: &ParamSet) -> Result<Option<(DualHairParams, Vec2)>> {
    let number = |name: &str| -> Result<Option<(f32, pbrt_parser::Location)>> {
        let Some(param) = p.find(name, &[ParamType::Float])? else {
            return Ok(None);
        };
        match param.numbers() {
            [x] if (*x as f32).is_finite() => Ok(Some((*x as f32, param.location.clone()))),
            [x] => scene_error(
                format!("\"{name}\" must be finite, not {x}"),
                &param.location,
            ),
            _ => scene_error(format!("\"{name}\" takes one value"), &param.location),
        }
    };
    let choice = |name: &str, options: &[&str]| -> Result<Option<String>> {
        let Some(param) = p.find(name, &[ParamType::String])? else {
            return Ok(None);
        };
        match param.strings() {
            [s] if options.contains(&s.as_str()) => Ok(Some(s.to_string())),
            _ => scene_error(
                format!("\"{name}\" must be one of \"{}\"", options.join("\", \"")),
                &param.location,
            ),
        }
    };
    let a = number("ellipse_a")?;
    let b = number("ellipse_b")?;
    let d_diff = number("d_diff")?;
    let orientation = number("ellipse_orientation")?;
    let diffraction = choice("diffraction", &["closedform", "logistic", "spectral"])?;
    let s_diff = number("s_diff")?;
    let variant = choice("variant", &["exact", "paper"])?;
    let fresnel = choice("internal_fresnel", &["pbrt", "paper"])?;
    let polarization = choice("fresnel", &["averaged", "polarized"])?;
    let residual = choice("residual", &["uniform", "trrt"])?;
    if a.is_none()
        && b.is_none()
        && d_diff.is_none()
        && orientation.is_none()
        && diffraction.is_none()
        && s_diff.is_none()
        && variant.is_none()
        && fresnel.is_none()
        && polarization.is_none()
        && residual.is_none()
    {
        return Ok(None);
    }
    let (ellipse, mean_radius_um) = match (a, b) {
        (None, None) => (Ellipse::CIRCLE, DEFAULT_RADIUS_UM),
        (Some((_, loc)), None) | (None, Some((_, loc))) => {
            return scene_error(
                "\"ellipse_a\" and \"ellipse_b\" must be given together",
                &loc,
            )
        }
        (Some((a, la)), Some((b, lb))) => {
            if a <= 0.0 {
                return scene_error(format!("\"ellipse_a\" must be positive, not {a}"), &la);
            }
            if b <= 0.0 {
                return scene_error(format!("\"ellipse_b\" must be positive, not {b}"), &lb);
            }
            if a < b {
                return scene_error(
                    format!("\"ellipse_a\" ({a}) is the semi-major axis: it must be at least \"ellipse_b\" ({b})"),
                    &la,
                );
            }
            (Ellipse::new(a, b), 0.5 * (a + b))
        }
    };
    let d_diff = match d_diff {
        None => 0.0,
        Some((d, _)) if (0.0..=1.0).contains(&d) => d,
        Some((d, loc)) => {
            return scene_error(format!("\"d_diff\" must be in [0, 1], not {d}"), &loc)
        }
    };
    let variant = match variant.as_deref() {
        Some("paper") => Variant::Paper,
        _ => Variant::Exact,
    };
    let internal_fresnel = match (fresnel.as_deref(), variant, polarization.as_deref()) {
        (_, _, Some("polarized")) => match (fresnel.as_deref(), p.find("fresnel", &[ParamType::String])?) {
            (Some("paper"), Some(param)) => return scene_error(
                "\"fresnel\" \"polarized\" takes each interface's Fresnel from its own side: it cannot be combined with \"internal_fresnel\" \"paper\"",
                &param.location,
            ),
            _ => InternalFresnel::Polarized,
        },
        (Some("paper"), _, _) | (None, Variant::Paper, _) => InternalFresnel::Paper,
        _ => InternalFresnel::Pbrt,
    };
    // The paper's model (and its artistic control s_diff) is the logistic.
    let diffraction = match diffraction.as_deref() {
        Some("spectral") => Diffraction::Spectral,
        Some("closedform") => Diffraction::ClosedForm,
        Some(_) => Diffraction::Logistic,
        None if s_diff.is_some() || variant == Variant::Paper => Diffraction::Logistic,
        None => Diffraction::ClosedForm,
    };
    let s_diff = match s_diff {
        None => None,
        Some((_, loc)) if diffraction != Diffraction::Logistic => {
            return scene_error(
                "\"s_diff\" is the logistic lobe's scale: it has no meaning with \"diffraction\" \"closedform\" or \"spectral\"",
                &loc,
            )
        }
        Some((s, _)) if s > 0.0 => Some(s),
        Some((s, loc)) => {
            return scene_error(format!("\"s_diff\" must be positive, not {s}"), &loc)
        }
    };
    let residual = match residual.as_deref() {
        Some("trrt") if variant == Variant::Paper => {
            return match p.find("residual", &[ParamType::String])? {
                Some(param) => scene_error(
                    "\"residual\" \"trrt\" splits the exact variant's residual: the paper's variant has none",
                    &param.location,
                ),
                None => Ok(None),
            };
        }
        Some("trrt") => Residual::Trrt,
        _ => Residual::Uniform,
    };
    let params = DualHairParams {
        ellipse,
        mean_radius_um,
        d_diff,
        diffraction,
        s_diff,
        variant,
        internal_fresnel,
        residual,
    };
    Ok(Some((
        params,
        Vec2::from_angle(orientation.map_or(0.0, |(o, _)| o.to_radians())),
    )))
}
