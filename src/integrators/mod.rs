//! Integrators: radiance along camera rays.

mod ambient_occlusion;
pub mod bdpt;
mod diffraction_connection;
pub mod light_path;
pub mod path;
mod random_walk;
pub mod ray_counts;
mod simple_path;
pub mod simple_vol_path;
mod surface_hit;
pub mod visible_surface;
pub mod volpath;

pub use path::path_li;
pub use ray_counts::RayCounts;
pub use volpath::volpath_li;

use crate::cameras::CameraRay;
use crate::samplers::Sampler;
use crate::scene::build::{BuiltScene, IntegratorKind};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Radiance arriving along the camera ray, by the scene's integrator.
pub fn li(
    scene: &BuiltScene,
    camera_ray: &CameraRay,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
) -> SampledSpectrum {
    match &scene.integrator.kind {
        // With media, volpath's null-scattering estimator (`has_media` is
        // set for volpath only: path ignores media, as pbrt-v4's does).
        IntegratorKind::VolPath if scene.has_media => {
            volpath_li(scene, camera_ray, lambda, sampler, rays)
        }
        IntegratorKind::Path | IntegratorKind::VolPath => {
            path_li(scene, camera_ray, lambda, sampler, rays)
        }
        IntegratorKind::AmbientOcclusion(s) => {
            ambient_occlusion::ambient_occlusion_li(scene, s, camera_ray, lambda, sampler, rays)
        }
        IntegratorKind::RandomWalk => {
            random_walk::random_walk_li(scene, camera_ray, lambda, sampler, rays)
        }
        IntegratorKind::SimpleVolPath => {
            simple_vol_path::simple_vol_path_li(scene, camera_ray, lambda, sampler, rays)
        }
        IntegratorKind::SimplePath(s) => {
            simple_path::simple_path_li(scene, s, camera_ray, lambda, sampler, rays)
        }
        // Their light reaches the film (partly) by splats: the pipeline
        // calls them with the film's splat buffer.
        IntegratorKind::LightPath | IntegratorKind::Bdpt => SampledSpectrum::ZERO,
    }
}
