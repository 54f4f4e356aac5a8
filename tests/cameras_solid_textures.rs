//! The orthographic and spherical cameras and a solid texture in rendered
//! scenes: where each pixel looks, checked against the geometry.

use rpbrt::image::Image;
use rpbrt::scene::build::RenderOverrides;

fn render(name: &str, scene: &str, spp: u32) -> Image {
    let dir = std::env::temp_dir().join(format!("rpbrt-cameras-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join("out.exr");
    let overrides = RenderOverrides {
        spp: Some(spp),
        outfile: Some(out.clone()),
        ..Default::default()
    };
    rpbrt::pipeline::render_file(&path, &overrides, 2, false).unwrap();
    let image = Image::read(&out).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    image
}

fn grey(image: &Image, x: u32, y: u32) -> f32 {
    let p = image.pixel(x, y);
    (p[0] + p[1] + p[2]) / 3.0
}

/// An orthographic camera looking down −z over the square [−2, 2]² (32 ×
/// 32 pixels of 1/8) at a plane textured with a 3D checkerboard of
/// half-unit cubes (reflectance 0.8 on even cells, 0.2 on odd), under a
/// white sky: each pixel shows the reflectance of the cell straight below
/// its centre. Pixel edges fall on cell edges, so no pixel straddles two
/// (texture filtering off, box filter within the pixel). Camera space is
/// left-handed: world x is −screen x.
#[test]
fn orthographic_pixels_see_the_solid_checks_straight_below_them() {
    let scene = "Option \"disabletexturefiltering\" true\n\
        LookAt 0 0 5  0 0 0  0 1 0\n\
        Camera \"orthographic\" \"float screenwindow\" [-2 2 -2 2]\n\
        Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32\n\
        PixelFilter \"box\"\n\
        WorldBegin\n\
        LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
        AttributeBegin\n\
        Scale 0.5 0.5 0.5\n\
        Texture \"checks\" \"spectrum\" \"checkerboard\" \"integer dimension\" 3 \"rgb tex1\" [0.8 0.8 0.8] \"rgb tex2\" [0.2 0.2 0.2]\n\
        AttributeEnd\n\
        Material \"diffuse\" \"texture reflectance\" \"checks\"\n\
        Shape \"trianglemesh\" \"point3 P\" [-9 -9 0.25  9 -9 0.25  9 9 0.25  -9 9 0.25] \"integer indices\" [0 1 2 0 2 3]\n";
    let image = render("ortho-checks", scene, 16);
    let (mut even, mut odd) = ((0.0, 0), (0.0, 0));
    for j in 0..32 {
        for i in 0..32 {
            let screen_x = -2.0 + 0.125 * (i as f32 + 0.5);
            let screen_y = 2.0 - 0.125 * (j as f32 + 0.5);
            let (world_x, world_y) = (-screen_x, screen_y);
            // Texture space is world space doubled; the plane's z is in cell 0.
            let parity =
                ((2.0 * world_x).floor() as i32 + (2.0 * world_y).floor() as i32).rem_euclid(2);
            let v = grey(&image, i, j);
            if parity == 0 {
                assert!(v > 0.6, "pixel {i},{j} should be light: {v}");
                even = (even.0 + v, even.1 + 1);
            } else {
                assert!(v < 0.35, "pixel {i},{j} should be dark: {v}");
                odd = (odd.0 + v, odd.1 + 1);
            }
        }
    }
    // A Lambertian plane under a uniform unit sky reflects its albedo.
    let (even, odd) = (even.0 / even.1 as f32, odd.0 / odd.1 as f32);
    eprintln!("orthographic checks: even cells {even:.4}, odd cells {odd:.4}");
    assert!((even - 0.8).abs() < 0.03 && (odd - 0.2).abs() < 0.01);
}

/// A black ceiling (y = 1, reaching far out) over a spherical camera under
/// a white sky: the upper half of the sphere of directions is black, the
/// lower half sky. Equirectangular: the top rows are black, the bottom
/// rows white. Equal-area: the centre of the square (up) is black, the
/// corners (down) white, and half the pixels are each.
#[test]
fn spherical_cameras_see_the_ceiling_above_and_the_sky_below() {
    let view = |mapping: &str| {
        format!(
            "LookAt 0 0 0  0 0 -1  0 1 0\n\
             Camera \"spherical\" \"string mapping\" \"{mapping}\"\n\
             Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32\n\
             PixelFilter \"box\"\n\
             WorldBegin\n\
             LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
             Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n\
             Shape \"trianglemesh\" \"point3 P\" [-1e4 1 -1e4  1e4 1 -1e4  1e4 1 1e4  -1e4 1 1e4] \"integer indices\" [0 1 2 0 2 3]\n"
        )
    };
    let image = render("equirect", &view("equirectangular"), 4);
    // The sky's spectrum is sampled at 4 wavelengths per sample, so a
    // pixel's grey is noisy; the mean over the lower rows is 1.
    let mut sky = 0.0;
    for i in 0..32 {
        for j in 0..15 {
            assert!(grey(&image, i, j) < 1e-4, "row {j} should see the ceiling");
        }
        for j in 17..32 {
            let v = grey(&image, i, j);
            assert!(v > 0.5, "row {j} should see the sky: {v}");
            sky += v / (32.0 * 15.0);
        }
    }
    eprintln!("equirectangular: sky rows {sky:.4}");
    assert!((sky - 1.0).abs() < 0.02, "{sky}");
    let image = render("equalarea", &view("equalarea"), 4);
    assert!(grey(&image, 16, 16) < 1e-4);
    for (x, y) in [(0, 0), (31, 0), (0, 31), (31, 31)] {
        assert!(grey(&image, x, y) > 0.5);
    }
    let mean: f32 = (0..32)
        .flat_map(|j| (0..32).map(move |i| (i, j)))
        .map(|(i, j)| grey(&image, i, j))
        .sum::<f32>()
        / 1024.0;
    eprintln!("equal-area: mean {mean:.4}");
    assert!((mean - 0.5).abs() < 0.03, "{mean}");
}
