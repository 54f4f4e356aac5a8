//! What a camera ray sees first, for the `gbuffer` film (pbrt-v4's
//! `VisibleSurface`): the first surface with a BSDF along the ray
//! (`interface` surfaces are passed through), its geometry, how far it
//! moves per pixel, and its reflectance for the camera's direction.
//!
//! It is found by a ray of its own, apart from the integrator's path, so
//! that it draws no number from the sampler (the path keeps pbrt-v4's
//! sample dimensions). Unlike pbrt-v4's `volpath`, which records no
//! surface when the camera ray first scatters in a medium, it ignores
//! media.

use super::surface_hit::texture_context;
use crate::bxdfs::{BxDFReflTransFlags, TransportMode};
use crate::cameras::CameraRay;
use crate::film::visible_surface::VisibleSurface;
use crate::scene::build::BuiltScene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec2;

/// Most `interface` surfaces passed before giving up.
const MAX_INTERFACES: usize = 256;

/// Samples of the reflectance estimate: a 4 × 4 grid of directions, each
/// with its own lobe choice.
const RHO_SAMPLES: usize = 16;

/// The surface `camera_ray` sees first, if any.
pub fn visible_surface(
    scene: &BuiltScene,
    camera_ray: &CameraRay,
    lambda: &SampledWavelengths,
) -> Option<VisibleSurface> {
    let mut ray = camera_ray.ray;
    for _ in 0..MAX_INTERFACES {
        let (mut si, prim) = scene.intersect(&ray, f32::INFINITY)?;
        si.wo = -ray.direction.normalize();
        let ctx = texture_context(scene, camera_ray, &si, true);
        // A dispersive BSDF may terminate wavelengths: not the path's.
        let mut lambda = *lambda;
        let Some(bsdf) = scene.materials[prim.material as usize].bsdf(&mut si, &ctx, &mut lambda)
        else {
            ray = si.spawn_ray(ray.direction);
            continue;
        };
        let mut rho = SampledSpectrum::ZERO;
        for i in 0..RHO_SAMPLES {
            let u = Vec2::new(((i % 4) as f32 + 0.5) / 4.0, ((i / 4) as f32 + 0.5) / 4.0);
            let uc = ((i * 7 % RHO_SAMPLES) as f32 + 0.5) / RHO_SAMPLES as f32;
            if let Some(bs) = bsdf.sample_f(
                si.wo,
                uc,
                u,
                TransportMode::Radiance,
                BxDFReflTransFlags::All,
            ) {
                if bs.pdf > 0.0 {
                    rho += bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
                }
            }
        }
        let (dpdx, dpdy) = scene.camera.first_hit_dp_dxy(
            camera_ray,
            si.p,
            si.n,
            scene.sampler.samples_per_pixel(),
        );
        return Some(VisibleSurface {
            p: si.p,
            n: si.n,
            ns: si.shading.n,
            uv: si.uv,
            dpdx,
            dpdy,
            albedo: rho * (1.0 / RHO_SAMPLES as f32),
        });
    }
    None
}
