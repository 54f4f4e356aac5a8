//! Motion blur (`ActiveTransform`, `TransformTimes`, the camera's shutter):
//! moving shapes, instances and cameras are where their interpolated
//! transforms put them at each ray's time, and an image averages over the
//! shutter interval.

mod common;

use glam::Vec3;
use rpbrt::math::Ray;
use rpbrt::scene::build::{build, BuiltScene, RenderOverrides};
use std::path::Path;

fn built(text: &str) -> BuiltScene {
    let loaded = rpbrt::scene::load_text(Path::new("motion.pbrt"), text).unwrap();
    build(loaded.scene, &RenderOverrides::default()).unwrap()
}

fn build_error(text: &str) -> String {
    let loaded = rpbrt::scene::load_text(Path::new("motion.pbrt"), text).unwrap();
    match build(loaded.scene, &RenderOverrides::default()) {
        Ok(_) => panic!("the scene should be refused"),
        Err(e) => e.to_string(),
    }
}

/// Whether a ray down −z through (x, y) at `time` hits anything.
fn hit_at(scene: &BuiltScene, x: f32, y: f32, time: f32) -> bool {
    let ray = Ray::new(Vec3::new(x, y, 10.0), -Vec3::Z, time);
    let hit = scene.intersect(&ray, f32::INFINITY).is_some();
    assert_eq!(hit, scene.intersect_p(&ray, f32::INFINITY));
    hit
}

#[test]
fn a_moving_sphere_is_where_its_transform_puts_it_at_each_time() {
    // From x = 0 at time 0 to x = 2 at time 1, radius 0.5.
    let scene = built(
        "Camera \"perspective\"\nWorldBegin\n\
         AttributeBegin\nActiveTransform EndTime\nTranslate 2 0 0\nActiveTransform All\n\
         Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n",
    );
    assert!(scene.has_motion());
    for time in [0.0f32, 0.25, 0.5, 0.9, 1.0] {
        let x = 2.0 * time;
        assert!(hit_at(&scene, x + 0.45, 0.0, time), "time {time}");
        assert!(hit_at(&scene, x - 0.45, 0.0, time), "time {time}");
        assert!(!hit_at(&scene, x + 0.55, 0.0, time), "time {time}");
        assert!(!hit_at(&scene, x - 0.55, 0.0, time), "time {time}");
    }
    // Before and after the transform times, the ends hold.
    assert!(hit_at(&scene, 0.0, 0.0, -3.0) && !hit_at(&scene, 2.0, 0.0, -3.0));
    assert!(hit_at(&scene, 2.0, 0.0, 7.0) && !hit_at(&scene, 0.0, 0.0, 7.0));
}

#[test]
fn a_turning_instance_follows_the_interpolated_rotation() {
    // A small sphere 2 units out along x, turned a quarter turn about z
    // over the transform times 0…2: at time t it is at angle t·π/4.
    let scene = built(
        "Camera \"perspective\"\nTransformTimes 0 2\nWorldBegin\n\
         ObjectBegin \"ball\"\nTranslate 2 0 0\nShape \"sphere\" \"float radius\" 0.2\nObjectEnd\n\
         AttributeBegin\nActiveTransform EndTime\nRotate 90 0 0 1\nActiveTransform All\n\
         ObjectInstance \"ball\"\nAttributeEnd\n",
    );
    for time in [0.0f32, 0.5, 1.0, 1.5, 2.0] {
        let angle = time * std::f32::consts::FRAC_PI_4;
        let (x, y) = (2.0 * angle.cos(), 2.0 * angle.sin());
        assert!(hit_at(&scene, x, y, time), "time {time}");
        assert!(hit_at(&scene, x + 0.15, y, time), "time {time}");
        assert!(!hit_at(&scene, x + 0.25, y, time), "time {time}");
        // Where the chord between start and end would put it: empty.
        let chord = Vec3::new(2.0, 0.0, 0.0).lerp(Vec3::new(0.0, 2.0, 0.0), time / 2.0);
        if time == 1.0 {
            assert!(!hit_at(&scene, chord.x, chord.y, time));
        }
    }
}

/// An orthographic view down on a black sphere crossing a white
/// background: each pixel on its path is dark for the fraction of the
/// shutter during which the sphere covers it.
#[test]
fn a_pixel_is_dark_for_the_fraction_of_the_shutter_it_is_covered() {
    let radius = 0.5f64;
    let text = format!(
        "LookAt 0 0 10  0 0 0  0 1 0\n\
         Camera \"orthographic\" \"float screenwindow\" [-2 2 -0.125 0.125] \"float shutteropen\" 0 \"float shutterclose\" 1\n\
         Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 4\n\
         PixelFilter \"box\" \"float xradius\" 0.5 \"float yradius\" 0.5\n\
         Sampler \"zsobol\"\nIntegrator \"path\" \"integer maxdepth\" 1\n\
         WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n\
         AttributeBegin\nTranslate -1 0 0\nActiveTransform EndTime\nTranslate 2 0 0\nActiveTransform All\n\
         Shape \"sphere\" \"float radius\" {radius}\nAttributeEnd\n"
    );
    let image = common::render_text(
        "motion-coverage",
        &text,
        1024,
        2,
        RenderOverrides::default(),
    );
    let values = common::channel_averages(&image);
    // Row 1, column 0: off the sphere's path.
    let background = values[64];
    assert!((background - 1.0).abs() < 0.05, "background {background}");
    // The screen spans x ∈ [−2, 2] (x flips: the camera looks down −z
    // with +y up, so screen +x is world −x); the sphere's centre runs
    // from −1 to 1. Rows 1 and 2 straddle y = 0 (|y| ≤ 0.0625): the
    // chord there is within 0.4 % of the radius.
    let mut compared = 0;
    for column in 0..64 {
        let screen_x = -2.0 + 4.0 * (column as f64 + 0.5) / 64.0;
        let x = -screen_x;
        // Covered while |x − (−1 + 2t)| < r.
        let t0 = ((x - radius + 1.0) / 2.0).clamp(0.0, 1.0);
        let t1 = ((x + radius + 1.0) / 2.0).clamp(0.0, 1.0);
        let expected = background * (1.0 - (t1 - t0));
        for row in [1, 2] {
            let got = values[row * 64 + column];
            assert!(
                (got - expected).abs() < 0.04,
                "column {column} (x = {x:.3}): {got:.4}, expected {expected:.4}"
            );
        }
        compared += (t1 > t0) as usize;
    }
    assert!(compared > 40, "{compared} columns on the path");
}

/// A camera moving by d renders what a still camera renders of the
/// world moving by −d.
#[test]
fn a_moving_camera_sees_what_a_still_one_sees_of_the_opposite_motion() {
    let world = |motion: &str| {
        format!(
            "WorldBegin\nLightSource \"distant\" \"point3 from\" [1 2 3] \"rgb L\" [3 3 3]\n\
             LightSource \"infinite\" \"rgb L\" [0.2 0.2 0.2]\n\
             AttributeBegin\n{motion}\
             Material \"diffuse\" \"rgb reflectance\" [0.8 0.4 0.2]\n\
             Shape \"sphere\" \"float radius\" 0.6\n\
             Translate 1 0.3 -0.5\nShape \"sphere\" \"float radius\" 0.4\nAttributeEnd\n"
        )
    };
    let head = "Film \"rgb\" \"integer xresolution\" 48 \"integer yresolution\" 32\n\
                Sampler \"zsobol\"\nIntegrator \"path\" \"integer maxdepth\" 2\n";
    let moving_camera = format!(
        "{head}ActiveTransform StartTime\nLookAt 0 0 6  0 0 0  0 1 0\n\
         ActiveTransform EndTime\nLookAt 0.8 0 6  0.8 0 0  0 1 0\nActiveTransform All\n\
         Camera \"perspective\" \"float fov\" 40\n{}",
        world("")
    );
    let moving_world = format!(
        "{head}LookAt 0 0 6  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n{}",
        world("ActiveTransform EndTime\nTranslate -0.8 0 0\nActiveTransform All\n")
    );
    let still = format!(
        "{head}LookAt 0 0 6  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n{}",
        world("")
    );
    let render = |name: &str, text: &str| {
        common::channel_averages(&common::render_text(
            name,
            text,
            64,
            2,
            RenderOverrides::default(),
        ))
    };
    let a = render("motion-camera", &moving_camera);
    let b = render("motion-world", &moving_world);
    let c = render("motion-still", &still);
    let mean_square = |x: &[f64], y: &[f64]| {
        x.iter().zip(y).map(|(p, q)| (p - q) * (p - q)).sum::<f64>() / x.len() as f64
    };
    // Same samples, same rays up to rounding: nearly identical. Against
    // the still image the blur is a large difference.
    let same = mean_square(&a, &b);
    let blur = mean_square(&a, &c);
    assert!(
        same < 1e-3 * blur,
        "moving camera vs moving world {same}, vs still {blur}"
    );
    assert!(blur > 1e-3, "the motion should blur the image: {blur}");
}

#[test]
fn what_cannot_move_is_refused_with_its_location() {
    let error = build_error(
        "Camera \"perspective\"\nWorldBegin\n\
         AttributeBegin\nActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\n\
         AreaLightSource \"diffuse\"\nShape \"sphere\"\nAttributeEnd\n",
    );
    assert!(
        error.contains("moving area light") && error.contains(":8:"),
        "{error}"
    );
    let error = build_error(
        "Camera \"perspective\"\nWorldBegin\nObjectBegin \"o\"\n\
         ActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\n\
         Shape \"sphere\"\nObjectEnd\nObjectInstance \"o\"\n",
    );
    assert!(
        error.contains("inside an object") && error.contains(":7:"),
        "{error}"
    );
    let error = build_error(
        "Camera \"perspective\"\nIntegrator \"bdpt\"\nWorldBegin\nLightSource \"point\"\n\
         ActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\nShape \"sphere\"\n",
    );
    assert!(
        error.contains("motion blur") && error.contains(":2:"),
        "{error}"
    );
}
