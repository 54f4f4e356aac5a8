//! The triangles fur grows on, read with rpbrt's own readers.
//!
//! | `--mesh` file | what is read |
//! |---------------|--------------|
//! | `.ply`, `.ply.gz` | the file's triangles (and quads, each split into two triangles p00 p10 p11, p00 p11 p01), in the file's coordinates, with its vertex normals when it has them |
//! | anything else (`.pbrt`, `.pbrt.gz`) | a pbrt scene (or a geometry file meant for `Include`, read as if inside `WorldBegin`): every `Shape "trianglemesh"`, `"plymesh"` and `"bilinearmesh"`, top level and in instanced objects, in world space with its transform and `ReverseOrientation` |
//!
//! Without vertex normals a triangle's front is counter-clockwise (its
//! winding's right-hand normal), reversed by `ReverseOrientation` or a
//! transform that swaps handedness, as pbrt-v4 orients a mesh's geometric
//! normal; `--flip-normals` turns every front around.

use super::roots::Triangle;
use crate::error::{Error, Result};
use crate::math::Transform;
use crate::scene_description::{SceneDescription, Shape};
use crate::shapes::mesh::{BilinearPatchMesh, TriangleMesh};
use crate::shapes::ply::{read_ply, PlyMeshes};
use glam::Vec3;
use pbrt_parser::Location;
use std::path::Path;

fn usage(path: &Path, message: impl std::fmt::Display) -> Error {
    Error::Usage(format!("--mesh {}: {message}", path.display()))
}

/// Reads the triangles of `path` (see the module's table).
pub fn load(path: &Path, flip: bool) -> Result<Vec<Triangle>> {
    if !path.is_file() {
        return Err(usage(path, "no such file"));
    }
    let name = path.to_string_lossy().to_ascii_lowercase();
    let mut triangles = Vec::new();
    if name.ends_with(".ply") || name.ends_with(".ply.gz") {
        let ply = read_ply(path, &Location::nowhere()).map_err(|e| usage(path, e))?;
        add_ply(
            ply.into_meshes(&Transform::IDENTITY, false),
            flip,
            &mut triangles,
        );
    } else {
        let scene = load_scene(path)?;
        for (shape, transform) in placed_shapes(&scene) {
            add_shape(&scene, shape, &transform, flip, &mut triangles)
                .map_err(|e| usage(path, e))?;
        }
    }
    if triangles.is_empty() {
        return Err(usage(
            path,
            "no triangles of positive area (fur needs a triangle mesh: a PLY, or Shape \"trianglemesh\" / \"plymesh\" in a pbrt file)",
        ));
    }
    Ok(triangles)
}

/// A whole scene, or a file meant to be included in the world block.
fn load_scene(path: &Path) -> Result<SceneDescription> {
    match crate::scene::load(path) {
        Ok(loaded) => Ok(loaded.scene),
        Err(error) => match crate::scene::load_fragment(path) {
            Ok(loaded) => Ok(loaded.scene),
            Err(fragment_error) => {
                let text = error.to_string();
                Err(usage(
                    path,
                    if text.contains("only allowed inside the world block") {
                        fragment_error
                    } else {
                        error
                    },
                ))
            }
        },
    }
}

/// Every shape with its world-from-object transform (instances included).
fn placed_shapes(scene: &SceneDescription) -> Vec<(&Shape, Transform)> {
    let mut out: Vec<(&Shape, Transform)> = scene
        .shapes
        .iter()
        .map(|s| (s, scene.transform(s.world_from_object).start))
        .collect();
    for instance in &scene.instances {
        let Some(object) = scene.objects.get(instance.object) else {
            continue;
        };
        let world_from_instance = scene.transform(instance.world_from_instance).start;
        for s in &object.shapes {
            let placed = world_from_instance.then(&scene.transform(s.world_from_object).start);
            out.push((s, placed));
        }
    }
    out
}

fn add_shape(
    scene: &SceneDescription,
    shape: &Shape,
    transform: &Transform,
    flip: bool,
    out: &mut Vec<Triangle>,
) -> Result<()> {
    let params = &shape.entity.params;
    let location = &shape.entity.location.0;
    let reverse = shape.reverse_orientation;
    match shape.entity.kind.as_str() {
        "trianglemesh" => {
            let mesh = TriangleMesh::from_parameters(params, location, transform, reverse)?;
            add_triangles(&mesh, flip, out);
        }
        "bilinearmesh" => {
            let mesh = BilinearPatchMesh::from_parameters(params, location, transform, reverse)?;
            add_patches(&mesh, flip, out);
        }
        "plymesh" => {
            let Some((filename, at)) = params.string_at("filename")? else {
                return Ok(());
            };
            let path = pbrt_parser::resolve_path(&scene.base_directory, &filename);
            let ply = read_ply(&path, &at)?;
            add_ply(ply.into_meshes(transform, reverse), flip, out);
        }
        _ => {}
    }
    Ok(())
}

fn add_ply(meshes: PlyMeshes, flip: bool, out: &mut Vec<Triangle>) {
    if let Some(mesh) = &meshes.triangles {
        add_triangles(mesh, flip, out);
    }
    if let Some(mesh) = &meshes.quads {
        add_patches(mesh, flip, out);
    }
}

fn add_triangles(mesh: &TriangleMesh, flip: bool, out: &mut Vec<Triangle>) {
    let flip = flip ^ mesh.reverse_orientation ^ mesh.transform_swaps_handedness;
    for i in 0..mesh.triangle_count() {
        let v = mesh.triangle(i as u32);
        push(&mesh.positions, &mesh.normals, v, flip, out);
    }
}

fn add_patches(mesh: &BilinearPatchMesh, flip: bool, out: &mut Vec<Triangle>) {
    let flip = flip ^ mesh.reverse_orientation ^ mesh.transform_swaps_handedness;
    for i in 0..mesh.patch_count() {
        let [p00, p10, p01, p11] = mesh.patch(i as u32);
        push(&mesh.positions, &mesh.normals, [p00, p10, p11], flip, out);
        push(&mesh.positions, &mesh.normals, [p00, p11, p01], flip, out);
    }
}

/// Adds the triangle of vertices `v` unless it is degenerate or refers to
/// a vertex that is not there.
fn push(positions: &[Vec3], normals: &[Vec3], v: [usize; 3], flip: bool, out: &mut Vec<Triangle>) {
    let (Some(a), Some(b), Some(c)) = (
        positions.get(v[0]),
        positions.get(v[1]),
        positions.get(v[2]),
    ) else {
        return;
    };
    let p = [a.as_dvec3(), b.as_dvec3(), c.as_dvec3()];
    if !p.iter().all(|p| p.is_finite()) {
        return;
    }
    let n = match (normals.get(v[0]), normals.get(v[1]), normals.get(v[2])) {
        (Some(a), Some(b), Some(c)) => Some([a.as_dvec3(), b.as_dvec3(), c.as_dvec3()]),
        _ => None,
    }
    .filter(|n| n.iter().all(|n| n.is_finite()));
    if let Some(t) = Triangle::new(p, n, flip) {
        out.push(t);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn temp(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("rpbrt-hairgen-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn a_pbrt_mesh_is_read_with_its_transform_and_orientation() {
        let path = temp(
            "mesh.pbrt",
            "WorldBegin\nAttributeBegin\nTranslate 0 0 5\nReverseOrientation\n\
             Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n\
             AttributeEnd\n",
        );
        let t = load(&path, false).unwrap();
        assert_eq!(t.len(), 1);
        assert_eq!(t[0].p[1], DVec3::new(1.0, 0.0, 5.0));
        assert!(t[0].face_normal.dot(DVec3::NEG_Z) > 0.999);
        let flipped = load(&path, true).unwrap();
        assert!(flipped[0].face_normal.dot(DVec3::Z) > 0.999);
    }

    #[test]
    fn a_geometry_fragment_is_read_too() {
        let path = temp(
            "fragment.pbrt",
            "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n",
        );
        let t = load(&path, false).unwrap();
        assert_eq!(t.len(), 2);
        assert!((t[0].area() + t[1].area() - 1.0).abs() < 1e-9);
    }

    #[test]
    fn missing_and_empty_meshes_are_named() {
        let e = load(Path::new("/nonexistent/bunny.ply"), false).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/bunny.ply"), "{e}");
        let path = temp("empty.pbrt", "WorldBegin\nShape \"sphere\"\n");
        let e = load(&path, false).unwrap_err().to_string();
        assert!(
            e.contains("empty.pbrt") && e.contains("no triangles"),
            "{e}"
        );
        let path = temp(
            "broken.pbrt",
            "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0]\n",
        );
        let e = load(&path, false).unwrap_err().to_string();
        assert!(e.contains("broken.pbrt"), "{e}");
    }
}
