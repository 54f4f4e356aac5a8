//! Splitting a triangle mesh's edges until every edge is shorter than a
//! given length, measured in render space: the refinement pbrt-v4's
//! `TriQuadMesh::Displace` does before it moves the vertices of a
//! displaced `plymesh`.
//!
//! The mesh stays in object space; only the lengths are measured after
//! `render_from_object`. A triangle whose three edges are all shorter than
//! the length is kept; otherwise its longest edge is cut at its midpoint
//! (position and (u,v) averaged, normal the normalised sum) and the two
//! halves are refined the same way, the half holding the edge's first
//! vertex first. This is longest-edge bisection, with pbrt-v4's choice
//! among equally long edges, so the triangles and vertices come out in
//! the same order as pbrt-v4's.
//!
//! Whether an edge is cut depends on the edge alone (its length), and a
//! cut edge's midpoint is remembered by its two vertex indices, smaller
//! first: the two triangles that share an edge share its midpoint, and the
//! refined mesh has no cracks. An edge whose length is not finite (a
//! vertex at infinity or NaN) is never cut, so that refinement always
//! ends; pbrt-v4 would cut it forever.
//!
//! pbrt-v4 sets no bound on the number of triangles; here the refinement
//! stops with [`TooManyTriangles`] past a limit (the caller's), and a mesh
//! whose render-space area alone shows that it would pass the limit is
//! refused before any work.

use crate::math::Transform;
use glam::{Vec2, Vec3};
use std::collections::HashMap;

/// A triangle mesh in object space, as refinement reads and extends it.
/// Optional per-vertex arrays (`normals`, `uvs`) are empty or one per
/// vertex; `face_indices` is empty or one per triangle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RefinableMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    /// Three vertex indices per triangle.
    pub triangle_indices: Vec<u32>,
    pub face_indices: Vec<i32>,
}

/// Refinement would make more triangles than its limit allows.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error(
    "splitting edges to shorter than {edge_length} (render space) would make more than {limit} triangles{}",
    estimate_text(*.at_least)
)]
pub struct TooManyTriangles {
    pub edge_length: f32,
    pub limit: usize,
    /// A lower bound on the count, when known before refining.
    pub at_least: Option<f64>,
}

fn estimate_text(at_least: Option<f64>) -> String {
    match at_least {
        Some(count) => format!(" (at least {count:.3e})"),
        None => String::new(),
    }
}

/// The largest area a triangle with all three edges shorter than 1 can
/// have (the equilateral one): √3/4.
const UNIT_EDGE_MAX_AREA: f64 = 0.433_012_701_892_219_3;

/// Cuts the edges of `mesh` until every edge of finite render-space length
/// is shorter than `edge_length` (positive), creating at most
/// `max_triangles` triangles in all.
pub fn refine(
    mesh: &mut RefinableMesh,
    edge_length: f32,
    render_from_object: &Transform,
    max_triangles: usize,
) -> Result<(), TooManyTriangles> {
    let to_render = |p: Vec3| render_from_object.point(p.as_dvec3()).as_vec3();
    let mut render_positions: Vec<Vec3> = mesh.positions.iter().map(|&p| to_render(p)).collect();
    let too_many = |at_least| TooManyTriangles {
        edge_length,
        limit: max_triangles,
        at_least,
    };
    // Every triangle left has all edges shorter than `edge_length`, so at
    // most the equilateral triangle's area: the area to cover bounds the
    // count from below, and hopeless requests stop here, in a moment.
    let lower_bound = render_space_area(&mesh.triangle_indices, &render_positions)
        / (UNIT_EDGE_MAX_AREA * f64::from(edge_length).powi(2));
    if lower_bound > max_triangles as f64 {
        return Err(too_many(Some(lower_bound)));
    }

    let input_indices = std::mem::take(&mut mesh.triangle_indices);
    let input_faces = std::mem::take(&mut mesh.face_indices);
    let has_faces = !input_faces.is_empty();
    let mut triangle_count = input_indices.len() / 3;
    if triangle_count > max_triangles {
        return Err(too_many(None));
    }
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    // Triangles still to look at: depth first, in pbrt-v4's order, without
    // recursion (a long, thin triangle is cut many times over).
    let mut pending: Vec<[u32; 3]> = Vec::new();
    for (triangle, corners) in input_indices.chunks_exact(3).enumerate() {
        let face = if has_faces { input_faces[triangle] } else { 0 };
        pending.push([corners[0], corners[1], corners[2]]);
        while let Some(v) = pending.pop() {
            let length = |a: u32, b: u32| {
                let d = render_positions[b as usize] - render_positions[a as usize];
                let length = d.length();
                // Edges that are never cut take no part in the choice.
                if length.is_finite() && length >= edge_length {
                    length
                } else {
                    f32::NEG_INFINITY
                }
            };
            let (d01, d12, d20) = (length(v[0], v[1]), length(v[1], v[2]), length(v[2], v[0]));
            if d01 == f32::NEG_INFINITY && d12 == f32::NEG_INFINITY && d20 == f32::NEG_INFINITY {
                mesh.triangle_indices.extend_from_slice(&v);
                if has_faces {
                    mesh.face_indices.push(face);
                }
                continue;
            }
            // The longest edge; among equal ones the choice pbrt-v4 makes.
            let longest = if d01 > d12 {
                if d01 > d20 {
                    0
                } else {
                    2
                }
            } else if d12 > d20 {
                1
            } else {
                2
            };
            // (start, end, opposite) of the edge to cut.
            let [a, b, opposite] = [v[longest], v[(longest + 1) % 3], v[(longest + 2) % 3]];
            triangle_count += 1;
            if triangle_count > max_triangles {
                return Err(too_many(None));
            }
            let key = (a.min(b), a.max(b));
            let middle = match midpoints.get(&key) {
                Some(&m) => m,
                None => {
                    let m = mesh.positions.len() as u32;
                    let (ia, ib) = (a as usize, b as usize);
                    let p = (mesh.positions[ia] + mesh.positions[ib]) * 0.5;
                    mesh.positions.push(p);
                    render_positions.push(to_render(p));
                    if !mesh.normals.is_empty() {
                        let n = (mesh.normals[ia] + mesh.normals[ib]).normalize_or_zero();
                        mesh.normals.push(n);
                    }
                    if !mesh.uvs.is_empty() {
                        mesh.uvs.push((mesh.uvs[ia] + mesh.uvs[ib]) * 0.5);
                    }
                    midpoints.insert(key, m);
                    m
                }
            };
            // Popped last-in first-out: the half at `a` is refined first.
            pending.push([middle, b, opposite]);
            pending.push([a, middle, opposite]);
        }
    }
    Ok(())
}

/// The total area of the triangles in render space (f64: a sum over
/// millions of triangles).
fn render_space_area(triangle_indices: &[u32], render_positions: &[Vec3]) -> f64 {
    triangle_indices
        .chunks_exact(3)
        .map(|v| {
            let [p0, p1, p2] = [v[0], v[1], v[2]].map(|i| render_positions[i as usize].as_dvec3());
            let area = 0.5 * (p1 - p0).cross(p2 - p0).length();
            if area.is_finite() {
                area
            } else {
                0.0
            }
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use std::collections::HashSet;

    /// A right isosceles triangle with legs 1 along x and y, normals
    /// tilted apart and (u,v) equal to (x,y).
    fn right_triangle() -> RefinableMesh {
        RefinableMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![
                Vec3::Z,
                Vec3::new(1.0, 0.0, 1.0).normalize(),
                Vec3::new(0.0, 1.0, 1.0).normalize(),
            ],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y],
            triangle_indices: vec![0, 1, 2],
            face_indices: vec![7],
        }
    }

    fn edges(mesh: &RefinableMesh) -> Vec<(u32, u32)> {
        mesh.triangle_indices
            .chunks_exact(3)
            .flat_map(|v| [(v[0], v[1]), (v[1], v[2]), (v[2], v[0])])
            .collect()
    }

    fn longest_edge(mesh: &RefinableMesh) -> f32 {
        edges(mesh)
            .iter()
            .map(|&(a, b)| (mesh.positions[a as usize] - mesh.positions[b as usize]).length())
            .fold(0.0, f32::max)
    }

    /// Each cut halves the triangle into two similar ones with legs 1/√2
    /// as long: after k levels the hypotenuse is √2 (1/√2)^k, below 0.3
    /// first at k = 5, so 2⁵ triangles.
    #[test]
    fn a_triangle_is_cut_until_every_edge_is_shorter_than_the_length() {
        let mut mesh = right_triangle();
        refine(&mut mesh, 0.3, &Transform::IDENTITY, 1000).unwrap();
        assert_eq!(mesh.triangle_indices.len() / 3, 32);
        assert!(longest_edge(&mesh) < 0.3, "{}", longest_edge(&mesh));
        assert!(longest_edge(&mesh) > 0.15);
        assert_eq!(mesh.face_indices, vec![7; 32]);
        // Every vertex is a distinct point and is used.
        let distinct: HashSet<[u32; 3]> = mesh
            .positions
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect();
        assert_eq!(distinct.len(), mesh.positions.len());
        let used: HashSet<u32> = mesh.triangle_indices.iter().copied().collect();
        assert_eq!(used.len(), mesh.positions.len());
        // Area is kept, and the orientation of every piece (+z).
        let mut area = 0.0;
        for v in mesh.triangle_indices.chunks_exact(3) {
            let [p0, p1, p2] = [v[0], v[1], v[2]].map(|i| mesh.positions[i as usize]);
            let n = (p1 - p0).cross(p2 - p0);
            assert!(n.z > 0.0);
            area += 0.5 * n.length();
        }
        assert!((area - 0.5).abs() < 1e-6);
    }

    #[test]
    fn midpoints_interpolate_uv_and_normals() {
        let original = right_triangle();
        let mut mesh = original.clone();
        refine(&mut mesh, 0.3, &Transform::IDENTITY, 1000).unwrap();
        // (u,v) was (x,y) at the corners: it stays so everywhere.
        for (p, uv) in mesh.positions.iter().zip(&mesh.uvs) {
            assert!((p.truncate() - *uv).length() < 1e-6, "{p} {uv}");
        }
        // The first cut is the hypotenuse, its midpoint vertex 3: the
        // normalised sum of the two end normals.
        assert_eq!(mesh.positions[3], Vec3::new(0.5, 0.5, 0.0));
        let expected = (original.normals[1] + original.normals[2]).normalize();
        assert!((mesh.normals[3] - expected).length() < 1e-6);
        assert!(mesh.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
    }

    /// A unit square as two triangles sharing the diagonal: the cut
    /// pieces share their vertices along it, so every edge inside the
    /// square has two triangles and those used once make up the
    /// square's outline (a crack would add edges used once inside).
    #[test]
    fn triangles_sharing_an_edge_share_its_midpoints() {
        let mut mesh = RefinableMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            triangle_indices: vec![0, 1, 2, 0, 2, 3],
            ..Default::default()
        };
        refine(&mut mesh, 0.2, &Transform::IDENTITY, 10_000).unwrap();
        assert!(longest_edge(&mesh) < 0.2);
        let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
        for (a, b) in edges(&mesh) {
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
        assert!(uses.values().all(|&n| n <= 2));
        let outline: f32 = uses
            .iter()
            .filter(|(_, &n)| n == 1)
            .map(|(&(a, b), _)| (mesh.positions[a as usize] - mesh.positions[b as usize]).length())
            .sum();
        assert!((outline - 4.0).abs() < 1e-5, "{outline}");
        // The diagonal's midpoint is one vertex, in both halves.
        let centre: Vec<usize> = mesh
            .positions
            .iter()
            .enumerate()
            .filter(|(_, p)| (**p - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-7)
            .map(|(i, _)| i)
            .collect();
        assert_eq!(centre.len(), 1);
        let halves = mesh
            .triangle_indices
            .chunks_exact(3)
            .filter(|v| v.contains(&(centre[0] as u32)))
            .map(|v| {
                let centroid: Vec3 =
                    v.iter().map(|&i| mesh.positions[i as usize]).sum::<Vec3>() / 3.0;
                centroid.x > centroid.y
            })
            .collect::<HashSet<bool>>();
        assert_eq!(halves.len(), 2);
        // The same mesh every time.
        let mut again = RefinableMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            triangle_indices: vec![0, 1, 2, 0, 2, 3],
            ..Default::default()
        };
        refine(&mut again, 0.2, &Transform::IDENTITY, 10_000).unwrap();
        assert_eq!(again, mesh);
    }

    /// Lengths are measured after the transform: scaled up 4 times, the
    /// same triangle is cut as the original would be at a quarter of the
    /// length.
    #[test]
    fn lengths_are_measured_in_render_space() {
        let scale = Transform::scale(DVec3::splat(4.0)).unwrap();
        let mut scaled = right_triangle();
        refine(&mut scaled, 0.3, &scale, 100_000).unwrap();
        let mut quarter = right_triangle();
        refine(&mut quarter, 0.3 / 4.0, &Transform::IDENTITY, 100_000).unwrap();
        assert_eq!(
            scaled.triangle_indices.len(),
            quarter.triangle_indices.len()
        );
        assert_eq!(scaled.triangle_indices.len() / 3, 512);
        // The positions stay in object space.
        assert!(longest_edge(&scaled) < 0.3 / 4.0);
        let mut plain = right_triangle();
        refine(&mut plain, 0.3, &Transform::IDENTITY, 100_000).unwrap();
        assert!(plain.triangle_indices.len() < scaled.triangle_indices.len());
    }

    #[test]
    fn too_many_triangles_are_refused_early_or_on_the_way() {
        // The area alone needs ~10¹² triangles.
        let e = refine(&mut right_triangle(), 1e-6, &Transform::IDENTITY, 1000).unwrap_err();
        assert!(e.at_least.is_some_and(|n| n > 1e11), "{e}");
        assert!(e.to_string().contains("more than 1000 triangles"), "{e}");
        // A sliver of no area passes the estimate and is stopped by the
        // count.
        let mut sliver = RefinableMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0)],
            triangle_indices: vec![0, 1, 2],
            ..Default::default()
        };
        let e = refine(&mut sliver, 1e-4, &Transform::IDENTITY, 1000).unwrap_err();
        assert_eq!(e.at_least, None);
    }

    #[test]
    fn edges_of_infinite_or_nan_length_are_left_alone() {
        let mut mesh = RefinableMesh {
            positions: vec![
                Vec3::ZERO,
                Vec3::new(f32::INFINITY, 0.0, 0.0),
                Vec3::new(0.0, f32::NAN, 0.0),
            ],
            triangle_indices: vec![0, 1, 2],
            ..Default::default()
        };
        refine(&mut mesh, 0.5, &Transform::IDENTITY, 100).unwrap();
        assert_eq!(mesh.triangle_indices, vec![0, 1, 2]);
    }
}
