//! pbrt-v4's `simplevolpath` integrator: plain delta tracking through
//! media at one wavelength, with no light sampling — a reference for
//! `volpath` in scenes of media, emission and medium boundaries.
//!
//! At each tentative collision (drawn against the majorant) the path is
//! absorbed, scatters or goes on, in proportion to σa, σs and σn at the
//! first wavelength (the others are terminated at the start). Absorption
//! collects the medium's emission, scattering samples the phase function,
//! and light counts where the path reaches an area light or escapes to an
//! infinite one. Surfaces may only be medium boundaries (`interface`) or
//! black: pbrt-v4 stops with an error when a surface would scatter, and
//! rpbrt checks that when the scene is built
//! (`scene::build::check_simple_vol_path`).
//!
//! | Parameter | Type | Default | Meaning |
//! |---|---|---|---|
//! | `maxdepth` | integer | 5 | Most scattering events along a path |

use super::ray_counts::RayCounts;
use super::surface_hit::emitted;
use super::volpath::{choose_collision, majorant_rng, Collision};
use crate::bxdfs::HenyeyGreenstein;
use crate::cameras::CameraRay;
use crate::materials::Material;
use crate::math::Ray;
use crate::media::sample_t_maj;
use crate::samplers::Sampler;
use crate::scene::build::BuiltScene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// What a tentative collision turned out to be.
enum Event {
    Absorbed,
    Scattered(Ray),
    /// The ray reached its end (the surface hit, or nothing) unscattered.
    Passed,
}

/// Radiance along the camera ray by delta tracking.
pub fn simple_vol_path_li(
    scene: &BuiltScene,
    camera_ray: &CameraRay,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
) -> SampledSpectrum {
    let max_depth = scene.integrator.max_depth;
    lambda.terminate_secondary();
    let lambda: &SampledWavelengths = lambda;
    let mut ray = camera_ray.ray;
    let mut medium = scene.camera_medium;
    let mut l = SampledSpectrum::ZERO;
    // The phase function is sampled exactly (p / pdf = 1), so the
    // throughput stays 1 (pbrt-v4 keeps it as a number all the same).
    let mut beta = 1.0f32;
    let mut depth = 0;
    loop {
        rays.closest_hit += 1;
        let hit = scene.intersect(&ray, f32::INFINITY);
        let mut event = Event::Passed;
        if let Some(m) = medium {
            let mut rng = majorant_rng(sampler);
            let t_max = hit.as_ref().map_or(f32::INFINITY, |(si, _)| si.t);
            let u = sampler.get_1d();
            let mut u_mode = sampler.get_1d();
            sample_t_maj(
                &scene.media[m as usize],
                &ray,
                t_max,
                u,
                &mut rng,
                lambda,
                |rng, p, mp, sigma_maj, _t_maj| match choose_collision(mp, sigma_maj, u_mode) {
                    Collision::Absorb => {
                        l += mp.le * beta;
                        event = Event::Absorbed;
                        false
                    }
                    Collision::Scatter => {
                        if depth >= max_depth {
                            event = Event::Absorbed;
                            return false;
                        }
                        depth += 1;
                        let u = glam::Vec2::new(rng.uniform_f32(), rng.uniform_f32());
                        let wo = -ray.direction.normalize();
                        event = match HenyeyGreenstein::new(mp.g).sample_p(wo, u) {
                            Some(ps) if ps.pdf > 0.0 => {
                                beta *= ps.p / ps.pdf;
                                Event::Scattered(Ray::new(p, ps.wi, ray.time))
                            }
                            _ => Event::Absorbed,
                        };
                        false
                    }
                    Collision::Null => {
                        u_mode = rng.uniform_f32();
                        true
                    }
                },
            );
        }
        match event {
            Event::Absorbed => return l,
            Event::Scattered(next) => {
                ray = next;
                continue;
            }
            Event::Passed => {}
        }
        let Some((mut si, prim)) = hit else {
            for &i in &scene.infinite_lights {
                l += scene.lights[i].le(&ray, lambda) * beta;
            }
            return l;
        };
        si.wo = -ray.direction.normalize();
        l += emitted(scene, prim, &si, lambda) * beta;
        if matches!(scene.materials[prim.material as usize], Material::Interface) {
            medium = prim
                .medium_interface()
                .map_or(medium, |interface| interface.towards(ray.direction, si.n));
            ray = si.spawn_ray(ray.direction);
            continue;
        }
        // A black surface (the only other kind the scene's check
        // lets through): pbrt-v4 draws its BSDF sample's numbers, gets none,
        // and ends the path.
        sampler.skip(3);
        return l;
    }
}
