//! pbrt-v4's `rgb` film with the `cie1931` sensor, and the settings the
//! `spectral` film shares with it (`spectral.rs` adds its buckets).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `xresolution`, `yresolution` | integer | 1280, 720 | full image size |
//! | `cropwindow` | float[4] | 0 1 0 1 | x0 x1 y0 y1 fractions of the image to render |
//! | `pixelbounds` | integer[4] | the whole image | x0 x1 y0 y1 pixels to render (cropwindow wins) |
//! | `filename` | string | "pbrt.exr" | output (.exr, .png, .pfm) |
//! | `savefp16` | bool | true | half-float EXR |
//! | `iso` | float | 100 | sensitivity: imaging ratio = exposure time × iso / 100 |
//! | `whitebalance` | float | 0 | white balance: XYZ under CIE daylight of this temperature (K) adapted to the colour space's white (0: none) |
//! | `sensor` | string | "cie1931" | sensor response |
//! | `maxcomponentvalue` | float | ∞ | samples are scaled down so no RGB component exceeds it |
//! | `diagonal` | float | 35 | film diagonal in mm (realistic camera only) |
//!
//! The `spectral` and `gbuffer` films' own parameters: see `spectral.rs`
//! and `gbuffer.rs`.

use crate::error::{scene_error, Result};
use crate::scene_description::Entity;

use super::spectral_buckets::SpectralBuckets;
use super::visible_surface::GBufferSpace;
use crate::cameras::CameraTransform;
use crate::spectrum::color_space::RgbColorSpace;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum, LAMBDA_MAX, LAMBDA_MIN};
use glam::{IVec2, Mat3, Vec2, Vec3};
use std::path::PathBuf;
use std::sync::Arc;

/// One pixel's weighted sums (f64: millions of samples are summed).
#[derive(Clone, Copy, Debug, Default)]
pub struct Pixel {
    pub rgb_sum: [f64; 3],
    pub weight_sum: f64,
}

/// Film settings and the conversion from sampled radiance to output RGB.
pub struct RgbFilm {
    pub full_resolution: IVec2,
    /// Pixels rendered: [min, max) in x and y.
    pub pixel_bounds: (IVec2, IVec2),
    pub filename: PathBuf,
    pub save_fp16: bool,
    /// The physical film's diagonal in metres (for the realistic camera).
    pub diagonal: f32,
    /// exposure time × ISO / 100.
    imaging_ratio: f32,
    max_component_value: f32,
    /// Sensor XYZ → output colour space RGB.
    output_rgb_from_sensor: Mat3,
    /// For the `spectral` film: its wavelength buckets.
    pub spectral: Option<SpectralBuckets>,
    /// For the `gbuffer` film: the space its geometry is written in
    /// (`coordinatesystem`), set once the camera is made
    /// ([`RgbFilm::place_gbuffer`]).
    gbuffer_in_world: Option<bool>,
    pub gbuffer: Option<GBufferSpace>,
    color_space: &'static RgbColorSpace,
}

impl RgbFilm {
    /// `exposure_time`: the camera's shutter interval. `outfile` overrides
    /// the scene's file name (`--outfile`). The resolution is divided by
    /// `resolution_divisor` in each axis first (4 for `--quick`, as pbrt-v4
    /// does), so the film's own `pixelbounds` are clipped to, and its
    /// `cropwindow` taken of, the reduced image.
    pub fn create(
        entity: &Entity,
        exposure_time: f32,
        outfile: Option<PathBuf>,
        base_directory: &std::path::Path,
        resolution_divisor: i32,
    ) -> Result<Self> {
        let p = &entity.params;
        let loc = &entity.location.0;
        if !matches!(entity.kind.as_str(), "rgb" | "spectral" | "gbuffer") {
            return scene_error(
                format!(
                    "film \"{}\" is not supported yet (supported: rgb, spectral, gbuffer)",
                    entity.kind
                ),
                loc,
            );
        }
        let xres = p.int("xresolution", 1280)?;
        let yres = p.int("yresolution", 720)?;
        if xres <= 0 || yres <= 0 {
            return scene_error(
                format!("film resolution {xres}×{yres} must be positive"),
                loc,
            );
        }
        let full = (IVec2::new(xres, yres) / resolution_divisor.max(1)).max(IVec2::ONE);
        let mut bounds = (IVec2::ZERO, full);
        let pb = p.ints("pixelbounds")?;
        match pb.len() {
            0 => {}
            4 => {
                bounds = (
                    IVec2::new(pb[0], pb[2]).clamp(IVec2::ZERO, full),
                    IVec2::new(pb[1], pb[3]).clamp(IVec2::ZERO, full),
                )
            }
            n => return scene_error(format!("\"pixelbounds\" needs 4 values, not {n}"), loc),
        }
        let crop = p.floats("cropwindow")?;
        match crop.len() {
            0 => {}
            4 => bounds = crop_to_bounds([crop[0], crop[1], crop[2], crop[3]], full),
            n => return scene_error(format!("\"cropwindow\" needs 4 values, not {n}"), loc),
        }
        if bounds.1.x <= bounds.0.x || bounds.1.y <= bounds.0.y {
            return scene_error("the film's pixel bounds are empty", loc);
        }
        // Read even under --outfile, so that it counts as used.
        let scene_filename = p.string("filename", "pbrt.exr")?;
        let filename = outfile.unwrap_or_else(|| base_directory.join(scene_filename));
        let save_fp16 = p.bool("savefp16", true)?;
        let iso = p.float("iso", 100.0)? as f32;
        let white_balance = p.float("whitebalance", 0.0)?;
        let sensor = p.string("sensor", "cie1931")?;
        let max_component_value = p.float("maxcomponentvalue", f64::INFINITY)? as f32;
        // Millimetres in the scene, metres in the renderer (as pbrt-v4).
        let diagonal = p.float("diagonal", 35.0)? as f32 * 0.001;
        let spectral = if entity.kind == "spectral" {
            Some(spectral_buckets(p, &filename, loc)?)
        } else {
            None
        };
        let gbuffer_in_world = if entity.kind == "gbuffer" {
            require_exr(&filename, "gbuffer", loc)?;
            match p.string("coordinatesystem", "camera")?.as_str() {
                "camera" => Some(false),
                "world" => Some(true),
                other => {
                    return scene_error(
                        format!("unknown \"coordinatesystem\" \"{other}\" (expected \"camera\" or \"world\")"),
                        loc,
                    )
                }
            }
        } else {
            None
        };
        p.report_unused(|| format!("film \"{}\"", entity.kind))?;
        if sensor != "cie1931" {
            return scene_error(
                format!("film sensor \"{sensor}\" is not supported yet (supported: cie1931)"),
                loc,
            );
        }
        let color_space = crate::spectrum::color_space::get(entity.color_space);
        // pbrt-v4's XYZ sensor: with a white balance temperature, XYZ seen
        // under CIE daylight of that temperature is adapted (von Kries,
        // Bradford cones) to the output colour space's white.
        let mut output_rgb_from_sensor = color_space.rgb_from_xyz;
        if white_balance != 0.0 {
            let Some(daylight) = crate::spectrum::daylight_spectrum(white_balance as f32) else {
                return scene_error(
                    format!("film \"whitebalance\" {white_balance} must be a positive temperature in kelvin (or 0: none)"),
                    loc,
                );
            };
            let xyz =
                crate::spectrum::spectrum_to_xyz(&Spectrum::DenselySampled(Arc::new(daylight)));
            let source_white = Vec2::new(xyz.x, xyz.y) / (xyz.x + xyz.y + xyz.z);
            output_rgb_from_sensor *=
                crate::spectrum::white_balance(source_white, color_space.whitepoint);
        }
        Ok(RgbFilm {
            full_resolution: full,
            pixel_bounds: bounds,
            filename,
            save_fp16,
            diagonal,
            imaging_ratio: exposure_time * iso / 100.0,
            max_component_value,
            output_rgb_from_sensor,
            spectral,
            gbuffer_in_world,
            gbuffer: None,
            color_space,
        })
    }

    /// Sets a `gbuffer` film's output space from the camera's: camera
    /// space (pbrt-v4's default) or world space.
    pub fn place_gbuffer(&mut self, camera: &CameraTransform) {
        self.gbuffer = self.gbuffer_in_world.map(|in_world| {
            let (output_from_render, render_from_output) = if in_world {
                let render_from_world = camera.render_from_world.to_mat4();
                (render_from_world.inverse(), render_from_world)
            } else {
                (camera.camera_from_render, camera.render_from_camera)
            };
            GBufferSpace {
                output_from_render,
                normal_output_from_render: Mat3::from_mat4(render_from_output).transpose(),
            }
        });
    }

    /// A reflectance lit by the colour space's white, in the colour
    /// space's RGB (the g-buffer's albedo).
    pub fn albedo_rgb(&self, albedo: SampledSpectrum, lambda: &SampledWavelengths) -> Vec3 {
        let lit = albedo * self.color_space.illuminant.sample(lambda);
        self.color_space.rgb_from_xyz * lit.to_xyz(lambda)
    }

    /// `maxcomponentvalue`.
    pub fn max_component_value(&self) -> f32 {
        self.max_component_value
    }

    /// A sample's wavelengths from `u`: importance-sampled over the
    /// visible range, or uniform over a spectral film's buckets.
    pub fn sample_wavelengths(&self, u: f32) -> SampledWavelengths {
        match &self.spectral {
            None => SampledWavelengths::sample_visible(u),
            Some(buckets) => buckets.sample_wavelengths(u),
        }
    }

    /// Replaces the pixel bounds (`--pixelbounds`, `--cropwindow`).
    pub fn set_pixel_bounds(&mut self, bounds: (IVec2, IVec2)) {
        self.pixel_bounds = (
            bounds.0.clamp(IVec2::ZERO, self.full_resolution),
            bounds.1.clamp(IVec2::ZERO, self.full_resolution),
        );
    }

    pub fn crop_window_bounds(&self, crop: [f64; 4]) -> (IVec2, IVec2) {
        crop_to_bounds(crop, self.full_resolution)
    }

    /// Radiance at the sampled wavelengths → sensor RGB (here CIE XYZ),
    /// clamped by `maxcomponentvalue`.
    pub fn sensor_rgb(&self, l: SampledSpectrum, lambda: &SampledWavelengths) -> Vec3 {
        // pbrt-v4's sensor integrates against x̄, ȳ, z̄ without dividing by
        // ∫ȳ (lights are normalised photometrically instead).
        let mut rgb = self.imaging_ratio * crate::spectrum::CIE_Y_INTEGRAL * l.to_xyz(lambda);
        let m = rgb.max_element();
        if m > self.max_component_value {
            rgb *= self.max_component_value / m;
        }
        rgb
    }

    pub fn add_sample(
        &self,
        pixel: &mut Pixel,
        l: SampledSpectrum,
        lambda: &SampledWavelengths,
        weight: f32,
    ) {
        let rgb = self.sensor_rgb(l, lambda);
        for i in 0..3 {
            pixel.rgb_sum[i] += (weight * rgb[i]) as f64;
        }
        pixel.weight_sum += weight as f64;
    }

    /// Splatted sensor RGB (a splat buffer's sum, already scaled) in the
    /// output colour space.
    pub fn splat_rgb(&self, sensor: Vec3) -> Vec3 {
        self.output_rgb_from_sensor * sensor
    }

    /// The output RGB of a pixel.
    pub fn pixel_rgb(&self, pixel: &Pixel) -> Vec3 {
        if pixel.weight_sum == 0.0 {
            return Vec3::ZERO;
        }
        let sensor = Vec3::new(
            (pixel.rgb_sum[0] / pixel.weight_sum) as f32,
            (pixel.rgb_sum[1] / pixel.weight_sum) as f32,
            (pixel.rgb_sum[2] / pixel.weight_sum) as f32,
        );
        self.output_rgb_from_sensor * sensor
    }
}

/// The `spectral` film's buckets (`nbuckets`, `lambdamin`, `lambdamax`),
/// checked as pbrt-v4 does: an EXR file, a range within 360–830 nm.
fn spectral_buckets(
    p: &crate::scene_description::ParamSet,
    filename: &std::path::Path,
    loc: &pbrt_parser::Location,
) -> Result<SpectralBuckets> {
    let count = p.int("nbuckets", 16)?;
    let lambda_min = p.float("lambdamin", LAMBDA_MIN as f64)? as f32;
    let lambda_max = p.float("lambdamax", LAMBDA_MAX as f64)? as f32;
    require_exr(filename, "spectral", loc)?;
    if !(1..=1024).contains(&count) {
        return scene_error(format!("\"nbuckets\" {count} must be 1 to 1024"), loc);
    }
    if !(lambda_min >= LAMBDA_MIN && lambda_max <= LAMBDA_MAX && lambda_min < lambda_max) {
        return scene_error(
            format!(
                "wavelength range [{lambda_min}, {lambda_max}] nm must lie within [{LAMBDA_MIN}, {LAMBDA_MAX}] (as pbrt-v4's)"
            ),
            loc,
        );
    }
    Ok(SpectralBuckets {
        lambda_min,
        lambda_max,
        count: count as usize,
    })
}

/// The `spectral` and `gbuffer` films write EXR files only, as pbrt-v4's.
fn require_exr(filename: &std::path::Path, kind: &str, loc: &pbrt_parser::Location) -> Result<()> {
    if filename
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
    {
        return Ok(());
    }
    scene_error(
        format!(
            "\"{}\": the {kind} film writes EXR files only",
            filename.display()
        ),
        loc,
    )
}

/// pbrt's crop window → pixel bounds: ceil of the scaled window.
fn crop_to_bounds(crop: [f64; 4], full: IVec2) -> (IVec2, IVec2) {
    let c = |v: f64| v.clamp(0.0, 1.0);
    let (x0, x1) = (c(crop[0].min(crop[1])), c(crop[0].max(crop[1])));
    let (y0, y1) = (c(crop[2].min(crop[3])), c(crop[2].max(crop[3])));
    (
        IVec2::new(
            (full.x as f64 * x0).ceil() as i32,
            (full.y as f64 * y0).ceil() as i32,
        ),
        IVec2::new(
            (full.x as f64 * x1).ceil() as i32,
            (full.y as f64 * y1).ceil() as i32,
        ),
    )
}
