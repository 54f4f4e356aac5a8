//! Displaced `plymesh` shapes through the normal scene path: a displaced
//! mesh renders where the displacement puts it, and the displacement edge
//! scale (option and command line) changes how finely it is cut.

mod common;

use common::{fresh_dir, render_text_with_report};
use rpbrt::scene::build::{build, RenderOverrides};
use std::path::{Path, PathBuf};

/// A 2×2 square in z = 0 (one quad, (u,v) over it), written as
/// `square.ply` in a fresh folder.
fn square_ply(name: &str) -> PathBuf {
    let dir = fresh_dir("displacement", name);
    std::fs::write(
        dir.join("square.ply"),
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nproperty float u\nproperty float v\nelement face 1\n\
         property list uchar int vertex_indices\nend_header\n\
         -1 -1 0 0 0\n1 -1 0 1 0\n1 1 0 1 1\n-1 1 0 0 1\n4 0 1 2 3\n",
    )
    .unwrap();
    dir
}

/// The square seen from above, lit by a point light 1 above its centre;
/// `shape_parameters` go on its `Shape "plymesh"`.
fn lit_square(dir: &Path, shape_parameters: &str) -> String {
    format!(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 2\n\
         Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8 \"bool savefp16\" false\n\
         Sampler \"independent\"\nIntegrator \"path\" \"integer maxdepth\" 1\nWorldBegin\n\
         LightSource \"point\" \"point3 from\" [0 0 1] \"rgb I\" [1 1 1]\n\
         Texture \"lift\" \"float\" \"constant\" \"float value\" 0.5\n\
         Material \"diffuse\"\n\
         Shape \"plymesh\" \"string filename\" \"{}\" {shape_parameters}\n",
        dir.join("square.ply").display()
    )
}

/// The mean of the middle 2×2 pixels (R, G, B averaged).
fn centre(image: &rpbrt::image::Image) -> f64 {
    let mut sum = 0.0;
    for (x, y) in [(3, 3), (3, 4), (4, 3), (4, 4)] {
        let pixel = image.pixel(x, y);
        sum += pixel[..3].iter().map(|&v| v as f64).sum::<f64>() / 3.0;
    }
    sum / 4.0
}

/// Lifted by 0.5 towards a light 1 above it, the square's centre is at
/// half the distance: four times as bright (cos θ ≈ 1 in the narrow view,
/// which sees 0.09 either side of the centre).
#[test]
fn a_displaced_plymesh_renders_where_the_displacement_puts_it() {
    let dir = square_ply("render");
    let render = |name: &str, parameters: &str| {
        let (image, report) = render_text_with_report(
            name,
            &lit_square(&dir, parameters),
            4,
            2,
            RenderOverrides::default(),
        );
        assert_eq!(report.bad_samples, 0);
        assert!(image.first_non_finite().is_none());
        centre(&image)
    };
    let flat = render("displacement-flat", "");
    let lifted = render(
        "displacement-lifted",
        "\"texture displacement\" \"lift\" \"float edgelength\" 0.5",
    );
    assert!(flat > 0.0);
    let ratio = lifted / flat;
    assert!((ratio - 4.0).abs() < 0.05, "{flat} {lifted} {ratio}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The triangles of the scene's one triangle mesh, built with `overrides`.
fn triangle_count(dir: &Path, options: &str, overrides: &RenderOverrides) -> usize {
    let text = format!(
        "{options}\n{}",
        lit_square(
            dir,
            "\"texture displacement\" \"lift\" \"float edgelength\" 0.6"
        )
    );
    let loaded = rpbrt::scene::load_text(&dir.join("scene.pbrt"), &text).unwrap();
    let scene = build(loaded.scene, overrides).unwrap();
    scene.shapes.triangle_meshes[0].triangle_count()
}

/// Each right triangle (legs 2) is halved until its hypotenuse (2√2, 2,
/// √2, 1, ..., halved every two cuts) is under the edge length: 0.6
/// takes 2^5 pieces, 1.2 (scale 2) 2^3, 0.3 (scale 0.5) 2^7.
#[test]
fn the_displacement_edge_scale_changes_how_finely_the_mesh_is_cut() {
    let dir = square_ply("edge-scale");
    let plain = RenderOverrides::default();
    assert_eq!(triangle_count(&dir, "", &plain), 2 * 32);
    let option = "Option \"displacementedgescale\" 2";
    assert_eq!(triangle_count(&dir, option, &plain), 2 * 8);
    let command_line = RenderOverrides {
        displacement_edge_scale: Some(0.5),
        ..Default::default()
    };
    assert_eq!(triangle_count(&dir, option, &command_line), 2 * 128);
    let _ = std::fs::remove_dir_all(&dir);
}
