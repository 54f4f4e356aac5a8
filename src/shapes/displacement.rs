//! Displaced `plymesh` shapes: the `displacement` float texture and the
//! `edgelength` parameter (pbrt-v4's `TriQuadMesh::Displace`, called by
//! `Shape::Create`).
//!
//! The mesh read from the file becomes triangles only (each quad two
//! triangles, its face vertices 0 1 2 and 0 2 3). Without normals in the
//! file, each vertex gets the normalised sum of the unit normals of the
//! triangles around it. The edges are then cut until all are shorter than
//! the edge length in render space ([`mesh_subdivision`]), and each vertex
//! moves along its normal by the texture's value there: the texture is
//! evaluated once per vertex, at build time, at the vertex's object-space
//! position and (u,v), with no differentials (as pbrt-v4 does; a 3D
//! texture thus sees object space). The normals are finally computed
//! again from the displaced triangles, as pbrt-v4 does, so the file's own
//! normals only steer the displacement.
//!
//! pbrt-v4 requires (u,v) in the file for displacement; so does rpbrt (an
//! error naming the shape). The edge length times the displacement edge
//! scale must be positive (pbrt-v4 would cut edges forever). A constant
//! `"float displacement"` is accepted too (pbrt-v4 takes only a texture). Where pbrt-v4 would keep the file's face
//! indices as they were (a mismatch it aborts on once triangles are
//! added), each piece here carries the index of the face it came from.
//!
//! [`mesh_subdivision`]: super::mesh_subdivision

use super::mesh::MeshData;
use super::mesh_subdivision::{refine, RefinableMesh, TooManyTriangles};
use super::ply::PlyMesh;
use crate::error::{scene_error, Result};
use crate::math::Transform;
use crate::scene_description;
use crate::textures::{FloatTexture, NamedTextures, TextureEvalContext, TextureParams};
use glam::Vec3;
use pbrt_parser::ParamType;
use rayon::prelude::*;
use std::path::Path;

/// The most triangles a displaced mesh may have. pbrt-v4 has no bound; a
/// tiny edge length on a large mesh would fill the memory (a triangle
/// costs some 100 bytes by the time it is rendered, so this is about
/// 5 GB).
pub const MAX_DISPLACED_TRIANGLES: usize = 50_000_000;

/// Why a mesh could not be displaced.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DisplacementError {
    #[error("displacement needs per-vertex (u,v) in the PLY file (as in pbrt-v4)")]
    NoUvs,
    #[error("displacement: {0}")]
    TooManyTriangles(#[from] TooManyTriangles),
}

/// What a `plymesh` shape's `displacement` and `edgelength` ask for.
#[derive(Clone, Debug)]
pub struct Displacement {
    pub texture: FloatTexture,
    /// `edgelength` times the displacement edge scale: positive.
    pub edge_length: f32,
}

impl Displacement {
    /// The shape's displacement, if it names one: its texture (a named
    /// float texture, or a constant) and its edge length times
    /// `edge_scale` (pbrt-v4's `displacementedgescale`), which must be
    /// positive (pbrt-v4 would cut edges forever). Errors point at the
    /// parameter.
    pub fn from_shape(
        shape: &scene_description::Shape,
        textures: &NamedTextures,
        base_directory: &Path,
        edge_scale: f32,
    ) -> Result<Option<Self>> {
        let params = &shape.entity.params;
        let edge_length = params.float("edgelength", 1.0)? as f32;
        let texture_params = TextureParams {
            params,
            color_space: shape.entity.color_space,
            textures,
            base_directory,
        };
        let Some(texture) = texture_params.float_texture_opt("displacement")? else {
            return Ok(None);
        };
        let scaled = edge_length * edge_scale;
        // NaN (from either factor) is refused too.
        if scaled.is_nan() || scaled <= 0.0 {
            let location = match params.find("edgelength", &[ParamType::Float])? {
                Some(p) => p.location.clone(),
                None => shape.entity.location.0.clone(),
            };
            return scene_error(
                format!(
                    "plymesh: the displacement edge length must be positive (\"edgelength\" {edge_length} × displacement edge scale {edge_scale})"
                ),
                &location,
            );
        }
        Ok(Some(Displacement {
            texture,
            edge_length: scaled,
        }))
    }
}

/// The triangles of `ply` cut to shorter than `edge_length` (render space,
/// positive) and displaced by `texture`, in object space, with normals
/// and (u,v); at most `max_triangles` of them.
pub fn displace(
    ply: PlyMesh,
    texture: &FloatTexture,
    edge_length: f32,
    render_from_object: &Transform,
    max_triangles: usize,
) -> Result<MeshData, DisplacementError> {
    if ply.uvs.is_empty() {
        return Err(DisplacementError::NoUvs);
    }
    let mut mesh = only_triangles(ply);
    if mesh.normals.is_empty() {
        mesh.normals = vertex_normals(&mesh.positions, &mesh.triangle_indices);
    }
    refine(&mut mesh, edge_length, render_from_object, max_triangles)?;
    mesh.positions
        .par_iter_mut()
        .zip(&mesh.normals)
        .zip(&mesh.uvs)
        .for_each(|((p, n), uv)| {
            let context = TextureEvalContext {
                p: *p,
                uv: *uv,
                ..Default::default()
            };
            *p += texture.evaluate(&context) * *n;
        });
    let normals = vertex_normals(&mesh.positions, &mesh.triangle_indices);
    Ok(MeshData {
        vertex_indices: mesh.triangle_indices,
        positions: mesh.positions,
        normals,
        tangents: Vec::new(),
        uvs: mesh.uvs,
        face_indices: mesh.face_indices,
    })
}

/// The file's triangles, then each quad as two triangles (quads are held
/// in bilinear-patch order p00 p10 p01 p11, face vertices 0 1 3 2), with
/// their face indices.
fn only_triangles(ply: PlyMesh) -> RefinableMesh {
    let PlyMesh {
        positions,
        normals,
        uvs,
        mut triangle_indices,
        quad_indices,
        mut triangle_face_indices,
        quad_face_indices,
        ..
    } = ply;
    triangle_indices.reserve(quad_indices.len() / 4 * 6);
    for q in quad_indices.chunks_exact(4) {
        triangle_indices.extend([q[0], q[1], q[3], q[0], q[3], q[2]]);
    }
    for &face in &quad_face_indices {
        triangle_face_indices.extend([face, face]);
    }
    RefinableMesh {
        positions,
        normals,
        uvs,
        triangle_indices,
        face_indices: triangle_face_indices,
    }
}

/// Per vertex, the normalised sum of the unit normals of its triangles
/// (by their winding; degenerate ones add nothing), or zero where they
/// cancel or there are none.
fn vertex_normals(positions: &[Vec3], triangle_indices: &[u32]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for v in triangle_indices.chunks_exact(3) {
        let [p0, p1, p2] = [v[0], v[1], v[2]].map(|i| positions[i as usize]);
        let face_normal = (p1 - p0).cross(p2 - p1);
        if face_normal.length_squared() > 0.0 {
            let unit = face_normal.normalize();
            for &i in v {
                normals[i as usize] += unit;
            }
        }
    }
    for n in &mut normals {
        *n = n.normalize_or_zero();
    }
    normals
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::textures::bilerp::BilerpTexture;
    use crate::textures::TextureMapping2D;
    use glam::{DVec3, Vec2};

    /// A flat `n`×`n` grid of unit cells in the z = 0 plane as quads, with
    /// (u,v) = (x, y) / n and no normals.
    fn grid(n: u32) -> PlyMesh {
        let mut ply = PlyMesh::default();
        for y in 0..=n {
            for x in 0..=n {
                ply.positions.push(Vec3::new(x as f32, y as f32, 0.0));
                ply.uvs.push(Vec2::new(x as f32, y as f32) / n as f32);
            }
        }
        let index = |x: u32, y: u32| y * (n + 1) + x;
        for y in 0..n {
            for x in 0..n {
                // Face 0 1 2 3 counterclockwise, held as 0 1 3 2.
                ply.quad_indices.extend([
                    index(x, y),
                    index(x + 1, y),
                    index(x, y + 1),
                    index(x + 1, y + 1),
                ]);
                ply.quad_face_indices.push((y * n + x) as i32);
            }
        }
        ply
    }

    #[test]
    fn a_constant_texture_moves_every_vertex_along_the_normal() {
        let flat = grid(2);
        let displaced = displace(
            flat.clone(),
            &FloatTexture::Constant(0.25),
            0.6,
            &Transform::IDENTITY,
            10_000,
        )
        .unwrap();
        // Cut: more vertices than the grid's 9, every one lifted by 0.25
        // along the computed normal +z.
        assert!(displaced.positions.len() > 9);
        assert!(displaced
            .positions
            .iter()
            .all(|p| (p.z - 0.25).abs() < 1e-6));
        assert!(displaced.positions.iter().all(|p| p.x >= 0.0 && p.x <= 2.0));
        assert!(displaced
            .normals
            .iter()
            .all(|&n| (n - Vec3::Z).length() < 1e-6));
        // Each piece keeps the index of its quad.
        assert_eq!(
            displaced.face_indices.len(),
            displaced.vertex_indices.len() / 3
        );
        for (v, &face) in displaced
            .vertex_indices
            .chunks_exact(3)
            .zip(&displaced.face_indices)
        {
            let centroid: Vec3 = v
                .iter()
                .map(|&i| displaced.positions[i as usize])
                .sum::<Vec3>()
                / 3.0;
            let cell = centroid.y.floor() as i32 * 2 + centroid.x.floor() as i32;
            assert_eq!(face, cell, "{centroid}");
        }
    }

    #[test]
    fn the_files_normals_steer_the_displacement_and_are_then_recomputed() {
        let mut tilted = grid(1);
        tilted.normals = vec![Vec3::X; tilted.positions.len()];
        let displaced = displace(
            tilted,
            &FloatTexture::Constant(0.5),
            10.0,
            &Transform::IDENTITY,
            10,
        )
        .unwrap();
        assert_eq!(displaced.positions[0], Vec3::new(0.5, 0.0, 0.0));
        assert_eq!(displaced.positions[3], Vec3::new(1.5, 1.0, 0.0));
        assert!(displaced
            .normals
            .iter()
            .all(|&n| (n - Vec3::Z).length() < 1e-6));
    }

    /// `bilerp` with corners 0, 1, 2, 3 is 0 + s + 2t at (s,t): each
    /// vertex rises by that at its own (u,v), midpoints included.
    #[test]
    fn a_bilerp_texture_lifts_each_vertex_by_its_value() {
        let texture = FloatTexture::Bilerp(Box::new(BilerpTexture {
            mapping: TextureMapping2D::Uv {
                scale: Vec2::ONE,
                delta: Vec2::ZERO,
            },
            values: [0.0, 1.0, 2.0, 3.0],
        }));
        let displaced = displace(grid(2), &texture, 0.4, &Transform::IDENTITY, 10_000).unwrap();
        assert!(displaced.positions.len() > 25);
        for (p, uv) in displaced.positions.iter().zip(&displaced.uvs) {
            assert!((uv.x - p.x / 2.0).abs() < 1e-6 && (uv.y - p.y / 2.0).abs() < 1e-6);
            let expected = uv.x + 2.0 * uv.y;
            assert!((p.z - expected).abs() < 1e-5, "{p} at {uv}");
        }
        // A tilted plane: the recomputed normals are its normal.
        let plane_normal = Vec3::new(-0.5, -1.0, 1.0).normalize();
        assert!(displaced
            .normals
            .iter()
            .all(|n| (*n - plane_normal).length() < 1e-5));
    }

    #[test]
    fn a_scaled_mesh_is_cut_finer() {
        let texture = FloatTexture::Constant(0.0);
        let count = |transform: &Transform| {
            displace(grid(2), &texture, 0.6, transform, 100_000)
                .unwrap()
                .vertex_indices
                .len()
                / 3
        };
        let plain = count(&Transform::IDENTITY);
        let scaled = count(&Transform::scale(DVec3::splat(3.0)).unwrap());
        assert!(scaled >= 8 * plain, "{plain} {scaled}");
    }

    #[test]
    fn meshes_without_uv_and_huge_refinements_are_refused() {
        let mut no_uv = grid(1);
        no_uv.uvs.clear();
        let texture = FloatTexture::Constant(1.0);
        assert_eq!(
            displace(no_uv, &texture, 1.0, &Transform::IDENTITY, 10),
            Err(DisplacementError::NoUvs)
        );
        let e = displace(
            grid(1),
            &texture,
            1e-5,
            &Transform::IDENTITY,
            MAX_DISPLACED_TRIANGLES,
        )
        .unwrap_err();
        assert!(matches!(e, DisplacementError::TooManyTriangles(_)), "{e}");
    }

    #[test]
    fn vertex_normals_skip_degenerate_triangles() {
        let positions = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(5.0, 5.0, 5.0),
        ];
        let normals = vertex_normals(&positions, &[0, 1, 2, 0, 1, 3]);
        assert_eq!(normals[..3], [Vec3::Z; 3]);
        assert_eq!(normals[3], Vec3::ZERO);
        assert_eq!(normals[4], Vec3::ZERO);
    }
}
