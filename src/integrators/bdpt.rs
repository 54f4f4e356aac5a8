//! pbrt-v4's `bdpt` integrator: bidirectional path tracing. Each pixel
//! sample traces a camera subpath and a light subpath and joins every
//! prefix of one to every prefix of the other (s light vertices, t camera
//! vertices); each strategy is weighted by the balance heuristic over all
//! the strategies that could have made the same path (pbrt-v4's
//! `MISWeight`, with its densities per unit area). Strategies with t = 1
//! join a light-path vertex to the lens and are splatted onto the film.
//! Surfaces only (no media); point and diffuse area lights and the
//! perspective camera (as `lightpath`).
//!
//! | Parameter | Type | Default | Meaning |
//! |---|---|---|---|
//! | `maxdepth` | integer | 5 | Most scattering events along a path |
//! | `regularize` | bool | false | Roughen near-specular BSDFs after a non-specular bounce |
//! | `visualizestrategies`, `visualizeweights` | bool | false | Not supported yet (an error when true) |

use super::light_path::sample_bounds;
use super::ray_counts::RayCounts;
use super::surface_hit::texture_context;
use crate::bxdfs::{BxDFReflTransFlags, TransportMode, BSDF};
use crate::cameras::importance::SampleBounds;
use crate::cameras::{CameraRay, PerspectiveCamera};
use crate::film::splat::SplatBuffer;
use crate::interaction::SurfaceInteraction;
use crate::lights::{Light, LightKind, LightSampleContext};
use crate::math::Ray;
use crate::samplers::Sampler;
use crate::scene::build::BuiltScene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum VertexKind {
    Camera,
    Light,
    Surface,
}

/// A subpath vertex.
#[derive(Clone, Copy)]
struct Vertex {
    kind: VertexKind,
    /// Throughput from the subpath's start up to here.
    beta: SampledSpectrum,
    /// The point, its geometric normal (zero where none: a pinhole's
    /// point, a point light) and the interaction (for spawning rays).
    si: SurfaceInteraction,
    /// Shading normal (the geometric one where there is no shading).
    ns: Vec3,
    bsdf: Option<BSDF>,
    /// The light (light vertices, and surfaces that emit).
    light: Option<usize>,
    /// Sampled from a specular lobe.
    delta: bool,
    /// Area densities of sampling this vertex forwards (along its
    /// subpath) and in reverse (from the other end).
    pdf_fwd: f32,
    pdf_rev: f32,
}

impl Vertex {
    fn p(&self) -> Vec3 {
        self.si.p
    }

    fn on_surface(&self) -> bool {
        self.si.n != Vec3::ZERO
    }

    fn is_light(&self) -> bool {
        self.kind == VertexKind::Light || (self.kind == VertexKind::Surface && self.light.is_some())
    }

    fn is_delta_light(&self, scene: &BuiltScene) -> bool {
        self.kind == VertexKind::Light && self.light.is_some_and(|l| scene.lights[l].sampled_only())
    }

    fn connectible(&self, scene: &BuiltScene) -> bool {
        match self.kind {
            VertexKind::Camera => true,
            VertexKind::Light => self
                .light
                .is_none_or(|l| scene.lights[l].kind() != LightKind::DeltaDirection),
            VertexKind::Surface => self.bsdf.is_some_and(|b| b.flags().is_non_specular()),
        }
    }

    /// The BSDF towards `next` (zero for end points).
    fn f(&self, next: &Vertex, mode: TransportMode) -> SampledSpectrum {
        let d = next.p() - self.p();
        if d.length_squared() == 0.0 {
            return SampledSpectrum::ZERO;
        }
        match (&self.bsdf, self.kind) {
            (Some(b), VertexKind::Surface) => b.f(self.si.wo, d.normalize(), mode),
            _ => SampledSpectrum::ZERO,
        }
    }

    /// A solid-angle density at this vertex turned into an area density
    /// at `next`.
    fn convert_density(&self, pdf: f32, next: &Vertex) -> f32 {
        let w = next.p() - self.p();
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let mut pdf = pdf / d2;
        if next.on_surface() {
            pdf *= next.si.n.dot(w / d2.sqrt()).abs();
        }
        pdf
    }

    /// Area density at `next` of sampling it from this vertex, having come
    /// from `prev`.
    fn pdf(
        &self,
        scene: &BuiltScene,
        camera: &PerspectiveCamera,
        bounds: SampleBounds,
        prev: Option<&Vertex>,
        next: &Vertex,
    ) -> f32 {
        if self.kind == VertexKind::Light {
            return self.pdf_light(scene, next);
        }
        let wn = (next.p() - self.p()).normalize_or_zero();
        if wn == Vec3::ZERO {
            return 0.0;
        }
        let pdf = match self.kind {
            VertexKind::Camera => camera.pdf_we(self.p(), wn, bounds).1,
            _ => {
                let (Some(b), Some(prev)) = (&self.bsdf, prev) else {
                    return 0.0;
                };
                let wp = (prev.p() - self.p()).normalize_or_zero();
                b.pdf(wp, wn, TransportMode::Radiance, BxDFReflTransFlags::All)
            }
        };
        self.convert_density(pdf, next)
    }

    /// Area density at `next` of a ray leaving this light vertex (or
    /// emitting surface) towards it.
    fn pdf_light(&self, scene: &BuiltScene, next: &Vertex) -> f32 {
        let Some(l) = self.light else {
            return 0.0;
        };
        let w = next.p() - self.p();
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let w = w / d2.sqrt();
        let (_, pdf_dir) = scene.lights[l].pdf_le(self.si.n, w);
        let mut pdf = pdf_dir / d2;
        if next.on_surface() {
            pdf *= next.si.n.dot(w).abs();
        }
        pdf
    }

    /// Area density of choosing this light vertex (or emitting surface) as
    /// a light path's start, as seen from `next`.
    fn pdf_light_origin(&self, scene: &BuiltScene, next: &Vertex) -> f32 {
        let Some(l) = self.light else {
            return 0.0;
        };
        let w = (next.p() - self.p()).normalize_or_zero();
        let choice = scene.light_sampler.pmf(&anywhere(), l);
        let (pdf_pos, _) = scene.lights[l].pdf_le(self.si.n, w);
        pdf_pos * choice
    }

    /// Radiance this vertex emits towards `towards` (emitting surfaces).
    fn le(
        &self,
        scene: &BuiltScene,
        towards: &Vertex,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        let Some(l) = self.light else {
            return SampledSpectrum::ZERO;
        };
        let w = (towards.p() - self.p()).normalize_or_zero();
        match &scene.lights[l] {
            Light::DiffuseArea(a) => a.l(self.si.p, self.si.n, self.si.uv, w, lambda),
            _ => SampledSpectrum::ZERO,
        }
    }
}

/// A light-sampling context that no light sampler here depends on.
fn anywhere() -> LightSampleContext {
    LightSampleContext {
        p: Vec3::ZERO,
        p_error: Vec3::ZERO,
        n: Vec3::ZERO,
        ns: Vec3::ZERO,
        time: 0.5,
    }
}

fn end_point(p: Vec3, p_error: Vec3, n: Vec3) -> SurfaceInteraction {
    SurfaceInteraction {
        p,
        p_error,
        n,
        time: 0.5,
        ..Default::default()
    }
}

struct Context<'a> {
    scene: &'a BuiltScene,
    camera: &'a PerspectiveCamera,
    bounds: SampleBounds,
    camera_ray: &'a CameraRay,
}

/// Extends `path` from its last vertex along `ray` by BSDF sampling, for
/// up to `max_depth` more vertices.
#[allow(clippy::too_many_arguments)]
fn random_walk(
    cx: &Context,
    mut ray: Ray,
    mut beta: SampledSpectrum,
    pdf: f32,
    max_depth: i32,
    mode: TransportMode,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    path: &mut Vec<Vertex>,
    rays: &mut RayCounts,
) {
    if max_depth <= 0 {
        return;
    }
    let scene = cx.scene;
    let (mut pdf_fwd, mut bounces) = (pdf, 0);
    let mut any_non_specular = false;
    let mut from_camera = mode == TransportMode::Radiance;
    loop {
        rays.closest_hit += 1;
        let Some((mut si, prim)) = scene.intersect(&ray, f32::INFINITY) else {
            break;
        };
        si.wo = -ray.direction.normalize();
        let ctx = texture_context(scene, cx.camera_ray, &si, from_camera);
        let Some(mut bsdf) = scene.materials[prim.material as usize].bsdf(&mut si, &ctx, lambda)
        else {
            ray = si.spawn_ray(ray.direction);
            continue;
        };
        from_camera = false;
        if scene.integrator.regularize && any_non_specular {
            bsdf.regularize();
        }
        let prev = path.len() - 1;
        let mut vertex = Vertex {
            kind: VertexKind::Surface,
            beta,
            si,
            ns: si.shading.n,
            bsdf: Some(bsdf),
            light: prim.area_light().map(|l| l as usize),
            delta: false,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
        };
        vertex.pdf_fwd = path[prev].convert_density(pdf_fwd, &vertex);
        path.push(vertex);
        bounces += 1;
        if bounces >= max_depth {
            break;
        }
        let wo = si.wo;
        let u = sampler.get_1d();
        let Some(bs) = bsdf.sample_f(wo, u, sampler.get_2d(), mode, BxDFReflTransFlags::All) else {
            break;
        };
        pdf_fwd = if bs.pdf_is_proportional {
            bsdf.pdf(wo, bs.wi, mode, BxDFReflTransFlags::All)
        } else {
            bs.pdf
        };
        any_non_specular |= !bs.is_specular();
        beta *= bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
        let mut pdf_rev = bsdf.pdf(bs.wi, wo, mode.opposite(), BxDFReflTransFlags::All);
        let last = path.len() - 1;
        if bs.is_specular() {
            path[last].delta = true;
            pdf_rev = 0.0;
            pdf_fwd = 0.0;
        }
        ray = if bsdf.diffracting_ring().is_some() {
            si.spawn_ray_through(bs.wi)
        } else {
            si.spawn_ray(bs.wi)
        };
        let converted = path[last].convert_density(pdf_rev, &path[last - 1]);
        path[last - 1].pdf_rev = converted;
    }
}

/// The visibility-free geometry term between two vertices times their
/// visibility.
fn g(scene: &BuiltScene, a: &Vertex, b: &Vertex, rays: &mut RayCounts) -> f32 {
    let d = a.p() - b.p();
    let d2 = d.length_squared();
    if d2 == 0.0 {
        return 0.0;
    }
    let w = d / d2.sqrt();
    let mut g = 1.0 / d2;
    if a.on_surface() {
        g *= a.ns.dot(w).abs();
    }
    if b.on_surface() {
        g *= b.ns.dot(w).abs();
    }
    if g == 0.0 {
        return 0.0;
    }
    if visible(scene, a, b, rays) {
        g
    } else {
        0.0
    }
}

/// Whether nothing lies between two vertices.
fn visible(scene: &BuiltScene, a: &Vertex, b: &Vertex, rays: &mut RayCounts) -> bool {
    rays.shadow += 1;
    let through = a.bsdf.is_some_and(|b| b.diffracting_ring().is_some());
    scene.unoccluded(&a.si, through, b.p(), b.si.p_error, b.si.n)
}

/// Radiance along the camera ray by bidirectional path tracing; the
/// strategies that reach the film elsewhere (t = 1) are splatted.
#[allow(clippy::too_many_arguments)]
pub fn bdpt_li(
    scene: &BuiltScene,
    camera_ray: &CameraRay,
    lambda: &mut SampledWavelengths,
    sampler: &mut Sampler,
    splats: &SplatBuffer,
    rays: &mut RayCounts,
) -> SampledSpectrum {
    let Some(camera) = scene.camera.as_perspective() else {
        return SampledSpectrum::ZERO;
    };
    let cx = Context {
        scene,
        camera,
        bounds: sample_bounds(scene),
        camera_ray,
    };
    let max_depth = scene.integrator.max_depth;
    // The camera subpath.
    let ray = camera_ray.ray;
    let mut camera_path = Vec::with_capacity(max_depth.max(0) as usize + 2);
    camera_path.push(Vertex {
        kind: VertexKind::Camera,
        // The camera ray's weight is applied to the whole sample by the
        // caller.
        beta: SampledSpectrum::ONE,
        si: end_point(ray.origin, Vec3::ZERO, Vec3::ZERO),
        ns: Vec3::ZERO,
        bsdf: None,
        light: None,
        delta: false,
        pdf_fwd: 0.0,
        pdf_rev: 0.0,
    });
    let (_, pdf_dir) = camera.pdf_we(ray.origin, ray.direction, cx.bounds);
    random_walk(
        &cx,
        ray,
        SampledSpectrum::ONE,
        pdf_dir,
        max_depth + 1,
        TransportMode::Radiance,
        lambda,
        sampler,
        &mut camera_path,
        rays,
    );
    // The light subpath.
    let mut light_path = Vec::with_capacity(max_depth.max(0) as usize + 1);
    if let Some((l, p_choice)) = scene.light_sampler.sample(&anywhere(), sampler.get_1d()) {
        let (u_pos, u_dir) = (sampler.get_2d(), sampler.get_2d());
        if let Some(les) = scene.lights[l].sample_le(u_pos, u_dir, lambda, &scene.shapes) {
            if les.pdf_pos > 0.0 && les.pdf_dir > 0.0 && les.l.is_nonzero() {
                let si = end_point(les.p, les.p_error, les.n);
                light_path.push(Vertex {
                    kind: VertexKind::Light,
                    beta: les.l,
                    si,
                    ns: les.n,
                    bsdf: None,
                    light: Some(l),
                    delta: false,
                    pdf_fwd: les.pdf_pos * p_choice,
                    pdf_rev: 0.0,
                });
                let cos = if les.n == Vec3::ZERO {
                    1.0
                } else {
                    les.n.dot(les.dir).abs()
                };
                let beta = les.l * (cos / (p_choice * les.pdf_pos * les.pdf_dir));
                let ray = if les.n == Vec3::ZERO {
                    Ray::new(les.p, les.dir, 0.5)
                } else {
                    si.spawn_ray(les.dir)
                };
                random_walk(
                    &cx,
                    ray,
                    beta,
                    les.pdf_dir,
                    max_depth,
                    TransportMode::Importance,
                    lambda,
                    sampler,
                    &mut light_path,
                    rays,
                );
            }
        }
    }
    // Every connection.
    let mut l = SampledSpectrum::ZERO;
    for t in 1..=camera_path.len() {
        for s in 0..=light_path.len() {
            let depth = t as i32 + s as i32 - 2;
            if (s == 1 && t == 1) || depth < 0 || depth > max_depth {
                continue;
            }
            if let Some((contribution, p_raster)) = connect(
                &cx,
                &mut light_path,
                &mut camera_path,
                s,
                t,
                lambda,
                sampler,
                rays,
            ) {
                match p_raster {
                    Some(p) => {
                        if !(contribution.has_nan()
                            || contribution.0.iter().any(|v| v.is_infinite()))
                        {
                            splats.add(
                                p,
                                scene.film.sensor_rgb(contribution, lambda),
                                &scene.filter,
                            );
                        }
                    }
                    None => l += contribution,
                }
            }
        }
    }
    l
}

/// The path of the first `s` light and `t` camera vertices joined, MIS
/// weighted; with the raster point for t = 1 (a splat).
#[allow(clippy::too_many_arguments)]
fn connect(
    cx: &Context,
    light_path: &mut [Vertex],
    camera_path: &mut [Vertex],
    s: usize,
    t: usize,
    lambda: &SampledWavelengths,
    sampler: &mut Sampler,
    rays: &mut RayCounts,
) -> Option<(SampledSpectrum, Option<Vec2>)> {
    let scene = cx.scene;
    let mut sampled: Option<Vertex> = None;
    let mut p_raster = None;
    let l = if s == 0 {
        let pt = &camera_path[t - 1];
        if !pt.is_light() {
            return None;
        }
        pt.le(scene, &camera_path[t - 2], lambda) * pt.beta
    } else if t == 1 {
        let qs = light_path[s - 1];
        if !qs.connectible(scene) {
            return None;
        }
        let cs = cx.camera.sample_wi(qs.p(), sampler.get_2d(), cx.bounds)?;
        if cs.pdf == 0.0 {
            return None;
        }
        p_raster = Some(cs.p_raster);
        let v = Vertex {
            kind: VertexKind::Camera,
            beta: SampledSpectrum::ONE * (cs.we / cs.pdf),
            si: end_point(cs.p_lens, Vec3::ZERO, cs.n_lens),
            ns: cs.n_lens,
            bsdf: None,
            light: None,
            delta: false,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
        };
        let mut l = qs.beta * qs.f(&v, TransportMode::Importance) * v.beta;
        if qs.on_surface() {
            l *= cs.wi.dot(qs.ns).abs();
        }
        sampled = Some(v);
        if l.is_zero() || !visible(scene, &qs, &v_without_normal(&v), rays) {
            return None;
        }
        l
    } else if s == 1 {
        let pt = camera_path[t - 1];
        if !pt.connectible(scene) {
            return None;
        }
        let ctx = LightSampleContext {
            p: pt.p(),
            p_error: pt.si.p_error,
            n: pt.si.n,
            ns: pt.ns,
            time: pt.si.time,
        };
        let (light_index, p_choice) = scene.light_sampler.sample(&ctx, sampler.get_1d())?;
        let u = sampler.get_2d();
        let light = &scene.lights[light_index];
        let ls = light.sample_li(&ctx, u, lambda, &scene.shapes, true)?;
        let le = ls.l.value(lambda);
        if le.is_zero() || ls.pdf == 0.0 {
            return None;
        }
        let mut v = Vertex {
            kind: VertexKind::Light,
            beta: le / (ls.pdf * p_choice),
            si: end_point(ls.p_light, ls.p_light_error, ls.n_light),
            ns: ls.n_light,
            bsdf: None,
            light: Some(light_index),
            delta: false,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
        };
        v.pdf_fwd = v.pdf_light_origin(scene, &pt);
        let mut l = pt.beta * pt.f(&v, TransportMode::Radiance) * v.beta;
        if pt.on_surface() {
            l *= ls.wi.dot(pt.ns).abs();
        }
        sampled = Some(v);
        if l.is_zero() || !visible(scene, &pt, &v, rays) {
            return None;
        }
        l
    } else {
        let (qs, pt) = (light_path[s - 1], camera_path[t - 1]);
        if !(qs.connectible(scene) && pt.connectible(scene)) {
            return None;
        }
        let l = qs.beta
            * qs.f(&pt, TransportMode::Importance)
            * pt.f(&qs, TransportMode::Radiance)
            * pt.beta;
        if l.is_zero() {
            return None;
        }
        l * g(scene, &qs, &pt, rays)
    };
    if l.is_zero() {
        return None;
    }
    let weight = mis_weight(cx, light_path, camera_path, sampled, s, t);
    Some((l * weight, p_raster))
}

/// The lens point as a shadow-ray target: rays end at the point itself
/// (no offset along the lens's normal).
fn v_without_normal(v: &Vertex) -> Vertex {
    let mut v = *v;
    v.si.n = Vec3::ZERO;
    v
}

/// pbrt-v4's balance-heuristic weight of strategy (s, t) against every
/// other strategy that makes the same path, from the ratios of their
/// area densities vertex by vertex. The vertices the connection changes
/// are changed on copies.
fn mis_weight(
    cx: &Context,
    light_path: &[Vertex],
    camera_path: &[Vertex],
    sampled: Option<Vertex>,
    s: usize,
    t: usize,
) -> f32 {
    if s + t == 2 {
        return 1.0;
    }
    let scene = cx.scene;
    let mut lights: Vec<Vertex> = light_path[..s].to_vec();
    let mut cameras: Vec<Vertex> = camera_path[..t].to_vec();
    if s == 1 {
        if let Some(v) = sampled {
            lights[0] = v;
        }
    } else if t == 1 {
        if let Some(v) = sampled {
            cameras[0] = v;
        }
    }
    if t > 0 {
        cameras[t - 1].delta = false;
    }
    if s > 0 {
        lights[s - 1].delta = false;
    }
    let pdf = |v: &Vertex, prev: Option<&Vertex>, next: &Vertex| {
        v.pdf(scene, cx.camera, cx.bounds, prev, next)
    };
    // The end points' reverse densities under this strategy.
    if t > 0 {
        let pt = cameras[t - 1];
        cameras[t - 1].pdf_rev = if s > 0 {
            let qs_minus = (s > 1).then(|| lights[s - 2]);
            pdf(&lights[s - 1], qs_minus.as_ref(), &pt)
        } else if t > 1 {
            pt.pdf_light_origin(scene, &cameras[t - 2])
        } else {
            0.0
        };
    }
    if t > 1 {
        let pt = cameras[t - 1];
        cameras[t - 2].pdf_rev = if s > 0 {
            pdf(&pt, Some(&lights[s - 1]), &cameras[t - 2])
        } else {
            pt.pdf_light(scene, &cameras[t - 2])
        };
    }
    if s > 0 {
        let pt_minus = (t > 1).then(|| cameras[t - 2]);
        lights[s - 1].pdf_rev = pdf(&cameras[t - 1], pt_minus.as_ref(), &lights[s - 1]);
    }
    if s > 1 {
        lights[s - 2].pdf_rev = pdf(&lights[s - 1], Some(&cameras[t - 1]), &lights[s - 2]);
    }
    let remap = |f: f32| if f != 0.0 { f } else { 1.0 };
    let mut sum = 0.0f32;
    let mut ri = 1.0f32;
    for i in (1..t).rev() {
        ri *= remap(cameras[i].pdf_rev) / remap(cameras[i].pdf_fwd);
        if !cameras[i].delta && !cameras[i - 1].delta {
            sum += ri;
        }
    }
    ri = 1.0;
    for i in (0..s).rev() {
        ri *= remap(lights[i].pdf_rev) / remap(lights[i].pdf_fwd);
        let delta_before = if i > 0 {
            lights[i - 1].delta
        } else {
            lights[0].is_delta_light(scene)
        };
        if !lights[i].delta && !delta_before {
            sum += ri;
        }
    }
    1.0 / (1.0 + sum)
}
