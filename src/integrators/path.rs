//! pbrt-v4's `path` integrator (and `volpath` for scenes without media):
//! unidirectional path tracing with next-event estimation and multiple
//! importance sampling of lights and BSDFs, Russian roulette after the
//! second bounce.
//!
//! Without media the two differ in two ways, both kept: `volpath` weighs
//! light and BSDF samples by the balance heuristic (its rescaled path
//! probabilities divide by the sum of the two densities) where `path` uses
//! the power heuristic, and `volpath` draws its Russian-roulette number at
//! every bounce where `path` draws it only when roulette applies.

use super::diffraction_connection::{self, ConnectionOrigin};
use super::ray_counts::RayCounts;
use crate::bxdfs::{BxDFReflTransFlags, TransportMode, BSDF};
use crate::cameras::CameraRay;
use crate::interaction::SurfaceInteraction;
use crate::lights::{Light, LightSampleContext};
use crate::math::sampling::{balance_heuristic, power_heuristic};
use crate::samplers::Sampler;
use crate::scene::build::BuiltScene;
use crate::scene::build::IntegratorKind;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::textures::TextureEvalContext;
use glam::{Vec2, Vec3};

/// The MIS weight of a sample drawn with density `f` against the other
/// strategy's `g`, by the integrator's heuristic.
fn mis_weight(volpath: bool, f: f32, g: f32) -> f32 {
    if volpath {
        balance_heuristic(1.0, f, 1.0, g)
    } else {
        power_heuristic(1.0, f, 1.0, g)
    }
}

/// The light-sampling context at `si`. At a diffracting-ring hit the point
/// carries no error bound: rays from it go along their direction
/// ([`SurfaceInteraction::spawn_ray_through`]), and an area light's density
/// is then taken along the line the path really follows, not from a point
/// pushed a curve's width sideways.
pub(super) fn light_context(si: &SurfaceInteraction, ring: bool) -> LightSampleContext {
    LightSampleContext {
        p: si.p,
        p_error: if ring { Vec3::ZERO } else { si.p_error },
        n: si.n,
        ns: si.shading.n,
        time: si.time,
    }
}

/// Radiance arriving along the camera ray at the path's wavelengths; the
/// rays the path traced are added to `rays`.
pub fn path_li(
    scene: &BuiltScene,
    camera_ray: &CameraRay,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
) -> SampledSpectrum {
    let mut ray = camera_ray.ray;
    // The camera ray's differentials hold until the first scattering
    // (through `interface` surfaces too, as the offset rays go straight on).
    let mut from_camera = true;
    let max_depth = scene.integrator.max_depth;
    let volpath = scene.integrator.kind == IntegratorKind::VolPath;
    let regularize = scene.integrator.regularize;
    let spp = scene.sampler.samples_per_pixel();
    let mut l = SampledSpectrum::ZERO;
    let mut beta = SampledSpectrum::ONE;
    let mut depth = 0;
    let mut specular_bounce = false;
    let mut any_non_specular = false;
    let mut eta_scale = 1.0f32;
    let mut p_b = 1.0f32;
    let mut prev_ctx: Option<LightSampleContext> = None;
    // Light through one diffracting ring from a non-specular vertex is
    // connected there ([`diffraction_connection`]): after such a vertex, a
    // ring hit neither samples a light nor counts the emission its sample
    // reaches (the same paths, made once).
    let connect_diffraction = scene.integrator.connect_diffraction;
    // The last non-specular vertex, while its connections cover the ring
    // hit that follows it (and that ring's sample after it).
    let mut connected_from: Option<ConnectionOrigin> = None;
    let mut ring_connected = false;
    let mut skip_emission = false;
    loop {
        rays.closest_hit += 1;
        let Some((mut si, prim)) = scene.intersect(&ray, f32::INFINITY) else {
            // Escaped: infinite lights.
            for &i in &scene.infinite_lights {
                let light = &scene.lights[i];
                let le = light.le(&ray, lambda);
                if skip_emission {
                    // Through a ring: counted here only where the
                    // connection could not have made the path.
                    if let Some(origin) = &connected_from {
                        if !origin.covers(scene, i, None, ray.direction) {
                            l += beta * le;
                        }
                    }
                    continue;
                }
                match (&prev_ctx, depth == 0 || specular_bounce) {
                    (Some(ctx), false) => {
                        let p_l = scene.light_sampler.pmf(ctx, i)
                            * light.pdf_li(ctx, ray.direction, &scene.shapes, true);
                        l += beta * le * mis_weight(volpath, p_b, p_l);
                    }
                    _ => l += beta * le,
                }
            }
            break;
        };
        si.wo = -ray.direction.normalize();
        // Emission of an area light that was hit.
        if let Some(light_index) = prim.area_light() {
            if let Light::DiffuseArea(area) = &scene.lights[light_index as usize] {
                let le = area.l(si.p, si.n, si.uv, si.wo, lambda);
                if le.is_nonzero() && skip_emission {
                    let origin = connected_from.as_ref();
                    if origin
                        .is_some_and(|o| !o.covers(scene, light_index as usize, Some(&si), si.wo))
                    {
                        l += beta * le;
                    }
                } else if le.is_nonzero() {
                    match (&prev_ctx, depth == 0 || specular_bounce) {
                        (Some(ctx), false) => {
                            let light = &scene.lights[light_index as usize];
                            let p_l = scene.light_sampler.pmf(ctx, light_index as usize)
                                * light.pdf_li(ctx, ray.direction, &scene.shapes, true);
                            l += beta * le * mis_weight(volpath, p_b, p_l);
                        }
                        _ => l += beta * le,
                    }
                }
            }
        }
        let material = &scene.materials[prim.material as usize];
        // Where the vertex will surely sample a light (hair, below the
        // depth limit), its numbers are drawn now (no draw comes between,
        // so the order is pbrt-v4's) and the light's sampling table is
        // fetched from memory while the BSDF is made.
        let light_u = (depth != max_depth && material.always_non_specular()).then(|| {
            let u = (sampler.get_1d(), sampler.get_2d());
            if let Some(i) = scene.light_sampler.sample_anywhere(u.0) {
                scene.lights[i].prefetch_sample(u.1, true);
            }
            u
        });
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
            // Interface: continue through the surface without counting a
            // bounce.
            specular_bounce = true;
            ring_connected = false;
            skip_emission = false;
            ray = si.spawn_ray(ray.direction);
            continue;
        };
        from_camera = false;
        if regularize && any_non_specular {
            bsdf.regularize();
        }
        if depth == max_depth {
            break;
        }
        depth += 1;
        let flags = bsdf.flags();
        let in_ring = bsdf.diffracting_ring().is_some();
        // A ring hit whose direct light the previous vertex connected.
        let connected_ring = ring_connected && in_ring;
        // Through a ring the path is a bounce longer: connected below the
        // depth limit only, as the ring's own light sample would be.
        let connect_here = connect_diffraction && depth < max_depth;
        if flags.is_non_specular() && !connected_ring {
            let ld = sample_ld(
                scene,
                &si,
                &bsdf,
                lambda,
                sampler,
                volpath,
                light_u,
                connect_here,
                rays,
            );
            l += beta * ld;
        }
        skip_emission = connected_ring;
        ring_connected = connect_here && flags.is_non_specular() && !connected_ring;
        if ring_connected {
            connected_from = Some(ConnectionOrigin {
                ctx: nee_context(&si, &bsdf),
            });
        }
        prev_ctx = Some(light_context(&si, in_ring));

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
        p_b = if bs.pdf_is_proportional {
            bsdf.pdf(wo, bs.wi, TransportMode::Radiance, BxDFReflTransFlags::All)
        } else {
            bs.pdf
        };
        specular_bounce = bs.is_specular();
        any_non_specular |= !bs.is_specular();
        if bs.is_transmission() {
            eta_scale *= bs.eta * bs.eta;
        }
        ray = if in_ring {
            si.spawn_ray_through(bs.wi)
        } else {
            si.spawn_ray(bs.wi)
        };

        // A path that carries nothing ends here (after it, roulette would
        // only end it too).
        if beta.is_zero() {
            break;
        }
        // Russian roulette (`volpath` takes its number at every bounce).
        let u_rr = volpath.then(|| sampler.get_1d());
        let rr_beta = beta * eta_scale;
        if rr_beta.max_component() < 1.0 && depth > 1 {
            let q = (1.0 - rr_beta.max_component()).max(0.0);
            if u_rr.unwrap_or_else(|| sampler.get_1d()) < q {
                break;
            }
            beta /= 1.0 - q;
        }
    }
    l
}

/// Where lights are sampled from at `si`: offset to the side light can
/// arrive from when the BSDF only reflects or only transmits.
pub(super) fn nee_context(si: &SurfaceInteraction, bsdf: &BSDF) -> LightSampleContext {
    let mut ctx = light_context(si, bsdf.diffracting_ring().is_some());
    let flags = bsdf.flags();
    if flags.is_reflective() && !flags.is_transmissive() {
        ctx.p = crate::math::offset_ray_origin(si.p, si.p_error, si.n, si.wo);
    } else if flags.is_transmissive() && !flags.is_reflective() {
        ctx.p = crate::math::offset_ray_origin(si.p, si.p_error, si.n, -si.wo);
    }
    ctx
}

/// Direct lighting at `si` from one sampled light, MIS-weighted against
/// BSDF sampling (by `volpath`'s heuristic when `volpath`); with
/// `connect_diffraction`, a shadow ray stopped by a diffracting ring is
/// connected through it ([`diffraction_connection::through_ring`]).
#[allow(clippy::too_many_arguments)]
fn sample_ld(
    scene: &BuiltScene,
    si: &SurfaceInteraction,
    bsdf: &BSDF,
    lambda: &SampledWavelengths,
    sampler: &mut Sampler,
    volpath: bool,
    light_u: Option<(f32, Vec2)>,
    connect_diffraction: bool,
    rays: &mut RayCounts,
) -> SampledSpectrum {
    let through = bsdf.diffracting_ring().is_some();
    let ctx = nee_context(si, bsdf);
    let (u, u_light) = light_u.unwrap_or_else(|| (sampler.get_1d(), sampler.get_2d()));
    let Some((light_index, p_light)) = scene.light_sampler.sample(&ctx, u) else {
        return SampledSpectrum::ZERO;
    };
    let light = &scene.lights[light_index];
    let Some(ls) = light.sample_li(&ctx, u_light, lambda, &scene.shapes, true) else {
        return SampledSpectrum::ZERO;
    };
    if ls.l.is_known_zero() || ls.pdf == 0.0 {
        return SampledSpectrum::ZERO;
    }
    ls.l.prefetch();
    let (f, p_b) = bsdf.f_and_pdf(si.wo, ls.wi, TransportMode::Radiance);
    let f = f * ls.wi.dot(si.shading.n).abs();
    if connect_diffraction {
        // The connection's direction differs from the light's: a zero f
        // here does not make it zero.
        rays.shadow += 1;
        if let Some(blocker) =
            scene.first_blocker(si, through, ls.p_light, ls.p_light_error, ls.n_light)
        {
            return diffraction_connection::through_ring(
                scene, si, bsdf, &ctx, light, &ls, p_light, &blocker, u_light, lambda, sampler,
                rays,
            )
            .unwrap_or(SampledSpectrum::ZERO);
        }
        if f.is_zero() {
            return SampledSpectrum::ZERO;
        }
    } else {
        if f.is_zero() {
            return SampledSpectrum::ZERO;
        }
        rays.shadow += 1;
        if !scene.unoccluded(si, through, ls.p_light, ls.p_light_error, ls.n_light) {
            return SampledSpectrum::ZERO;
        }
    }
    let l = ls.l.value(lambda);
    if l.is_zero() {
        return SampledSpectrum::ZERO;
    }
    let p_l = p_light * ls.pdf;
    if light.sampled_only() {
        return l * f / p_l;
    }
    let p_b = p_b.unwrap_or_else(|| {
        bsdf.pdf(
            si.wo,
            ls.wi,
            TransportMode::Radiance,
            BxDFReflTransFlags::All,
        )
    });
    l * f * (mis_weight(volpath, p_l, p_b) / p_l)
}
