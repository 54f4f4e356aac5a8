//! The film's sensor settings, seen in rendered images.

mod common;

/// Mean R, G and B of an image of a sky of CIE illuminant D50 (a white
/// wall seen under daylight of about 5000 K).
fn sky_rgb(film_params: &str) -> [f64; 3] {
    let scene = format!(
        "Camera \"perspective\"\n\
         Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 {film_params}\n\
         Sampler \"zsobol\"\nWorldBegin\n\
         LightSource \"infinite\" \"spectrum L\" \"stdillum-D50\"\n"
    );
    let image = common::render_text("white-balance", &scene, 16, 2, Default::default());
    let data = image.rgb_data();
    let n = data.len() / 3;
    [0, 1, 2].map(|c| (0..n).map(|i| data[3 * i + c] as f64).sum::<f64>() / n as f64)
}

/// `whitebalance` 5000 adapts daylight of 5000 K (D50) to the colour
/// space's white: the sky comes out neutral. Without it, sRGB's white is
/// D65, and D50 looks warm.
#[test]
fn white_balance_makes_daylight_of_its_temperature_neutral() {
    let [r, g, b] = sky_rgb("\"float whitebalance\" 5000");
    assert!(
        (r / g - 1.0).abs() < 0.01 && (b / g - 1.0).abs() < 0.01,
        "{r} {g} {b}"
    );
    let [r, _, b] = sky_rgb("");
    assert!(
        r / b > 1.1,
        "without white balance D50 is warm: r/b = {}",
        r / b
    );
}

#[test]
fn a_negative_white_balance_is_a_located_error() {
    let scene = "Camera \"perspective\"\nFilm \"rgb\" \"float whitebalance\" -10\nWorldBegin\n";
    let loaded = rpbrt::scene::load_text(std::path::Path::new("wb.pbrt"), scene).unwrap();
    let error = match rpbrt::scene::build::build(loaded.scene, &Default::default()) {
        Ok(_) => panic!("should be refused"),
        Err(e) => e.to_string(),
    };
    assert!(
        error.contains("wb.pbrt:2:") && error.contains("whitebalance"),
        "{error}"
    );
}
