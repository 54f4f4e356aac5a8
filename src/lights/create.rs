//! Lights from the scene description.

use super::{DiffuseAreaLight, DistantLight, Light, PointLight, SpotLight, UniformInfiniteLight};
use crate::error::{image_file_error, scene_error, Result};
use crate::math::Transform;
use crate::scene_description::{self, Entity};
use crate::shapes::{Shape, ShapeStorage};
use crate::spectrum::color_space::SpectrumKind;
use crate::spectrum::parameter::spectrum_param;
use crate::spectrum::{spectrum_to_photometric as photometric, Spectrum};
use glam::{DVec3, Vec3};
use std::f32::consts::PI;
use std::path::Path;

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
            if p.find("portal", &[pbrt_parser::ParamType::Point3])?.is_some() {
                return scene_error("infinite light \"portal\" is not supported yet", loc);
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
            let data = image.rgb_data();
            let rgb: Vec<[f32; 3]> = data.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            // Images carry no colour space here: linear sRGB (pbrt-v4's
            // default when the file names none).
            let color_space = crate::spectrum::color_space::get(crate::scene_description::ColorSpaceName::Srgb);
            let scale = p.float("scale", 1.0)? as f32 / photometric(&color_space.illuminant);
            p.report_unused(|| "light \"infinite\"".into())?;
            let render_from_light = render_from_light.to_mat4();
            return Ok(Light::ImageInfinite(super::ImageInfiniteLight::new(render_from_light, rgb, image.width() as i32, color_space, scale)));
        }
        "infinite" => {
            if p.find("portal", &[pbrt_parser::ParamType::Point3])?.is_some() {
                return scene_error("infinite light \"portal\" is not supported yet", loc);
            }
            let (radiance, mut scale) = emission(e, "L", base)?;
            let illuminance = p.float("illuminance", -1.0)? as f32;
            if illuminance > 0.0 {
                scale *= illuminance / PI;
            }
            Light::UniformInfinite(UniformInfiniteLight { radiance, scale, scene_center: Vec3::ZERO, scene_radius: 0.0 })
        }
        other => {
            return scene_error(
                format!("light \"{other}\" is not supported yet (supported: point, spot, distant, infinite)"),
                loc,
            )
        }
    };
    p.report_unused(|| format!("light \"{}\"", e.kind))?;
    Ok(created)
}

/// The `AreaLightSource "diffuse"` of one shape.
pub fn create_area_light(
    entity: &Entity,
    shape: &Shape,
    shapes: &ShapeStorage,
    base: &Path,
) -> Result<DiffuseAreaLight> {
    let p = &entity.params;
    let loc = &entity.location.0;
    if entity.kind != "diffuse" {
        return scene_error(
            format!("area light \"{}\" unknown (expected diffuse)", entity.kind),
            loc,
        );
    }
    if p.find("filename", &[pbrt_parser::ParamType::String])?
        .is_some()
    {
        return scene_error(
            "area lights with an image (\"filename\") are not supported yet",
            loc,
        );
    }
    let (radiance, mut scale) = emission(entity, "L", base)?;
    let two_sided = p.bool("twosided", false)?;
    let area = shape.area(shapes);
    let power = p.float("power", -1.0)? as f32;
    if power > 0.0 {
        // pbrt-v4: k_e = π (×2 if two-sided) × area, per shape.
        let k_e = PI * if two_sided { 2.0 } else { 1.0 } * area;
        scale *= power / k_e;
    }
    p.report_unused(|| "area light \"diffuse\"".into())?;
    Ok(DiffuseAreaLight {
        shape: shape.clone(),
        radiance,
        scale,
        two_sided,
        area,
    })
}
