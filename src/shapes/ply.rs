//! Reading `plymesh` files (pbrt-v4's `TriQuadMesh::ReadPLY`).
//!
//! | parameter      | type          | default | meaning                                   |
//! |----------------|---------------|---------|-------------------------------------------|
//! | `filename`     | string        | required| `.ply` or gzip-compressed `.ply.gz` file, relative to the scene file's directory |
//! | `displacement` | float texture | none    | moves each vertex along its normal by the texture's value (`super::displacement`) |
//! | `edgelength`   | float         | 1       | with `displacement`: edges are cut until shorter than this times the displacement edge scale (measured after the shape's transform: in render space, or a moving shape's own space, as pbrt-v4); must then be positive |
//!
//! ASCII and binary (either byte order) files are read. From the `vertex`
//! element: `x y z` (required), `nx ny nz`, and texture coordinates under
//! the first complete pair of `u v`, `s t`, `texture_u texture_v`,
//! `texture_s texture_t`; any numeric type. From the `face` element:
//! `vertex_indices` (also accepted: `vertex_index`) and `face_indices`.
//! Triangles become a triangle mesh; quads become bilinear patches, their
//! vertices 0 1 3 2 taken as p00 p10 p01 p11 (as pbrt-v4 does). Faces with
//! other vertex counts are skipped (pbrt warns about them). `face_indices`
//! are split between the two meshes in face order (pbrt-v4 hands the whole
//! list to both, which only works when all faces are of one kind).
//!
//! Elements are parsed straight into small typed structs (no per-element
//! maps), so large meshes read quickly.
//!
//! With `displacement` the file must have (u,v); its quads become two
//! triangles each and the mesh one triangle mesh, refined and displaced
//! at build time ([`super::displacement`]). The refinement stops with an
//! error past [`super::displacement::MAX_DISPLACED_TRIANGLES`] (50
//! million) triangles, where pbrt-v4 has no bound. The displacement edge
//! scale is `Option "displacementedgescale"` or `--displacement-edge-scale`
//! (default 1).

use super::mesh::{BilinearPatchMesh, MeshData, TriangleMesh};
use crate::error::{scene_error, unreadable_file, Error, Result};
use crate::math::Transform;
use glam::{Vec2, Vec3};
use pbrt_parser::Location;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{PropertyAccess, PropertyAccessResult};
use std::io::{BufRead, BufReader};
use std::path::Path;

/// The contents of a PLY file, in object space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyMesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex normals, or empty.
    pub normals: Vec<Vec3>,
    /// Per-vertex (u,v), or empty.
    pub uvs: Vec<Vec2>,
    /// Three vertex indices per triangle.
    pub triangle_indices: Vec<u32>,
    /// Four vertex indices per quad, in bilinear patch order
    /// (p00 p10 p01 p11 = face vertices 0 1 3 2).
    pub quad_indices: Vec<u32>,
    /// `face_indices` of the triangles and of the quads (empty if absent).
    pub triangle_face_indices: Vec<i32>,
    pub quad_face_indices: Vec<i32>,
    /// Faces with neither 3 nor 4 vertices, which were skipped.
    pub skipped_faces: usize,
}

/// The meshes a PLY file makes.
#[derive(Clone, Debug, PartialEq)]
pub struct PlyMeshes {
    pub triangles: Option<TriangleMesh>,
    pub quads: Option<BilinearPatchMesh>,
}

impl PlyMesh {
    /// The triangle mesh and bilinear patch mesh of the file, in render
    /// space (each keeps all the file's vertices, as in pbrt-v4).
    pub fn into_meshes(
        self,
        render_from_object: &Transform,
        reverse_orientation: bool,
    ) -> PlyMeshes {
        let PlyMesh {
            positions,
            normals,
            uvs,
            triangle_indices,
            quad_indices,
            triangle_face_indices,
            quad_face_indices,
            ..
        } = self;
        let quads = (!quad_indices.is_empty()).then(|| {
            let data = MeshData {
                vertex_indices: quad_indices,
                positions: positions.clone(),
                normals: normals.clone(),
                tangents: Vec::new(),
                uvs: uvs.clone(),
                face_indices: quad_face_indices,
            };
            BilinearPatchMesh::new(render_from_object, reverse_orientation, data)
        });
        let triangles = (!triangle_indices.is_empty()).then(|| {
            let data = MeshData {
                vertex_indices: triangle_indices,
                positions,
                normals,
                tangents: Vec::new(),
                uvs,
                face_indices: triangle_face_indices,
            };
            TriangleMesh::new(render_from_object, reverse_orientation, data)
        });
        PlyMeshes { triangles, quads }
    }
}

/// Reads a `.ply` or `.ply.gz` file. Errors name the file and point at
/// `location` (the `filename` parameter that names it).
pub fn read_ply(path: &Path, location: &Location) -> Result<PlyMesh> {
    let file = std::fs::File::open(path)
        .map_err(|source| unreadable_file("plymesh", path, &source, location))?;
    let gzipped = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    if gzipped {
        read_ply_from(
            BufReader::new(flate2::read::MultiGzDecoder::new(file)),
            path,
            location,
        )
    } else {
        read_ply_from(BufReader::new(file), path, location)
    }
}

/// Reads the bytes of a `.ply` file (or, if `path` ends in `.gz`, of a
/// gzip-compressed one) held in memory, exactly as [`read_ply`] reads a
/// file; `path` only names it in errors and picks the compression. For
/// fuzzing and tests.
pub fn read_ply_bytes(bytes: &[u8], path: &Path, location: &Location) -> Result<PlyMesh> {
    let gzipped = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    if gzipped {
        read_ply_from(
            BufReader::new(flate2::read::MultiGzDecoder::new(bytes)),
            path,
            location,
        )
    } else {
        read_ply_from(bytes, path, location)
    }
}

/// The texture coordinate property names, best first, as (u name, v name).
const UV_NAMES: [(&str, &str); 4] = [
    ("u", "v"),
    ("s", "t"),
    ("texture_u", "texture_v"),
    ("texture_s", "texture_t"),
];

/// A vertex as read: position, normal, and the best-ranked texture
/// coordinates seen (rank = index into [`UV_NAMES`]).
#[derive(Clone, Copy, Debug)]
struct PlyVertex {
    position: [f32; 3],
    normal: [f32; 3],
    uv: [f32; 2],
    uv_rank: [u8; 2],
}

impl PlyVertex {
    fn set(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        match name {
            "x" => self.position[0] = value,
            "y" => self.position[1] = value,
            "z" => self.position[2] = value,
            "nx" => self.normal[0] = value,
            "ny" => self.normal[1] = value,
            "nz" => self.normal[2] = value,
            _ => {
                let found = UV_NAMES.iter().enumerate().find_map(|(rank, (u, v))| {
                    if name == *u {
                        Some((0, rank))
                    } else if name == *v {
                        Some((1, rank))
                    } else {
                        None
                    }
                });
                let Some((axis, rank)) = found else {
                    return PropertyAccessResult::Ignored;
                };
                if (rank as u8) < self.uv_rank[axis] {
                    self.uv[axis] = value;
                    self.uv_rank[axis] = rank as u8;
                }
            }
        }
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        PlyVertex {
            position: [0.0; 3],
            normal: [0.0; 3],
            uv: [0.0; 2],
            uv_rank: [u8::MAX; 2],
        }
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set(name, value)
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        self.set(name, value as f32)
    }
    fn set_char(&mut self, name: &str, value: i8) -> PropertyAccessResult {
        self.set(name, value as f32)
    }
    fn set_uchar(&mut self, name: &str, value: u8) -> PropertyAccessResult {
        self.set(name, value as f32)
    }
    fn set_short(&mut self, name: &str, value: i16) -> PropertyAccessResult {
        self.set(name, value as f32)
    }
    fn set_ushort(&mut self, name: &str, value: u16) -> PropertyAccessResult {
        self.set(name, value as f32)
    }
    fn set_int(&mut self, name: &str, value: i32) -> PropertyAccessResult {
        self.set(name, value as f32)
    }
    fn set_uint(&mut self, name: &str, value: u32) -> PropertyAccessResult {
        self.set(name, value as f32)
    }
}

/// A face as read: up to four vertex indices (i64, so that negative and
/// huge values can be reported), the vertex count, and the face index.
#[derive(Clone, Copy, Debug)]
struct PlyFace {
    vertices: [i64; 4],
    count: usize,
    face_index: i32,
}

fn is_vertex_index_list(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

impl PlyFace {
    fn set_indices(
        &mut self,
        name: &str,
        values: impl ExactSizeIterator<Item = i64>,
    ) -> PropertyAccessResult {
        if !is_vertex_index_list(name) {
            return PropertyAccessResult::Ignored;
        }
        self.count = values.len();
        for (slot, value) in self.vertices.iter_mut().zip(values) {
            *slot = value;
        }
        PropertyAccessResult::Set
    }

    fn set_face_index(&mut self, name: &str, value: i64) -> PropertyAccessResult {
        if name != "face_indices" {
            return PropertyAccessResult::Ignored;
        }
        self.face_index = value as i32;
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        PlyFace {
            vertices: [0; 4],
            count: 0,
            face_index: 0,
        }
    }
    fn set_list_char(&mut self, name: &str, value: Vec<i8>) -> PropertyAccessResult {
        self.set_indices(name, value.into_iter().map(i64::from))
    }
    fn set_list_uchar(&mut self, name: &str, value: Vec<u8>) -> PropertyAccessResult {
        self.set_indices(name, value.into_iter().map(i64::from))
    }
    fn set_list_short(&mut self, name: &str, value: Vec<i16>) -> PropertyAccessResult {
        self.set_indices(name, value.into_iter().map(i64::from))
    }
    fn set_list_ushort(&mut self, name: &str, value: Vec<u16>) -> PropertyAccessResult {
        self.set_indices(name, value.into_iter().map(i64::from))
    }
    fn set_list_int(&mut self, name: &str, value: Vec<i32>) -> PropertyAccessResult {
        self.set_indices(name, value.into_iter().map(i64::from))
    }
    fn set_list_uint(&mut self, name: &str, value: Vec<u32>) -> PropertyAccessResult {
        self.set_indices(name, value.into_iter().map(i64::from))
    }
    fn set_char(&mut self, name: &str, value: i8) -> PropertyAccessResult {
        self.set_face_index(name, value as i64)
    }
    fn set_uchar(&mut self, name: &str, value: u8) -> PropertyAccessResult {
        self.set_face_index(name, value as i64)
    }
    fn set_short(&mut self, name: &str, value: i16) -> PropertyAccessResult {
        self.set_face_index(name, value as i64)
    }
    fn set_ushort(&mut self, name: &str, value: u16) -> PropertyAccessResult {
        self.set_face_index(name, value as i64)
    }
    fn set_int(&mut self, name: &str, value: i32) -> PropertyAccessResult {
        self.set_face_index(name, value as i64)
    }
    fn set_uint(&mut self, name: &str, value: u32) -> PropertyAccessResult {
        self.set_face_index(name, value as i64)
    }
}

/// Any other element: read and dropped.
struct IgnoredElement;

impl PropertyAccess for IgnoredElement {
    fn new() -> Self {
        IgnoredElement
    }
}

fn read_ply_from<R: BufRead>(source: R, path: &Path, location: &Location) -> Result<PlyMesh> {
    let name = path.display();
    let parse_error = |e: ply_rs_bw::parser::ParseError| -> Error {
        crate::error::SceneError::new(
            format!("{name}: unable to read the PLY file: {e}"),
            location,
        )
        .into()
    };
    let mut reader = Reader::new(source);
    let vertex_parser = Parser::<PlyVertex>::new();
    let face_parser = Parser::<PlyFace>::new();
    let ignored_parser = Parser::<IgnoredElement>::new();
    let header = vertex_parser
        .read_header(&mut reader)
        .map_err(parse_error)?;

    let Some(vertex_element) = header.elements.get("vertex") else {
        return scene_error(
            format!("{name}: PLY file is invalid: no \"vertex\" element"),
            location,
        );
    };
    let Some(face_element) = header.elements.get("face") else {
        return scene_error(
            format!("{name}: PLY file is invalid: no \"face\" element"),
            location,
        );
    };
    if vertex_element.count == 0 || face_element.count == 0 {
        return scene_error(
            format!("{name}: PLY file is invalid: no vertices or no faces"),
            location,
        );
    }
    let has = |property: &str| vertex_element.properties.contains_key(property);
    if !(has("x") && has("y") && has("z")) {
        return scene_error(
            format!("{name}: vertex coordinate property (x, y, z) not found"),
            location,
        );
    }
    let has_normals = has("nx") && has("ny") && has("nz");
    let has_uvs = UV_NAMES.iter().any(|(u, v)| has(u) && has(v));
    if !face_element
        .properties
        .keys()
        .any(|k| is_vertex_index_list(k))
    {
        return scene_error(
            format!("{name}: vertex indices not found in the PLY file"),
            location,
        );
    }
    let has_face_indices = face_element.properties.contains_key("face_indices");

    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for element in header.elements.values() {
        match element.name.as_str() {
            "vertex" => {
                vertices = vertex_parser
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(parse_error)?
            }
            "face" => {
                faces = face_parser
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(parse_error)?
            }
            _ => {
                ignored_parser
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(parse_error)?;
            }
        }
    }

    let mut mesh = PlyMesh {
        positions: vertices.iter().map(|v| Vec3::from(v.position)).collect(),
        normals: if has_normals {
            vertices.iter().map(|v| Vec3::from(v.normal)).collect()
        } else {
            Vec::new()
        },
        uvs: if has_uvs {
            vertices.iter().map(|v| Vec2::from(v.uv)).collect()
        } else {
            Vec::new()
        },
        ..PlyMesh::default()
    };
    let vertex_count = mesh.positions.len() as i64;
    for face in &faces {
        let indices = &face.vertices[..face.count.min(4)];
        if let Some(&bad) = indices.iter().find(|&&i| i < 0 || i >= vertex_count) {
            return scene_error(
                format!("{name}: vertex index {bad} is out of bounds (valid range is [0..{vertex_count}))"),
                location,
            );
        }
        let v = face.vertices.map(|i| i as u32);
        match face.count {
            3 => {
                mesh.triangle_indices.extend([v[0], v[1], v[2]]);
                if has_face_indices {
                    mesh.triangle_face_indices.push(face.face_index);
                }
            }
            4 => {
                mesh.quad_indices.extend([v[0], v[1], v[3], v[2]]);
                if has_face_indices {
                    mesh.quad_face_indices.push(face.face_index);
                }
            }
            _ => mesh.skipped_faces += 1,
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;
    use std::path::PathBuf;

    /// A fresh directory for one test's files.
    fn temporary_directory(test: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("rpbrt-ply-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    const HEADER_VERTEX: &str =
        "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n\
property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n";

    /// Vertices: a unit square at z = 0 and an apex; faces: the square as a
    /// quad, two triangles to the apex, and a skipped pentagon.
    const VERTICES: [[f32; 8]; 5] = [
        [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0],
        [1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        [0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0],
        [0.5, 0.5, 1.0, 0.0, 1.0, 0.0, 0.5, 0.5],
    ];
    const FACES: [&[i32]; 4] = [&[0, 1, 2, 3], &[0, 1, 4], &[1, 2, 4], &[0, 1, 2, 3, 4]];

    fn ascii_ply() -> String {
        let mut text = String::from("ply\nformat ascii 1.0\ncomment made by a test\n");
        text += HEADER_VERTEX;
        text +=
            "element face 4\nproperty list uchar int vertex_indices\nproperty int face_indices\n";
        text += "element material 1\nproperty float shininess\nend_header\n";
        for v in VERTICES {
            let line: Vec<String> = v.iter().map(|x| x.to_string()).collect();
            text += &(line.join(" ") + "\n");
        }
        for (i, f) in FACES.iter().enumerate() {
            let indices: Vec<String> = f.iter().map(|x| x.to_string()).collect();
            text += &format!("{} {} {}\n", f.len(), indices.join(" "), 10 + i);
        }
        text += "0.5\n";
        text
    }

    fn binary_ply(little_endian: bool) -> Vec<u8> {
        let format = if little_endian {
            "binary_little_endian"
        } else {
            "binary_big_endian"
        };
        let mut bytes = format!("ply\nformat {format} 1.0\n").into_bytes();
        bytes.extend(HEADER_VERTEX.as_bytes());
        bytes.extend(b"element face 4\nproperty list uchar uint vertex_indices\nproperty int face_indices\nend_header\n");
        let f32_bytes = |x: f32| {
            if little_endian {
                x.to_le_bytes()
            } else {
                x.to_be_bytes()
            }
        };
        let i32_bytes = |x: i32| {
            if little_endian {
                x.to_le_bytes()
            } else {
                x.to_be_bytes()
            }
        };
        for v in VERTICES {
            for x in v {
                bytes.extend(f32_bytes(x));
            }
        }
        for (i, f) in FACES.iter().enumerate() {
            bytes.push(f.len() as u8);
            for &x in f.iter() {
                bytes.extend(i32_bytes(x));
            }
            bytes.extend(i32_bytes(10 + i as i32));
        }
        bytes
    }

    fn check(mesh: &PlyMesh) {
        assert_eq!(mesh.positions.len(), 5);
        assert_eq!(mesh.positions[4], Vec3::new(0.5, 0.5, 1.0));
        assert_eq!(mesh.normals[4], Vec3::Y);
        assert_eq!(mesh.uvs[2], Vec2::ONE);
        assert_eq!(mesh.triangle_indices, vec![0, 1, 4, 1, 2, 4]);
        assert_eq!(mesh.quad_indices, vec![0, 1, 3, 2]);
        assert_eq!(mesh.triangle_face_indices, vec![11, 12]);
        assert_eq!(mesh.quad_face_indices, vec![10]);
        assert_eq!(mesh.skipped_faces, 1);
    }

    fn location() -> Location {
        Location::nowhere()
    }

    #[test]
    fn ascii_binary_and_gzipped_files_read_the_same() {
        let dir = temporary_directory("formats");
        let ascii = dir.join("mesh.ply");
        std::fs::write(&ascii, ascii_ply()).unwrap();
        check(&read_ply(&ascii, &location()).unwrap());
        for little_endian in [true, false] {
            let binary = dir.join(format!("binary-{little_endian}.ply"));
            std::fs::write(&binary, binary_ply(little_endian)).unwrap();
            check(&read_ply(&binary, &location()).unwrap());
        }
        let gz = dir.join("mesh.ply.gz");
        let mut encoder = flate2::write::GzEncoder::new(
            std::fs::File::create(&gz).unwrap(),
            flate2::Compression::fast(),
        );
        encoder.write_all(&binary_ply(true)).unwrap();
        encoder.finish().unwrap();
        check(&read_ply(&gz, &location()).unwrap());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn quads_become_bilinear_patches_that_cover_the_quad() {
        let dir = temporary_directory("quads");
        let path = dir.join("mesh.ply");
        std::fs::write(&path, ascii_ply()).unwrap();
        let meshes = read_ply(&path, &location())
            .unwrap()
            .into_meshes(&Transform::IDENTITY, false);
        let quads = meshes.quads.unwrap();
        let patch = crate::shapes::BilinearPatch::new(0, 0);
        assert!(patch.is_rectangle(&quads));
        assert_eq!(patch.area(&quads), 1.0);
        let ray = crate::math::Ray::new(Vec3::new(0.25, 0.75, 2.0), -Vec3::Z, 0.0);
        let si = patch
            .intersect(&quads, &ray, f32::INFINITY)
            .unwrap()
            .interaction;
        assert!((si.uv - Vec2::new(0.25, 0.75)).length() < 1e-6, "{}", si.uv);
        assert_eq!(si.n, Vec3::Z);
        assert_eq!(patch.face_index(&quads), 10);
        let triangles = meshes.triangles.unwrap();
        assert_eq!(triangles.triangle_count(), 2);
        assert_eq!(
            crate::shapes::Triangle::new(0, 1).face_index(&triangles),
            12
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn broken_files_are_reported() {
        let dir = temporary_directory("broken");
        let missing = read_ply(&dir.join("nope.ply"), &location())
            .unwrap_err()
            .to_string();
        assert!(missing.contains("nope.ply"), "{missing}");
        let out_of_range = ascii_ply().replace("3 1 2 4 12", "3 1 2 9 12");
        std::fs::write(dir.join("range.ply"), out_of_range).unwrap();
        let e = read_ply(&dir.join("range.ply"), &location())
            .unwrap_err()
            .to_string();
        assert!(e.contains("vertex index 9 is out of bounds"), "{e}");
        std::fs::write(dir.join("truncated.ply"), &binary_ply(true)[..300]).unwrap();
        let e = read_ply(&dir.join("truncated.ply"), &location())
            .unwrap_err()
            .to_string();
        assert!(e.contains("truncated.ply: unable to read"), "{e}");
        let no_faces = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
        std::fs::write(dir.join("nofaces.ply"), no_faces).unwrap();
        let e = read_ply(&dir.join("nofaces.ply"), &location())
            .unwrap_err()
            .to_string();
        assert!(e.contains("no \"face\" element"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
