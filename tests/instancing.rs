//! Object instancing renders what the same shapes written out by hand
//! render.

mod common;

/// What the instanced object holds: a sphere, a quad and a disk, each
/// with its own transform and material inside the definition.
const OBJECT: &str = r#"
  AttributeBegin
    Translate 0 0.5 0
    Material "diffuse" "rgb reflectance" [0.8 0.3 0.2]
    Shape "sphere" "float radius" 0.5
  AttributeEnd
  Shape "trianglemesh" "point3 P" [-1 0 -1  1 0 -1  1 0 1  -1 0 1]
        "integer indices" [0 1 2 0 2 3]
  AttributeBegin
    Translate 0.7 0.3 0.7
    Rotate -90 1 0 0
    Material "diffuse" "rgb reflectance" [0.2 0.4 0.8]
    Shape "disk" "float radius" 0.25
  AttributeEnd
"#;

/// Where the object is placed: translated, rotated, non-uniformly scaled.
/// (Not mirrored: pbrt-v4 flips a quadric's normal for a handedness-swapping
/// render-from-object transform but not for a swapping instance transform,
/// so a mirrored instance and its hand-flattened copy differ in the sign of
/// their quadrics' normals — by design, in pbrt-v4 as here.)
const PLACEMENTS: [&str; 3] = [
    "Translate -2.2 0 0  Rotate 30 0 1 0",
    "Translate 2.2 0.2 0  Scale 1 1.5 0.8",
    "Translate 0 0 2 Rotate 20 1 0 1",
];

fn scene(world: &str) -> String {
    format!(
        r#"LookAt 0 5 9  0 0 0  0 1 0
Camera "perspective" "float fov" 45
Film "rgb" "integer xresolution" 96 "integer yresolution" 64 "bool savefp16" false
Sampler "zsobol"
Integrator "path" "integer maxdepth" 5
WorldBegin
LightSource "distant" "point3 from" [1 3 2] "point3 to" [0 0 0] "blackbody L" 5000 "float scale" 1.5
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 4 4]
  Translate 0 4 0
  Rotate 90 1 0 0
  Shape "disk" "float radius" 1
AttributeEnd
Material "diffuse" "rgb reflectance" [0.5 0.5 0.5]
Shape "trianglemesh" "point3 P" [-10 -0.01 -10  10 -0.01 -10  10 -0.01 10  -10 -0.01 10]
      "integer indices" [0 1 2 0 2 3]
{world}"#
    )
}

/// The object defined once and instanced at every placement (plus an
/// object used once, which is flattened, and an empty one).
fn instanced() -> String {
    let mut world = format!("ObjectBegin \"thing\"\n{OBJECT}ObjectEnd\n");
    world.push_str("ObjectBegin \"once\"\n  Shape \"sphere\" \"float radius\" 0.3\nObjectEnd\n");
    world.push_str("ObjectBegin \"empty\"\nObjectEnd\nObjectInstance \"empty\"\n");
    for placement in PLACEMENTS {
        world.push_str(&format!(
            "AttributeBegin\n  {placement}\n  ObjectInstance \"thing\"\nAttributeEnd\n"
        ));
    }
    world
        .push_str("AttributeBegin\n  Translate 0 1.5 0\n  ObjectInstance \"once\"\nAttributeEnd\n");
    scene(&world)
}

/// The same shapes written out at each placement.
fn flattened() -> String {
    let mut world = String::new();
    for placement in PLACEMENTS {
        world.push_str(&format!(
            "AttributeBegin\n  {placement}\n{OBJECT}AttributeEnd\n"
        ));
    }
    world.push_str(
        "AttributeBegin\n  Translate 0 1.5 0\n  Shape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n",
    );
    scene(&world)
}

/// Same sampler, same seed: the two images agree pixel for pixel up to
/// float rounding (instance-space rays and render-space meshes round
/// differently, so a path may rarely take another branch).
#[test]
fn instances_render_as_the_flattened_scene() {
    let spp = 16;
    let a = common::render_text("inst", &instanced(), spp, 2, Default::default());
    let b = common::render_text("flat", &flattened(), spp, 2, Default::default());
    let (a, b) = (a.rgb_data(), b.rgb_data());
    assert_eq!(a.len(), b.len());
    let mean = b.iter().map(|&v| v as f64).sum::<f64>() / b.len() as f64;
    let mean_abs_diff = a
        .iter()
        .zip(&b)
        .map(|(&x, &y)| (x - y).abs() as f64)
        .sum::<f64>()
        / a.len() as f64;
    let pixels = a.len() / 3;
    let differing = (0..pixels)
        .filter(|&p| {
            (0..3).any(|c| (a[3 * p + c] - b[3 * p + c]).abs() > 1e-3 * (1.0 + b[3 * p + c].abs()))
        })
        .count();
    eprintln!(
        "mean {mean:.5}; mean |instanced − flattened| {mean_abs_diff:.3e}; pixels differing by > 1e-3: {differing} of {pixels}"
    );
    assert!(mean > 0.01, "the scene is lit");
    assert!(
        mean_abs_diff < 1e-3 * mean,
        "mean difference {mean_abs_diff}"
    );
    assert!(
        differing * 100 <= pixels,
        "{differing} of {pixels} pixels differ"
    );
}

fn build(world: &str) -> rpbrt::error::Result<rpbrt::scene::build::BuiltScene> {
    let text = format!(
        "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n{world}"
    );
    let loaded = rpbrt::scene::load_text(std::path::Path::new("instancing.pbrt"), &text)?;
    rpbrt::scene::build::build(loaded.scene, &Default::default())
}

/// Objects used twice are instanced, an object used once is flattened,
/// instances of an empty object are skipped with a warning, and a moving
/// instance (motion blur) stays an instance even when used once.
#[test]
fn instancing_follows_pbrt_v4() {
    let world = "ObjectBegin \"a\"\nShape \"sphere\"\nShape \"disk\"\nObjectEnd\n\
                 ObjectBegin \"b\"\nShape \"sphere\"\nObjectEnd\n\
                 ObjectBegin \"none\"\nObjectEnd\n\
                 ObjectInstance \"a\"\nTranslate 3 0 0\nObjectInstance \"a\"\n\
                 ObjectInstance \"b\"\nObjectInstance \"none\"\nObjectInstance \"none\"\n";
    let scene = build(world).unwrap();
    assert_eq!(scene.instances.len(), 2);
    // "b" is flattened to the top level; "a"'s two shapes are stored once.
    assert_eq!(scene.primitives.len(), 3);
    let empty: Vec<_> = scene
        .warnings
        .iter()
        .filter(|w| w.message.contains("has no shapes"))
        .collect();
    assert_eq!(empty.len(), 1, "{:?}", scene.warnings);

    let animated = "ObjectBegin \"a\"\nShape \"sphere\"\nObjectEnd\n\
                    ActiveTransform EndTime\nTranslate 1 0 0\nActiveTransform All\n\
                    ObjectInstance \"a\"\n";
    let scene = build(animated).unwrap();
    assert_eq!(
        scene.instances.len(),
        1,
        "a moving object used once is not flattened"
    );
    assert!(scene.has_motion());
}
