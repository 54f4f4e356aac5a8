//! pbrt-v4's `volpath` integrator in scenes with participating media:
//! unidirectional path tracing where a ray through a medium meets
//! tentative collisions drawn against the medium's majorant σmaj (delta
//! tracking), each one absorbing, scattering or a null collision in
//! proportion to σa, σs and σn = σmaj − σt at the first wavelength.
//!
//! The other wavelengths ride along with rescaled path probabilities:
//! `r_u` is the ratio of each wavelength's unidirectional (BSDF, phase
//! function, distance) sampling density to the density actually used,
//! `r_l` the same for the light-sampling strategy, so that the estimate
//! is unbiased at every wavelength (chromatic media) and light and
//! unidirectional samples are combined by the balance heuristic, as in
//! pbrt-v4. Shadow rays pass through `interface` surfaces and estimate
//! the media's transmittance by ratio tracking, with Russian roulette
//! where it falls below 0.05.
//!
//! Used only when rays meet media (the camera or a surface has one);
//! otherwise `path.rs` renders the scene (the same estimator without the
//! medium steps). The dual hair model's explicit ring connection is left
//! out here: its BSDF samples make the same paths.

use super::path::{light_context, nee_context};
use super::ray_counts::RayCounts;
use crate::bxdfs::{BxDFReflTransFlags, HenyeyGreenstein, TransportMode, BSDF};
use crate::cameras::CameraRay;
use crate::interaction::SurfaceInteraction;
use crate::lights::{Light, LightSampleContext};
use crate::materials::Material;
use crate::math::hash::{hash_floats, hash_vector};
use crate::math::pcg32::Pcg32;
use crate::math::{offset_ray_origin, Ray};
use crate::media::{sample_t_maj, MediumProperties};
use crate::samplers::Sampler;
use crate::scene::build::{BuiltScene, Primitive};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::textures::TextureEvalContext;
use glam::Vec3;

/// Shadow rays stop this far (in their parameter) short of the light.
const SHADOW_EPSILON: f32 = 1e-4;

/// Where a path's vertex is: on a surface or at a point in a medium.
enum Vertex<'a> {
    Surface {
        si: &'a SurfaceInteraction,
        bsdf: &'a BSDF,
        prim: &'a Primitive,
        /// The medium of the ray that arrived.
        medium: Option<u16>,
    },
    Medium {
        medium: u16,
        p: Vec3,
        wo: Vec3,
        time: f32,
        phase: HenyeyGreenstein,
    },
}

/// The medium a ray leaving a surface of `prim` (geometric normal `n`) in
/// direction `w` is in: the surface's interface decides, else the ray
/// keeps `current`.
fn medium_after(prim: &Primitive, w: Vec3, n: Vec3, current: Option<u16>) -> Option<u16> {
    prim.medium_interface()
        .map_or(current, |interface| interface.towards(w, n))
}

/// The light-sampling context of a point in a medium (no normal).
fn medium_context(p: Vec3, time: f32) -> LightSampleContext {
    LightSampleContext {
        p,
        p_error: Vec3::ZERO,
        n: Vec3::ZERO,
        ns: Vec3::ZERO,
        time,
    }
}

/// The event a tentative collision is, chosen in proportion to σa, σs and
/// σn at the first wavelength (pbrt-v4's `SampleDiscrete` over the three).
pub(super) enum Collision {
    Absorb,
    Scatter,
    Null,
}

pub(super) fn choose_collision(
    mp: &MediumProperties,
    sigma_maj: SampledSpectrum,
    u: f32,
) -> Collision {
    let p_absorb = mp.sigma_a[0] / sigma_maj[0];
    let p_scatter = mp.sigma_s[0] / sigma_maj[0];
    let p_null = (1.0 - p_absorb - p_scatter).max(0.0);
    let up = u * (p_absorb + p_scatter + p_null);
    if up < p_absorb {
        Collision::Absorb
    } else if up < p_absorb + p_scatter {
        Collision::Scatter
    } else {
        Collision::Null
    }
}

/// The random stream of a ray's tentative collisions, seeded by two of
/// the sampler's numbers (as pbrt-v4 seeds it).
pub(super) fn majorant_rng(sampler: &mut Sampler) -> Pcg32 {
    let h0 = hash_floats(&[sampler.get_1d()]);
    let h1 = hash_floats(&[sampler.get_1d()]);
    Pcg32::new_with_seed(h0, h1)
}

/// Radiance arriving along the camera ray at the path's wavelengths, in
/// a scene with media; the rays traced are added to `rays`.
pub fn volpath_li(
    scene: &BuiltScene,
    camera_ray: &CameraRay,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
) -> SampledSpectrum {
    let mut ray = camera_ray.ray;
    let mut medium = scene.camera_medium;
    let mut from_camera = true;
    let max_depth = scene.integrator.max_depth;
    let regularize = scene.integrator.regularize;
    let spp = scene.sampler.samples_per_pixel();
    let mut l = SampledSpectrum::ZERO;
    let mut beta = SampledSpectrum::ONE;
    let mut r_u = SampledSpectrum::ONE;
    let mut r_l = SampledSpectrum::ONE;
    let mut depth = 0;
    let mut specular_bounce = false;
    let mut any_non_specular = false;
    let mut eta_scale = 1.0f32;
    let mut prev_ctx = medium_context(ray.origin, ray.time);
    loop {
        rays.closest_hit += 1;
        let hit = scene.intersect(&ray, f32::INFINITY);
        if let Some(m) = medium {
            let lambda: &SampledWavelengths = lambda;
            let mut scattered: Option<Ray> = None;
            let mut terminated = false;
            let t_max = hit.as_ref().map_or(f32::INFINITY, |(si, _)| si.t);
            let mut rng = majorant_rng(sampler);
            let u = sampler.get_1d();
            let t_maj = sample_t_maj(
                &scene.media[m as usize],
                &ray,
                t_max,
                u,
                &mut rng,
                lambda,
                |rng, p, mp, sigma_maj, t_maj| {
                    // Emission, weighted as if a collision were taken here.
                    if depth < max_depth && mp.le.is_nonzero() {
                        let pdf = sigma_maj[0] * t_maj[0];
                        let beta_e = beta * t_maj / pdf;
                        let r_e = r_u * sigma_maj * t_maj / pdf;
                        if r_e.is_nonzero() {
                            l += beta_e * mp.sigma_a * mp.le / r_e.average();
                        }
                    }
                    match choose_collision(mp, sigma_maj, rng.uniform_f32()) {
                        Collision::Absorb => {
                            terminated = true;
                            false
                        }
                        Collision::Scatter => {
                            if depth >= max_depth {
                                terminated = true;
                                return false;
                            }
                            depth += 1;
                            let pdf = t_maj[0] * mp.sigma_s[0];
                            beta *= t_maj * mp.sigma_s / pdf;
                            r_u *= t_maj * mp.sigma_s / pdf;
                            if beta.is_nonzero() && r_u.is_nonzero() {
                                let wo = -ray.direction.normalize();
                                let phase = HenyeyGreenstein::new(mp.g);
                                let vertex = Vertex::Medium {
                                    medium: m,
                                    p,
                                    wo,
                                    time: ray.time,
                                    phase,
                                };
                                l += sample_ld(scene, &vertex, lambda, sampler, rays, beta, r_u);
                                match phase.sample_p(wo, sampler.get_2d()) {
                                    Some(ps) if ps.pdf > 0.0 => {
                                        beta *= ps.p / ps.pdf;
                                        r_l = r_u / ps.pdf;
                                        prev_ctx = medium_context(p, ray.time);
                                        scattered = Some(Ray::new(p, ps.wi, ray.time));
                                        specular_bounce = false;
                                        any_non_specular = true;
                                    }
                                    _ => terminated = true,
                                }
                            }
                            false
                        }
                        Collision::Null => {
                            let sigma_n = (sigma_maj - mp.sigma_a - mp.sigma_s).clamp_zero();
                            let pdf = t_maj[0] * sigma_n[0];
                            if pdf == 0.0 {
                                beta = SampledSpectrum::ZERO;
                            } else {
                                beta *= t_maj * sigma_n / pdf;
                                r_u *= t_maj * sigma_n / pdf;
                                r_l *= t_maj * sigma_maj / pdf;
                            }
                            beta.is_nonzero() && r_u.is_nonzero()
                        }
                    }
                },
            );
            if terminated || beta.is_zero() || r_u.is_zero() {
                return l;
            }
            if let Some(next) = scattered {
                ray = next;
                from_camera = false;
                continue;
            }
            beta *= t_maj / t_maj[0];
            r_u *= t_maj / t_maj[0];
            r_l *= t_maj / t_maj[0];
        }

        let Some((mut si, prim)) = hit else {
            // Escaped: infinite lights.
            for &i in &scene.infinite_lights {
                let light = &scene.lights[i];
                let le = light.le(&ray, lambda);
                if le.is_zero() {
                    continue;
                }
                if depth == 0 || specular_bounce {
                    l += beta * le / r_u.average();
                } else {
                    let p_l = scene.light_sampler.pmf(&prev_ctx, i)
                        * light.pdf_li(&prev_ctx, ray.direction, &scene.shapes, true);
                    l += beta * le / (r_u + r_l * p_l).average();
                }
            }
            break;
        };
        si.wo = -ray.direction.normalize();
        if let Some(light_index) = prim.area_light() {
            if let Light::DiffuseArea(area) = &scene.lights[light_index as usize] {
                let le = area.l(si.p, si.n, si.uv, si.wo, lambda);
                if le.is_nonzero() {
                    if depth == 0 || specular_bounce {
                        l += beta * le / r_u.average();
                    } else {
                        let light = &scene.lights[light_index as usize];
                        let p_l = scene.light_sampler.pmf(&prev_ctx, light_index as usize)
                            * light.pdf_li(&prev_ctx, ray.direction, &scene.shapes, true);
                        l += beta * le / (r_u + r_l * p_l).average();
                    }
                }
            }
        }
        let material = &scene.materials[prim.material as usize];
        let ctx = if scene.integrator.texture_filtering {
            let (dpdx, dpdy) = if from_camera {
                scene.camera.first_hit_dp_dxy(camera_ray, si.p, si.n, spp)
            } else {
                scene.camera.approximate_dp_dxy(si.p, si.n, spp)
            };
            TextureEvalContext::with_differentials(&si, dpdx, dpdy)
        } else {
            TextureEvalContext::at(&si)
        };
        let Some(mut bsdf) = material.bsdf(&mut si, &ctx, lambda) else {
            // A medium boundary: continue through it, into the medium on
            // its far side, without counting a bounce.
            medium = medium_after(prim, ray.direction, si.n, medium);
            ray = si.spawn_ray(ray.direction);
            continue;
        };
        from_camera = false;
        if regularize && any_non_specular {
            bsdf.regularize();
        }
        if depth >= max_depth {
            break;
        }
        depth += 1;
        let flags = bsdf.flags();
        let in_ring = bsdf.diffracting_ring().is_some();
        if flags.is_non_specular() {
            let vertex = Vertex::Surface {
                si: &si,
                bsdf: &bsdf,
                prim,
                medium,
            };
            l += sample_ld(scene, &vertex, lambda, sampler, rays, beta, r_u);
        }
        prev_ctx = light_context(&si, in_ring);

        let wo = si.wo;
        let u = sampler.get_1d();
        let Some(bs) = bsdf.sample_f(
            wo,
            u,
            sampler.get_2d(),
            TransportMode::Radiance,
            BxDFReflTransFlags::All,
        ) else {
            break;
        };
        beta *= bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
        let pdf = if bs.pdf_is_proportional {
            bsdf.pdf(wo, bs.wi, TransportMode::Radiance, BxDFReflTransFlags::All)
        } else {
            bs.pdf
        };
        r_l = r_u / pdf;
        specular_bounce = bs.is_specular();
        any_non_specular |= !bs.is_specular();
        if bs.is_transmission() {
            eta_scale *= bs.eta * bs.eta;
        }
        medium = medium_after(prim, bs.wi, si.n, medium);
        ray = if in_ring {
            si.spawn_ray_through(bs.wi)
        } else {
            si.spawn_ray(bs.wi)
        };
        if beta.is_zero() {
            break;
        }
        let rr_beta = beta * eta_scale / r_u.average();
        let u_rr = sampler.get_1d();
        if rr_beta.max_component() < 1.0 && depth > 1 {
            let q = (1.0 - rr_beta.max_component()).max(0.0);
            if u_rr < q {
                break;
            }
            beta /= 1.0 - q;
        }
    }
    l
}

/// Direct light at a path vertex from one sampled light, through the media
/// and `interface` surfaces between (ratio tracking), weighted against the
/// vertex's own sampling by the balance heuristic over the rescaled path
/// probabilities; `beta` and `r_p` are the path's throughput and
/// unidirectional probability ratios up to the vertex.
fn sample_ld(
    scene: &BuiltScene,
    vertex: &Vertex,
    lambda: &SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
    beta: SampledSpectrum,
    r_p: SampledSpectrum,
) -> SampledSpectrum {
    let ctx = match vertex {
        Vertex::Surface { si, bsdf, .. } => nee_context(si, bsdf),
        Vertex::Medium { p, time, .. } => medium_context(*p, *time),
    };
    let u = sampler.get_1d();
    let sampled = scene.light_sampler.sample(&ctx, u);
    let u_light = sampler.get_2d();
    let Some((light_index, p_light)) = sampled else {
        return SampledSpectrum::ZERO;
    };
    let light = &scene.lights[light_index];
    let Some(ls) = light.sample_li(&ctx, u_light, lambda, &scene.shapes, true) else {
        return SampledSpectrum::ZERO;
    };
    if ls.l.is_known_zero() || ls.pdf == 0.0 {
        return SampledSpectrum::ZERO;
    }
    let (f_hat, scatter_pdf, origin, medium) = match vertex {
        Vertex::Surface {
            si,
            bsdf,
            prim,
            medium,
        } => {
            let f = bsdf.f(si.wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(si.shading.n).abs();
            let pdf = bsdf.pdf(
                si.wo,
                ls.wi,
                TransportMode::Radiance,
                BxDFReflTransFlags::All,
            );
            let to = ls.p_light - si.p;
            let origin = if bsdf.diffracting_ring().is_some() {
                si.point_through(to)
            } else {
                offset_ray_origin(si.p, si.p_error, si.n, to)
            };
            (f, pdf, origin, medium_after(prim, to, si.n, *medium))
        }
        Vertex::Medium {
            medium,
            p,
            wo,
            phase,
            ..
        } => {
            let f = phase.p(*wo, ls.wi);
            (
                SampledSpectrum::splat(f),
                phase.pdf(*wo, ls.wi),
                *p,
                Some(*medium),
            )
        }
    };
    if f_hat.is_zero() {
        return SampledSpectrum::ZERO;
    }
    let time = ctx.time;
    let target = if ls.n_light == Vec3::ZERO {
        ls.p_light
    } else {
        offset_ray_origin(
            ls.p_light,
            ls.p_light_error,
            ls.n_light,
            origin - ls.p_light,
        )
    };
    let Some((t_ray, r_u, r_l)) = transmittance(scene, origin, target, medium, time, lambda, rays)
    else {
        return SampledSpectrum::ZERO;
    };
    let le = ls.l.value(lambda);
    if le.is_zero() {
        return SampledSpectrum::ZERO;
    }
    let r_l = r_l * r_p * (p_light * ls.pdf);
    let r_u = r_u * r_p * scatter_pdf;
    let weight = if light.sampled_only() {
        r_l.average()
    } else {
        (r_l + r_u).average()
    };
    beta * f_hat * t_ray * le / weight
}

/// The transmittance from `origin` to `target` (ratio tracking through
/// each medium, passing `interface` surfaces), with the ratio-tracking
/// path probabilities (r_u, r_l); `None` when an opaque surface blocks
/// the way or the estimate is zero.
fn transmittance(
    scene: &BuiltScene,
    mut origin: Vec3,
    target: Vec3,
    mut medium: Option<u16>,
    time: f32,
    lambda: &SampledWavelengths,
    rays: &mut RayCounts,
) -> Option<(SampledSpectrum, SampledSpectrum, SampledSpectrum)> {
    let mut t_ray = SampledSpectrum::ONE;
    let mut r_u = SampledSpectrum::ONE;
    let mut r_l = SampledSpectrum::ONE;
    let mut rng = Pcg32::new_with_seed(hash_vector(origin), hash_vector(target - origin));
    loop {
        let ray = Ray::new(origin, target - origin, time);
        rays.shadow += 1;
        let hit = scene.intersect(&ray, 1.0 - SHADOW_EPSILON);
        if let Some((_, prim)) = &hit {
            if !matches!(scene.materials[prim.material as usize], Material::Interface) {
                return None;
            }
        }
        if let Some(m) = medium {
            let t_max = hit.as_ref().map_or(1.0 - SHADOW_EPSILON, |(si, _)| si.t);
            let u = rng.uniform_f32();
            let t_maj = sample_t_maj(
                &scene.media[m as usize],
                &ray,
                t_max,
                u,
                &mut rng,
                lambda,
                |rng, _, mp, sigma_maj, t_maj| {
                    let sigma_n = (sigma_maj - mp.sigma_a - mp.sigma_s).clamp_zero();
                    let pdf = t_maj[0] * sigma_maj[0];
                    t_ray *= t_maj * sigma_n / pdf;
                    r_l *= t_maj * sigma_maj / pdf;
                    r_u *= t_maj * sigma_n / pdf;
                    // Russian roulette on a path that transmits little.
                    let tr = t_ray / (r_l + r_u).average();
                    if tr.max_component() < 0.05 {
                        if rng.uniform_f32() < 0.75 {
                            t_ray = SampledSpectrum::ZERO;
                        } else {
                            t_ray /= 0.25;
                        }
                    }
                    t_ray.is_nonzero()
                },
            );
            t_ray *= t_maj / t_maj[0];
            r_l *= t_maj / t_maj[0];
            r_u *= t_maj / t_maj[0];
        }
        if t_ray.is_zero() || t_ray.has_nan() {
            return None;
        }
        let Some((si, prim)) = hit else {
            return Some((t_ray, r_u, r_l));
        };
        let to = target - si.p;
        medium = medium_after(prim, to, si.n, medium);
        origin = offset_ray_origin(si.p, si.p_error, si.n, to);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::build::{build, RenderOverrides};
    use glam::IVec2;
    use std::path::Path;

    /// A unit sphere at z = 5 holding medium `medium` (an `interface`
    /// boundary), lit by a constant infinite light of spectrum 1 (or
    /// nothing, when `light` is false); the camera sits at the origin.
    fn sphere_scene(medium: &str, light: bool) -> BuiltScene {
        let light = if light {
            "LightSource \"infinite\" \"spectrum L\" [300 1 900 1]"
        } else {
            ""
        };
        let text = format!(
            "Integrator \"volpath\" \"integer maxdepth\" 1000\n\
             Sampler \"independent\" \"integer pixelsamples\" 1000000\n\
             Camera \"perspective\"\nWorldBegin\n{light}\n\
             MakeNamedMedium \"m\" \"string type\" {medium}\n\
             AttributeBegin\nTranslate 0 0 5\nMediumInterface \"m\" \"\"\n\
             Material \"interface\"\nShape \"sphere\"\nAttributeEnd\n"
        );
        let loaded = crate::scene::load_text(Path::new("media.pbrt"), &text).unwrap();
        let scene = build(loaded.scene, &RenderOverrides::default()).unwrap();
        assert!(scene.has_media);
        scene
    }

    /// The mean radiance along the ray from the origin in direction `d`
    /// per wavelength of `lambdas`, each wavelength taking each place in
    /// the sampled set in turn (the hero wavelength decides the sampling,
    /// and the estimate is unbiased over its choice), divided by the light's
    /// radiance `le` at that wavelength.
    fn mean_radiance(scene: &BuiltScene, d: Vec3, lambdas: [f32; 4], n: u32, le: f32) -> [f32; 4] {
        let mut sampler = scene.sampler.clone();
        let mut sum = [0.0f64; 4];
        let mut rays = RayCounts::default();
        for rotation in 0..4 {
            let mut lambda = SampledWavelengths {
                lambda: std::array::from_fn(|i| lambdas[(i + rotation) % 4]),
                pdf: [1.0; 4],
            };
            for i in 0..n {
                sampler.start_pixel_sample(IVec2::new(rotation as i32, 0), i, 0);
                let camera_ray = CameraRay {
                    ray: Ray::new(Vec3::ZERO, d, 0.0),
                    weight: 1.0,
                    differentials: None,
                };
                let l = volpath_li(scene, &camera_ray, &mut lambda, &mut sampler, &mut rays);
                for k in 0..4 {
                    sum[(k + rotation) % 4] += l[k] as f64;
                }
            }
        }
        sum.map(|s| (s / (4 * n) as f64) as f32 / le)
    }

    /// The light's radiance (constant over wavelength).
    fn light_radiance(scene: &BuiltScene) -> f32 {
        let lambda = SampledWavelengths::sample_visible(0.5);
        let le = scene.lights[0].le(&Ray::new(Vec3::ZERO, Vec3::Y, 0.0), &lambda);
        assert!((le.max_component() - le.min_component()).abs() < 1e-4 * le[0]);
        le[0]
    }

    const LAMBDAS: [f32; 4] = [420.0, 500.0, 610.0, 700.0];

    /// Each of [`LAMBDAS`]' radiances in `l` within 0.01 + 2 % of
    /// `expected(λ)`.
    fn assert_per_wavelength(l: [f32; 4], expected: impl Fn(f32) -> f32, what: &str) {
        for (i, &lambda) in LAMBDAS.iter().enumerate() {
            let expected = expected(lambda);
            assert!(
                (l[i] - expected).abs() < 0.01 + 0.02 * expected,
                "λ {lambda}: {} vs {what} {expected}",
                l[i]
            );
        }
    }

    /// σa(λ) of `"spectrum sigma_a" [360 0.2 830 1.6]`.
    fn sigma_of(lambda: f32) -> f32 {
        0.2 + (lambda - 360.0) / 470.0 * 1.4
    }

    #[test]
    fn chromatic_absorber_transmits_exp_minus_sigma_lambda_d() {
        let scene = sphere_scene(
            "\"homogeneous\" \"spectrum sigma_a\" [360 0.2 830 1.6] \"spectrum sigma_s\" [360 0 830 0]",
            true,
        );
        let le = light_radiance(&scene);
        // Through the centre: d = 2.
        let l = mean_radiance(&scene, Vec3::Z, LAMBDAS, 40_000, le);
        assert_per_wavelength(l, |lambda| (-sigma_of(lambda) * 2.0).exp(), "exp(−σ(λ) d)");
    }

    #[test]
    fn scattering_medium_in_a_furnace_conserves_energy() {
        // Albedo 1 at every wavelength, σs chromatic, forward-peaked: all
        // light that enters leaves, so every ray sees the light's radiance.
        let scene = sphere_scene(
            "\"homogeneous\" \"spectrum sigma_a\" [360 0 830 0] \"spectrum sigma_s\" [360 0.5 830 3] \"float g\" 0.4",
            true,
        );
        let le = light_radiance(&scene);
        for d in [Vec3::Z, Vec3::new(0.15, 0.05, 1.0)] {
            let l = mean_radiance(&scene, d, LAMBDAS, 6_000, le);
            for (i, &lambda) in LAMBDAS.iter().enumerate() {
                assert!((l[i] - 1.0).abs() < 0.03, "λ {lambda}, d {d}: {}", l[i]);
            }
        }
    }

    #[test]
    fn emissive_absorber_glows_1_minus_exp_minus_sigma_d() {
        // No light: along a chord of length d, an absorbing medium with
        // emission Le gives Le (1 − e^(−σa d)).
        let scene = sphere_scene(
            "\"homogeneous\" \"spectrum sigma_a\" [360 0.2 830 1.6] \"spectrum sigma_s\" [360 0 830 0] \"spectrum Le\" [300 2 900 2]",
            false,
        );
        // (An illuminant spectrum from a file's values is normalised to
        // luminance 1: the medium's own Le is the reference.)
        let le = scene.media[0]
            .sample_point(
                Vec3::new(0.0, 0.0, 5.0),
                &SampledWavelengths::sample_visible(0.5),
            )
            .le[0];
        let l = mean_radiance(&scene, Vec3::Z, LAMBDAS, 20_000, le);
        assert_per_wavelength(
            l,
            |lambda| 1.0 - (-sigma_of(lambda) * 2.0).exp(),
            "1 − exp(−σ(λ) d)",
        );
    }

    #[test]
    fn grid_of_constant_density_matches_the_homogeneous_medium() {
        // A 3×3×3 grid of density 1 (cell centres at −5, 5, 15 on each
        // axis): between the centres, around the sphere, it is σ
        // everywhere.
        let ones = ["1"; 27].join(" ");
        let scene = sphere_scene(
            &format!("\"uniformgrid\" \"integer nx\" 3 \"integer ny\" 3 \"integer nz\" 3 \"float density\" [{ones}] \"point3 p0\" [-10 -10 -10] \"point3 p1\" [20 20 20] \"spectrum sigma_a\" [360 0.2 830 1.6] \"spectrum sigma_s\" [360 0 830 0]"),
            true,
        );
        let le = light_radiance(&scene);
        let l = mean_radiance(&scene, Vec3::Z, LAMBDAS, 20_000, le);
        assert_per_wavelength(l, |lambda| (-sigma_of(lambda) * 2.0).exp(), "exp(−σ(λ) d)");
    }

    /// A NanoVDB file (in a fresh temporary directory) of one 8³ leaf of
    /// density 1 whose world box, −3.5…3.5 × −3.5…3.5 × 1.5…8.5, holds
    /// the unit sphere at z = 5.
    fn constant_nvdb(tag: &str) -> std::path::PathBuf {
        use crate::media::nanovdb_file::test_writer::{file_bytes, ramp};
        let dir = std::env::temp_dir().join(format!("rpbrt-volpath-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut spec = ramp("density", 0.0, |_, _, _| 1.0);
        spec.translation = [-3.5, -3.5, 1.5];
        spec.world_min = [-3.5, -3.5, 1.5];
        spec.world_max = [3.5, 3.5, 8.5];
        let path = dir.join("constant.nvdb");
        std::fs::write(&path, file_bytes(&[spec], 1, true)).unwrap();
        path
    }

    #[test]
    fn nanovdb_of_constant_density_matches_the_homogeneous_medium() {
        let path = constant_nvdb("absorber");
        let scene = sphere_scene(
            &format!("\"nanovdb\" \"string filename\" \"{}\" \"spectrum sigma_a\" [360 0.2 830 1.6] \"spectrum sigma_s\" [360 0 830 0]", path.display()),
            true,
        );
        let le = light_radiance(&scene);
        let l = mean_radiance(&scene, Vec3::Z, LAMBDAS, 20_000, le);
        assert_per_wavelength(l, |lambda| (-sigma_of(lambda) * 2.0).exp(), "exp(−σ(λ) d)");
        // Scattering: the same radiance as the homogeneous medium.
        let coefficients = "\"spectrum sigma_a\" [360 0.3 830 0.1] \"spectrum sigma_s\" [360 0.5 830 2] \"float g\" 0.3";
        let vdb = sphere_scene(
            &format!(
                "\"nanovdb\" \"string filename\" \"{}\" {coefficients}",
                path.display()
            ),
            true,
        );
        let homogeneous = sphere_scene(&format!("\"homogeneous\" {coefficients}"), true);
        let d = Vec3::new(0.1, 0.05, 1.0);
        let a = mean_radiance(&vdb, d, LAMBDAS, 8_000, le);
        let b = mean_radiance(&homogeneous, d, LAMBDAS, 8_000, le);
        for i in 0..4 {
            assert!(
                (a[i] - b[i]).abs() < 0.03,
                "λ {}: {} vs {}",
                LAMBDAS[i],
                a[i],
                b[i]
            );
        }
        std::fs::remove_dir_all(path.parent().unwrap()).ok();
    }
}
