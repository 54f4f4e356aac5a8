//! Loop subdivision surfaces (`Shape "loopsubdiv"`), as pbrt-v4 makes
//! them: a triangle mesh refined `levels` times by Loop's rules, its
//! vertices then pushed to their limit positions, with the limit surface's
//! normals as shading normals. The result is an ordinary triangle mesh.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `levels` | integer | 3 | subdivision steps (each makes 4 triangles of one) |
//! | `indices` | integer[] | — (required) | three vertex indices per triangle |
//! | `P` | point3[] | — (required) | control points |
//! | `scheme` | string | `loop` | read and ignored, as pbrt-v4 |
//!
//! Each step keeps the old vertices ("even", moved by the one-ring rule:
//! (1 − nβ) p + β Σ ring, β = 1/16 at a regular interior vertex of valence
//! 6, 3/16 at valence 3, 3/(8n) otherwise; on a boundary ¾ p + ⅛ (the two
//! boundary neighbours)) and adds one "odd" vertex per edge (⅜ the edge's
//! ends + ⅛ the two opposite vertices, or the midpoint of a boundary edge).
//! The limit position of an interior vertex is the one-ring average with
//! weight γ = 1/(n + 3/(8β)); of a boundary vertex ⅗ p + ⅕ each boundary
//! neighbour. The limit normal is the cross product of two tangents made
//! from the one ring (cos- and sin-weighted sums inside, pbrt-v4's
//! boundary stencils on the boundary). As in pbrt-v4 the ring runs
//! clockwise seen from the side where the triangles' vertices run
//! counter-clockwise, so the normals point to the other side (the side a
//! triangle mesh's geometric normal does not); the triangles' geometric
//! normals follow them.
//!
//! The mesh must be a manifold with consistently oriented triangles (each
//! edge in at most two triangles, in opposite directions) and use every
//! vertex; pbrt-v4 assumes this without checking, here it is an error.
//! A vertex where two fans of triangles meet at a point is subdivided, as
//! in pbrt-v4, with only the fan of the last triangle that uses it.

use super::mesh::{MeshData, TriangleMesh};
use crate::error::{scene_error, Result};
use crate::math::Transform;
use crate::scene_description::ParamSet;
use glam::Vec3;
use pbrt_parser::{Location, ParamType};
use std::collections::HashMap;
use std::f32::consts::PI;

/// No face: across a boundary edge.
const NONE: u32 = u32::MAX;

/// The most triangles a subdivision may make (memory, not principle).
const MAX_TRIANGLES: u64 = 1 << 27;

#[inline]
fn next(i: usize) -> usize {
    (i + 1) % 3
}

#[inline]
fn prev(i: usize) -> usize {
    (i + 2) % 3
}

#[derive(Clone, Copy, Debug)]
struct Face {
    /// Vertices, counter-clockwise.
    v: [u32; 3],
    /// `f[k]`: the face across edge (v[k], v[k + 1]), or [`NONE`].
    f: [u32; 3],
}

#[derive(Clone, Copy, Debug)]
struct Vertex {
    p: Vec3,
    /// A face that uses the vertex: where walks around it start.
    start_face: u32,
    boundary: bool,
    /// Valence 6 inside, 4 on a boundary.
    regular: bool,
}

struct Mesh {
    vertices: Vec<Vertex>,
    faces: Vec<Face>,
}

/// The key of the edge between two vertices, either way round.
fn edge_key(a: u32, b: u32) -> u64 {
    (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
}

fn beta(valence: usize) -> f32 {
    if valence == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * valence as f32)
    }
}

fn loop_gamma(valence: usize) -> f32 {
    1.0 / (valence as f32 + 3.0 / (8.0 * beta(valence)))
}

impl Mesh {
    /// Where `vertex` is in `face` (which uses it).
    fn vnum(&self, face: u32, vertex: u32) -> usize {
        let v = self.faces[face as usize].v;
        debug_assert!(v.contains(&vertex));
        if v[0] == vertex {
            0
        } else if v[1] == vertex {
            1
        } else {
            2
        }
    }

    /// The face after `face` counter-clockwise around `vertex`.
    fn next_face(&self, face: u32, vertex: u32) -> u32 {
        self.faces[face as usize].f[self.vnum(face, vertex)]
    }

    fn prev_face(&self, face: u32, vertex: u32) -> u32 {
        self.faces[face as usize].f[prev(self.vnum(face, vertex))]
    }

    fn next_vert(&self, face: u32, vertex: u32) -> u32 {
        self.faces[face as usize].v[next(self.vnum(face, vertex))]
    }

    fn prev_vert(&self, face: u32, vertex: u32) -> u32 {
        self.faces[face as usize].v[prev(self.vnum(face, vertex))]
    }

    /// The number of neighbours of `vertex`.
    fn valence(&self, vertex: u32) -> usize {
        let start = self.vertices[vertex as usize].start_face;
        let mut count = 1;
        let mut face = start;
        if !self.vertices[vertex as usize].boundary {
            loop {
                face = self.next_face(face, vertex);
                if face == start || face == NONE {
                    return count;
                }
                count += 1;
            }
        }
        loop {
            face = self.next_face(face, vertex);
            if face == NONE {
                break;
            }
            count += 1;
        }
        face = start;
        loop {
            face = self.prev_face(face, vertex);
            if face == NONE {
                break;
            }
            count += 1;
        }
        count + 1
    }

    /// The positions of `vertex`'s neighbours in order (a boundary
    /// vertex's from one boundary neighbour to the other).
    fn one_ring(&self, vertex: u32, ring: &mut Vec<Vec3>) {
        ring.clear();
        let p = |v: u32| self.vertices[v as usize].p;
        let start = self.vertices[vertex as usize].start_face;
        if !self.vertices[vertex as usize].boundary {
            let mut face = start;
            loop {
                ring.push(p(self.next_vert(face, vertex)));
                face = self.next_face(face, vertex);
                if face == start || face == NONE {
                    return;
                }
            }
        }
        let mut face = start;
        loop {
            let f2 = self.next_face(face, vertex);
            if f2 == NONE {
                break;
            }
            face = f2;
        }
        ring.push(p(self.next_vert(face, vertex)));
        while face != NONE {
            ring.push(p(self.prev_vert(face, vertex)));
            face = self.prev_face(face, vertex);
        }
    }

    /// (1 − nβ) p + β Σ ring.
    fn weight_one_ring(&self, vertex: u32, beta: f32, ring: &mut Vec<Vec3>) -> Vec3 {
        self.one_ring(vertex, ring);
        let mut p = (1.0 - ring.len() as f32 * beta) * self.vertices[vertex as usize].p;
        for &q in ring.iter() {
            p += beta * q;
        }
        p
    }

    /// (1 − 2β) p + β (first + last boundary neighbour).
    fn weight_boundary(&self, vertex: u32, beta: f32, ring: &mut Vec<Vec3>) -> Vec3 {
        self.one_ring(vertex, ring);
        let mut p = (1.0 - 2.0 * beta) * self.vertices[vertex as usize].p;
        p += beta * ring[0];
        p += beta * ring[ring.len() - 1];
        p
    }

    /// The control mesh, its topology checked.
    fn new(indices: &[u32], positions: &[Vec3]) -> std::result::Result<Mesh, String> {
        let mut vertices: Vec<Vertex> = positions
            .iter()
            .map(|&p| Vertex {
                p,
                start_face: NONE,
                boundary: false,
                regular: false,
            })
            .collect();
        let mut faces = Vec::with_capacity(indices.len() / 3);
        for (i, t) in indices.chunks_exact(3).enumerate() {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(format!(
                    "triangle {i} ({} {} {}) uses a vertex twice",
                    t[0], t[1], t[2]
                ));
            }
            for &v in t {
                // pbrt-v4 keeps the last face that uses the vertex.
                vertices[v as usize].start_face = i as u32;
            }
            faces.push(Face {
                v: [t[0], t[1], t[2]],
                f: [NONE; 3],
            });
        }
        if let Some(v) = vertices.iter().position(|v| v.start_face == NONE) {
            return Err(format!("vertex {v} is used by no triangle"));
        }
        // Each directed edge (a → b) once: its face.
        let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
        for (i, face) in faces.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (face.v[k], face.v[next(k)]);
                if edges.insert((a, b), i as u32).is_some() {
                    return Err(format!(
                        "the edge from vertex {a} to {b} is in two triangles the same way round (the triangles are not consistently oriented, or the mesh is not a manifold)"
                    ));
                }
            }
        }
        for face in &mut faces {
            for k in 0..3 {
                if let Some(&other) = edges.get(&(face.v[next(k)], face.v[k])) {
                    face.f[k] = other;
                }
            }
        }
        let mut mesh = Mesh { vertices, faces };
        for v in 0..mesh.vertices.len() as u32 {
            let start = mesh.vertices[v as usize].start_face;
            let mut face = start;
            loop {
                face = mesh.next_face(face, v);
                if face == NONE || face == start {
                    break;
                }
            }
            let boundary = face == NONE;
            mesh.vertices[v as usize].boundary = boundary;
            let valence = mesh.valence(v);
            mesh.vertices[v as usize].regular =
                (!boundary && valence == 6) || (boundary && valence == 4);
        }
        Ok(mesh)
    }

    /// One step of Loop subdivision: face i's children are 4i .. 4i + 3
    /// (child k < 3 at corner k, child 3 in the middle); vertex i's child
    /// is vertex i, the edge vertices follow in the order the faces meet
    /// them.
    fn refine(&self) -> Mesh {
        let mut ring = Vec::with_capacity(16);
        let mut vertices: Vec<Vertex> = Vec::with_capacity(4 * self.vertices.len());
        for (i, vertex) in self.vertices.iter().enumerate() {
            let i = i as u32;
            let p = if vertex.boundary {
                self.weight_boundary(i, 1.0 / 8.0, &mut ring)
            } else if vertex.regular {
                self.weight_one_ring(i, 1.0 / 16.0, &mut ring)
            } else {
                self.weight_one_ring(i, beta(self.valence(i)), &mut ring)
            };
            vertices.push(Vertex {
                p,
                start_face: 4 * vertex.start_face + self.vnum(vertex.start_face, i) as u32,
                boundary: vertex.boundary,
                regular: vertex.regular,
            });
        }
        let p = |v: u32| self.vertices[v as usize].p;
        let mut edge_vertices: HashMap<u64, u32> = HashMap::new();
        for (fi, face) in self.faces.iter().enumerate() {
            for k in 0..3 {
                let key = edge_key(face.v[k], face.v[next(k)]);
                if edge_vertices.contains_key(&key) {
                    continue;
                }
                let (a, b) = (
                    face.v[k].min(face.v[next(k)]),
                    face.v[k].max(face.v[next(k)]),
                );
                let boundary = face.f[k] == NONE;
                let position = if boundary {
                    0.5 * p(a) + 0.5 * p(b)
                } else {
                    let opposite = face.v[prev(k)];
                    let neighbour = self.faces[face.f[k] as usize].v;
                    let far = neighbour
                        .into_iter()
                        .find(|&v| v != a && v != b)
                        .unwrap_or(opposite);
                    3.0 / 8.0 * p(a)
                        + 3.0 / 8.0 * p(b)
                        + 1.0 / 8.0 * p(opposite)
                        + 1.0 / 8.0 * p(far)
                };
                edge_vertices.insert(key, vertices.len() as u32);
                vertices.push(Vertex {
                    p: position,
                    start_face: 4 * fi as u32 + 3,
                    boundary,
                    regular: true,
                });
            }
        }
        let mut faces = Vec::with_capacity(4 * self.faces.len());
        for face in &self.faces {
            let edge = |j: usize| edge_vertices[&edge_key(face.v[j], face.v[next(j)])];
            // The neighbour's child at the corner of vertex v.
            let child_across = |f2: u32, v: u32| {
                if f2 == NONE {
                    NONE
                } else {
                    4 * f2 + self.vnum(f2, v) as u32
                }
            };
            let first = faces.len() as u32;
            let mut children = [Face {
                v: [NONE; 3],
                f: [NONE; 3],
            }; 4];
            for j in 0..3 {
                children[3].f[j] = first + next(j) as u32;
                children[j].f[next(j)] = first + 3;
                children[j].f[j] = child_across(face.f[j], face.v[j]);
                children[j].f[prev(j)] = child_across(face.f[prev(j)], face.v[j]);
                children[j].v[j] = face.v[j];
                let odd = edge(j);
                children[j].v[next(j)] = odd;
                children[next(j)].v[j] = odd;
                children[3].v[j] = odd;
            }
            faces.extend(children);
        }
        Mesh { vertices, faces }
    }

    /// The limit positions and normals of the vertices.
    fn limit(mut self) -> (Vec<Vec3>, Vec<Vec3>, Vec<u32>) {
        let mut ring = Vec::with_capacity(16);
        let positions: Vec<Vec3> = (0..self.vertices.len() as u32)
            .map(|v| {
                if self.vertices[v as usize].boundary {
                    self.weight_boundary(v, 1.0 / 5.0, &mut ring)
                } else {
                    self.weight_one_ring(v, loop_gamma(self.valence(v)), &mut ring)
                }
            })
            .collect();
        for (vertex, &p) in self.vertices.iter_mut().zip(&positions) {
            vertex.p = p;
        }
        let normals = (0..self.vertices.len() as u32)
            .map(|v| {
                self.one_ring(v, &mut ring);
                let (s, t) = self.tangents(v, &ring);
                s.cross(t)
            })
            .collect();
        let indices = self.faces.iter().flat_map(|f| f.v).collect();
        (positions, normals, indices)
    }

    /// Two tangents of the limit surface at `vertex`, from its one ring.
    fn tangents(&self, vertex: u32, ring: &[Vec3]) -> (Vec3, Vec3) {
        let n = ring.len();
        let p = self.vertices[vertex as usize].p;
        if !self.vertices[vertex as usize].boundary {
            let (mut s, mut t) = (Vec3::ZERO, Vec3::ZERO);
            for (j, &q) in ring.iter().enumerate() {
                let angle = 2.0 * PI * j as f32 / n as f32;
                s += angle.cos() * q;
                t += angle.sin() * q;
            }
            return (s, t);
        }
        let s = ring[n - 1] - ring[0];
        let t = match n {
            2 => ring[0] + ring[1] - 2.0 * p,
            3 => ring[1] - p,
            4 => -ring[0] + 2.0 * ring[1] + 2.0 * ring[2] - ring[3] - 2.0 * p,
            _ => {
                let theta = PI / (n - 1) as f32;
                let mut t = theta.sin() * (ring[0] + ring[n - 1]);
                for (k, &q) in ring.iter().enumerate().take(n - 1).skip(1) {
                    let weight = (2.0 * theta.cos() - 2.0) * (k as f32 * theta).sin();
                    t += weight * q;
                }
                -t
            }
        };
        (s, t)
    }
}

/// The limit surface's positions, normals and triangles after `levels`
/// steps of Loop subdivision of the triangles `indices` over `positions`.
pub fn subdivide(
    indices: &[u32],
    positions: &[Vec3],
    levels: u32,
) -> std::result::Result<MeshData, String> {
    let mut mesh = Mesh::new(indices, positions)?;
    for _ in 0..levels {
        mesh = mesh.refine();
    }
    let (positions, normals, vertex_indices) = mesh.limit();
    Ok(MeshData {
        vertex_indices,
        positions,
        normals,
        ..Default::default()
    })
}

/// The mesh a `loopsubdiv` directive describes.
pub fn from_parameters(
    params: &ParamSet,
    location: &Location,
    render_from_object: &Transform,
    reverse_orientation: bool,
) -> Result<TriangleMesh> {
    let levels = params.int("levels", 3)?;
    let indices = params.ints("indices")?;
    let positions: Vec<Vec3> = params
        .point3s("P")?
        .into_iter()
        .map(|p| p.as_vec3())
        .collect();
    params.string("scheme", "loop")?;
    let at = |name: &str, ty: ParamType| {
        params
            .find(name, &[ty])
            .ok()
            .flatten()
            .map_or_else(|| location.clone(), |p| p.location.clone())
    };
    if indices.is_empty() {
        return scene_error(
            "loopsubdiv: vertex indices \"indices\" must be given",
            location,
        );
    }
    if positions.is_empty() {
        return scene_error("loopsubdiv: vertex positions \"P\" must be given", location);
    }
    if indices.len() % 3 != 0 {
        return scene_error(
            format!(
                "loopsubdiv: the number of \"indices\" ({}) is not a multiple of 3",
                indices.len()
            ),
            &at("indices", ParamType::Integer),
        );
    }
    if let Some(&bad) = indices
        .iter()
        .find(|&&i| i < 0 || i as usize >= positions.len())
    {
        return scene_error(
            format!(
                "loopsubdiv: \"indices\" values out of range: {bad} (there are {} \"P\")",
                positions.len()
            ),
            &at("indices", ParamType::Integer),
        );
    }
    // pbrt-v4 subdivides nothing for a negative count.
    let levels = levels.max(0) as u32;
    let triangles = (indices.len() / 3) as u64;
    if levels > 13 || triangles << (2 * levels) > MAX_TRIANGLES {
        return scene_error(
            format!(
                "loopsubdiv: {levels} levels would make {} × 4^{levels} triangles, more than {MAX_TRIANGLES}",
                triangles
            ),
            &at("levels", ParamType::Integer),
        );
    }
    let indices: Vec<u32> = indices.iter().map(|&i| i as u32).collect();
    let data = match subdivide(&indices, &positions, levels) {
        Ok(data) => data,
        Err(message) => {
            return scene_error(
                format!("loopsubdiv: {message}"),
                &at("indices", ParamType::Integer),
            )
        }
    };
    Ok(TriangleMesh::new(
        render_from_object,
        reverse_orientation,
        data,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn octahedron() -> (Vec<u32>, Vec<Vec3>) {
        let p = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        // Counter-clockwise seen from outside.
        let indices = vec![
            0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5,
        ];
        (indices, p)
    }

    fn tetrahedron() -> (Vec<u32>, Vec<Vec3>) {
        let p = vec![
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
        ];
        let indices = vec![0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2];
        (indices, p)
    }

    /// Each undirected edge and how many triangles use it.
    fn edge_uses(indices: &[u32]) -> HashMap<u64, usize> {
        let mut uses = HashMap::new();
        for t in indices.chunks_exact(3) {
            for k in 0..3 {
                *uses.entry(edge_key(t[k], t[next(k)])).or_insert(0) += 1;
            }
        }
        uses
    }

    /// A closed mesh stays closed: 4^levels × the faces, V − E + F = 2,
    /// every edge in exactly two triangles, and the normals point inwards
    /// (the triangles run counter-clockwise seen from outside).
    #[test]
    fn closed_meshes_stay_closed_with_the_expected_counts() {
        for (name, (indices, p)) in [("tetrahedron", tetrahedron()), ("octahedron", octahedron())] {
            let faces = indices.len() / 3;
            for levels in 0..4 {
                let data = subdivide(&indices, &p, levels).unwrap();
                let f = data.vertex_indices.len() / 3;
                assert_eq!(f, faces << (2 * levels), "{name} {levels}");
                let uses = edge_uses(&data.vertex_indices);
                assert!(
                    uses.values().all(|&n| n == 2),
                    "{name} {levels}: an open edge"
                );
                let (v, e) = (data.positions.len(), uses.len());
                assert_eq!(
                    v as i64 - e as i64 + f as i64,
                    2,
                    "{name} {levels}: Euler characteristic"
                );
                // The centroid is at the origin: outward is away from it.
                for (q, n) in data.positions.iter().zip(&data.normals) {
                    assert!(n.dot(*q) < 0.0, "{name} {levels}: normal {n} at {q}");
                }
            }
        }
    }

    /// Limit points are points of one surface whatever the level: a vertex
    /// of level L keeps its index at level L + 1 (children keep their
    /// parent's index), and its limit position is the same. The limit
    /// surface lies inside the control polyhedron, and at the octahedron's
    /// own vertices (valence 4, γ = ⅛) the limit is p/2 with a radial
    /// normal.
    #[test]
    fn limit_points_do_not_depend_on_the_level() {
        for (name, (indices, p)) in [("tetrahedron", tetrahedron()), ("octahedron", octahedron())] {
            let mut previous = subdivide(&indices, &p, 0).unwrap();
            for levels in 1..5 {
                let data = subdivide(&indices, &p, levels).unwrap();
                for (i, (a, b)) in previous.positions.iter().zip(&data.positions).enumerate() {
                    assert!(
                        (*a - *b).length() < 2e-6,
                        "{name} {levels}: vertex {i} {a} vs {b}"
                    );
                }
                previous = data;
            }
        }
        let (indices, p) = octahedron();
        let data = subdivide(&indices, &p, 4).unwrap();
        for q in &data.positions {
            assert!(q.x.abs() + q.y.abs() + q.z.abs() <= 1.0, "{q} outside");
        }
        for ((q, n), control) in data.positions.iter().zip(&data.normals).zip(&p) {
            assert!((*q - *control / 2.0).length() < 1e-6);
            let n = n.normalize();
            assert!(n.dot(-*control) > 1.0 - 1e-6, "{n} at {control}");
        }
    }

    /// A flat grid stays in its plane, with normals across the plane, and
    /// its interior vertices of valence 6 are regular; the boundary stays
    /// open: boundary edges in one triangle.
    #[test]
    fn planar_mesh_stays_planar() {
        // A 4 × 4 grid of quads in z = 0.5, each split into two triangles
        // (valence 6 inside).
        let n = 5;
        let p: Vec<Vec3> = (0..n * n)
            .map(|i| Vec3::new((i % n) as f32, (i / n) as f32, 0.5))
            .collect();
        let mut indices = Vec::new();
        for y in 0..n - 1 {
            for x in 0..n - 1 {
                let i = (y * n + x) as u32;
                let n = n as u32;
                indices.extend([i, i + 1, i + n + 1, i, i + n + 1, i + n]);
            }
        }
        let mesh = Mesh::new(&indices, &p).unwrap();
        let centre = (2 * n + 2) as u32;
        assert!(mesh.vertices[centre as usize].regular && !mesh.vertices[centre as usize].boundary);
        assert!(mesh.vertices[0].boundary);
        let data = subdivide(&indices, &p, 3).unwrap();
        for (q, normal) in data.positions.iter().zip(&data.normals) {
            assert!((q.z - 0.5).abs() < 1e-6, "{q}");
            // Counter-clockwise seen from +z: the normals point to −z.
            let normal = normal.normalize();
            assert!(normal.z < -1.0 + 1e-5, "{normal} at {q}");
        }
        let uses = edge_uses(&data.vertex_indices);
        let boundary_edges = uses.values().filter(|&&u| u == 1).count();
        // 4 sides of 4 edges, each halved three times.
        assert_eq!(boundary_edges, 16 * 8);
        // The centre vertex keeps its place: a regular vertex of a planar
        // grid with symmetric neighbours is a fixed point.
        assert!((data.positions[centre as usize] - p[centre as usize]).length() < 1e-6);
    }

    #[test]
    fn bad_topology_is_reported() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let twice = subdivide(&[0, 1, 2, 0, 1, 3], &p, 1).unwrap_err();
        assert!(twice.contains("the same way round"), "{twice}");
        let unused = subdivide(&[0, 1, 2], &p, 1).unwrap_err();
        assert!(
            unused.contains("vertex 3 is used by no triangle"),
            "{unused}"
        );
        let degenerate = subdivide(&[0, 1, 1, 0, 2, 3], &p, 1).unwrap_err();
        assert!(degenerate.contains("uses a vertex twice"), "{degenerate}");
    }
}
