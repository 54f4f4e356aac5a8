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

/// Every channel of an EXR file, by name (the image reader keeps R, G, B
/// only).
fn exr_channels(path: &std::path::Path) -> Vec<(String, Vec<f32>)> {
    let image = exr::prelude::read_all_flat_layers_from_file(path).unwrap();
    image.layer_data[0]
        .channel_data
        .list
        .iter()
        .map(|c| {
            (
                c.name.to_string(),
                c.sample_data.values_as_f32().collect::<Vec<f32>>(),
            )
        })
        .collect()
}

/// The spectral film's buckets hold each bucket's average radiance: a
/// blackbody sky of 4000 K, normalised to luminance 1 as pbrt-v4 does
/// for lights, measured against the spectrum integrated over each bucket.
#[test]
fn spectral_film_buckets_average_the_radiance_over_their_wavelengths() {
    let dir = common::fresh_dir("film", "spectral");
    let out = dir.join("sky.exr");
    let scene = format!(
        "Camera \"perspective\"\n\
         Film \"spectral\" \"integer xresolution\" 8 \"integer yresolution\" 8 \
         \"integer nbuckets\" 10 \"float lambdamin\" 400 \"float lambdamax\" 700 \
         \"bool savefp16\" false \"string filename\" \"{}\"\n\
         Sampler \"zsobol\" \"integer pixelsamples\" 256\nWorldBegin\n\
         LightSource \"infinite\" \"blackbody L\" 4000\n",
        out.display()
    );
    let path = dir.join("sky.pbrt");
    std::fs::write(&path, scene).unwrap();
    rpbrt::pipeline::render_file(&path, &Default::default(), 2, false).unwrap();
    let channels = exr_channels(&out);
    let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
    // R, G, B and the ten buckets of 30 nm, centred on 415 … 685 nm
    // (the reader sorts channels by name).
    for expected in ["R", "G", "B", "S0.415,000nm", "S0.685,000nm"] {
        assert!(names.contains(&expected), "{names:?}");
    }
    assert_eq!(names.len(), 13, "{names:?}");
    let planck = |l: f32| rpbrt::spectrum::blackbody::blackbody(l, 4000.0) as f64;
    // pbrt-v4 normalises the light to luminance 1: ∫ȳ B over 360–830 nm
    // at whole nanometres, and the film multiplies by ∫ȳ.
    let luminance: f64 = (360..=830)
        .map(|l| rpbrt::spectrum::cie_y(l as f32) as f64 * planck(l as f32))
        .sum();
    let y_integral = rpbrt::spectrum::CIE_Y_INTEGRAL as f64;
    for b in 0..10 {
        let (lo, hi) = (400.0 + 30.0 * b as f64, 430.0 + 30.0 * b as f64);
        let steps = 300;
        let mean_b: f64 = (0..steps)
            .map(|i| planck((lo + (hi - lo) * (i as f64 + 0.5) / steps as f64) as f32))
            .sum::<f64>()
            / steps as f64;
        let expected = mean_b / luminance * y_integral;
        let name = format!(
            "S0.{}nm",
            format!("{:.3}", (lo + hi) / 2.0).replace('.', ",")
        );
        let (_, values) = channels.iter().find(|(n, _)| *n == name).unwrap();
        let got = values.iter().map(|&v| v as f64).sum::<f64>() / values.len() as f64;
        assert!(
            (got - expected).abs() < 0.01 * expected,
            "{name}: {got} against {expected}"
        );
    }
    let header = exr::meta::MetaData::read_from_file(&out, false).unwrap();
    let attributes = &header.headers[0].own_attributes.other;
    let text = |k: &str| {
        attributes
            .get(&exr::prelude::Text::from(k))
            .map(|v| format!("{v:?}"))
            .unwrap_or_default()
    };
    assert!(text("spectralLayoutVersion").contains("1.0"));
    assert!(text("emissiveUnits").contains("W.m^-2.sr^-1"));
}

#[test]
fn spectral_film_refuses_other_formats_and_ranges() {
    for (params, expected) in [
        ("\"string filename\" \"a.png\"", "EXR files only"),
        ("\"float lambdamin\" 300", "wavelength range"),
        ("\"integer nbuckets\" 0", "nbuckets"),
    ] {
        let scene = format!("Camera \"perspective\"\nFilm \"spectral\" {params}\nWorldBegin\n");
        let loaded = rpbrt::scene::load_text(std::path::Path::new("s.pbrt"), &scene).unwrap();
        let error = match rpbrt::scene::build::build(loaded.scene, &Default::default()) {
            Ok(_) => panic!("should be refused: {params}"),
            Err(e) => e.to_string(),
        };
        assert!(
            error.contains("s.pbrt:2:") && error.contains(expected),
            "{error}"
        );
    }
}

/// The `gbuffer` film's channels on a square seen head-on by an
/// orthographic camera 3 units away: depth 3, the normal facing the
/// camera (in camera and in world space), (u, v) running across the
/// image, depth slopes zero, and the albedo of a diffuse reflectance of
/// 0.5, lit white.
#[test]
fn gbuffer_film_records_what_the_camera_sees_first() {
    for (system, normal) in [("camera", [0.0f32, 0.0, -1.0]), ("world", [0.0, 0.0, 1.0])] {
        let dir = common::fresh_dir("film", &format!("gbuffer-{system}"));
        let out = dir.join("g.exr");
        let scene = format!(
            "LookAt 0 0 3  0 0 0  0 1 0\n\
             Camera \"orthographic\" \"float screenwindow\" [-1 1 -1 1]\n\
             Film \"gbuffer\" \"integer xresolution\" 8 \"integer yresolution\" 8 \
             \"bool savefp16\" false \"string coordinatesystem\" \"{system}\" \"string filename\" \"{}\"\n\
             Sampler \"zsobol\" \"integer pixelsamples\" 64\nWorldBegin\n\
             LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
             Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n\
             Shape \"bilinearmesh\" \"point3 P\" [-2 -2 0  2 -2 0  -2 2 0  2 2 0] \
             \"integer indices\" [0 1 2 3] \"point2 uv\" [0 0 1 0 0 1 1 1]\n",
            out.display()
        );
        let path = dir.join("g.pbrt");
        std::fs::write(&path, scene).unwrap();
        rpbrt::pipeline::render_file(&path, &Default::default(), 2, false).unwrap();
        let channels = exr_channels(&out);
        let get = |name: &str| &channels.iter().find(|(n, _)| n == name).unwrap().1;
        assert_eq!(channels.len(), 25);
        for (axis, expected) in ["N.X", "N.Y", "N.Z"].iter().zip(normal) {
            assert!(
                get(axis).iter().all(|v| (v - expected).abs() < 1e-5),
                "{system} {axis}"
            );
        }
        let depth = if system == "camera" { 3.0 } else { 0.0 };
        assert!(
            get("P.Z").iter().all(|z| (z - depth).abs() < 1e-4),
            "{system} P.Z"
        );
        assert!(get("dzdx")
            .iter()
            .chain(get("dzdy"))
            .all(|d| d.abs() < 1e-5));
        // u = (x + 2) / 4 across the square; the pixel centres of the
        // ends of a row are at world x = ±0.875 (the screen's +x is the
        // world's −x for a camera looking down −z).
        let u = get("u");
        let (left, right) = (u[8 * 4], u[8 * 4 + 7]);
        assert!(
            (left - 2.875 / 4.0).abs() < 0.005 && (right - 1.125 / 4.0).abs() < 0.005,
            "u {left} … {right}"
        );
        for c in ["Albedo.R", "Albedo.G", "Albedo.B"] {
            let mean = get(c).iter().sum::<f32>() / 64.0;
            assert!((mean - 0.5).abs() < 0.01, "{c}: {mean}");
        }
    }
}
