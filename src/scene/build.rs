//! Scene description → built scene: textures, materials, shapes and their
//! BVH, lights and the light sampler, camera, film, sampler, filter.
//! The built scene is immutable and shared by all render threads.

use super::alpha;
use super::placed_shapes;
use crate::accel::bvh::{build_box, BuildBox};
#[cfg(target_arch = "x86_64")]
use crate::accel::child_test::Avx2;
use crate::accel::child_test::{ChildTest, Portable};
use crate::accel::instance::{build_levels, InstanceAccel};
use crate::accel::{Bvh, InstructionSet};
use crate::cameras::Camera;
use crate::error::{scene_error, Result};
use crate::film::RgbFilm;
use crate::filters::Filter;
use crate::interaction::SurfaceInteraction;
use crate::lights::{self, Light, LightKind, LightSampler};
use crate::materials::Material;
use crate::math::{offset_ray_origin, Ray};
use crate::media::Medium;
use crate::samplers::Sampler;
use crate::scene_description::{Entity, SceneDescription, TextureValue};
use crate::shapes::curve::CurvePiece;
use crate::shapes::{Shape, ShapeStorage};
use crate::spectrum::color_space::SpectrumKind;
use crate::textures::{create_texture, FloatTexture, NamedTextures, SpectrumTexture};
use glam::{IVec2, Vec3};
use pbrt_parser::{Location as FileLoc, Warning};
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;

/// Command-line settings that override the scene's.
#[derive(Clone, Debug, Default)]
pub struct RenderOverrides {
    pub spp: Option<u32>,
    pub seed: Option<i32>,
    pub outfile: Option<PathBuf>,
    pub crop_window: Option<[f64; 4]>,
    pub pixel_bounds: Option<[i32; 4]>,
    /// `--quick`, as pbrt-v4: a quarter of the resolution in each axis
    /// (the film's own bounds taken of the reduced image) and 1 sample per
    /// pixel, over `spp`.
    pub quick: bool,
    /// Divides the film's resolution in each axis (not a pbrt-v4 flag: for
    /// `rpbrt reproduce`'s previews); `--quick` uses 4.
    pub resolution_divisor: Option<u32>,
    /// `--displacement-edge-scale`: multiplies the edge length of every
    /// displaced `plymesh` (over `Option "displacementedgescale"`).
    pub displacement_edge_scale: Option<f64>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IntegratorKind {
    Path,
    VolPath,
    AmbientOcclusion(AmbientOcclusionSettings),
    RandomWalk,
    SimplePath(SimplePathSettings),
    SimpleVolPath,
    LightPath,
    Bdpt,
}

/// The `ambientocclusion` integrator's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AmbientOcclusionSettings {
    /// `"bool cossample"`: directions by cos θ, else uniform.
    pub cos_sample: bool,
    /// `"float maxdistance"`: occluders further away do not count.
    pub max_distance: f32,
    /// The colour space where the `Integrator` directive stood: its
    /// illuminant, times `illuminant_scale`, is the colour of an
    /// unoccluded point.
    pub color_space: crate::scene_description::ColorSpaceName,
    /// 1 / the illuminant's photometric integral (so that it is white of
    /// luminance 1 on the film, as lights' spectra are scaled).
    pub illuminant_scale: f32,
}

/// The `simplepath` integrator's switches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SimplePathSettings {
    /// `"bool samplelights"`.
    pub sample_lights: bool,
    /// `"bool samplebsdf"`.
    pub sample_bsdf: bool,
}

/// Integrator settings (pbrt-v4 `Integrator` parameters).
#[derive(Clone, Copy, Debug)]
pub struct IntegratorSettings {
    pub kind: IntegratorKind,
    pub max_depth: i32,
    pub regularize: bool,
    /// Whether textures are looked up with screen-space differentials:
    /// false under `Option "disabletexturefiltering" true`, and when no
    /// texture of the scene varies (nothing to filter).
    pub texture_filtering: bool,
    /// Whether light through the dual hair model's diffracting rings is
    /// connected explicitly (`"bool connectdiffraction"`, an rpbrt
    /// parameter, default true; false leaves it to the BSDF's samples):
    /// true only where some material has a ring.
    pub connect_diffraction: bool,
}

pub use super::primitive::Primitive;

pub struct BuiltScene {
    pub camera: Camera,
    pub film: RgbFilm,
    pub sampler: Sampler,
    pub filter: Filter,
    pub integrator: IntegratorSettings,
    pub shapes: ShapeStorage,
    /// In BVH order.
    pub primitives: Vec<Primitive>,
    /// Over the top-level primitives.
    pub bvh: Bvh,
    /// Object instances (their primitives follow the top level's in
    /// `primitives`).
    pub instances: InstanceAccel,
    /// Which primitives a ray tests as curves, and where their pieces are
    /// (see [`CurveLookup`]).
    curve_lookup: CurveLookup,
    /// Which copy of the BVH queries rays run ([`InstructionSet`]).
    instruction_set: InstructionSet,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    pub infinite_lights: Vec<usize>,
    pub light_sampler: LightSampler,
    /// Alpha cutout textures of the primitives that have one.
    pub alpha_textures: Vec<FloatTexture>,
    /// Participating media, by index (`MediumInterface`'s).
    pub media: Vec<Medium>,
    /// The medium camera rays start in.
    pub camera_medium: Option<u16>,
    /// Whether rays meet media at all (the camera or some surface has
    /// one): only then is the volumetric path tracer used.
    pub has_media: bool,
    pub warnings: Vec<Warning>,
}

impl BuiltScene {
    /// Whether anything moves during the shutter interval (the camera,
    /// a shape or an instance): camera rays then need their own times.
    pub fn has_motion(&self) -> bool {
        self.instances.has_motion() || self.camera.transform().is_moving()
    }

    /// The closest surface hit by `ray` before `t_max`: the top level's,
    /// then the instances' (nearer than it).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<(SurfaceInteraction, &Primitive)> {
        let mut found = self.intersect_bvh(&self.bvh, ray, t_max);
        let t_max = found.as_ref().map_or(t_max, |si| si.t);
        if let Some(si) = self.instances.intersect(ray, t_max, |bvh, ray, t_max| {
            self.intersect_bvh(bvh, ray, t_max)
        }) {
            found = Some(si);
        }
        let si = found?;
        Some((si, &self.primitives[si.primitive as usize]))
    }

    /// The closest hit among the primitives of one BVH (the top level's or
    /// an object's, in its own space), with `primitive` and `t` set. Curve
    /// hits are kept light until the closest one is known (building a
    /// curve's interaction costs more than finding it).
    fn intersect_bvh(&self, bvh: &Bvh, ray: &Ray, t_max: f32) -> Option<SurfaceInteraction> {
        #[cfg(target_arch = "x86_64")]
        if self.instruction_set == InstructionSet::X86_64V3 {
            // SAFETY: `detect` found every feature the copy is compiled for.
            return unsafe { self.intersect_bvh_x86_64_v3(bvh, ray, t_max) };
        }
        self.intersect_bvh_inlined(bvh, ray, t_max, Portable)
    }

    /// [`Self::intersect_bvh`] compiled for x86-64-v3, testing nodes eight
    /// children at a time.
    ///
    /// # Safety
    /// The processor must have the features named (`InstructionSet::detect`).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,sse3,ssse3,sse4.1,sse4.2")]
    unsafe fn intersect_bvh_x86_64_v3(
        &self,
        bvh: &Bvh,
        ray: &Ray,
        t_max: f32,
    ) -> Option<SurfaceInteraction> {
        // SAFETY: the caller's contract: the processor has the features.
        let children = unsafe { Avx2::new_unchecked() };
        self.intersect_bvh_inlined(bvh, ray, t_max, children)
    }

    /// Inlined into each copy, and with it the traversal.
    #[inline(always)]
    fn intersect_bvh_inlined(
        &self,
        bvh: &Bvh,
        ray: &Ray,
        t_max: f32,
        children: impl ChildTest,
    ) -> Option<SurfaceInteraction> {
        enum Best {
            Full(SurfaceInteraction, usize),
            Curve(crate::shapes::curve::CurveHit, u32, usize),
        }
        let frame = crate::shapes::curve::RayFrame::new(ray)?;
        let mut best = None;
        let test = |i, t_max| {
            if let Some(c) = self.curve_without_alpha(i) {
                let (piece, segment) = self.shapes.curve(c);
                let hit = piece.intersect_in(segment, &frame, t_max)?;
                best = Some(Best::Curve(hit, c, i));
                return Some(hit.t);
            }
            let (si, t) = self.intersect_primitive(i, ray, t_max)?;
            best = Some(Best::Full(si, i));
            Some(t)
        };
        if self.has_curves() {
            let start = self.prefetch_start();
            bvh.closest_hit_prefetching(ray, t_max, children, |i| start.prefetch(i), test)?;
        } else {
            bvh.closest_hit_prefetching(ray, t_max, children, |_| {}, test)?;
        }
        let (mut si, i) = match best? {
            Best::Full(si, i) => (si, i),
            Best::Curve(hit, c, i) => (hit.interaction(self.shapes.curve(c).1, ray), i),
        };
        si.primitive = i as u32;
        Some(si)
    }

    /// The hit of `ray` with primitive `i` before `t_max`, and its t: the
    /// closest-hit query's test of anything but a curve without alpha,
    /// kept out of line so that the curve test, most of a hair scene's,
    /// is inlined into the traversal.
    #[inline(never)]
    fn intersect_primitive(
        &self,
        i: usize,
        ray: &Ray,
        t_max: f32,
    ) -> Option<(SurfaceInteraction, f32)> {
        let prim = &self.primitives[i];
        if let Some(alpha) = prim.alpha() {
            return self.intersect_cut_out(prim, alpha, ray, t_max);
        }
        let hit = prim.shape.intersect(&self.shapes, ray, t_max)?;
        Some((hit.interaction, hit.t_hit))
    }

    /// The first surface between a surface point and a light point (both
    /// ends offset as in [`Self::unoccluded`]), if any.
    /// `through`: `from` is a hit in a diffracting ring, whose rays start
    /// along their direction ([`SurfaceInteraction::spawn_ray_through`]).
    pub fn first_blocker(
        &self,
        from: &SurfaceInteraction,
        through: bool,
        p_to: Vec3,
        p_to_error: Vec3,
        n_to: Vec3,
    ) -> Option<SurfaceInteraction> {
        let ray = Self::shadow_ray(from, through, p_to, p_to_error, n_to);
        let (mut si, _) = self.intersect(&ray, 1.0 - 1e-4)?;
        si.wo = -ray.direction.normalize();
        Some(si)
    }

    /// Whether anything lies on `ray` before `t_max`.
    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        self.intersect_p_bvh(&self.bvh, ray, t_max)
            || self.instances.intersect_p(ray, t_max, |bvh, ray, t_max| {
                self.intersect_p_bvh(bvh, ray, t_max)
            })
    }

    /// Whether any primitive of one BVH lies on `ray` before `t_max`.
    fn intersect_p_bvh(&self, bvh: &Bvh, ray: &Ray, t_max: f32) -> bool {
        #[cfg(target_arch = "x86_64")]
        if self.instruction_set == InstructionSet::X86_64V3 {
            // SAFETY: `detect` found every feature the copy is compiled for.
            return unsafe { self.intersect_p_bvh_x86_64_v3(bvh, ray, t_max) };
        }
        self.intersect_p_bvh_inlined(bvh, ray, t_max, Portable)
    }

    /// [`Self::intersect_p_bvh`] compiled for x86-64-v3, testing nodes
    /// eight children at a time.
    ///
    /// # Safety
    /// The processor must have the features named (`InstructionSet::detect`).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,sse3,ssse3,sse4.1,sse4.2")]
    unsafe fn intersect_p_bvh_x86_64_v3(&self, bvh: &Bvh, ray: &Ray, t_max: f32) -> bool {
        // SAFETY: the caller's contract: the processor has the features.
        let children = unsafe { Avx2::new_unchecked() };
        self.intersect_p_bvh_inlined(bvh, ray, t_max, children)
    }

    /// Inlined into each copy, and with it the traversal.
    #[inline(always)]
    fn intersect_p_bvh_inlined(
        &self,
        bvh: &Bvh,
        ray: &Ray,
        t_max: f32,
        children: impl ChildTest,
    ) -> bool {
        let frame = crate::shapes::curve::RayFrame::new(ray);
        let test = |i, t_max| {
            if let (Some(c), Some(frame)) = (self.curve_without_alpha(i), &frame) {
                let (piece, segment) = self.shapes.curve(c);
                return piece.intersect_in(segment, frame, t_max).is_some();
            }
            let prim = &self.primitives[i];
            match prim.alpha() {
                Some(alpha) => self.intersect_cut_out(prim, alpha, ray, t_max).is_some(),
                None => prim.shape.intersect_p(&self.shapes, ray, t_max),
            }
        };
        if self.has_curves() {
            let start = self.prefetch_start();
            bvh.any_hit_prefetching(ray, t_max, children, |i| start.prefetch(i), test)
        } else {
            bvh.any_hit_prefetching(ray, t_max, children, |_| {}, test)
        }
    }

    /// The curve piece of primitive `i`, if it is a curve without an alpha
    /// cutout.
    #[inline]
    fn curve_without_alpha(&self, i: usize) -> Option<u32> {
        match &self.curve_lookup {
            CurveLookup::ByPrimitive => {
                let piece = self.shapes.curve_pieces.get(i)?;
                (!piece.is_placeholder()).then_some(i as u32)
            }
            CurveLookup::Mapped(curve_of_primitive) => curve_of_primitive
                .get(i)
                .copied()
                .filter(|&c| c != NOT_A_CURVE),
        }
    }

    /// Whether the scene has curves: only then do rays prefetch (a
    /// triangle scene's traversal is faster without it).
    fn has_curves(&self) -> bool {
        !matches!(&self.curve_lookup, CurveLookup::Mapped(map) if map.is_empty())
    }

    /// Where what testing primitive `i` reads first lies, for every `i`:
    /// taken once per ray query, so that each prefetch is an address
    /// computation (no match on the lookup, no bounds check).
    #[inline(always)]
    fn prefetch_start(&self) -> PrefetchStart {
        match &self.curve_lookup {
            CurveLookup::ByPrimitive => PrefetchStart::of(&self.shapes.curve_pieces),
            CurveLookup::Mapped(curve_of_primitive) => PrefetchStart::of(curve_of_primitive),
        }
    }

    /// The closest hit of a primitive with an alpha cutout (and its t along
    /// `ray`): a cut-out hit is skipped and the ray continues from it
    /// through the same primitive, as pbrt-v4's `GeometricPrimitive` does.
    fn intersect_cut_out(
        &self,
        prim: &Primitive,
        alpha: u32,
        ray: &Ray,
        t_max: f32,
    ) -> Option<(SurfaceInteraction, f32)> {
        let alpha = &self.alpha_textures[alpha as usize];
        let (mut ray, mut t_max, mut t_before) = (*ray, t_max, 0.0);
        // A shape is crossed a few times at most (a closed quadric twice);
        // the bound only guards against a ray stuck at one point.
        for _ in 0..16 {
            let (mut si, t) = match prim.shape {
                Shape::Curve(c) => {
                    let (piece, segment) = self.shapes.curve(c);
                    let frame = crate::shapes::curve::RayFrame::new(&ray)?;
                    let hit = piece.intersect_in(segment, &frame, t_max)?;
                    (hit.interaction(segment, &ray), hit.t)
                }
                _ => {
                    let hit = prim.shape.intersect(&self.shapes, &ray, t_max)?;
                    (hit.interaction, hit.t_hit)
                }
            };
            if !alpha::cut_out(alpha, &si, &ray) {
                si.t = t_before + t;
                return Some((si, t_before + t));
            }
            t_before += t;
            t_max -= t;
            ray = si.spawn_ray(ray.direction);
        }
        None
    }

    /// Whether the segment between a surface point and a light point is
    /// clear (both ends offset off their surfaces; `through`: `from` is a
    /// hit in a diffracting ring, whose rays start along their direction,
    /// [`SurfaceInteraction::spawn_ray_through`]).
    pub fn unoccluded(
        &self,
        from: &SurfaceInteraction,
        through: bool,
        p_to: Vec3,
        p_to_error: Vec3,
        n_to: Vec3,
    ) -> bool {
        !self.intersect_p(
            &Self::shadow_ray(from, through, p_to, p_to_error, n_to),
            1.0 - 1e-4,
        )
    }

    /// The ray from a surface point to a light point, both offset off their
    /// surfaces (`through`: the first along the ray, for a ring hit), with
    /// the light point at t = 1.
    fn shadow_ray(
        from: &SurfaceInteraction,
        through: bool,
        p_to: Vec3,
        p_to_error: Vec3,
        n_to: Vec3,
    ) -> Ray {
        let origin = if through {
            from.point_through(p_to - from.p)
        } else {
            offset_ray_origin(from.p, from.p_error, from.n, p_to - from.p)
        };
        let target = if n_to == Vec3::ZERO {
            p_to
        } else {
            offset_ray_origin(p_to, p_to_error, n_to, origin - p_to)
        };
        Ray::new(origin, target - origin, from.time)
    }
}

/// Builds the scene (warnings are collected in the result), phase by
/// phase as pbrt-v4's `BasicScene`: what the scene is seen through
/// ([`create_view`]), textures ([`create_textures`]), materials
/// ([`create_materials`]), shapes with their primitives and area lights
/// and the scene's own lights ([`create_primitives_and_lights`]), the
/// accelerator ([`create_aggregate`]), and the lights' preprocessing and
/// sampler ([`prepare_lights`]).
pub fn build(mut description: SceneDescription, overrides: &RenderOverrides) -> Result<BuiltScene> {
    let mut warnings = Vec::new();
    if let Some(scale) = overrides.displacement_edge_scale {
        description.options.displacement_edge_scale = Some(scale);
    }

    let View {
        camera,
        film,
        sampler,
        filter,
    } = create_view(&description, overrides)?;
    let render_from_world = camera.transform().render_from_world;
    let mut integrator = integrator_settings(&description)?;
    // The plan takes the shapes out of the description: each is freed as
    // soon as it is made (`placed_shapes::create`).
    let plan = super::instancing::plan(&mut description, &render_from_world, &mut warnings)?;
    let scene = &description;
    let base = &scene.base_directory;

    let textures = create_textures(scene, &render_from_world)?;
    // Differentials are only worth computing when some texture varies.
    integrator.texture_filtering &= some_texture_varies(&textures);

    let (media, medium_index) = create_media(scene, &render_from_world)?;
    let camera_medium = medium_ref(&medium_index, &scene.camera.medium);

    let (materials, named_index) = create_materials(scene, &textures)?;
    integrator.connect_diffraction &= materials.iter().any(Material::has_diffracting_ring);
    for (material, entity) in materials
        .iter()
        .zip(scene.materials.iter().chain(scene.named_materials.values()))
    {
        if let Some(warning) = dual_hair_width_warning(material, entity)? {
            warnings.push(warning);
        }
    }
    warnings.extend(super::deviations::warnings(
        scene,
        &materials,
        integrator.texture_filtering,
        base,
    ));
    warnings.extend(
        scene
            .lights
            .iter()
            .filter_map(lights::create::portal_light_warning),
    );

    let context = placed_shapes::Context {
        scene,
        render_from_world: &render_from_world,
        textures: &textures,
        materials: &materials,
        named_materials: &named_index,
        media: &medium_index,
        base,
        flattened: &plan.flattened,
    };
    let Primitives {
        mut shapes,
        primitives,
        mut lights,
        alpha_textures,
        group_ends,
        placed_ends,
    } = create_primitives_and_lights(plan.placements, plan.object_count, &context, &mut warnings)?;
    // What the shapes' runs and the bounds freed goes back before the
    // BVH's arrays come.
    crate::memory::return_freed_memory("shapes and primitives");
    let bounds = primitive_bounds(&primitives, &shapes, &placed_ends)?;
    crate::memory::return_freed_memory("bounds");

    let Aggregate {
        bvh,
        instances,
        primitives,
        curve_lookup,
    } = create_aggregate(
        primitives,
        bounds,
        &mut shapes,
        &group_ends,
        &plan.instances,
    )?;

    let (infinite_lights, light_sampler) =
        prepare_lights(scene, &mut lights, &shapes, &bvh, &instances)?;
    let has_media =
        camera_medium.is_some() || primitives.iter().any(|p| p.medium_interface().is_some());
    if has_media {
        let e = &scene.integrator;
        match integrator.kind {
            IntegratorKind::VolPath | IntegratorKind::SimpleVolPath => {}
            // pbrt-v4's bdpt scatters in media: ignoring them would be a
            // silently different image.
            IntegratorKind::Bdpt => {
                return scene_error(
                    "integrator \"bdpt\" with participating media is not supported yet; use \"volpath\"".to_string(),
                    &e.location.0,
                )
            }
            _ => warnings.push(Warning {
                message: format!(
                    "the \"{}\" integrator ignores participating media (as pbrt-v4's does); use \"volpath\"",
                    e.kind
                ),
                location: e.location.0.clone(),
            }),
        }
    }
    if integrator.kind == IntegratorKind::SimpleVolPath {
        check_simple_vol_path(
            &lights,
            &primitives,
            &materials,
            &scene.integrator.location.0,
        )?;
    }
    if matches!(
        integrator.kind,
        IntegratorKind::LightPath | IntegratorKind::Bdpt
    ) {
        check_light_tracing(scene, &camera, &film, &lights, &instances)?;
    }
    Ok(BuiltScene {
        camera,
        film,
        sampler,
        filter,
        integrator,
        shapes,
        primitives,
        bvh,
        instances,
        curve_lookup,
        instruction_set: InstructionSet::detect(),
        materials,
        lights,
        infinite_lights,
        light_sampler,
        alpha_textures,
        media,
        camera_medium,
        has_media: has_media && integrator.kind == IntegratorKind::VolPath,
        warnings,
    })
}

/// The media phase (pbrt-v4's `CreateMedia`): each `MakeNamedMedium`, with
/// each name's index.
fn create_media<'s>(
    scene: &'s SceneDescription,
    render_from_world: &crate::math::Transform,
) -> Result<(Vec<Medium>, HashMap<&'s str, u16>)> {
    let mut media = Vec::new();
    let mut index = HashMap::new();
    for m in &scene.media {
        if media.len() >= super::primitive::VACUUM as usize {
            return scene_error(
                format!(
                    "too many media: a scene may have at most {}",
                    super::primitive::VACUUM
                ),
                &m.entity.location.0,
            );
        }
        let render_from_medium = render_from_world.then(&m.world_from_medium);
        index.insert(m.name.as_str(), media.len() as u16);
        media.push(Medium::create(
            &m.entity,
            &render_from_medium,
            &scene.base_directory,
        )?);
    }
    Ok((media, index))
}

/// The medium a name refers to (`""`: none; the scene builder has checked
/// that every name is defined).
fn medium_ref(index: &HashMap<&str, u16>, name: &str) -> Option<u16> {
    index.get(name).copied()
}

/// What the scene is seen and sampled through: camera, film, sampler and
/// pixel filter.
struct View {
    camera: Camera,
    film: RgbFilm,
    sampler: Sampler,
    filter: Filter,
}

/// The camera phase: the film (with the command line's crop window or
/// pixel bounds), the camera (its exposure time from the shutter), the
/// sampler and the filter.
fn create_view(scene: &SceneDescription, overrides: &RenderOverrides) -> Result<View> {
    let cam_params = &scene.camera.entity.params;
    let exposure = (cam_params.float("shutterclose", 1.0)?
        - cam_params.float("shutteropen", 0.0)?)
    .abs() as f32;
    let mut film = RgbFilm::create(
        &scene.film,
        exposure,
        overrides.outfile.clone(),
        &scene.base_directory,
        if overrides.quick {
            4
        } else {
            overrides
                .resolution_divisor
                .unwrap_or(1)
                .min(i32::MAX as u32) as i32
        },
    )?;
    if let Some([x0, x1, y0, y1]) = overrides.pixel_bounds {
        film.set_pixel_bounds((IVec2::new(x0, y0), IVec2::new(x1, y1)));
    }
    if let Some(c) = overrides.crop_window {
        let b = film.crop_window_bounds(c);
        film.set_pixel_bounds(b);
    }
    let camera = Camera::create_for_film(
        &scene.camera,
        crate::cameras::FilmGeometry {
            full_resolution: film.full_resolution,
            diagonal: film.diagonal,
            base_directory: &scene.base_directory,
        },
    )?
    .with_pixel_jitter(!scene.options.disable_pixel_jitter);
    film.place_gbuffer(camera.transform());

    let seed = overrides.seed.unwrap_or(scene.options.seed);
    let spp = if overrides.quick {
        Some(1)
    } else {
        overrides.spp
    };
    let sampler = Sampler::create(&scene.sampler, seed, film.full_resolution, spp)?;
    let filter = Filter::create(&scene.filter)?;
    Ok(View {
        camera,
        film,
        sampler,
        filter,
    })
}

/// The textures phase (pbrt-v4's `CreateTextures`): in file order, images
/// shared through the cache; a spectrum texture is made once per
/// spectrum kind (albedo, unbounded, illuminant).
fn create_textures(
    scene: &SceneDescription,
    render_from_world: &crate::math::Transform,
) -> Result<NamedTextures> {
    let mut textures = NamedTextures::default();
    for t in &scene.textures {
        let render_from_texture = render_from_world.then(&t.world_from_texture).to_mat4();
        let kinds: &[(u8, SpectrumKind)] = match t.value {
            TextureValue::Float => &[(0, SpectrumKind::Albedo)],
            TextureValue::Spectrum => &[
                (0, SpectrumKind::Albedo),
                (1, SpectrumKind::Unbounded),
                (2, SpectrumKind::Illuminant),
            ],
        };
        for &(key, kind) in kinds {
            let created = create_texture(
                &t.entity,
                t.value,
                &mut textures,
                render_from_texture,
                &scene.base_directory,
                kind,
            )?;
            match created {
                Some((Some(f), _)) => {
                    textures.float.insert(t.name.clone(), f);
                }
                Some((_, Some(s))) => {
                    textures.spectrum.insert((t.name.clone(), key), s);
                }
                _ => {}
            }
        }
    }
    Ok(textures)
}

/// Whether some texture is not a constant (so that lookups with
/// screen-space differentials can change the image).
fn some_texture_varies(textures: &NamedTextures) -> bool {
    textures
        .float
        .values()
        .any(|t| !matches!(t, FloatTexture::Constant(_)))
        || textures
            .spectrum
            .values()
            .any(|t| !matches!(t, SpectrumTexture::Constant(_)))
}

/// The materials phase (pbrt-v4's `CreateMaterials`): anonymous materials
/// by index, then named ones after them (with each name's index), all
/// made diffuse under `Option "forcediffuse"`.
fn create_materials<'s>(
    scene: &'s SceneDescription,
    textures: &NamedTextures,
) -> Result<(Vec<Material>, HashMap<&'s str, u32>)> {
    let base = &scene.base_directory;
    let mut normal_maps = crate::materials::normal_map::NormalMapCache::default();
    let mut materials = Vec::new();
    for m in &scene.materials {
        materials.push(Material::create(m, textures, base, &mut normal_maps)?);
    }
    let mut named_index = HashMap::new();
    for (name, m) in &scene.named_materials {
        named_index.insert(name.as_str(), materials.len() as u32);
        materials.push(Material::create(m, textures, base, &mut normal_maps)?);
    }
    crate::materials::mix::resolve(&mut materials, &named_index)?;
    if scene.options.force_diffuse {
        materials = materials
            .into_iter()
            .map(Material::forced_diffuse)
            .collect();
    }
    Ok((materials, named_index))
}

/// What the primitives phase makes: shapes and their primitives in
/// placement order (not yet BVH order), every light, and where each
/// group and each Shape directive's primitives end.
struct Primitives {
    shapes: ShapeStorage,
    primitives: Vec<Primitive>,
    lights: Vec<Light>,
    alpha_textures: Vec<FloatTexture>,
    /// Where each group (top level, then each instanced object) ends.
    group_ends: Vec<usize>,
    /// Where each Shape directive's primitives end, and its location (for
    /// the bounds check of [`create_aggregate`]).
    placed_ends: Vec<(usize, pbrt_parser::Location)>,
}

/// The primitives phase (the shapes half of pbrt-v4's `CreateAggregate`,
/// with `CreateLights`): the shapes of the instancing plan made in
/// parallel runs, each with its material, alpha cutout and area light;
/// the scene's own lights (an environment map's image and sampling
/// tables) are made while the shapes are, and follow the area lights.
fn create_primitives_and_lights<'s>(
    placements: Vec<super::instancing::ShapePlacement>,
    object_count: usize,
    context: &placed_shapes::Context<'s>,
    warnings: &mut Vec<Warning>,
) -> Result<Primitives> {
    let scene = context.scene;
    let base = context.base;
    let mut shapes = ShapeStorage::default();
    let mut primitives = Vec::new();
    let mut lights: Vec<Light> = Vec::new();
    let mut alpha_textures = Vec::new();
    // Kept current before and after each shape (an invisible one is
    // skipped).
    let mut group_ends = vec![0; object_count + 1];
    let (runs, scene_lights) = rayon::join(
        || placed_shapes::create(placements, context),
        || -> Result<Vec<Light>> {
            scene
                .lights
                .iter()
                .map(|light| lights::create_light(light, context.render_from_world, base))
                .collect()
        },
    );
    primitives.reserve(runs.iter().map(|r| r.shapes.len()).sum());
    let (storages, runs): (Vec<ShapeStorage>, Vec<_>) = runs
        .into_iter()
        .map(|run| {
            (
                run.storage,
                (run.placed, run.shapes, run.warnings, run.error),
            )
        })
        .unzip();
    let offsets = match shapes.append_all(storages) {
        Ok(offsets) => offsets,
        Err(i) => {
            let message = format!(
                "too many curve segments: a scene may have at most {}",
                crate::shapes::curve::MAX_SEGMENTS
            );
            return match runs[i].0.first() {
                Some(placed) => scene_error(message, &placed.location),
                None => Err(crate::error::Error::Usage(message)),
            };
        }
    };
    let mut placed_ends = Vec::new();
    // Each run's shapes are freed once they are primitives, and handed back
    // about 32 times in all, so that the primitives do not add to all of
    // them (the 120 MB curve file: 77 MB of shapes, 155 MB of primitives).
    let trim_every = runs.len().div_ceil(32).max(1);
    for (k, ((placed_shapes, run_shapes, run_warnings, run_error), offsets)) in
        runs.into_iter().zip(offsets).enumerate()
    {
        if k % trim_every == trim_every - 1 {
            crate::memory::return_freed_memory("primitives of runs");
        }
        warnings.extend(run_warnings);
        let mut run_shapes = run_shapes.into_iter();
        for placed in placed_shapes {
            group_ends[placed.group] = primitives.len();
            let alpha = placed.alpha.map(|texture| {
                alpha_textures.push(texture);
                alpha_textures.len() as u32 - 1
            });
            let area_light = match placed.area_light {
                Some(entity) => {
                    let mask = match (alpha, placed.invisible) {
                        (_, true) => lights::AreaLightAlpha::Invisible,
                        (Some(a), false) => {
                            lights::AreaLightAlpha::Cutout(&alpha_textures[a as usize])
                        }
                        (None, false) => lights::AreaLightAlpha::Opaque,
                    };
                    Some(lights::create_area_light(entity, mask, base)?)
                }
                None => None,
            };
            for shape in run_shapes.by_ref().take(placed.shape_count) {
                let shape = shape.relocated(&offsets);
                let area_light = match &area_light {
                    Some(template) => {
                        lights.push(Light::DiffuseArea(template.light(&shape, &shapes)));
                        Some(lights.len() as u32 - 1)
                    }
                    None => None,
                };
                if placed.invisible {
                    continue;
                }
                primitives.push(Primitive::new(
                    shape,
                    placed.material,
                    area_light,
                    alpha,
                    placed.medium_interface,
                ));
            }
            group_ends[placed.group] = primitives.len();
            placed_ends.push((primitives.len(), placed.location));
        }
        if let Some(error) = run_error {
            return Err(error);
        }
    }
    lights.extend(scene_lights?);
    Ok(Primitives {
        shapes,
        primitives,
        lights,
        alpha_textures,
        group_ends,
        placed_ends,
    })
}

/// Each primitive's bounds in render space, as the accelerator phase's
/// boxes; an error at its `Shape` directive (`placed_ends`) if one is not
/// finite.
fn primitive_bounds(
    primitives: &[Primitive],
    shapes: &ShapeStorage,
    placed_ends: &[(usize, pbrt_parser::Location)],
) -> Result<Vec<BuildBox>> {
    // Made as the builder's boxes directly: the scene never holds a second
    // array of bounds beside them.
    let boxes: Vec<BuildBox> = primitives
        .par_iter()
        .map(|p| build_box(&p.shape.bounds(shapes)))
        .collect();
    // The BVH builder needs finite boxes (a projective transform or huge
    // coordinates can give infinite or NaN ones; obvhs then indexes out
    // of bounds).
    let finite = |b: &BuildBox| b.min.is_finite() && b.max.is_finite();
    if let Some(i) = boxes.par_iter().position_first(|b| !finite(b)) {
        let b = boxes[i];
        let message = format!(
            "the shape's bounds in render space are not finite (from {} to {}): \
             a projective transform or coordinates beyond the float range?",
            Vec3::from(b.min),
            Vec3::from(b.max)
        );
        let placed = placed_ends.partition_point(|&(end, _)| end <= i);
        return match placed_ends.get(placed) {
            Some((_, location)) => scene_error(message, location),
            None => Err(crate::error::Error::Usage(message)),
        };
    }
    Ok(boxes)
}

/// What the accelerator phase makes.
struct Aggregate {
    bvh: Bvh,
    instances: InstanceAccel,
    /// In BVH order.
    primitives: Vec<Primitive>,
    curve_lookup: CurveLookup,
}

/// The accelerator phase (pbrt-v4's `CreateAggregate`): the BVHs (top
/// level, each instanced object), the primitives and curve pieces put in
/// their order, and the instances.
fn create_aggregate(
    unordered: Vec<Primitive>,
    boxes: Vec<BuildBox>,
    shapes: &mut ShapeStorage,
    group_ends: &[usize],
    instance_transforms: &[(u32, crate::math::MotionTransform)],
) -> Result<Aggregate> {
    let object_ranges: Vec<std::ops::Range<usize>> = (1..group_ends.len())
        .map(|g| group_ends[g - 1]..group_ends[g])
        .collect();
    let (bvh, objects, order) = build_levels(&boxes, group_ends[0], &object_ranges);
    drop(boxes);
    // The builder's working arrays go back before the reordered copies
    // of the primitives and pieces are made.
    crate::memory::return_freed_memory("BVH");
    // The old order is freed (and handed back) before the pieces are put
    // in the new one.
    let mut primitives: Vec<Primitive> = order
        .par_iter()
        .map(|&i| unordered[i as usize].clone())
        .collect();
    drop((unordered, order));
    crate::memory::return_freed_memory("primitives in BVH order");
    let curve_lookup = order_curve_pieces(&mut primitives, shapes);
    crate::memory::return_freed_memory("curve pieces in BVH order");
    let instances = if instance_transforms.is_empty() {
        InstanceAccel::empty()
    } else {
        InstanceAccel::build(objects, instance_transforms)
    };
    Ok(Aggregate {
        bvh,
        instances,
        primitives,
        curve_lookup,
    })
}

/// The lights phase: each light preprocessed with the scene's bounding
/// sphere, the infinite lights listed, and the light sampler of the
/// integrator's `"lightsampler"` made. Returns (infinite lights' indices,
/// light sampler).
fn prepare_lights(
    scene: &SceneDescription,
    lights: &mut [Light],
    shapes: &ShapeStorage,
    bvh: &Bvh,
    instances: &InstanceAccel,
) -> Result<(Vec<usize>, LightSampler)> {
    let (center, radius) = bvh.bounds().union(instances.bounds()).bounding_sphere();
    for l in lights.iter_mut() {
        l.preprocess(center, radius);
    }
    let infinite_lights = lights
        .iter()
        .enumerate()
        .filter(|(_, l)| l.kind() == lights::LightKind::Infinite)
        .map(|(i, _)| i)
        .collect();
    // `simplepath` always chooses lights uniformly (and takes no
    // "lightsampler"); the other integrators that sample lights default
    // to the BVH sampler.
    let kind = match scene.integrator.kind.as_str() {
        "simplepath" => "uniform".to_string(),
        "lightpath" | "bdpt" => "power".to_string(),
        _ => scene.integrator.params.string("lightsampler", "bvh")?,
    };
    let light_sampler = match kind.as_str() {
        "uniform" => LightSampler::uniform(lights.len()),
        "power" => LightSampler::power(lights, shapes),
        "bvh" => LightSampler::bvh(lights, shapes),
        other => {
            return scene_error(
                format!("light sampler \"{other}\" unknown (expected uniform, power or bvh)"),
                &scene.integrator.location.0,
            )
        }
    };
    Ok((infinite_lights, light_sampler))
}

/// How a ray's test of primitive `i` finds its curve piece. A BVH leaf's
/// primitives are neighbours in the primitive array, and the pieces are
/// stored in the same order, so a ray tests a leaf's curves without
/// reading the primitives.
enum CurveLookup {
    /// `ShapeStorage::curve_pieces[i]` is primitive `i`'s piece, or a
    /// placeholder where primitive `i` is not tested as a curve: the piece
    /// is found without a lookup that the load of it would wait on. For
    /// scenes mostly of curves (at most as many placeholders as pieces).
    ByPrimitive,
    /// For each primitive, its piece if it is a curve without an alpha
    /// cutout, else [`NOT_A_CURVE`]; empty in a scene without curves.
    Mapped(Vec<u32>),
}

/// An array's start and element size: where element `i` lies.
#[derive(Clone, Copy)]
struct PrefetchStart {
    start: *const u8,
    size: usize,
}

impl PrefetchStart {
    fn of<T>(array: &[T]) -> Self {
        PrefetchStart {
            start: array.as_ptr().cast(),
            size: std::mem::size_of::<T>(),
        }
    }

    /// Starts loading element `i` (past the end: a line loaded for
    /// nothing, never a fault).
    #[inline(always)]
    fn prefetch(self, i: usize) {
        crate::accel::prefetch_address(self.start.wrapping_add(i.wrapping_mul(self.size)));
    }
}

/// In `CurveLookup::Mapped`: the primitive is not a curve (or has an alpha
/// cutout).
const NOT_A_CURVE: u32 = u32::MAX;

/// Stores the curve pieces in the order of `primitives` (BVH order):
/// by primitive index where the placeholders that needs are affordable,
/// else packed. Curves with an alpha cutout are intersected through their
/// primitive (`intersect_cut_out`); their pieces go after the others.
fn order_curve_pieces(primitives: &mut [Primitive], shapes: &mut ShapeStorage) -> CurveLookup {
    if shapes.curve_pieces.is_empty() {
        return CurveLookup::Mapped(Vec::new());
    }
    let created = std::mem::take(&mut shapes.curve_pieces);
    let pieces = &mut shapes.curve_pieces;
    let tested_as_curve =
        |prim: &Primitive| prim.alpha().is_none() && matches!(prim.shape, Shape::Curve(_));
    let tested = primitives.iter().filter(|p| tested_as_curve(p)).count();
    let by_primitive = primitives.len() - tested <= tested;
    let mut curve_of_primitive = Vec::new();
    if by_primitive {
        // Gathered in parallel: half a million random reads in hair.
        *pieces = primitives
            .par_iter_mut()
            .enumerate()
            .map(|(i, prim)| {
                let tested = tested_as_curve(prim);
                match &mut prim.shape {
                    Shape::Curve(c) if tested => {
                        let piece = created[*c as usize];
                        *c = i as u32;
                        piece
                    }
                    _ => CurvePiece::placeholder(),
                }
            })
            .collect();
    } else {
        pieces.reserve(created.len());
        curve_of_primitive.reserve(primitives.len());
        for prim in primitives.iter_mut() {
            let tested = tested_as_curve(prim);
            if let Shape::Curve(c) = &mut prim.shape {
                if tested {
                    pieces.push(created[*c as usize]);
                    *c = pieces.len() as u32 - 1;
                }
            }
            curve_of_primitive.push(if tested {
                pieces.len() as u32 - 1
            } else {
                NOT_A_CURVE
            });
        }
    }
    for prim in primitives.iter_mut() {
        let cut_out = prim.alpha().is_some();
        if let (Shape::Curve(c), true) = (&mut prim.shape, cut_out) {
            pieces.push(created[*c as usize]);
            *c = pieces.len() as u32 - 1;
        }
    }
    if by_primitive {
        CurveLookup::ByPrimitive
    } else {
        CurveLookup::Mapped(curve_of_primitive)
    }
}

/// The fibre widths for which the diffraction lobe's width (κ/D, fitted
/// over this range) and the spectral lobe's normalisation (k = D/λ ≥ 50
/// over the visible range) are checked, µm.
const DIFFRACTION_WIDTHS_UM: std::ops::RangeInclusive<f32> = 50.0..=100.0;

/// A warning where a dual hair material diffracts (d_diff > 0) around a
/// fibre whose mean diameter lies outside [`DIFFRACTION_WIDTHS_UM`].
fn dual_hair_width_warning(material: &Material, entity: &Entity) -> Result<Option<Warning>> {
    let Some(params) = material.dual_hair() else {
        return Ok(None);
    };
    let diameter = 2.0 * params.mean_radius_um;
    if params.d_diff == 0.0 || DIFFRACTION_WIDTHS_UM.contains(&diameter) {
        return Ok(None);
    }
    let location = match entity
        .params
        .find("ellipse_a", &[pbrt_parser::ParamType::Float])?
    {
        Some(param) => param.location.clone(),
        None => entity.location.0.clone(),
    };
    Ok(Some(Warning {
        message: format!(
            "\"ellipse_a\" + \"ellipse_b\" = {diameter} µm: the diffraction lobe's width and normalisation hold for fibres {}–{} µm across",
            DIFFRACTION_WIDTHS_UM.start(),
            DIFFRACTION_WIDTHS_UM.end()
        ),
        location,
    }))
}

/// Light tracing needs the camera's importance and the lights' emission
/// sampled: refuses what does not have them yet.
fn check_light_tracing(
    scene: &SceneDescription,
    camera: &Camera,
    film: &RgbFilm,
    lights: &[Light],
    instances: &InstanceAccel,
) -> Result<()> {
    let e = &scene.integrator;
    // Their splats are RGB only.
    if film.spectral.is_some() {
        return scene_error(
            format!(
                "integrator \"{}\" with the \"spectral\" film is not supported yet",
                e.kind
            ),
            &e.location.0,
        );
    }
    // Light paths would need the camera ray's time, which they do not
    // carry yet.
    if instances.has_motion() || camera.transform().is_moving() {
        return scene_error(
            format!(
                "integrator \"{}\" with motion blur (a moving camera, shape or instance) is not supported yet",
                e.kind
            ),
            &e.location.0,
        );
    }
    if camera.as_perspective().is_none() {
        return scene_error(
            format!(
                "integrator \"{}\" with camera \"{}\" is not supported yet (perspective only)",
                e.kind, scene.camera.entity.kind
            ),
            &e.location.0,
        );
    }
    if lights.iter().any(|l| !l.samples_emission()) {
        return scene_error(
            format!(
                "integrator \"{}\" with lights other than point and diffuse area lights is not supported yet",
                e.kind
            ),
            &e.location.0,
        );
    }
    Ok(())
}

/// pbrt-v4's conditions, checked before rendering: lights are area or
/// infinite lights (no delta lights), and no surface scatters (every
/// material is `interface` or a black `diffuse`), since pbrt-v4 stops
/// with an error at the first surface that would.
fn check_simple_vol_path(
    lights: &[Light],
    primitives: &[Primitive],
    materials: &[Material],
    integrator_location: &FileLoc,
) -> Result<()> {
    if lights.iter().any(|l| {
        matches!(
            l.kind(),
            LightKind::DeltaPosition | LightKind::DeltaDirection
        )
    }) {
        return scene_error(
            "integrator \"simplevolpath\" supports only area and infinite lights (as pbrt-v4)",
            integrator_location,
        );
    }
    // A bump or normal map changes where a black surface faces, not that
    // it is black.
    fn black(m: &Material) -> bool {
        match m {
            Material::Interface => true,
            Material::Diffuse { reflectance } => {
                matches!(reflectance, SpectrumTexture::Constant(r) if r.max_value() == 0.0)
            }
            Material::Bumped(bumped) => black(&bumped.material),
            _ => false,
        }
    }
    let mut used = vec![false; materials.len()];
    for p in primitives {
        used[p.material as usize] = true;
    }
    if materials
        .iter()
        .zip(&used)
        .any(|(m, &used)| used && !black(m))
    {
        return scene_error(
            "integrator \"simplevolpath\" does not scatter at surfaces (as pbrt-v4): every shape's material must be \"interface\" or a black \"diffuse\"",
            integrator_location,
        );
    }
    Ok(())
}

fn integrator_settings(scene: &SceneDescription) -> Result<IntegratorSettings> {
    let e = &scene.integrator;
    let p = &e.params;
    let mut max_depth = 5;
    let mut regularize = false;
    let mut connect_diffraction = false;
    let kind = match e.kind.as_str() {
        "path" | "volpath" => {
            max_depth = p.int("maxdepth", 5)?;
            regularize = p.bool("regularize", false)?;
            p.string("lightsampler", "bvh")?;
            connect_diffraction = p.bool("connectdiffraction", true)?;
            if e.kind == "path" {
                IntegratorKind::Path
            } else {
                IntegratorKind::VolPath
            }
        }
        "ambientocclusion" => IntegratorKind::AmbientOcclusion(AmbientOcclusionSettings {
            cos_sample: p.bool("cossample", true)?,
            max_distance: p.float("maxdistance", f64::INFINITY)? as f32,
            color_space: e.color_space,
            illuminant_scale: 1.0
                / crate::spectrum::spectrum_to_photometric(
                    &crate::spectrum::color_space::get(e.color_space).illuminant,
                ),
        }),
        "randomwalk" => {
            max_depth = p.int("maxdepth", 5)?;
            IntegratorKind::RandomWalk
        }
        "lightpath" => {
            max_depth = p.int("maxdepth", 5)?;
            IntegratorKind::LightPath
        }
        "simplevolpath" => {
            max_depth = p.int("maxdepth", 5)?;
            IntegratorKind::SimpleVolPath
        }
        "bdpt" => {
            max_depth = p.int("maxdepth", 5)?;
            regularize = p.bool("regularize", false)?;
            // Read as pbrt-v4 reads it, but its light paths (and light
            // samples) always choose lights by power.
            p.string("lightsampler", "power")?;
            for name in ["visualizestrategies", "visualizeweights"] {
                if p.bool(name, false)? {
                    return scene_error(
                        format!("\"{name}\" of integrator \"bdpt\" is not supported yet"),
                        &e.location.0,
                    );
                }
            }
            IntegratorKind::Bdpt
        }
        "simplepath" => {
            max_depth = p.int("maxdepth", 5)?;
            IntegratorKind::SimplePath(SimplePathSettings {
                sample_lights: p.bool("samplelights", true)?,
                sample_bsdf: p.bool("samplebsdf", true)?,
            })
        }
        other => {
            return scene_error(
                format!(
                    "integrator \"{other}\" is not supported yet (supported: path, volpath, \
                     simplepath, simplevolpath, randomwalk, ambientocclusion, lightpath, bdpt)"
                ),
                &e.location.0,
            )
        }
    };
    p.report_unused(|| format!("integrator \"{}\"", e.kind))?;
    Ok(IntegratorSettings {
        kind,
        max_depth,
        regularize,
        texture_filtering: !scene.options.disable_texture_filtering,
        connect_diffraction,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::test_support::TestRng;
    use std::fmt::Write as _;
    use std::path::Path;

    /// `curves` random curves, `cut_out` more with a fractional alpha, and
    /// `quads` random quads (two triangles each) in the unit box.
    fn random_scene(curves: usize, cut_out: usize, quads: usize) -> BuiltScene {
        let mut rng = TestRng::new(1);
        let mut rnd = move || rng.uniform();
        let mut text = String::from("Camera \"perspective\"\nWorldBegin\n");
        for i in 0..curves + cut_out {
            let start: Vec<f32> = (0..3).map(|_| rnd()).collect();
            let mut p = String::new();
            for k in 0..4 {
                for (a, s) in start.iter().enumerate() {
                    let wiggle = 0.1 * (rnd() - 0.5);
                    let along = if a == 0 { 0.1 * k as f32 } else { 0.0 };
                    write!(p, "{} ", s + along + wiggle).unwrap();
                }
            }
            let alpha = if i >= curves {
                "\"float alpha\" 0.5"
            } else {
                ""
            };
            writeln!(
                text,
                "Shape \"curve\" \"point3 P\" [ {p}] \"float width\" 0.02 {alpha}"
            )
            .unwrap();
        }
        for _ in 0..quads {
            let c: Vec<f32> = (0..3).map(|_| rnd()).collect();
            let (dx, dy) = (0.1 * rnd(), 0.1 * rnd());
            let corner =
                |sx: f32, sy: f32| format!("{} {} {} ", c[0] + sx * dx, c[1] + sy * dy, c[2]);
            writeln!(
                text,
                "Shape \"trianglemesh\" \"point3 P\" [ {}{}{}{}] \"integer indices\" [ 0 1 2 0 2 3 ]",
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0)
            )
            .unwrap();
        }
        let loaded = crate::scene::load_text(Path::new("random.pbrt"), &text).unwrap();
        build(loaded.scene, &RenderOverrides::default()).unwrap()
    }

    /// The closest hit found through the BVH, its curve lookup included,
    /// is the closest over every primitive tested on its own, and a shadow
    /// ray is blocked exactly when that hit is nearer than its end.
    fn check_against_every_primitive(scene: &BuiltScene) {
        let mut rng = TestRng::new(2);
        let mut rnd = move || rng.uniform();
        let mut hits = 0;
        for _ in 0..3000 {
            let origin = Vec3::new(rnd(), rnd(), rnd()) * 1.4 - 0.2;
            let direction = (Vec3::new(rnd(), rnd(), rnd()) - 0.5).normalize();
            let ray = Ray::new(origin, direction, 0.0);
            let t_max = 2.0;
            let brute = scene
                .primitives
                .iter()
                .filter_map(|prim| match prim.alpha() {
                    Some(alpha) => scene
                        .intersect_cut_out(prim, alpha, &ray, t_max)
                        .map(|(_, t)| t),
                    None => prim
                        .shape
                        .intersect(&scene.shapes, &ray, t_max)
                        .map(|h| h.t_hit),
                })
                .fold(f32::INFINITY, f32::min);
            let found = scene.intersect(&ray, t_max).map(|(si, _)| si.t);
            assert_eq!(found.unwrap_or(f32::INFINITY), brute);
            let end = 0.3;
            assert_eq!(scene.intersect_p(&ray, end), brute < end, "{brute}");
            hits += found.is_some() as usize;
        }
        assert!(hits > 150, "{hits} hits: the test should hit something");
    }

    /// The x86-64-v3 copy of the ray queries finds the same hits, to the
    /// bit, as the baseline one: curves, cut-out curves and triangles, with
    /// a BVH large enough to be built in parts.
    #[test]
    fn both_instruction_sets_find_the_same_hits() {
        if InstructionSet::detect() == InstructionSet::Baseline {
            eprintln!("skipped: this processor has no x86-64-v3 instructions");
            return;
        }
        let mut scene = random_scene(9000, 200, 300);
        let mut rng = TestRng::new(3);
        let mut rnd = move || rng.uniform();
        let rays: Vec<Ray> = (0..20_000)
            .map(|_| {
                let origin = Vec3::new(rnd(), rnd(), rnd()) * 1.4 - 0.2;
                let direction = (Vec3::new(rnd(), rnd(), rnd()) - 0.5).normalize();
                Ray::new(origin, direction, 0.0)
            })
            .collect();
        let answers = |scene: &BuiltScene| -> Vec<(Option<[u32; 12]>, bool)> {
            rays.iter()
                .map(|ray| {
                    let hit = scene.intersect(ray, 2.0).map(|(si, _)| {
                        let mut bits = [0; 12];
                        bits[..3].copy_from_slice(&[
                            si.t.to_bits(),
                            si.primitive,
                            si.curve_h.to_bits(),
                        ]);
                        let vectors = [si.p, si.n, si.dpdu].map(|v| v.to_array().map(f32::to_bits));
                        bits[3..].copy_from_slice(vectors.as_flattened());
                        bits
                    });
                    (hit, scene.intersect_p(ray, 0.3))
                })
                .collect()
        };
        scene.instruction_set = InstructionSet::X86_64V3;
        let wide = answers(&scene);
        scene.instruction_set = InstructionSet::Baseline;
        let baseline = answers(&scene);
        let hits = baseline.iter().filter(|(hit, _)| hit.is_some()).count();
        assert!(hits > 1000, "{hits} hits: the test should hit something");
        assert!(wide == baseline);
    }

    /// An instanced object whose only shape is invisible (alpha 0) is an
    /// empty group between others: the groups' ranges stay in order.
    #[test]
    fn an_object_of_invisible_shapes_is_an_empty_group() {
        let text = "Camera \"perspective\"\nWorldBegin\n\
            Shape \"sphere\"\n\
            ObjectBegin \"ghost\"\nShape \"sphere\" \"float alpha\" 0\nObjectEnd\n\
            ObjectBegin \"ball\"\nShape \"sphere\"\nShape \"sphere\" \"float radius\" 2\nObjectEnd\n\
            ObjectInstance \"ghost\"\nObjectInstance \"ghost\"\n\
            ObjectInstance \"ball\"\nTranslate 5 0 0\nObjectInstance \"ball\"\n";
        let loaded = crate::scene::load_text(Path::new("ghost.pbrt"), text).unwrap();
        let scene = build(loaded.scene, &RenderOverrides::default()).unwrap();
        assert_eq!(scene.primitives.len(), 3);
        let ray = Ray::new(Vec3::new(5.0, 0.0, -10.0), Vec3::Z, 0.0);
        assert!(scene.intersect(&ray, f32::INFINITY).is_some());
    }

    /// Of several bad shapes in different runs, the first in the file is
    /// the one reported, with its line.
    #[test]
    fn the_first_bad_shape_of_the_runs_is_reported() {
        let mut text = String::from("Camera \"perspective\"\nWorldBegin\n");
        for i in 0..400 {
            let kind = if i == 250 || i == 390 {
                "twisted"
            } else {
                "flat"
            };
            writeln!(
                text,
                "Shape \"curve\" \"point3 P\" [ {i} 0 5 {i} 0.1 5 {i} 0.2 5 {i} 0.3 5 ] \"string type\" \"{kind}\""
            )
            .unwrap();
        }
        let loaded = crate::scene::load_text(Path::new("bad.pbrt"), &text).unwrap();
        let error = build(loaded.scene, &RenderOverrides::default())
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        // Line 1 is the camera, 2 WorldBegin: shape 250 is on line 253.
        assert!(error.contains("bad.pbrt:253:"), "{error}");
        assert!(error.contains("twisted"), "{error}");
    }

    /// Shapes made in parallel runs (`placed_shapes`) and appended keep
    /// their own geometry, segment and material: shape i, a curve or a
    /// quad by turns, lies at x = i with material i + 1. Enough shapes for
    /// several runs.
    #[test]
    fn shapes_made_in_runs_keep_their_geometry_and_material() {
        let n = 300;
        let mut text = String::from("Camera \"perspective\"\nWorldBegin\n");
        for i in 0..n {
            let x = i as f32;
            writeln!(
                text,
                "Material \"diffuse\" \"rgb reflectance\" [ {} 0 0 ]",
                (i + 1) as f32 / 1000.0
            )
            .unwrap();
            if i % 2 == 0 {
                writeln!(
                    text,
                    "Shape \"curve\" \"point3 P\" [ {x} 0 5 {} 0.1 5 {} 0.1 5 {} 0 5 ] \"float width\" 0.1",
                    x + 0.1,
                    x + 0.3,
                    x + 0.4
                )
                .unwrap();
            } else {
                writeln!(
                    text,
                    "Shape \"trianglemesh\" \"point3 P\" [ {x} 0 5 {} 0 5 {} 1 5 {x} 1 5 ] \"integer indices\" [ 0 1 2 0 2 3 ]",
                    x + 0.4,
                    x + 0.4
                )
                .unwrap();
            }
        }
        let loaded = crate::scene::load_text(Path::new("runs.pbrt"), &text).unwrap();
        let scene = build(loaded.scene, &RenderOverrides::default()).unwrap();
        // Material 0 is the default, before the first `Material`.
        assert_eq!(scene.materials.len(), n + 1);
        assert_eq!(scene.primitives.len(), n / 2 * 8 + n / 2 * 2);
        for p in &scene.primitives {
            let i = p.material as usize - 1;
            let b = p.shape.bounds(&scene.shapes);
            assert!(
                b.min.x > i as f32 - 0.1 && b.max.x < i as f32 + 0.5,
                "shape {i}: {b:?}"
            );
            match p.shape {
                Shape::Curve(c) => {
                    assert_eq!(i % 2, 0);
                    let piece = &scene.shapes.curve_pieces[c as usize];
                    let segment = &scene.shapes.curve_segments[piece.segment() as usize];
                    assert_eq!(segment.cp[0].x, i as f32, "shape {i}'s segment");
                }
                _ => assert_eq!(i % 2, 1),
            }
        }
    }

    #[test]
    fn curves_are_found_by_primitive_index_in_a_scene_mostly_of_curves() {
        let scene = random_scene(60, 10, 8);
        assert!(matches!(scene.curve_lookup, CurveLookup::ByPrimitive));
        check_against_every_primitive(&scene);
    }

    #[test]
    fn curves_are_found_through_a_map_in_a_scene_mostly_of_other_shapes() {
        let scene = random_scene(5, 2, 60);
        assert!(matches!(scene.curve_lookup, CurveLookup::Mapped(_)));
        check_against_every_primitive(&scene);
    }
}
