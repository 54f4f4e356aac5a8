//! Lights from the scene description.

use super::diffuse_area::EmissionImage;
use super::portal_infinite::{portal_corners, PortalInfiniteLight};
use super::{
    DiffuseAreaLight, DistantLight, GoniometricLight, Light, PointLight, ProjectionLight,
    SpotLight, UniformInfiniteLight,
};
use crate::error::{image_file_error, scene_error, Result};
use crate::math::Transform;
use crate::scene_description::{self, Entity};
use crate::shapes::{Shape, ShapeStorage};
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::parameter::spectrum_param;
use crate::spectrum::{spectrum_to_photometric as photometric, Spectrum};
use crate::textures::FloatTexture;
use glam::{DMat4, DVec3, DVec4, Mat3, Vec3};
use std::f32::consts::PI;
use std::path::Path;
use std::sync::Arc;

/// The emission spectrum `name` (default: the colour space's illuminant)
/// and pbrt-v4's photometric normalisation: `scale` is divided by the
/// spectrum's luminance so that scale 1 means 1 nit of the given colour.
fn emission(entity: &Entity, name: &str, base: &Path) -> Result<(Spectrum, f32)> {
    let p = &entity.params;
    let spectrum = spectrum_param(p, name, SpectrumKind::Illuminant, entity.color_space, base)?
        .unwrap_or_else(|| {
            crate::spectrum::color_space::get(entity.color_space)
                .illuminant
                .clone()
        });
    let scale = p.float("scale", 1.0)? as f32 / photometric(&spectrum);
    Ok((spectrum, scale))
}

/// A `LightSource`.
pub fn create_light(
    light: &scene_description::Light,
    render_from_world: &Transform,
    base: &Path,
) -> Result<Light> {
    let e = &light.entity;
    let p = &e.params;
    let loc = &e.location.0;
    let render_from_light = render_from_world.then(&light.world_from_light);
    let point = |v: DVec3| render_from_light.point(v).as_vec3();
    let vector = |v: DVec3| render_from_light.matrix.transform_vector3(v).as_vec3();
    let created = match e.kind.as_str() {
        "point" => {
            let (intensity, mut scale) = emission(e, "I", base)?;
            let power = p.float("power", -1.0)? as f32;
            if power > 0.0 {
                scale *= power / (4.0 * PI);
            }
            Light::Point(PointLight { position: point(p.point3("from", DVec3::ZERO)?), intensity, scale })
        }
        "spot" => {
            let (intensity, mut scale) = emission(e, "I", base)?;
            let from = p.point3("from", DVec3::ZERO)?;
            let to = p.point3("to", DVec3::Z)?;
            let cone = p.float("coneangle", 30.0)? as f32;
            let delta = p.float("conedeltaangle", 5.0)? as f32;
            let cos_end = cone.to_radians().cos();
            let cos_start = (cone - delta).to_radians().cos();
            let power = p.float("power", -1.0)? as f32;
            if power > 0.0 {
                scale *= power / (2.0 * PI * ((1.0 - cos_start) + (cos_start - cos_end) / 2.0));
            }
            let Some(axis) = vector(to - from).try_normalize() else {
                return scene_error("spot light: \"from\" and \"to\" are the same point", loc);
            };
            Light::Spot(SpotLight {
                position: point(from),
                axis,
                intensity,
                scale,
                cos_falloff_start: cos_start,
                cos_falloff_end: cos_end,
            })
        }
        "goniometric" => {
            let (intensity, mut scale) = emission(e, "I", base)?;
            let (image, resolution) = goniometric_image(light_image(e, "goniometric light", base)?)?;
            let light = GoniometricLight {
                position: point(DVec3::ZERO),
                // pbrt-v4 composes the light's transform with a y/z swap
                // (its own inverse), so looking up a render-space
                // direction applies the inverse transform, then the swap.
                image_from_render: Mat3::from_mat4((swap_y_z() * render_from_light.inverse).as_mat4()),
                intensity,
                scale: 1.0,
                image,
                resolution,
            };
            let power = p.float("power", -1.0)? as f32;
            let k_e = 4.0 * PI * light.image_mean();
            // A black map emits nothing whatever the scale (pbrt-v4 would
            // divide by zero here).
            if power > 0.0 && k_e > 0.0 {
                scale *= power / k_e;
            }
            Light::Goniometric(GoniometricLight { scale, ..light })
        }
        "projection" => {
            let fov = p.float("fov", 90.0)? as f32;
            if !(fov > 0.0 && fov < 180.0) {
                return scene_error(format!("projection light: \"fov\" {fov} is not between 0 and 180 degrees"), loc);
            }
            let image = light_image(e, "projection light", base)?;
            let LightImage { image, filename_at, .. } = image;
            let Some(rgb_image) = image.to_linear().select_channels(&["R", "G", "B"]) else {
                return scene_error(
                    "projection light: the image has no R, G and B channels",
                    &filename_at,
                );
            };
            let (width, height) = (rgb_image.width() as usize, rgb_image.height() as usize);
            let rgb: Vec<[f32; 3]> = rgb_image.data().chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            // Images carry no colour space here: linear sRGB (pbrt-v4's
            // default when the file names none).
            let color_space = crate::spectrum::color_space::get(crate::scene_description::ColorSpaceName::Srgb);
            // pbrt-v4 composes the light's transform with a flip of y (its
            // own inverse) so the image's top row projects upwards.
            let flip_y = DMat4::from_diagonal(DVec4::new(1.0, -1.0, 1.0, 1.0));
            let light_from_render = Mat3::from_mat4((flip_y * render_from_light.inverse).as_mat4());
            let Some(axis) = vector(DVec3::Z).try_normalize() else {
                return scene_error("projection light: the transform collapses the projection axis", loc);
            };
            let scale = p.float("scale", 1.0)? as f32 / photometric(&color_space.illuminant);
            let mut light = ProjectionLight::new(
                point(DVec3::ZERO),
                axis,
                light_from_render,
                rgb,
                width,
                height,
                color_space,
                scale,
                fov,
            );
            let power = p.float("power", -1.0)? as f32;
            let k_e = light.luminance_power();
            // A black image emits nothing whatever the scale (pbrt-v4
            // would divide by zero here).
            if power > 0.0 && k_e > 0.0 {
                light.scale *= power / k_e;
            }
            Light::Projection(light)
        }
        "distant" => {
            let (radiance, mut scale) = emission(e, "L", base)?;
            let from = p.point3("from", DVec3::ZERO)?;
            let to = p.point3("to", DVec3::Z)?;
            let illuminance = p.float("illuminance", -1.0)? as f32;
            if illuminance > 0.0 {
                scale *= illuminance;
            }
            let Some(towards_light) = vector(from - to).try_normalize() else {
                return scene_error("distant light: \"from\" and \"to\" are the same point", loc);
            };
            Light::Distant(DistantLight { towards_light, radiance, scale, scene_radius: 0.0 })
        }
        "infinite" if p.find("portal", &[pbrt_parser::ParamType::Point3])?.is_some() => {
            return create_portal_light(e, render_from_world, render_from_light.to_mat4(), base);
        }
        "infinite" if p.find("filename", &[pbrt_parser::ParamType::String])?.is_some() => {
            let (filename, filename_at) = p
                .string_at("filename")?
                .unwrap_or_else(|| (String::new(), loc.clone()));
            if p.find("L", &[pbrt_parser::ParamType::Rgb, pbrt_parser::ParamType::Spectrum, pbrt_parser::ParamType::Blackbody])?.is_some() {
                return scene_error("infinite light: \"L\" and \"filename\" cannot both be given", loc);
            }
            if p.float("illuminance", -1.0)? > 0.0 {
                return scene_error("infinite light: \"illuminance\" with an image is not supported yet", loc);
            }
            let path = pbrt_parser::resolve_path(base, &filename);
            let image = crate::image::Image::read(&path)
                .map_err(|e| image_file_error("infinite light", e, &filename_at))?;
            if image.width() != image.height() {
                return scene_error(
                    format!(
                        "infinite light: \"{filename}\" is {}×{}, not square: it is unlikely to be an equal-area environment map",
                        image.width(), image.height()
                    ),
                    &filename_at,
                );
            }
            let resolution = image.width() as i32;
            // The image's own samples (no copy when they are linear RGB),
            // freed once the light has made its texels and distributions.
            let rgb = image.into_rgb_data();
            // Images carry no colour space here: linear sRGB (pbrt-v4's
            // default when the file names none).
            let color_space = crate::spectrum::color_space::get(crate::scene_description::ColorSpaceName::Srgb);
            let scale = p.float("scale", 1.0)? as f32 / photometric(&color_space.illuminant);
            p.report_unused(|| "light \"infinite\"".into())?;
            let render_from_light = render_from_light.to_mat4();
            return Ok(Light::ImageInfinite(super::ImageInfiniteLight::new(render_from_light, &rgb, resolution, color_space, scale)));
        }
        "infinite" => {
            let (radiance, mut scale) = emission(e, "L", base)?;
            let illuminance = p.float("illuminance", -1.0)? as f32;
            if illuminance > 0.0 {
                scale *= illuminance / PI;
            }
            Light::UniformInfinite(UniformInfiniteLight { radiance, scale, scene_center: Vec3::ZERO, scene_radius: 0.0 })
        }
        other => {
            return scene_error(
                format!("light \"{other}\" is not supported yet (supported: point, spot, goniometric, projection, distant, infinite)"),
                loc,
            )
        }
    };
    p.report_unused(|| format!("light \"{}\"", e.kind))?;
    Ok(created)
}

/// An `infinite` light with a `portal`: its environment from `filename`,
/// or else a constant `L` made into a 1×1 sRGB image (pbrt-v4 does the
/// same; with both, the image wins and `L` is ignored, as in pbrt-v4).
fn create_portal_light(
    e: &Entity,
    render_from_world: &Transform,
    render_from_light: glam::Mat4,
    base: &Path,
) -> Result<Light> {
    let p = &e.params;
    let loc = &e.location.0;
    let portal_at = p
        .find("portal", &[pbrt_parser::ParamType::Point3])?
        .map_or_else(|| loc.clone(), |q| q.location.clone());
    // pbrt-v4 places the portal with the camera's render-from-world
    // transform, not the light's own transform.
    let corners: Vec<Vec3> = p
        .point3s("portal")?
        .into_iter()
        .map(|c| render_from_world.point(c).as_vec3())
        .collect();
    let corners = match portal_corners(&corners) {
        Ok(corners) => corners,
        Err(problem) => return scene_error(format!("infinite light: {problem}"), &portal_at),
    };
    if p.float("illuminance", -1.0)? > 0.0 {
        return scene_error(
            "infinite light: \"illuminance\" with a portal is not supported yet",
            loc,
        );
    }
    let l = spectrum_param(p, "L", SpectrumKind::Illuminant, e.color_space, base)?;
    let srgb = crate::spectrum::color_space::get(crate::scene_description::ColorSpaceName::Srgb);
    let has_filename = p
        .find("filename", &[pbrt_parser::ParamType::String])?
        .is_some();
    let image = if has_filename {
        let LightImage {
            image,
            filename,
            filename_at,
        } = light_image(e, "infinite light", base)?;
        let Some(image) = image.to_linear().select_channels(&["R", "G", "B"]) else {
            return scene_error(
                format!("infinite light: \"{filename}\" has no R, G and B channels"),
                &filename_at,
            );
        };
        if image.width() != image.height() {
            return scene_error(
                format!(
                    "infinite light: \"{filename}\" is {}×{}, not square: it is unlikely to be an equal-area environment map",
                    image.width(),
                    image.height()
                ),
                &filename_at,
            );
        }
        image
    } else if let Some(l) = l {
        // pbrt-v4 converts the spectrum to sRGB by way of XYZ.
        let rgb = srgb.to_rgb(crate::spectrum::xyz::spectrum_to_xyz(&l));
        match crate::image::Image::from_rgb(1, 1, rgb.to_array().to_vec()) {
            Ok(image) => image,
            Err(problem) => return scene_error(format!("infinite light: {problem}"), loc),
        }
    } else {
        return scene_error(
            "infinite light: a \"portal\" needs an environment: \"filename\" (an equal-area image) or \"L\"",
            &portal_at,
        );
    };
    // Images carry no colour space here: linear sRGB (pbrt-v4's default
    // when the file names none).
    let scale = p.float("scale", 1.0)? as f32 / photometric(&srgb.illuminant);
    p.report_unused(|| "light \"infinite\"".into())?;
    Ok(Light::PortalInfinite(PortalInfiniteLight::new(
        render_from_light,
        &image,
        srgb,
        scale,
        corners,
    )))
}

/// pbrt-v4's warning for an `infinite` light with a `portal`, no
/// `filename` and an `L` that is not RGB: the spectrum is reduced to sRGB
/// RGB to fill the portal light's image.
pub fn portal_light_warning(light: &scene_description::Light) -> Option<pbrt_parser::Warning> {
    let p = &light.entity.params;
    let named = |name: &str| p.iter().any(|q| q.name == name);
    if light.entity.kind != "infinite" || !named("portal") || named("filename") {
        return None;
    }
    let l = p.iter().filter(|q| q.name == "L").last()?;
    if l.ty == pbrt_parser::ParamType::Rgb {
        return None;
    }
    Some(pbrt_parser::Warning {
        message: "infinite light: \"L\" is not RGB: converted to sRGB RGB so that a portal light can be used (as pbrt-v4 does)".into(),
        location: l.location.clone(),
    })
}

/// The `AreaLightSource "diffuse"` of one Shape directive, read once and
/// made into a light per shape by [`AreaLightTemplate::light`].
pub struct AreaLightTemplate {
    radiance: Spectrum,
    image: Option<Arc<EmissionImage>>,
    /// `scale` over the photometric normalisation.
    scale: f32,
    two_sided: bool,
    /// `power` (≤ 0: not given).
    power: f32,
    alpha: Option<Arc<FloatTexture>>,
    invisible: bool,
}

/// The shape's alpha as an area light sees it.
pub enum AreaLightAlpha<'a> {
    Opaque,
    /// Masks the emission.
    Cutout(&'a FloatTexture),
    /// Constant 0: the shape is never hit, and emits unmasked (pbrt-v4).
    Invisible,
}

/// Reads an `AreaLightSource` for a shape whose alpha is `alpha`.
pub fn create_area_light(
    entity: &Entity,
    alpha: AreaLightAlpha,
    base: &Path,
) -> Result<AreaLightTemplate> {
    let p = &entity.params;
    let loc = &entity.location.0;
    if entity.kind != "diffuse" {
        return scene_error(
            format!("area light \"{}\" unknown (expected diffuse)", entity.kind),
            loc,
        );
    }
    let image = if p
        .find("filename", &[pbrt_parser::ParamType::String])?
        .is_some()
    {
        if let Some(l) = p.iter().find(|q| q.name == "L") {
            return scene_error(
                "area light: both \"L\" and \"filename\" are given",
                &l.location,
            );
        }
        Some(Arc::new(emission_image(entity, base)?))
    } else {
        None
    };
    let (radiance, scale) = emission(entity, "L", base)?;
    let two_sided = p.bool("twosided", false)?;
    let power = p.float("power", -1.0)? as f32;
    p.report_unused(|| "area light \"diffuse\"".into())?;
    let (alpha, invisible) = match alpha {
        AreaLightAlpha::Opaque => (None, false),
        AreaLightAlpha::Cutout(texture) => (Some(Arc::new(texture.clone())), false),
        AreaLightAlpha::Invisible => (None, true),
    };
    Ok(AreaLightTemplate {
        radiance,
        image,
        scale,
        two_sided,
        power,
        alpha,
        invisible,
    })
}

impl AreaLightTemplate {
    /// The light of one of the directive's shapes.
    pub fn light(&self, shape: &Shape, shapes: &ShapeStorage) -> DiffuseAreaLight {
        let area = shape.area(shapes);
        let mut scale = self.scale;
        if self.power > 0.0 {
            // pbrt-v4, per shape: k_e = π (×2 if two-sided) × area × the
            // image's mean luminance (1 without an image).
            let luminance = self.image.as_ref().map_or(1.0, |image| {
                let weights = image.color_space.luminance_vector();
                let data = image.image.data();
                data.chunks_exact(3)
                    .map(|c| Vec3::new(c[0], c[1], c[2]).dot(weights))
                    .sum::<f32>()
                    / (data.len() / 3).max(1) as f32
            });
            let k_e = PI * if self.two_sided { 2.0 } else { 1.0 } * area * luminance;
            scale *= self.power / k_e;
        }
        DiffuseAreaLight {
            shape: shape.clone(),
            radiance: self.radiance.clone(),
            image: self.image.clone(),
            scale,
            two_sided: self.two_sided,
            area,
            alpha: self.alpha.clone(),
            invisible: self.invisible,
        }
    }
}

/// An area light's `filename`: its R, G, B, linear.
fn emission_image(entity: &Entity, base: &Path) -> Result<EmissionImage> {
    let LightImage {
        image,
        filename,
        filename_at,
    } = light_image(entity, "area light", base)?;
    let Some(image) = image.to_linear().select_channels(&["R", "G", "B"]) else {
        return scene_error(
            format!("area light: \"{filename}\" has no R, G and B channels"),
            &filename_at,
        );
    };
    // Images carry no colour space here: linear sRGB (pbrt-v4's default
    // when the file names none).
    let color_space =
        crate::spectrum::color_space::get(crate::scene_description::ColorSpaceName::Srgb);
    Ok(EmissionImage { image, color_space })
}

/// pbrt-v4's swap of a goniometric light's y and z axes.
fn swap_y_z() -> DMat4 {
    DMat4::from_cols(DVec4::X, DVec4::Z, DVec4::Y, DVec4::W)
}

/// A light's image as read, with where its `filename` was given.
struct LightImage {
    image: crate::image::Image,
    filename: String,
    filename_at: pbrt_parser::Location,
}

/// Reads the image a light's `filename` names: a missing parameter, an
/// unreadable file and non-finite pixels (pbrt-v4 refuses those as light
/// sources) are errors located at the scene.
fn light_image(entity: &Entity, what: &str, base: &Path) -> Result<LightImage> {
    let Some((filename, filename_at)) = entity.params.string_at("filename")? else {
        return scene_error(
            format!("{what}: \"filename\" is required"),
            &entity.location.0,
        );
    };
    let path = pbrt_parser::resolve_path(base, &filename);
    let image =
        crate::image::Image::read(&path).map_err(|e| image_file_error(what, e, &filename_at))?;
    if image.first_non_finite().is_some() {
        return scene_error(
            format!("{what}: \"{filename}\" has infinite or not-a-number pixels, unsuitable for a light"),
            &filename_at,
        );
    }
    Ok(LightImage {
        image,
        filename,
        filename_at,
    })
}

/// A goniometric light's square greyscale image: its `Y` channel, or the
/// average of R, G and B stored back at the file's precision (pbrt-v4
/// builds a one-channel image of the file's pixel format and encoding).
fn goniometric_image(light_image: LightImage) -> Result<(Vec<f32>, usize)> {
    let LightImage {
        image,
        filename,
        filename_at,
    } = light_image;
    if image.width() != image.height() {
        return scene_error(
            format!(
                "goniometric light: \"{filename}\" is {}×{}, not square: it is unlikely to be an equal-area map",
                image.width(),
                image.height()
            ),
            &filename_at,
        );
    }
    let (format, encoding) = (image.format(), image.encoding());
    let linear = image.to_linear();
    let rgb = linear.select_channels(&["R", "G", "B"]);
    let y = linear.select_channels(&["Y"]);
    let values = match (rgb, y) {
        (Some(_), Some(_)) => {
            return scene_error(
                format!("goniometric light: \"{filename}\" has both R, G, B and Y channels"),
                &filename_at,
            )
        }
        (Some(rgb), None) => rgb
            .data()
            .chunks_exact(3)
            .map(|c| format.round_trip_linear((c[0] + c[1] + c[2]) / 3.0, encoding))
            .collect(),
        (None, Some(y)) => y.into_data(),
        (None, None) => {
            return scene_error(
                format!("goniometric light: \"{filename}\" has neither R, G, B nor Y channels"),
                &filename_at,
            )
        }
    };
    Ok((values, image.width() as usize))
}
