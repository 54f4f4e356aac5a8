//! Spectrum-valued parameters (`rgb`, `blackbody`, `spectrum`) of a
//! scene description's entity to spectra (the spectrum family's reading of
//! `scene_description::params`).

use crate::error::{scene_error, Result};
use crate::scene_description::{ColorSpaceName, ParamSet};
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::{
    named_spectrum, read_spectrum_file, BlackbodySpectrum, PiecewiseLinear, Spectrum,
};
use glam::Vec3;
use pbrt_parser::ParamType;
use std::path::Path;
use std::sync::Arc;

/// The spectrum given for `name` (any of rgb, blackbody, spectrum), read
/// as `kind` in `color_space`; `None` when absent.
pub fn spectrum_param(
    params: &ParamSet,
    name: &str,
    kind: SpectrumKind,
    color_space: ColorSpaceName,
    base_directory: &Path,
) -> Result<Option<Spectrum>> {
    let Some(p) = params.find(
        name,
        &[ParamType::Rgb, ParamType::Blackbody, ParamType::Spectrum],
    )?
    else {
        return Ok(None);
    };
    let loc = &p.location;
    match p.ty {
        ParamType::Rgb => {
            let v = p.numbers();
            if v.len() != 3 {
                return scene_error(
                    format!("\"rgb {name}\": expected 3 values, found {}", v.len()),
                    loc,
                );
            }
            let rgb = Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
            if rgb.min_element() < 0.0 {
                return scene_error(format!("\"rgb {name}\" has a negative component"), loc);
            }
            if kind == SpectrumKind::Albedo && rgb.max_element() > 1.0 {
                return scene_error(
                    format!(
                        "\"rgb {name}\" is used as an albedo (reflectance) and has a component > 1"
                    ),
                    loc,
                );
            }
            Ok(Some(
                crate::spectrum::color_space::get(color_space).rgb_to_spectrum(rgb, kind),
            ))
        }
        ParamType::Blackbody => match p.numbers() {
            [t] if *t > 0.0 => Ok(Some(Spectrum::Blackbody(BlackbodySpectrum::new(*t as f32)))),
            _ => scene_error(
                format!("\"blackbody {name}\": expected one positive temperature in kelvin"),
                loc,
            ),
        },
        _ => {
            if let [s] = p.strings() {
                if let Some(named) = named_spectrum(s) {
                    return Ok(Some(named));
                }
                let path = pbrt_parser::resolve_path(base_directory, s);
                return match read_spectrum_file(&path) {
                    Ok(pl) => Ok(Some(Spectrum::PiecewiseLinear(Arc::new(pl)))),
                    Err(e) => scene_error(
                        format!("\"spectrum {name}\": \"{s}\" is neither a named spectrum nor a readable spectrum file ({e})"),
                        loc,
                    ),
                };
            }
            let v = p.numbers();
            match PiecewiseLinear::from_interleaved(v, kind == SpectrumKind::Illuminant) {
                Ok(pl) => Ok(Some(Spectrum::PiecewiseLinear(Arc::new(pl)))),
                Err(e) => scene_error(format!("\"spectrum {name}\": {e}"), loc),
            }
        }
    }
}
