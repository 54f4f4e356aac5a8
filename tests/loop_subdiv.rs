//! `Shape "loopsubdiv"` in rendered scenes: the shape renders as the
//! triangle mesh of its limit points and normals, and the public scenes
//! that use it render.

mod common;

use common::{channel_averages, render_text, shared_dir};
use glam::Vec3;
use rpbrt::scene::build::RenderOverrides;

/// Camera at z = 4 looking at the origin; a sky and a diffuse sphere-like
/// shape, lit by the sky.
const VIEW: &str = "LookAt 0 0.5 4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
     Film \"rgb\" \"integer xresolution\" 24 \"integer yresolution\" 24 \"bool savefp16\" false\n\
     Sampler \"independent\"\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
     Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n";

fn list<T>(values: &[T], each: impl Fn(&T) -> String) -> String {
    values.iter().map(each).collect::<Vec<_>>().join(" ")
}

/// A subdivided octahedron renders as the trianglemesh of the positions and
/// normals `loop_subdiv::subdivide` gives (the same picture to within the
/// rounding of the positions written as text), and covers part of the
/// image with a shaded (not black, not sky) surface.
#[test]
fn loopsubdiv_renders_as_its_limit_mesh() {
    let p = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    // Clockwise seen from outside, as Houdini writes them: the limit
    // normals then point outwards.
    let indices: [u32; 24] = [
        0, 4, 2, 2, 4, 1, 1, 4, 3, 3, 4, 0, 2, 5, 0, 1, 5, 2, 3, 5, 1, 0, 5, 3,
    ];
    let levels = 2;
    let subdivided = format!(
        "{VIEW}Shape \"loopsubdiv\" \"integer levels\" {levels} \"integer indices\" [{}] \"point3 P\" [{}]\n",
        list(&indices, |i| i.to_string()),
        list(&p, |v| format!("{} {} {}", v.x, v.y, v.z)),
    );
    let data = rpbrt::shapes::loop_subdiv::subdivide(&indices, &p, levels).unwrap();
    assert_eq!(data.vertex_indices.len(), 3 * 8 * 16);
    let mesh = format!(
        "{VIEW}Shape \"trianglemesh\" \"integer indices\" [{}] \"point3 P\" [{}] \"normal N\" [{}]\n",
        list(&data.vertex_indices, |i| i.to_string()),
        list(&data.positions, |v| format!("{} {} {}", v.x, v.y, v.z)),
        list(&data.normals, |v| format!("{} {} {}", v.x, v.y, v.z)),
    );
    let a = channel_averages(&render_text(
        "loop-a",
        &subdivided,
        16,
        2,
        RenderOverrides::default(),
    ));
    let b = channel_averages(&render_text(
        "loop-b",
        &mesh,
        16,
        2,
        RenderOverrides::default(),
    ));
    let largest = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    eprintln!("loopsubdiv vs its mesh: largest pixel difference {largest:.2e}");
    assert!(largest < 1e-3, "{largest}");
    // Sky pixels are 1; the shape's pixels are between 0 and 0.5 (a
    // diffuse 0.5 under a sky partly hidden by the ground-less shape).
    let shape_pixels = a.iter().filter(|&&v| v < 0.9).count();
    assert!(
        shape_pixels > a.len() / 10 && shape_pixels < a.len(),
        "{shape_pixels}"
    );
    assert!(a.iter().all(|&v| v > 0.05), "a black pixel");
}

/// The public scenes that use `loopsubdiv` render (at `--quick`).
#[test]
fn public_loopsubdiv_scenes_render() {
    let Some(shared) = shared_dir() else {
        eprintln!("skipped: ../shared is absent");
        return;
    };
    let dir = shared.join("scenes/houdini-pbrt-v4/tests/scenes/TestShapes");
    for name in [
        "test_loopsubdiv",
        "test_loopsubdiv_levels",
        "test_loopsubdiv_alpha",
    ] {
        let path = dir.join(format!("{name}.pbrt"));
        if !path.exists() {
            eprintln!("skipped: {} is absent", path.display());
            continue;
        }
        let out =
            std::env::temp_dir().join(format!("rpbrt-loop-{name}-{}.exr", std::process::id()));
        let overrides = RenderOverrides {
            quick: true,
            outfile: Some(out.clone()),
            ..Default::default()
        };
        rpbrt::pipeline::render_file(&path, &overrides, 2, false)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let image = rpbrt::image::Image::read(&out).unwrap();
        std::fs::remove_file(&out).ok();
        assert!(image.first_non_finite().is_none());
    }
}
