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
pub mod cylinder;
pub mod disk;
pub mod interval;
pub mod mesh;
pub mod object_transform;
pub mod ply;
pub mod sphere;
pub mod spherical;
pub mod surface;
pub mod triangle;
pub mod warps;

#[cfg(test)]
mod test_support;

pub use bilinear::BilinearPatch;
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use mesh::{BilinearPatchMesh, TriangleMesh};
pub use sphere::Sphere;
pub use triangle::Triangle;

use crate::error::{scene_error, Result};
use crate::interaction::SurfaceInteraction;
use crate::math::{offset_ray_origin, Bounds3, Ray, Transform};
use crate::scene::description;
use glam::{Vec2, Vec3};
use pbrt_parser::{ParamType, Warning};
use std::path::Path;

/// A shape of the scene. Per-ray code matches on it; no trait objects.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Sphere(Box<Sphere>),
    Disk(Box<Disk>),
    Cylinder(Box<Cylinder>),
    Triangle(Triangle),
    BilinearPatch(BilinearPatch),
    // curves: issue 4
}

/// The meshes that [`Triangle`] and [`BilinearPatch`] shapes index into.
/// [`create_shapes`] appends to it; every [`Shape`] method reads it.
#[derive(Clone, Debug, Default)]
pub struct ShapeStorage {
    pub triangle_meshes: Vec<TriangleMesh>,
    pub bilinear_meshes: Vec<BilinearPatchMesh>,
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

impl Shape {
    /// Render-space bounds.
    pub fn bounds(&self, storage: &ShapeStorage) -> Bounds3 {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Disk(d) => d.bounds(),
            Shape::Cylinder(c) => c.bounds(),
            Shape::Triangle(t) => t.bounds(t.mesh_of(storage)),
            Shape::BilinearPatch(b) => b.bounds(b.mesh_of(storage)),
        }
    }

    /// The closest hit with `0 < t < t_max` (t in units of `ray.direction`).
    pub fn intersect(&self, storage: &ShapeStorage, ray: &Ray, t_max: f32) -> Option<ShapeIntersection> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_max),
            Shape::Disk(d) => d.intersect(ray, t_max),
            Shape::Cylinder(c) => c.intersect(ray, t_max),
            Shape::Triangle(t) => t.intersect(t.mesh_of(storage), ray, t_max),
            Shape::BilinearPatch(b) => b.intersect(b.mesh_of(storage), ray, t_max),
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
        }
    }

    /// A point on the surface as seen from `ctx`; `pdf` is per unit solid
    /// angle at `ctx.p`.
    pub fn sample_from(&self, storage: &ShapeStorage, ctx: &ShapeSampleContext, u: Vec2) -> Option<ShapeSample> {
        match self {
            Shape::Sphere(s) => s.sample_from(ctx, u),
            Shape::Disk(d) => d.sample_from(ctx, u),
            Shape::Cylinder(c) => c.sample_from(ctx, u),
            Shape::Triangle(t) => t.sample_from(t.mesh_of(storage), ctx, u),
            Shape::BilinearPatch(b) => b.sample_from(b.mesh_of(storage), ctx, u),
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
pub(crate) fn area_sample_to_solid_angle(sample: ShapeSample, ctx: &ShapeSampleContext) -> Option<ShapeSample> {
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

/// The shapes a `Shape` directive makes, in render space.
///
/// `render_from_object` is the directive's transform composed with the
/// render-from-world transform; `reverse_orientation` the graphics state's
/// `ReverseOrientation`. Meshes are transformed now and appended to
/// `storage`; `plymesh` file names resolve against `base_directory`.
/// Problems pbrt-v4 only warns about (PLY faces that are neither triangles
/// nor quads) are added to `warnings`.
pub fn create_shapes(
    shape: &description::Shape,
    render_from_object: &Transform,
    reverse_orientation: bool,
    base_directory: &Path,
    storage: &mut ShapeStorage,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<Shape>> {
    let params = &shape.entity.params;
    let location = &shape.entity.location.0;
    let kind = shape.entity.kind.as_str();
    let shapes = match kind {
        "sphere" => vec![Shape::Sphere(Box::new(Sphere::from_parameters(
            params,
            render_from_object,
            reverse_orientation,
        )?))],
        "disk" => vec![Shape::Disk(Box::new(Disk::from_parameters(
            params,
            render_from_object,
            reverse_orientation,
        )?))],
        "cylinder" => vec![Shape::Cylinder(Box::new(Cylinder::from_parameters(
            params,
            render_from_object,
            reverse_orientation,
        )?))],
        "trianglemesh" => {
            let mesh = TriangleMesh::from_parameters(params, location, render_from_object, reverse_orientation)?;
            push_triangle_mesh(storage, mesh)
        }
        "bilinearmesh" => {
            let mesh =
                BilinearPatchMesh::from_parameters(params, location, render_from_object, reverse_orientation)?;
            push_bilinear_mesh(storage, mesh)
        }
        "plymesh" => {
            let filename = params.string("filename", "")?;
            params.float("edgelength", 1.0)?;
            if params.find("displacement", &[ParamType::Float, ParamType::Texture])?.is_some() {
                return scene_error("plymesh displacement is not supported yet", location);
            }
            if filename.is_empty() {
                return scene_error("plymesh: \"filename\" must be given", location);
            }
            let path = base_directory.join(&filename);
            let ply = ply::read_ply(&path, location)?;
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
            let meshes = ply.into_meshes(render_from_object, reverse_orientation);
            let mut shapes = Vec::new();
            if let Some(mesh) = meshes.triangles {
                shapes.extend(push_triangle_mesh(storage, mesh));
            }
            if let Some(mesh) = meshes.quads {
                shapes.extend(push_bilinear_mesh(storage, mesh));
            }
            shapes
        }
        "loopsubdiv" | "curve" | "bcurve" => {
            return scene_error(format!("shape \"{kind}\" is not supported yet"), location)
        }
        _ => return scene_error(format!("\"{kind}\": unknown shape type"), location),
    };
    if shapes.is_empty() {
        return scene_error(format!("{kind}: unable to create shape (it has no faces)"), location);
    }
    Ok(shapes)
}

fn push_triangle_mesh(storage: &mut ShapeStorage, mesh: TriangleMesh) -> Vec<Shape> {
    let mesh_index = storage.triangle_meshes.len() as u32;
    let count = mesh.triangle_count() as u32;
    storage.triangle_meshes.push(mesh);
    (0..count)
        .map(|index| Shape::Triangle(Triangle::new(mesh_index, index)))
        .collect()
}

fn push_bilinear_mesh(storage: &mut ShapeStorage, mesh: BilinearPatchMesh) -> Vec<Shape> {
    let mesh_index = storage.bilinear_meshes.len() as u32;
    let count = mesh.patch_count() as u32;
    storage.bilinear_meshes.push(mesh);
    (0..count)
        .map(|index| Shape::BilinearPatch(BilinearPatch::new(mesh_index, index)))
        .collect()
}
