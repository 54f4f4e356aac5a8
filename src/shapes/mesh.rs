//! Triangle and bilinear-patch meshes, held in render space.
//!
//! As pbrt-v4 does when it creates a mesh: positions are transformed to
//! render space, normals by the inverse transpose (and negated under
//! `ReverseOrientation`), tangents `S` by the matrix; (u,v) and face indices
//! are kept as given. The mesh remembers whether its orientation is
//! reversed and whether its transform swaps handedness: the two decide the
//! side of the geometric normal when there are no per-vertex normals.
//!
//! The parameters of `trianglemesh` and `bilinearmesh` are tabulated in
//! [`super::triangle`] and [`super::bilinear`]; this module reads and
//! checks them.
//!
//! Unlike pbrt-v4, which reports most inconsistencies and then drops the
//! offending data (or the mesh), rpbrt refuses such a scene with an error
//! naming the parameter.

use crate::error::{scene_error, Result};
use crate::math::Transform;
use crate::scene_description::params::ParamSet;
use glam::{DVec3, Vec2, Vec3};
use pbrt_parser::{Location, ParamType};

/// A triangle mesh in render space. Absent optional data are empty vectors.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleMesh {
    /// Three vertex indices per triangle.
    pub vertex_indices: Vec<u32>,
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (not normalised), or empty.
    pub normals: Vec<Vec3>,
    /// Per-vertex shading tangents, or empty.
    pub tangents: Vec<Vec3>,
    /// Per-vertex (u,v), or empty.
    pub uvs: Vec<Vec2>,
    /// Per-triangle face indices, or empty.
    pub face_indices: Vec<i32>,
    pub reverse_orientation: bool,
    pub transform_swaps_handedness: bool,
}

/// A bilinear patch mesh in render space. Absent optional data are empty.
#[derive(Clone, Debug, PartialEq)]
pub struct BilinearPatchMesh {
    /// Four vertex indices per patch: p00, p10, p01, p11.
    pub vertex_indices: Vec<u32>,
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub face_indices: Vec<i32>,
    pub reverse_orientation: bool,
    pub transform_swaps_handedness: bool,
}

/// Object-space vertex data, before it is taken to render space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub vertex_indices: Vec<u32>,
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub tangents: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub face_indices: Vec<i32>,
}

/// Object-space positions, normals and tangents taken to render space.
struct RenderSpaceVertices {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    tangents: Vec<Vec3>,
}

fn to_render_space(
    render_from_object: &Transform,
    reverse_orientation: bool,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    tangents: Vec<Vec3>,
) -> RenderSpaceVertices {
    let matrix = render_from_object.matrix;
    let normal_matrix = render_from_object.inverse.transpose();
    let sign = if reverse_orientation { -1.0 } else { 1.0 };
    RenderSpaceVertices {
        positions: positions
            .into_iter()
            .map(|p| render_from_object.point(p.as_dvec3()).as_vec3())
            .collect(),
        normals: normals
            .into_iter()
            .map(|n| (sign * normal_matrix.transform_vector3(n.as_dvec3())).as_vec3())
            .collect(),
        tangents: tangents
            .into_iter()
            .map(|s| matrix.transform_vector3(s.as_dvec3()).as_vec3())
            .collect(),
    }
}

impl TriangleMesh {
    /// A mesh from object-space data (already validated: indices in range,
    /// optional arrays empty or one per vertex / per triangle).
    pub fn new(render_from_object: &Transform, reverse_orientation: bool, data: MeshData) -> Self {
        let vertices = to_render_space(
            render_from_object,
            reverse_orientation,
            data.positions,
            data.normals,
            data.tangents,
        );
        TriangleMesh {
            vertex_indices: data.vertex_indices,
            positions: vertices.positions,
            normals: vertices.normals,
            tangents: vertices.tangents,
            uvs: data.uvs,
            face_indices: data.face_indices,
            reverse_orientation,
            transform_swaps_handedness: render_from_object.swaps_handedness(),
        }
    }

    /// The mesh a `trianglemesh` directive describes, checked.
    pub fn from_parameters(
        params: &ParamSet,
        location: &Location,
        render_from_object: &Transform,
        reverse_orientation: bool,
    ) -> Result<Self> {
        let data = read_mesh_parameters(params, location, 3, true)?;
        Ok(TriangleMesh::new(
            render_from_object,
            reverse_orientation,
            data,
        ))
    }

    pub fn triangle_count(&self) -> usize {
        self.vertex_indices.len() / 3
    }

    /// The vertex indices of triangle `index`.
    pub fn triangle(&self, index: u32) -> [usize; 3] {
        let first = 3 * index as usize;
        [
            self.vertex_indices[first] as usize,
            self.vertex_indices[first + 1] as usize,
            self.vertex_indices[first + 2] as usize,
        ]
    }
}

impl BilinearPatchMesh {
    /// A mesh from object-space data (validated; `tangents` are ignored).
    pub fn new(render_from_object: &Transform, reverse_orientation: bool, data: MeshData) -> Self {
        let vertices = to_render_space(
            render_from_object,
            reverse_orientation,
            data.positions,
            data.normals,
            Vec::new(),
        );
        BilinearPatchMesh {
            vertex_indices: data.vertex_indices,
            positions: vertices.positions,
            normals: vertices.normals,
            uvs: data.uvs,
            face_indices: data.face_indices,
            reverse_orientation,
            transform_swaps_handedness: render_from_object.swaps_handedness(),
        }
    }

    /// The mesh a `bilinearmesh` directive describes, checked.
    pub fn from_parameters(
        params: &ParamSet,
        location: &Location,
        render_from_object: &Transform,
        reverse_orientation: bool,
    ) -> Result<Self> {
        let data = read_mesh_parameters(params, location, 4, false)?;
        Ok(BilinearPatchMesh::new(
            render_from_object,
            reverse_orientation,
            data,
        ))
    }

    pub fn patch_count(&self) -> usize {
        self.vertex_indices.len() / 4
    }

    /// The vertex indices of patch `index`: p00, p10, p01, p11.
    pub fn patch(&self, index: u32) -> [usize; 4] {
        let first = 4 * index as usize;
        [
            self.vertex_indices[first] as usize,
            self.vertex_indices[first + 1] as usize,
            self.vertex_indices[first + 2] as usize,
            self.vertex_indices[first + 3] as usize,
        ]
    }
}

/// The location of parameter `name` (for errors), or the directive's.
fn parameter_location(
    params: &ParamSet,
    name: &str,
    ty: ParamType,
    fallback: &Location,
) -> Result<Location> {
    Ok(params
        .find(name, &[ty])?
        .map_or_else(|| fallback.clone(), |p| p.location.clone()))
}

fn to_vec3s(values: Vec<DVec3>) -> Vec<Vec3> {
    values.into_iter().map(|v| v.as_vec3()).collect()
}

/// Reads and checks the parameters of a mesh whose faces have
/// `vertices_per_face` vertices.
fn read_mesh_parameters(
    params: &ParamSet,
    location: &Location,
    vertices_per_face: usize,
    has_tangents: bool,
) -> Result<MeshData> {
    let what = if vertices_per_face == 3 {
        "trianglemesh"
    } else {
        "bilinearmesh"
    };
    let faces = if vertices_per_face == 3 {
        "triangles"
    } else {
        "patches"
    };
    let positions = to_vec3s(params.point3s("P")?);
    let indices = params.ints("indices")?;
    let uvs: Vec<Vec2> = params
        .point2s("uv")?
        .into_iter()
        .map(|v| v.as_vec2())
        .collect();
    let normals = to_vec3s(params.normals("N")?);
    let tangents = if has_tangents {
        to_vec3s(params.vector3s("S")?)
    } else {
        Vec::new()
    };
    let face_indices = params.ints("faceIndices")?;

    if positions.is_empty() {
        return scene_error(
            format!("{what}: \"P\" missing: vertex positions must be given"),
            location,
        );
    }
    let indices_location = parameter_location(params, "indices", ParamType::Integer, location)?;
    let vertex_indices: Vec<u32> = if indices.is_empty() {
        if positions.len() != vertices_per_face {
            return scene_error(
                format!(
                    "{what}: \"indices\" missing: vertex indices must be given unless there are exactly {vertices_per_face} \"P\" (there are {})",
                    positions.len()
                ),
                location,
            );
        }
        (0..vertices_per_face as u32).collect()
    } else {
        if indices.len() % vertices_per_face != 0 {
            return scene_error(
                format!(
                    "{what}: the number of \"indices\" ({}) is not a multiple of {vertices_per_face}",
                    indices.len()
                ),
                &indices_location,
            );
        }
        let mut checked = Vec::with_capacity(indices.len());
        for &index in &indices {
            if index < 0 || index as usize >= positions.len() {
                return scene_error(
                    format!(
                        "{what}: \"indices\" values out of range: {index} (there are {} \"P\")",
                        positions.len()
                    ),
                    &indices_location,
                );
            }
            checked.push(index as u32);
        }
        checked
    };
    let count_must_match = |name: &str, ty: ParamType, count: usize| -> Result<()> {
        if count != 0 && count != positions.len() {
            let at = parameter_location(params, name, ty, location)?;
            return scene_error(
                format!(
                    "{what}: \"{name}\" count must match \"P\" count ({count} \"{name}\", {} \"P\")",
                    positions.len()
                ),
                &at,
            );
        }
        Ok(())
    };
    count_must_match("uv", ParamType::Point2, uvs.len())?;
    count_must_match("N", ParamType::Normal3, normals.len())?;
    count_must_match("S", ParamType::Vector3, tangents.len())?;
    let face_count = vertex_indices.len() / vertices_per_face;
    if !face_indices.is_empty() && face_indices.len() != face_count {
        let at = parameter_location(params, "faceIndices", ParamType::Integer, location)?;
        return scene_error(
            format!(
                "{what}: \"faceIndices\" count ({}) must match the number of {faces} ({face_count})",
                face_indices.len()
            ),
            &at,
        );
    }
    Ok(MeshData {
        vertex_indices,
        positions,
        normals,
        tangents,
        uvs,
        face_indices,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use pbrt_parser::{Directive, Parser};

    /// The parameters and location of the first `Shape` in `text`.
    pub fn shape_parameters(text: &str) -> (ParamSet, Location) {
        let d = Parser::from_text("<t>", text).next().unwrap().unwrap();
        let Directive::Shape(e) = d.directive else {
            panic!("not a shape")
        };
        (ParamSet::new(e.params, &[]), d.location)
    }

    fn triangle_mesh(text: &str) -> Result<TriangleMesh> {
        let (params, location) = shape_parameters(text);
        TriangleMesh::from_parameters(&params, &location, &Transform::IDENTITY, false)
    }

    fn error_of(text: &str) -> String {
        triangle_mesh(text).unwrap_err().to_string()
    }

    #[test]
    fn a_single_triangle_needs_no_indices() {
        let mesh = triangle_mesh(r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0]"#).unwrap();
        assert_eq!(mesh.vertex_indices, vec![0, 1, 2]);
        assert_eq!(mesh.triangle_count(), 1);
    }

    #[test]
    fn bad_parameters_are_reported() {
        let e = error_of(r#"Shape "trianglemesh" "integer indices" [0 1 2]"#);
        assert!(e.contains("\"P\" missing"), "{e}");
        let e = error_of(r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0 1 1 0]"#);
        assert!(e.contains("\"indices\" missing"), "{e}");
        let e = error_of(
            r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 3]"#,
        );
        assert!(e.contains("\"indices\" values out of range: 3"), "{e}");
        assert!(e.contains("<t>:1:"), "{e}");
        let e = error_of(
            r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 -1]"#,
        );
        assert!(e.contains("out of range: -1"), "{e}");
        let e = error_of(
            r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2 0]"#,
        );
        assert!(e.contains("not a multiple of 3"), "{e}");
        let e =
            error_of(r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "normal N" [0 0 1]"#);
        assert!(e.contains("\"N\" count must match \"P\" count"), "{e}");
        let e = error_of(
            r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "point2 uv" [0 0 1 1]"#,
        );
        assert!(e.contains("\"uv\" count must match"), "{e}");
        let e =
            error_of(r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "vector3 S" [1 0 0]"#);
        assert!(e.contains("\"S\" count must match"), "{e}");
        let e = error_of(
            r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer faceIndices" [1 2]"#,
        );
        assert!(e.contains("\"faceIndices\" count (2)"), "{e}");
    }

    #[test]
    fn vertices_and_normals_go_to_render_space() {
        let (params, location) = shape_parameters(
            r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "normal N" [1 1 0 1 1 0 1 1 0]"#,
        );
        let t = Transform::translate(DVec3::new(0.0, 0.0, 5.0))
            .then(&Transform::scale(DVec3::new(1.0, 4.0, 1.0)).unwrap());
        let mesh = TriangleMesh::from_parameters(&params, &location, &t, true).unwrap();
        assert_eq!(mesh.positions[1], Vec3::new(1.0, 0.0, 5.0));
        assert_eq!(mesh.positions[2], Vec3::new(0.0, 4.0, 5.0));
        // Inverse transpose, then negated for ReverseOrientation.
        assert_eq!(mesh.normals[0], Vec3::new(-1.0, -0.25, 0.0));
        assert!(mesh.reverse_orientation && !mesh.transform_swaps_handedness);
    }

    #[test]
    fn bilinear_meshes_are_checked_too() {
        let (params, location) =
            shape_parameters(r#"Shape "bilinearmesh" "point3 P" [0 0 0 1 0 0 0 1 0 1 1 0]"#);
        let mesh =
            BilinearPatchMesh::from_parameters(&params, &location, &Transform::IDENTITY, false)
                .unwrap();
        assert_eq!(mesh.vertex_indices, vec![0, 1, 2, 3]);
        let (params, location) = shape_parameters(
            r#"Shape "bilinearmesh" "point3 P" [0 0 0 1 0 0 0 1 0 1 1 0] "integer indices" [0 1 2 4]"#,
        );
        let e = BilinearPatchMesh::from_parameters(&params, &location, &Transform::IDENTITY, false)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("bilinearmesh: \"indices\" values out of range: 4"),
            "{e}"
        );
    }
}
