//! The realistic camera in rendered scenes: a double-Gauss lens read from
//! a lens file, looking at a checkerboard.

mod common;

/// The double-Gauss 50 mm f/2 of US patent 2,673,491 (Tronnier), as
/// "Modern Lens Design" lists it, scaled from 100 mm to 50 mm.
const DOUBLE_GAUSS_50MM: &str = "\
# radius  thickness  index  diameter (mm)
29.475    3.76    1.67    25.2
84.83     0.12    1       25.2
19.275    4.025   1.67    23
40.77     3.275   1.699   23
12.75     5.705   1       18
0         4.5     0       17.1
-14.495   1.18    1.603   17
40.77     6.065   1.658   20
-20.385   0.19    1       20
437.065   3.22    1.717   20
-39.73    0       1       20
";

/// Renders `scene` with its lens file written to a folder of its own
/// (named in the scene by its absolute path).
fn render(name: &str, scene: &dyn Fn(&str) -> String, spp: u32) -> Vec<f64> {
    let dir = common::fresh_dir("realistic", name);
    let lens = dir.join("dgauss.50mm.dat");
    std::fs::write(&lens, DOUBLE_GAUSS_50MM).unwrap();
    let image = common::render_text(
        &format!("realistic-{name}"),
        &scene(&lens.display().to_string()),
        spp,
        2,
        Default::default(),
    );
    std::fs::remove_dir_all(&dir).ok();
    common::channel_averages(&image)
}

/// A checkerboard (10 cm checks, reflectance 0.8 and 0.1) filling the
/// view 2 m in front of the film, under a white sky, seen through the
/// double-Gauss at about f/3 focused at `focus` m.
fn checkerboard(focus: f32, lens_file: &str) -> String {
    format!(
        "LookAt 0 0 2  0 0 0  0 1 0\n\
        Camera \"realistic\" \"string lensfile\" \"{lens_file}\" \"float aperturediameter\" 17 \"float focusdistance\" {focus}\n\
        Film \"rgb\" \"integer xresolution\" 48 \"integer yresolution\" 32 \"float diagonal\" 35\n\
        Sampler \"halton\"\n\
        WorldBegin\n\
        LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
        Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 40 \"float vscale\" 40 \"rgb tex1\" [0.8 0.8 0.8] \"rgb tex2\" [0.1 0.1 0.1]\n\
        Material \"diffuse\" \"texture reflectance\" \"checks\"\n\
        Shape \"trianglemesh\" \"point3 P\" [-2 -2 0  2 -2 0  2 2 0  -2 2 0] \"point2 uv\" [0 0 1 0 1 1 0 1] \"integer indices\" [0 1 2 0 2 3]\n"
    )
}

/// Mean and standard deviation of the grey values in the middle half of
/// the 48 × 32 image (each way).
fn middle_statistics(values: &[f64]) -> (f64, f64) {
    let (w, h) = (48, 32);
    let middle: Vec<f64> = (h / 4..3 * h / 4)
        .flat_map(|y| (w / 4..3 * w / 4).map(move |x| values[y * w + x]))
        .collect();
    let mean = middle.iter().sum::<f64>() / middle.len() as f64;
    let variance =
        middle.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / middle.len() as f64;
    (mean, variance.sqrt())
}

/// Focused on the checkerboard, the checks are sharp: the middle of the
/// image swings between light and dark. Focused at 40 cm instead, the
/// blur (about a check wide) averages them out.
#[test]
fn the_plane_in_focus_is_sharp_and_a_defocused_one_blurred() {
    let sharp = render("sharp", &|lens| checkerboard(2.0, lens), 16);
    let blurred = render("blurred", &|lens| checkerboard(0.4, lens), 16);
    let (sharp_mean, sharp_deviation) = middle_statistics(&sharp);
    let (blurred_mean, blurred_deviation) = middle_statistics(&blurred);
    eprintln!(
        "realistic camera: focused mean {sharp_mean:.4} deviation {sharp_deviation:.4}; defocused mean {blurred_mean:.4} deviation {blurred_deviation:.4}"
    );
    assert!(sharp_mean > 0.0);
    assert!(
        sharp_deviation > 0.5 * sharp_mean,
        "{sharp_deviation} vs mean {sharp_mean}"
    );
    assert!(
        blurred_deviation < 0.5 * sharp_deviation,
        "{blurred_deviation} vs {sharp_deviation}"
    );
    // Moving the lens out to focus close dims the film (less of the
    // pupil's solid angle), but not to nothing.
    assert!(
        blurred_mean > 0.3 * sharp_mean,
        "{blurred_mean} vs {sharp_mean}"
    );
}
