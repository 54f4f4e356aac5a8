//! What every integrator needs at a surface hit, beside its BSDF: the
//! radiance an area light emits there, and the context its textures are
//! looked up in (with screen-space differentials where filtering is on).

use crate::cameras::CameraRay;
use crate::interaction::SurfaceInteraction;
use crate::lights::Light;
use crate::scene::build::{BuiltScene, Primitive};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::textures::TextureEvalContext;

/// Radiance emitted at `si` towards `si.wo` (zero unless `prim` is an area
/// light).
pub fn emitted(
    scene: &BuiltScene,
    prim: &Primitive,
    si: &SurfaceInteraction,
    lambda: &SampledWavelengths,
) -> SampledSpectrum {
    match prim.area_light().map(|i| &scene.lights[i as usize]) {
        Some(Light::DiffuseArea(area)) => area.l(si.p, si.n, si.uv, si.wo, lambda),
        _ => SampledSpectrum::ZERO,
    }
}

/// The texture context at `si`: with the camera ray's own differentials
/// while the path has not scattered yet (`from_camera`), else with the
/// camera's approximation at the point, as pbrt-v4.
pub fn texture_context(
    scene: &BuiltScene,
    camera_ray: &CameraRay,
    si: &SurfaceInteraction,
    from_camera: bool,
) -> TextureEvalContext {
    if !scene.integrator.texture_filtering {
        return TextureEvalContext::at(si);
    }
    let spp = scene.sampler.samples_per_pixel();
    let (dpdx, dpdy) = if from_camera {
        scene.camera.first_hit_dp_dxy(camera_ray, si.p, si.n, spp)
    } else {
        scene.camera.approximate_dp_dxy(si.p, si.n, spp)
    };
    TextureEvalContext::with_differentials(si, dpdx, dpdy)
}
