//! pbrt-v4's `ambientocclusion` integrator: at the first surface the
//! camera ray finds, the fraction of the hemisphere around the geometric
//! normal from which nothing is hit within `maxdistance`, cosine-weighted
//! and scaled so an open surface is 1, returned as the colour space's
//! illuminant scaled to unit luminance (white, 1).
//!
//! | Parameter | Type | Default | Meaning |
//! |---|---|---|---|
//! | `cossample` | bool | true | Sample directions by cos θ (else uniformly over the hemisphere) |
//! | `maxdistance` | float | ∞ | Occluders further than this do not count |

use super::ray_counts::RayCounts;
use super::surface_hit::texture_context;
use crate::cameras::CameraRay;
use crate::math::frame::Frame;
use crate::math::sampling::{
    cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_hemisphere,
    UNIFORM_HEMISPHERE_PDF,
};
use crate::samplers::Sampler;
use crate::scene::build::{AmbientOcclusionSettings, BuiltScene};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Ambient occlusion seen along the camera ray.
pub fn ambient_occlusion_li(
    scene: &BuiltScene,
    settings: &AmbientOcclusionSettings,
    camera_ray: &CameraRay,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
) -> SampledSpectrum {
    let mut ray = camera_ray.ray;
    loop {
        rays.closest_hit += 1;
        let Some((mut si, prim)) = scene.intersect(&ray, f32::INFINITY) else {
            return SampledSpectrum::ZERO;
        };
        si.wo = -ray.direction.normalize();
        let ctx = texture_context(scene, camera_ray, &si, true);
        let material = &scene.materials[prim.material as usize];
        if material.bsdf(&mut si, &ctx, lambda).is_none() {
            // An interface: look through it.
            ray = si.spawn_ray(ray.direction);
            continue;
        }
        // The geometric normal, on the side the ray came from.
        let n = if si.n.dot(si.wo) < 0.0 { -si.n } else { si.n };
        let u = sampler.get_2d();
        let (local, pdf) = if settings.cos_sample {
            let w = sample_cosine_hemisphere(u);
            (w, cosine_hemisphere_pdf(w.z.abs()))
        } else {
            (sample_uniform_hemisphere(u), UNIFORM_HEMISPHERE_PDF)
        };
        if pdf == 0.0 {
            return SampledSpectrum::ZERO;
        }
        let wi = Frame::from_z(n).from_local(local);
        rays.shadow += 1;
        if scene.intersect_p(&si.spawn_ray(wi), settings.max_distance) {
            return SampledSpectrum::ZERO;
        }
        let illuminant = crate::spectrum::color_space::get(settings.color_space)
            .illuminant
            .sample(lambda);
        return illuminant * (settings.illuminant_scale * wi.dot(n) / (std::f32::consts::PI * pdf));
    }
}
