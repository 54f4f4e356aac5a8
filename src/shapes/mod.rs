//! Shapes: geometry that rays hit and lights sample, in render space, as
//! pbrt-v4 defines them.
//!
//! - Quadrics ([`Sphere`], [`Disk`], [`Cylinder`]) keep their object-space
//!   parameters and a render-from-object transform; rays are taken to
//!   object space for the tests and hits are brought back.
//! - Meshes ([`TriangleMesh`], [`BilinearPatchMesh`]) are transformed to
//!   render space once, when created, and live in a [`ShapeStorage`]; a
//!   [`Triangle`] or [`BilinearPatch`] is just (mesh index, face index).
//!
//! Every [`Shape`] method takes the [`ShapeStorage`] the shape was created
//! into. Quadrics are boxed so that a `Shape` stays 16 bytes, the size of a
//! mesh face reference: scenes hold millions of triangles and few spheres.
//!
//! Per-ray results: [`ShapeIntersection`] (the hit and its ray parameter)
//! and [`ShapeSample`] (a point sampled on the surface, with its density
//! per unit area, or per unit solid angle for the `_from` variants).

pub mod bilinear;
pub mod curve;
pub mod cyhair;
pub mod cylinder;
pub mod disk;
pub mod displacement;
pub mod interval;
pub mod loop_subdiv;
pub mod mesh;
pub mod mesh_subdivision;
pub mod numeric;
pub mod object_transform;
pub mod ply;
pub mod sphere;
pub mod spherical;
pub mod surface;
pub mod triangle;
pub mod warps;

#[cfg(test)]
pub(crate) mod test_support;

pub use bilinear::BilinearPatch;
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use mesh::{BilinearPatchMesh, TriangleMesh};
pub use sphere::Sphere;
pub use triangle::Triangle;

use crate::error::{scene_error, Result, SceneError};
use crate::interaction::SurfaceInteraction;
use crate::math::{offset_ray_origin, Bounds3, Ray, Transform};
use crate::scene_description;
use crate::textures::NamedTextures;
use glam::{Vec2, Vec3};
use pbrt_parser::Warning;
use rayon::prelude::*;

use std::path::Path;

/// A shape of the scene. Per-ray code matches on it; no trait objects.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Sphere(Box<Sphere>),
    Disk(Box<Disk>),
    Cylinder(Box<Cylinder>),
    Triangle(Triangle),
    BilinearPatch(BilinearPatch),
    /// A piece of a curve segment (index into `ShapeStorage::curve_pieces`).
    Curve(u32),
}

/// The meshes that [`Triangle`] and [`BilinearPatch`] shapes index into.
/// [`create_shapes`] appends to it; every [`Shape`] method reads it.
#[derive(Clone, Debug, Default)]
pub struct ShapeStorage {
    pub triangle_meshes: Vec<TriangleMesh>,
    pub bilinear_meshes: Vec<BilinearPatchMesh>,
    pub curve_segments: Vec<curve::CurveSegment>,
    pub curve_pieces: Vec<curve::CurvePiece>,
}

/// Where one storage's items start in another it was appended to
/// ([`ShapeStorage::append_all`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct StorageOffsets {
    triangle_meshes: u32,
    bilinear_meshes: u32,
    curve_pieces: u32,
}

impl ShapeStorage {
    /// Moves the items of `others` to the end of this storage, in order;
    /// the shapes made into `others[i]` then need [`Shape::relocated`] with
    /// the `i`-th offsets. The curve pieces (most of a hair scene's bytes)
    /// are copied once each, run after run, each run's in parallel.
    /// `Err(i)` (and nothing moved) if `others[i]`'s curve segments would
    /// pass [`curve::MAX_SEGMENTS`].
    pub fn append_all(
        &mut self,
        mut others: Vec<ShapeStorage>,
    ) -> Result<Vec<StorageOffsets>, usize> {
        let mut offsets = Vec::with_capacity(others.len());
        let mut segment_offsets = Vec::with_capacity(others.len());
        let mut next = StorageOffsets {
            triangle_meshes: self.triangle_meshes.len() as u32,
            bilinear_meshes: self.bilinear_meshes.len() as u32,
            curve_pieces: self.curve_pieces.len() as u32,
        };
        let mut next_segment = self.curve_segments.len();
        for (i, other) in others.iter().enumerate() {
            if next_segment + other.curve_segments.len() > curve::MAX_SEGMENTS {
                return Err(i);
            }
            offsets.push(next);
            segment_offsets.push(next_segment as u32);
            next.triangle_meshes += other.triangle_meshes.len() as u32;
            next.bilinear_meshes += other.bilinear_meshes.len() as u32;
            next.curve_pieces += other.curve_pieces.len() as u32;
            next_segment += other.curve_segments.len();
        }
        // One storage after another, each freed once moved (and the freed
        // memory handed back about 32 times in all: after every run on 2
        // cores): the appended pieces do not sit beside all the runs'
        // copies of them.
        self.curve_pieces
            .reserve(next.curve_pieces as usize - self.curve_pieces.len());
        let trim_every = others.len().div_ceil(32).max(1);
        for (k, (other, &shift)) in others.iter_mut().zip(&segment_offsets).enumerate() {
            let other = std::mem::take(other);
            // Written in place by all threads (the pages of the new array
            // fault in on several cores).
            self.curve_pieces.par_extend(
                other
                    .curve_pieces
                    .par_iter()
                    .map(|piece| piece.with_segment_shifted(shift)),
            );
            self.triangle_meshes.extend(other.triangle_meshes);
            self.bilinear_meshes.extend(other.bilinear_meshes);
            self.curve_segments.extend(other.curve_segments);
            if k % trim_every == trim_every - 1 {
                crate::memory::return_freed_memory("append runs");
            }
        }
        Ok(offsets)
    }

    /// Multiplies the widths of the curve segments `shapes` belong to by
    /// `scale` (each segment once).
    pub fn scale_curve_widths(&mut self, shapes: &[Shape], scale: f32) {
        let mut last = None;
        for shape in shapes {
            if let Shape::Curve(c) = shape {
                let piece = &mut self.curve_pieces[*c as usize];
                let segment = &mut self.curve_segments[piece.segment() as usize];
                if last != Some(piece.segment()) {
                    segment.width = segment.width.map(|w| w * scale);
                    last = Some(piece.segment());
                }
                piece.update_width(segment);
            }
        }
    }

    /// Gives each strand of the curve pieces `shapes` (one shape's
    /// consecutive segments: a `Shape "curve"` is one strand, a `cyhair`
    /// shape one per strand of its file, each begun by a segment with
    /// `strand_start`) its own view-independent frame, `frame_of(k)` for
    /// the shape's k-th strand, for a material that orients the fibre by
    /// it (`curve::frame`).
    pub fn set_fibre_frames(
        &mut self,
        shapes: &[Shape],
        frame_of: impl Fn(usize) -> curve::frame::FibreFrame,
    ) {
        let mut segments = shapes.iter().filter_map(|shape| match shape {
            Shape::Curve(c) => Some(self.curve_pieces[*c as usize].segment() as usize),
            _ => None,
        });
        let Some(first) = segments.next() else {
            return;
        };
        let last = segments.next_back().unwrap_or(first);
        let shape_segments = &mut self.curve_segments[first..=last];
        // The first segment starts a strand whatever its flag says.
        let mut start = 0;
        let mut strand = 0;
        for end in 1..=shape_segments.len() {
            if end == shape_segments.len() || shape_segments[end].strand_start {
                curve::frame::set_frame(&mut shape_segments[start..end], frame_of(strand));
                strand += 1;
                start = end;
            }
        }
        for segment in shape_segments {
            segment.fibre_frame = true;
        }
    }

    pub fn curve(&self, piece: u32) -> (&curve::CurvePiece, &curve::CurveSegment) {
        let p = &self.curve_pieces[piece as usize];
        (p, &self.curve_segments[p.segment() as usize])
    }
}

/// A ray–shape hit: the surface interaction (render space) and the ray
/// parameter of the hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeIntersection {
    pub interaction: SurfaceInteraction,
    pub t_hit: f32,
}

/// A point sampled on a shape: position with its error bound, the surface
/// normal (on the side pbrt's orientation rules give), the surface (u,v),
/// and the density: per unit area for [`Shape::sample_area`], per unit
/// solid angle at the reference point for [`Shape::sample_from`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSample {
    pub p: Vec3,
    pub p_error: Vec3,
    pub n: Vec3,
    pub uv: Vec2,
    pub pdf: f32,
}

/// The reference point a shape is sampled from: its position and error
/// bound, its geometric normal `n` and shading normal `ns` (both zero for a
/// point in a medium), and the time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSampleContext {
    pub p: Vec3,
    pub p_error: Vec3,
    pub n: Vec3,
    pub ns: Vec3,
    pub time: f32,
}

impl ShapeSampleContext {
    /// The context of a surface point.
    pub fn from_surface(interaction: &SurfaceInteraction) -> Self {
        ShapeSampleContext {
            p: interaction.p,
            p_error: interaction.p_error,
            n: interaction.n,
            ns: interaction.shading.n,
            time: interaction.time,
        }
    }

    /// The context of a point in a participating medium (no normal).
    pub fn in_medium(p: Vec3, time: f32) -> Self {
        ShapeSampleContext {
            p,
            p_error: Vec3::ZERO,
            n: Vec3::ZERO,
            ns: Vec3::ZERO,
            time,
        }
    }

    /// The reference point moved off its surface towards `w`.
    pub fn offset_origin(&self, w: Vec3) -> Vec3 {
        offset_ray_origin(self.p, self.p_error, self.n, w)
    }

    /// A ray leaving the reference point in direction `w`.
    pub fn spawn_ray(&self, w: Vec3) -> Ray {
        Ray::new(self.offset_origin(w), w, self.time)
    }
}

/// What a quadric's object-space intersection test finds.
#[derive(Clone, Copy, Debug)]
pub(crate) struct QuadricHit {
    pub t: f32,
    pub p_object: Vec3,
    pub phi: f32,
}

/// The quadric hit at `t_hit` unless the partial shape's clipping (z range,
/// φmax) removes it, then the far root `t1` (pbrt-v4's second chance).
pub(crate) fn first_unclipped(
    t_hit: interval::Interval,
    t1: interval::Interval,
    t_max: f32,
    hit_point: impl Fn(f32) -> (Vec3, f32),
    is_clipped: impl Fn(Vec3, f32) -> bool,
) -> Option<QuadricHit> {
    let mut t = t_hit;
    let (mut p, mut phi) = hit_point(t.midpoint());
    if is_clipped(p, phi) {
        if t_hit == t1 || t1.high > t_max {
            return None;
        }
        t = t1;
        (p, phi) = hit_point(t.midpoint());
        if is_clipped(p, phi) {
            return None;
        }
    }
    Some(QuadricHit {
        t: t.midpoint(),
        p_object: p,
        phi,
    })
}

impl Shape {
    /// This shape after its storage was appended to another at `offsets`.
    pub fn relocated(self, offsets: &StorageOffsets) -> Shape {
        match self {
            Shape::Triangle(t) => {
                Shape::Triangle(Triangle::new(t.mesh + offsets.triangle_meshes, t.index))
            }
            Shape::BilinearPatch(b) => Shape::BilinearPatch(BilinearPatch::new(
                b.mesh + offsets.bilinear_meshes,
                b.index,
            )),
            Shape::Curve(c) => Shape::Curve(c + offsets.curve_pieces),
            other => other,
        }
    }

    /// Render-space bounds.
    pub fn bounds(&self, storage: &ShapeStorage) -> Bounds3 {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Disk(d) => d.bounds(),
            Shape::Cylinder(c) => c.bounds(),
            Shape::Triangle(t) => t.bounds(t.mesh_of(storage)),
            Shape::BilinearPatch(b) => b.bounds(b.mesh_of(storage)),
            Shape::Curve(c) => storage.curve_pieces[*c as usize].bounds(),
        }
    }

    /// The closest hit with `0 < t < t_max` (t in units of `ray.direction`).
    pub fn intersect(
        &self,
        storage: &ShapeStorage,
        ray: &Ray,
        t_max: f32,
    ) -> Option<ShapeIntersection> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_max),
            Shape::Disk(d) => d.intersect(ray, t_max),
            Shape::Cylinder(c) => c.intersect(ray, t_max),
            Shape::Triangle(t) => t.intersect(t.mesh_of(storage), ray, t_max),
            Shape::BilinearPatch(b) => b.intersect(b.mesh_of(storage), ray, t_max),
            Shape::Curve(c) => {
                let (piece, segment) = storage.curve(*c);
                let hit = piece.intersect(segment, ray, t_max)?;
                Some(ShapeIntersection {
                    interaction: hit.interaction(segment, ray),
                    t_hit: hit.t,
                })
            }
        }
    }

    /// Whether there is a hit with `0 < t < t_max` (no interaction built).
    pub fn intersect_p(&self, storage: &ShapeStorage, ray: &Ray, t_max: f32) -> bool {
        match self {
            Shape::Sphere(s) => s.intersect_p(ray, t_max),
            Shape::Disk(d) => d.intersect_p(ray, t_max),
            Shape::Cylinder(c) => c.intersect_p(ray, t_max),
            Shape::Triangle(t) => t.intersect_p(t.mesh_of(storage), ray, t_max),
            Shape::BilinearPatch(b) => b.intersect_p(b.mesh_of(storage), ray, t_max),
            Shape::Curve(c) => {
                let (piece, segment) = storage.curve(*c);
                piece.intersect(segment, ray, t_max).is_some()
            }
        }
    }

    /// Surface area. Quadrics report their object-space area (pbrt-v4 does
    /// not account for a scaling render-from-object transform); meshes are
    /// measured in render space.
    pub fn area(&self, storage: &ShapeStorage) -> f32 {
        match self {
            Shape::Sphere(s) => s.area(),
            Shape::Disk(d) => d.area(),
            Shape::Cylinder(c) => c.area(),
            Shape::Triangle(t) => t.area(t.mesh_of(storage)),
            Shape::BilinearPatch(b) => b.area(b.mesh_of(storage)),
            // Curves are never area lights; this is only an estimate.
            Shape::Curve(c) => {
                let (piece, segment) = storage.curve(*c);
                let cp = piece.control_points();
                (cp[3] - cp[0]).length() * segment.width_at(0.5 * (piece.u0 + piece.u1))
            }
        }
    }

    /// A point on the surface; `pdf` is per unit area.
    pub fn sample_area(&self, storage: &ShapeStorage, u: Vec2) -> Option<ShapeSample> {
        match self {
            Shape::Sphere(s) => s.sample_area(u),
            Shape::Disk(d) => d.sample_area(u),
            Shape::Cylinder(c) => c.sample_area(u),
            Shape::Triangle(t) => t.sample_area(t.mesh_of(storage), u),
            Shape::BilinearPatch(b) => b.sample_area(b.mesh_of(storage), u),
            Shape::Curve(_) => None,
        }
    }

    /// A point on the surface as seen from `ctx`; `pdf` is per unit solid
    /// angle at `ctx.p`.
    pub fn sample_from(
        &self,
        storage: &ShapeStorage,
        ctx: &ShapeSampleContext,
        u: Vec2,
    ) -> Option<ShapeSample> {
        match self {
            Shape::Sphere(s) => s.sample_from(ctx, u),
            Shape::Disk(d) => d.sample_from(ctx, u),
            Shape::Cylinder(c) => c.sample_from(ctx, u),
            Shape::Triangle(t) => t.sample_from(t.mesh_of(storage), ctx, u),
            Shape::BilinearPatch(b) => b.sample_from(b.mesh_of(storage), ctx, u),
            Shape::Curve(_) => None,
        }
    }

    /// The solid-angle density with which [`Shape::sample_from`] picks the
    /// direction `wi` (unit) from `ctx`; 0 when `wi` misses the shape.
    pub fn pdf_from(&self, storage: &ShapeStorage, ctx: &ShapeSampleContext, wi: Vec3) -> f32 {
        match self {
            Shape::Sphere(s) => s.pdf_from(ctx, wi),
            Shape::Disk(d) => d.pdf_from(ctx, wi),
            Shape::Cylinder(c) => c.pdf_from(ctx, wi),
            Shape::Triangle(t) => t.pdf_from(t.mesh_of(storage), ctx, wi),
            Shape::BilinearPatch(b) => b.pdf_from(b.mesh_of(storage), ctx, wi),
            Shape::Curve(_) => 0.0,
        }
    }

    /// pbrt's face index of a mesh face (the `faceIndices` parameter or the
    /// PLY `face_indices` property; 0 when absent and for quadrics). Ptex
    /// textures look it up.
    pub fn face_index(&self, storage: &ShapeStorage) -> i32 {
        match self {
            Shape::Triangle(t) => t.face_index(t.mesh_of(storage)),
            Shape::BilinearPatch(b) => b.face_index(b.mesh_of(storage)),
            _ => 0,
        }
    }
}

/// Converts an area-measure sample to solid angle at `ctx` (pbrt's shared
/// `Sample(ctx, u)` fallback): `pdf_ω = pdf_A · d² / |cos θ|`. `None` when the
/// sample is at the reference point or seen exactly edge-on.
pub(crate) fn area_sample_to_solid_angle(
    sample: ShapeSample,
    ctx: &ShapeSampleContext,
) -> Option<ShapeSample> {
    let to_sample = sample.p - ctx.p;
    let distance_squared = to_sample.length_squared();
    if distance_squared == 0.0 {
        return None;
    }
    let wi = to_sample.normalize();
    let pdf = sample.pdf / (sample.n.dot(-wi).abs() / distance_squared);
    if pdf.is_infinite() {
        return None;
    }
    Some(ShapeSample { pdf, ..sample })
}

/// The solid-angle density at `ctx` of area density `area_pdf` at the
/// point where the ray from `ctx` along `wi` hits (pbrt's shared
/// `PDF(ctx, wi)` fallback); 0 for a miss or an infinite density.
pub(crate) fn solid_angle_pdf_of_hit(
    hit: Option<&ShapeIntersection>,
    area_pdf: impl FnOnce(&ShapeIntersection) -> f32,
    ctx: &ShapeSampleContext,
    wi: Vec3,
) -> f32 {
    let Some(hit) = hit else {
        return 0.0;
    };
    let p = hit.interaction.p;
    let pdf = area_pdf(hit) / (hit.interaction.n.dot(-wi).abs() / ctx.p.distance_squared(p));
    if pdf.is_infinite() {
        0.0
    } else {
        pdf
    }
}

/// What creating shapes needs from the rest of the scene.
#[derive(Clone, Copy)]
pub struct ShapeContext<'a> {
    /// Where relative file names resolve (the scene file's directory).
    pub base_directory: &'a Path,
    /// The named textures (a `plymesh`'s `displacement`).
    pub textures: &'a NamedTextures,
    /// pbrt-v4's displacement edge scale (`Option "displacementedgescale"`
    /// or `--displacement-edge-scale`, default 1): multiplies every
    /// displaced `plymesh`'s `edgelength`.
    pub displacement_edge_scale: f32,
    /// The curve facts of `create_shapes`' render-from-object where the
    /// caller has them (a run of placements sharing a transform computes
    /// them once); `None`: computed for the shape.
    pub curve_transform: Option<curve::CurveTransform>,
}

/// The shapes a `Shape` directive makes, in render space.
///
/// `render_from_object` is the directive's transform composed with the
/// render-from-world transform; `reverse_orientation` the graphics state's
/// `ReverseOrientation`. Meshes are transformed now and appended to
/// `storage`; `plymesh` and `cyhair` file names resolve against
/// `context.base_directory`. Problems pbrt-v4 only warns about (PLY faces
/// that are neither triangles nor quads) are added to `warnings`. The
/// shapes made are appended to `shapes` (a run's one array: no array per
/// `Shape` directive, of which a hair file has hundreds of thousands); on
/// an error, some may have been.
pub fn create_shapes(
    shape: &scene_description::Shape,
    render_from_object: &Transform,
    reverse_orientation: bool,
    context: &ShapeContext,
    storage: &mut ShapeStorage,
    warnings: &mut Vec<Warning>,
    shapes: &mut Vec<Shape>,
) -> Result<()> {
    let params = &shape.entity.params;
    let location = &shape.entity.location.0;
    let kind = shape.entity.kind.as_str();
    let first_shape = shapes.len();
    match kind {
        "sphere" => shapes.push(Shape::Sphere(Box::new(Sphere::from_parameters(
            params,
            render_from_object,
            reverse_orientation,
        )?))),
        "disk" => shapes.push(Shape::Disk(Box::new(Disk::from_parameters(
            params,
            render_from_object,
            reverse_orientation,
        )?))),
        "cylinder" => shapes.push(Shape::Cylinder(Box::new(Cylinder::from_parameters(
            params,
            render_from_object,
            reverse_orientation,
        )?))),
        "trianglemesh" => {
            let mesh = TriangleMesh::from_parameters(
                params,
                location,
                render_from_object,
                reverse_orientation,
            )?;
            push_triangle_mesh(storage, mesh, shapes)
        }
        "bilinearmesh" => {
            let mesh = BilinearPatchMesh::from_parameters(
                params,
                location,
                render_from_object,
                reverse_orientation,
            )?;
            push_bilinear_mesh(storage, mesh, shapes)
        }
        "plymesh" => {
            let (filename, filename_at) = params
                .string_at("filename")?
                .unwrap_or_else(|| (String::new(), location.clone()));
            if filename.is_empty() {
                return scene_error("plymesh: \"filename\" must be given", location);
            }
            // The file first, as pbrt-v4: a missing file is the error a
            // scene without its assets stops at.
            let path = pbrt_parser::resolve_path(context.base_directory, &filename);
            let ply = ply::read_ply(&path, &filename_at)?;
            if ply.skipped_faces > 0 {
                warnings.push(Warning {
                    message: format!(
                        "{}: ignored {} face(s) that are neither triangles nor quads",
                        path.display(),
                        ply.skipped_faces
                    ),
                    location: location.clone(),
                });
            }
            let displacement = displacement::Displacement::from_shape(
                shape,
                context.textures,
                context.base_directory,
                context.displacement_edge_scale,
            )?;
            if let Some(displacement) = displacement {
                let data = displacement::displace(
                    ply,
                    &displacement.texture,
                    displacement.edge_length,
                    render_from_object,
                    displacement::MAX_DISPLACED_TRIANGLES,
                )
                .map_err(|e| SceneError::new(format!("{}: {e}", path.display()), location))?;
                let mesh = TriangleMesh::new(render_from_object, reverse_orientation, data);
                push_triangle_mesh(storage, mesh, shapes)
            } else {
                let meshes = ply.into_meshes(render_from_object, reverse_orientation);
                if let Some(mesh) = meshes.triangles {
                    push_triangle_mesh(storage, mesh, shapes);
                }
                if let Some(mesh) = meshes.quads {
                    push_bilinear_mesh(storage, mesh, shapes);
                }
            }
        }
        "curve" | "bcurve" | "cyhair" => {
            // Both append segments and pieces; the shape's are the new pieces.
            let first = storage.curve_pieces.len() as u32;
            if kind == "cyhair" {
                cyhair::create_cyhair(
                    shape,
                    render_from_object,
                    reverse_orientation,
                    context.base_directory,
                    &mut storage.curve_segments,
                    &mut storage.curve_pieces,
                )?;
            } else {
                let curve_transform = context
                    .curve_transform
                    .unwrap_or_else(|| curve::CurveTransform::of(render_from_object));
                curve::create_curves(
                    shape,
                    render_from_object,
                    &curve_transform,
                    reverse_orientation,
                    &mut storage.curve_segments,
                    &mut storage.curve_pieces,
                )?;
            }
            shapes.extend((first..storage.curve_pieces.len() as u32).map(Shape::Curve));
        }
        "loopsubdiv" => {
            let mesh = loop_subdiv::from_parameters(
                params,
                location,
                render_from_object,
                reverse_orientation,
            )?;
            push_triangle_mesh(storage, mesh, shapes)
        }
        _ => return scene_error(format!("\"{kind}\": unknown shape type"), location),
    };
    if shapes.len() == first_shape {
        return scene_error(
            format!("{kind}: unable to create shape (it has no faces)"),
            location,
        );
    }
    Ok(())
}

fn push_triangle_mesh(storage: &mut ShapeStorage, mesh: TriangleMesh, shapes: &mut Vec<Shape>) {
    let mesh_index = storage.triangle_meshes.len() as u32;
    let count = mesh.triangle_count() as u32;
    storage.triangle_meshes.push(mesh);
    shapes.extend((0..count).map(|index| Shape::Triangle(Triangle::new(mesh_index, index))));
}

fn push_bilinear_mesh(
    storage: &mut ShapeStorage,
    mesh: BilinearPatchMesh,
    shapes: &mut Vec<Shape>,
) {
    let mesh_index = storage.bilinear_meshes.len() as u32;
    let count = mesh.patch_count() as u32;
    storage.bilinear_meshes.push(mesh);
    shapes.extend(
        (0..count).map(|index| Shape::BilinearPatch(BilinearPatch::new(mesh_index, index))),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load_text;

    /// The shapes of a scene's world block, created with each shape's own
    /// transform as render-from-object.
    fn create_all(
        directory: &Path,
        world: &str,
    ) -> (Result<Vec<Shape>>, ShapeStorage, Vec<Warning>) {
        create_all_with_edge_scale(directory, world, 1.0)
    }

    /// [`create_all`] with a displacement edge scale.
    fn create_all_with_edge_scale(
        directory: &Path,
        world: &str,
        displacement_edge_scale: f32,
    ) -> (Result<Vec<Shape>>, ShapeStorage, Vec<Warning>) {
        let text = format!("WorldBegin\n{world}\n");
        let loaded = load_text(&directory.join("scene.pbrt"), &text).unwrap();
        let mut storage = ShapeStorage::default();
        let mut warnings = Vec::new();
        let mut all = Vec::new();
        let textures = NamedTextures::default();
        let context = ShapeContext {
            base_directory: directory,
            textures: &textures,
            displacement_edge_scale,
            curve_transform: None,
        };
        for shape in &loaded.scene.shapes {
            let transform = loaded.scene.transform(shape.world_from_object).start;
            if let Err(e) = create_shapes(
                shape,
                &transform,
                shape.reverse_orientation,
                &context,
                &mut storage,
                &mut warnings,
                &mut all,
            ) {
                return (Err(e), storage, warnings);
            }
        }
        (Ok(all), storage, warnings)
    }

    fn temporary_directory(test: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("rpbrt-shapes-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Widening a curve (the dual hair model's outer cylinder) widens the
    /// pieces the BVH bounds and the rays' hull tests use, not only the
    /// segments.
    #[test]
    fn scaled_curve_widths_reach_the_pieces() {
        let dir = temporary_directory("widen");
        let (shapes, mut storage, _) = create_all(
            &dir,
            r#"Shape "curve" "string type" "cylinder" "point3 P" [0 0 0 1 0 0 2 0 0 3 0 0] "float width" 0.2"#,
        );
        let shapes = shapes.unwrap();
        // A ray along -z passing 0.15 off the axis: outside the width 0.2,
        // inside the doubled width 0.4.
        let ray = Ray::new(Vec3::new(1.5, 0.15, 5.0), Vec3::new(0.0, 0.0, -1.0), 0.0);
        let hits = |storage: &ShapeStorage| {
            shapes
                .iter()
                .filter(|s| s.intersect_p(storage, &ray, f32::INFINITY))
                .count()
        };
        assert_eq!(hits(&storage), 0);
        let narrow = shapes[0].bounds(&storage);
        storage.scale_curve_widths(&shapes, 2.0);
        assert!(hits(&storage) > 0);
        let wide = shapes[0].bounds(&storage);
        assert!(
            (wide.max.y - narrow.max.y - 0.1).abs() < 1e-6,
            "{narrow:?} {wide:?}"
        );
    }

    #[test]
    fn every_supported_shape_is_created_in_render_space() {
        let dir = temporary_directory("create");
        std::fs::write(
            dir.join("quad.ply"),
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
element face 2\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n5 0 1 2 3 0\n",
        )
        .unwrap();
        let world = r#"
            AttributeBegin
              Translate 0 0 10
              Shape "sphere" "float radius" 2
              Shape "disk" "float radius" 3 "float height" 1
              ReverseOrientation
              Shape "cylinder" "float zmin" 0 "float zmax" 2
            AttributeEnd
            Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 1 1 0 0 1 0] "integer indices" [0 1 2 0 2 3]
            Shape "bilinearmesh" "point3 P" [0 0 5 1 0 5 0 1 5 1 1 5]
            Translate 0 0 -3
            Shape "plymesh" "string filename" "quad.ply"
        "#;
        let (shapes, storage, warnings) = create_all(&dir, world);
        let shapes = shapes.unwrap();
        assert_eq!(shapes.len(), 3 + 2 + 1 + 1);
        assert!(matches!(shapes[0], Shape::Sphere(_)));
        assert!(matches!(shapes[1], Shape::Disk(_)));
        assert!(matches!(shapes[2], Shape::Cylinder(_)));
        assert!(matches!(
            shapes[3],
            Shape::Triangle(Triangle { mesh: 0, index: 0 })
        ));
        assert!(matches!(
            shapes[4],
            Shape::Triangle(Triangle { mesh: 0, index: 1 })
        ));
        assert!(matches!(
            shapes[5],
            Shape::BilinearPatch(BilinearPatch { mesh: 0, index: 0 })
        ));
        assert!(matches!(
            shapes[6],
            Shape::BilinearPatch(BilinearPatch { mesh: 1, index: 0 })
        ));
        assert_eq!(storage.triangle_meshes.len(), 1);
        assert_eq!(storage.bilinear_meshes.len(), 2);
        // The pentagon of the PLY file was skipped with a warning.
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].message.contains("neither triangles nor quads"));

        let sphere_bounds = shapes[0].bounds(&storage);
        assert_eq!(sphere_bounds.min, Vec3::new(-2.0, -2.0, 8.0));
        assert_eq!(sphere_bounds.max, Vec3::new(2.0, 2.0, 12.0));
        // Shoot down the z axis through everything: the sphere's top first.
        let ray = Ray::new(Vec3::new(0.25, 0.5, 20.0), -Vec3::Z, 0.0);
        let nearest = shapes
            .iter()
            .enumerate()
            .filter_map(|(i, s)| {
                s.intersect(&storage, &ray, f32::INFINITY)
                    .map(|h| (i, h.t_hit))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        assert_eq!(nearest.0, 0);
        let t_of = |i: usize| {
            shapes[i]
                .intersect(&storage, &ray, f32::INFINITY)
                .map(|h| h.t_hit)
        };
        assert!((t_of(1).unwrap() - 9.0).abs() < 1e-5, "disk at z = 11");
        assert!(
            t_of(2).is_none(),
            "the cylinder's axis is the ray's neighbour, not its target"
        );
        assert!(t_of(3).is_none(), "(0.25, 0.5) is in the second triangle");
        assert!((t_of(4).unwrap() - 20.0).abs() < 1e-5);
        assert!((t_of(5).unwrap() - 15.0).abs() < 1e-5);
        assert!((t_of(6).unwrap() - 23.0).abs() < 1e-5, "plymesh at z = −3");
        // The reversed cylinder's normals point inwards.
        let side = Ray::new(Vec3::new(5.0, 0.0, 11.0), -Vec3::X, 0.0);
        let hit = shapes[2].intersect(&storage, &side, f32::INFINITY).unwrap();
        assert!((hit.interaction.n + Vec3::X).length() < 1e-5);
        assert!((shapes[5].area(&storage) - 1.0).abs() < 1e-6);
        assert!(shapes.iter().all(|s| s.face_index(&storage) == 0));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn odd_parameters_give_shapes_that_do_not_panic() {
        let dir = temporary_directory("odd");
        let world = r#"
            Shape "sphere" "float radius" -1
            Shape "sphere" "float radius" 0 "float phimax" -30
            Shape "sphere" "float zmin" 0.5 "float zmax" 0.5
            Shape "disk" "float radius" 0 "float innerradius" 2
            Shape "cylinder" "float radius" 0 "float zmin" 1 "float zmax" 1
            Shape "trianglemesh" "point3 P" [0 0 0 0 0 0 0 0 0]
            Shape "bilinearmesh" "point3 P" [0 0 0 0 0 0 0 0 0 0 0 0]
            Shape "bilinearmesh" "point3 P" [0 0 0 1 0 0 0 0 0 1 0 0]
        "#;
        let (shapes, storage, _) = create_all(&dir, world);
        let shapes = shapes.unwrap();
        let mut rng = test_support::TestRng::new(99);
        for shape in &shapes {
            let _ = shape.bounds(&storage);
            let _ = shape.area(&storage);
            for _ in 0..100 {
                let origin = rng.direction() * 3.0;
                let ray = Ray::new(origin, rng.direction(), 0.0);
                let _ = shape.intersect(&storage, &ray, f32::INFINITY);
                let u = rng.uniform2();
                let _ = shape.sample_area(&storage, u);
                let ctx = ShapeSampleContext::in_medium(origin, 0.0);
                let _ = shape.sample_from(&storage, &ctx, u);
                let _ = shape.pdf_from(&storage, &ctx, ray.direction);
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_shape_is_as_small_as_a_mesh_face_reference() {
        assert_eq!(std::mem::size_of::<Shape>(), 16);
    }

    #[test]
    fn unsupported_and_broken_shapes_are_errors() {
        let dir = temporary_directory("errors");
        let error = |world: &str| create_all(&dir, world).0.unwrap_err().to_string();
        let e =
            error(r#"Shape "loopsubdiv" "integer indices" [0 1 3] "point3 P" [0 0 0 1 0 0 0 1 0]"#);
        assert!(
            e.contains("loopsubdiv: \"indices\" values out of range: 3"),
            "{e}"
        );
        let e = error(
            r#"Shape "loopsubdiv" "integer indices" [0 1 2 0 1 2] "point3 P" [0 0 0 1 0 0 0 1 0]"#,
        );
        assert!(e.contains("in two triangles the same way round"), "{e}");
        // A displaced mesh whose file is absent stops at the file.
        let e = error(r#"Shape "plymesh" "string filename" "mesh.ply" "float displacement" 0.1"#);
        assert!(e.contains("cannot read") && e.contains("mesh.ply"), "{e}");
        let e = error(r#"Shape "plymesh" "string filename" "missing.ply""#);
        assert!(e.contains("missing.ply"), "{e}");
        let e = error(
            r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 7]"#,
        );
        assert!(
            e.contains("\"indices\" values out of range: 7") && e.contains("scene.pbrt:2:"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A unit square in z = 0 as one quad with (u,v), and the same
    /// without (u,v).
    fn write_square_plys(dir: &Path) {
        let header = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n";
        let faces = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
        std::fs::write(
            dir.join("square.ply"),
            format!("{header}property float u\nproperty float v\n{faces}0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n"),
        )
        .unwrap();
        std::fs::write(
            dir.join("no-uv.ply"),
            format!("{header}{faces}0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"),
        )
        .unwrap();
    }

    #[test]
    fn a_displaced_plymesh_is_cut_lifted_and_transformed() {
        let dir = temporary_directory("displaced");
        write_square_plys(&dir);
        let world = r#"
            Translate 0 0 10
            Shape "plymesh" "string filename" "square.ply" "float displacement" 0.5 "float edgelength" 0.3
        "#;
        let (shapes, storage, _) = create_all(&dir, world);
        let shapes = shapes.unwrap();
        // Two right triangles of legs 1, each cut into 2^5 (the
        // hypotenuse first under 0.3 after 5 halvings).
        assert_eq!(shapes.len(), 64);
        assert!(shapes.iter().all(|s| matches!(s, Shape::Triangle(_))));
        let mesh = &storage.triangle_meshes[0];
        assert!(mesh.positions.iter().all(|p| (p.z - 10.5).abs() < 1e-5));
        assert_eq!(mesh.normals.len(), mesh.positions.len());
        let area: f32 = shapes.iter().map(|s| s.area(&storage)).sum();
        assert!((area - 1.0).abs() < 1e-5);
        // The edge scale multiplies the edge length: at 0.6 three
        // halvings do.
        let (coarser, _, _) = create_all_with_edge_scale(&dir, world, 2.0);
        assert_eq!(coarser.unwrap().len(), 16);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn displacement_errors_point_at_the_parameter() {
        let dir = temporary_directory("displacement-errors");
        write_square_plys(&dir);
        let error = |world: &str, scale: f32| {
            create_all_with_edge_scale(&dir, world, scale)
                .0
                .unwrap_err()
                .to_string()
        };
        // An unknown texture is caught as the scene is read (a texture
        // must be defined before the shape that uses it).
        let text = "WorldBegin\nShape \"plymesh\" \"string filename\" \"square.ply\" \"texture displacement\" \"bumps\"\n";
        let e = match load_text(&dir.join("scene.pbrt"), text) {
            Ok(_) => panic!("an undefined texture was accepted"),
            Err(e) => e.to_string(),
        };
        assert!(
            e.contains("texture \"bumps\" is not defined") && e.contains("scene.pbrt:2:"),
            "{e}"
        );
        for edge in ["0", "-1"] {
            let e = error(
                &format!(
                    r#"Shape "plymesh" "string filename" "square.ply" "float displacement" 1 "float edgelength" {edge}"#
                ),
                1.0,
            );
            assert!(
                e.contains("edge length must be positive") && e.contains("scene.pbrt:2:"),
                "{e}"
            );
        }
        let e = error(
            r#"Shape "plymesh" "string filename" "square.ply" "float displacement" 1"#,
            f32::NAN,
        );
        assert!(e.contains("edge length must be positive"), "{e}");
        let e = error(
            r#"Shape "plymesh" "string filename" "no-uv.ply" "float displacement" 1"#,
            1.0,
        );
        assert!(
            e.contains("no-uv.ply: displacement needs per-vertex (u,v)"),
            "{e}"
        );
        let e = error(
            r#"Shape "plymesh" "string filename" "square.ply" "float displacement" 1 "float edgelength" 1e-6"#,
            1.0,
        );
        assert!(e.contains("more than 50000000 triangles"), "{e}");
        // Without a displacement the edge length is not looked at (as in
        // pbrt-v4), and quads stay bilinear patches.
        let (shapes, _, _) = create_all(
            &dir,
            r#"Shape "plymesh" "string filename" "square.ply" "float edgelength" 0"#,
        );
        assert!(matches!(shapes.unwrap()[..], [Shape::BilinearPatch(_)]));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
