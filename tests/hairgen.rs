//! `rpbrt hairgen` as a user runs it: the same seed writes the same bytes,
//! the output loads and renders with rpbrt, bad options are refused naming
//! the option, fur roots follow the mesh's area and normals, curly strands
//! stay within their amplitude, and fur grows on the Stanford bunny (when
//! `../shared` is there).
mod common;
use common::rpbrt;

use std::path::{Path, PathBuf};
use std::process::Output;

fn temp_dir(name: &str) -> PathBuf {
    common::fresh_dir("hairgen", name)
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Runs `rpbrt hairgen WORDS... --out OUT` and insists it succeeds.
fn hairgen(words: &str, out: &Path) {
    let mut args: Vec<String> = vec!["hairgen".into()];
    args.extend(words.split_whitespace().map(String::from));
    args.push("--out".into());
    args.push(out.to_string_lossy().into_owned());
    let result = rpbrt(&args);
    assert!(result.status.success(), "{words}: {}", stderr(&result));
}

/// A written strand: its widths and control points.
struct Curve {
    widths: (f64, f64),
    points: Vec<[f64; 3]>,
}

fn read_text(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap();
    if path.extension().is_some_and(|e| e == "gz") {
        use std::io::Read;
        let mut text = String::new();
        flate2::read::GzDecoder::new(&bytes[..])
            .read_to_string(&mut text)
            .unwrap();
        text
    } else {
        String::from_utf8(bytes).unwrap()
    }
}

fn bracket_after<'a>(line: &'a str, name: &str) -> &'a str {
    let start = line.find(name).unwrap() + name.len();
    let rest = &line[start..];
    let open = rest.find('[').unwrap() + 1;
    let close = rest.find(']').unwrap();
    &rest[open..close]
}

fn curves(path: &Path) -> Vec<Curve> {
    read_text(path)
        .lines()
        .filter(|l| l.starts_with("Shape \"curve\""))
        .map(|line| {
            assert!(line.contains("\"string type\" \"cylinder\""), "{line}");
            assert!(line.contains("\"string basis\" \"bezier\""), "{line}");
            let number = |s: &str| s.trim().parse::<f64>().unwrap();
            let values: Vec<f64> = bracket_after(line, "\"point3 P\"")
                .split_whitespace()
                .map(number)
                .collect();
            assert_eq!(values.len() % 3, 0);
            let points: Vec<[f64; 3]> = values.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
            assert_eq!(points.len() % 3, 1, "3n + 1 control points");
            Curve {
                widths: (
                    number(bracket_after(line, "\"float width0\"")),
                    number(bracket_after(line, "\"float width1\"")),
                ),
                points,
            }
        })
        .collect()
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn length(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
fn scaled(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn normalized(a: [f64; 3]) -> [f64; 3] {
    scaled(a, 1.0 / length(a))
}

/// Points along every Bézier segment of a curve.
fn curve_points(c: &Curve) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for b in c.points.windows(4).step_by(3) {
        for k in 0..=8 {
            let t = k as f64 / 8.0;
            let s = 1.0 - t;
            let w = [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t];
            let mut p = [0.0; 3];
            for (point, weight) in b.iter().zip(w) {
                for axis in 0..3 {
                    p[axis] += point[axis] * weight;
                }
            }
            out.push(p);
        }
    }
    out
}

/// An ASCII PLY of triangles.
fn write_ply(path: &Path, vertices: &[[f64; 3]], triangles: &[[usize; 3]]) {
    let mut text = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        vertices.len(),
        triangles.len()
    );
    for v in vertices {
        text += &format!("{} {} {}\n", v[0], v[1], v[2]);
    }
    for t in triangles {
        text += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn the_same_seed_writes_the_same_bytes() {
    let dir = temp_dir("seed");
    let recipe = "sphere --count 300 --style curly --gravity 0.4 --clumps 20 --clumping 0.7 \
                  --length-variation 0.5 --spread 10";
    let (a, b, c) = (dir.join("a.pbrt"), dir.join("b.pbrt"), dir.join("c.pbrt"));
    hairgen(&format!("{recipe} --seed 7"), &a);
    hairgen(&format!("{recipe} --seed 7"), &b);
    hairgen(&format!("{recipe} --seed 8"), &c);
    let (a, b, c) = (
        std::fs::read(a).unwrap(),
        std::fs::read(b).unwrap(),
        std::fs::read(c).unwrap(),
    );
    assert!(
        !dir.join("a.pbrt.partial").exists(),
        "the partial file is renamed"
    );
    assert!(a == b, "same seed, different bytes");
    assert!(a != c, "different seeds, same bytes");
    // Gzip output decompresses to the same text.
    let gz = dir.join("a.pbrt.gz");
    hairgen(&format!("{recipe} --seed 7"), &gz);
    assert!(read_text(&gz).as_bytes() == &a[..], "gzip holds other text");
}

#[test]
fn gzipped_output_loads_and_renders_with_its_strand_count() {
    let dir = temp_dir("render");
    let hair = dir.join("hair.pbrt.gz");
    hairgen(
        "cap --count 500 --radius 0.5 --style wavy --gravity 0.8 --seed 3",
        &hair,
    );
    let text = read_text(&hair);
    assert!(text
        .starts_with("# pbrt-v4 curves written by rpbrt hairgen\n# rpbrt hairgen cap --count 500"));
    assert!(text.contains("# seed 3, 500 strands,"), "{}", &text[..600]);
    let loaded = rpbrt::scene::load_fragment(&hair).expect("loads");
    assert_eq!(loaded.scene.shape_counts().get("curve"), Some(&500));

    let scene = dir.join("scene.pbrt");
    std::fs::write(
        &scene,
        "LookAt 0 0.3 3  0 0.3 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n\
         Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32 \"string filename\" \"hair.pfm\"\n\
         Sampler \"independent\" \"integer pixelsamples\" 1\nWorldBegin\n\
         LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Material \"hair\" \"float eumelanin\" 1.3\nInclude \"hair.pbrt.gz\"\n",
    )
    .unwrap();
    let out = rpbrt(&[scene.as_os_str(), "--quiet".as_ref()]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.join("hair.pfm").is_file());
}

#[test]
fn bad_options_are_refused_naming_the_option() {
    let dir = temp_dir("usage");
    let out = dir.join("x.pbrt");
    for (words, option) in [
        ("sphere --count 0", "--count"),
        ("sphere --length -2", "--length"),
        ("cap --length-variation 1.2", "--length-variation"),
        ("sphere --root-width 0", "--root-width"),
        ("sphere --clumping 2 --clumps 4", "--clumping"),
        ("sphere --gravity -0.1", "--gravity"),
        ("sphere --style frizzy", "--style"),
        ("sphere --center 1,2", "--center"),
        (
            "fur --mesh /nonexistent/bunny.ply",
            "/nonexistent/bunny.ply",
        ),
    ] {
        let mut args: Vec<String> = vec!["hairgen".into()];
        args.extend(words.split_whitespace().map(String::from));
        args.extend(["--out".into(), out.to_string_lossy().into_owned()]);
        let result = rpbrt(&args);
        assert!(!result.status.success(), "{words}: accepted");
        assert!(
            stderr(&result).contains(option),
            "{words}: {}",
            stderr(&result)
        );
    }
    assert!(!out.exists(), "nothing is written for a refused recipe");
    let nowhere = dir.join("no-such-directory").join("x.pbrt");
    let result = rpbrt(&["hairgen", "sphere", "--out", nowhere.to_str().unwrap()]);
    assert!(!result.status.success());
    assert!(
        stderr(&result).contains("no-such-directory"),
        "{}",
        stderr(&result)
    );
}

#[test]
fn fur_roots_follow_the_triangle_areas() {
    // Two triangles in the plane y = 0, areas 3 : 1, on either side of x = 0.
    let dir = temp_dir("areas");
    let mesh = dir.join("two.ply");
    write_ply(
        &mesh,
        &[
            [-3.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [-3.0, 0.0, -2.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, -2.0],
        ],
        &[[0, 1, 2], [1, 3, 4]],
    );
    let out = dir.join("fur.pbrt");
    let n = 20_000;
    hairgen(
        &format!("fur --mesh {} --count {n} --seed 5", mesh.display()),
        &out,
    );
    let curves = curves(&out);
    assert_eq!(curves.len(), n);
    let left = curves.iter().filter(|c| c.points[0][0] < 0.0).count();
    // Binomial: the fraction's standard deviation is sqrt(p(1 − p)/n).
    let fraction = left as f64 / n as f64;
    let sigma = (0.75 * 0.25 / n as f64).sqrt();
    assert!(
        (fraction - 0.75).abs() < 5.0 * sigma,
        "{fraction} of the roots on the triangle with 3/4 of the area (σ = {sigma})"
    );
    for c in &curves {
        assert!(c.points[0][1].abs() < 1e-5, "root off the plane");
        assert!(
            c.points[1][1] > 0.0,
            "fur grows on the counter-clockwise side (+y)"
        );
    }
}

#[test]
fn fur_roots_lie_on_a_pbrt_mesh_and_lean_as_asked() {
    // A tilted square as a pbrt trianglemesh under a transform: the plane
    // z = 0.5 x (before the translation), normal (−0.5, 0, 1)/|·|.
    let dir = temp_dir("lean");
    let mesh = dir.join("square.pbrt");
    std::fs::write(
        &mesh,
        "WorldBegin\nAttributeBegin\nTranslate 0 0 2\n\
         Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0.5  1 1 0.5  0 1 0] \"integer indices\" [0 1 2 0 2 3]\n\
         AttributeEnd\n",
    )
    .unwrap();
    let out = dir.join("fur.pbrt");
    let amount = 0.3;
    hairgen(
        &format!(
            "fur --mesh {} --count 400 --style wavy --gravity 0.5 --lean 0,1,0 --lean-amount {amount} --length 1 --period 0.5",
            mesh.display()
        ),
        &out,
    );
    let normal = normalized([-0.5, 0.0, 1.0]);
    let lean_angle = amount * 90.0;
    for c in curves(&out) {
        let root = c.points[0];
        let relative = sub(root, [0.0, 0.0, 2.0]);
        assert!(
            dot(relative, normal).abs() < 2e-5,
            "root {root:?} off the surface"
        );
        assert!((-1e-5..=1.0 + 1e-5).contains(&relative[0]));
        assert!((-1e-5..=1.0 + 1e-5).contains(&relative[1]));
        let tangent = normalized(sub(c.points[1], root));
        let angle = dot(tangent, normal).clamp(-1.0, 1.0).acos().to_degrees();
        assert!(
            angle <= lean_angle + 0.2 && angle >= lean_angle - 0.2,
            "first tangent {angle}° from the normal, lean {lean_angle}°"
        );
        assert!(tangent[1] > 0.0, "leans towards +y");
        assert!(c.widths.0 > c.widths.1, "tapers from root to tip");
    }
}

#[test]
fn curly_strands_stay_within_their_amplitude() {
    let dir = temp_dir("curly");
    let out = dir.join("curly.pbrt");
    let amplitude = 0.04;
    hairgen(
        &format!(
            "sphere --count 200 --center 1,2,3 --length 0.8 --style curly --amplitude {amplitude} --period 0.15"
        ),
        &out,
    );
    let mut widest: f64 = 0.0;
    for c in curves(&out) {
        let root = c.points[0];
        let axis = normalized(sub(root, [1.0, 2.0, 3.0]));
        for p in curve_points(&c) {
            let r = sub(p, root);
            let across = sub(r, scaled(axis, dot(r, axis)));
            widest = widest.max(length(across));
        }
    }
    assert!(
        widest <= amplitude * 1.02,
        "{widest} from the axis, amplitude {amplitude}"
    );
    assert!(
        widest >= amplitude * 0.9,
        "{widest}: the curls have their amplitude"
    );
}

#[test]
fn fur_grows_on_the_stanford_bunny() {
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/scenes/stanford-bunny/bun_zipper_res3.ply");
    if !bunny.is_file() {
        eprintln!("skipping: {} not found", bunny.display());
        return;
    }
    let dir = temp_dir("bunny");
    let out = dir.join("bunny-fur.pbrt.gz");
    // The bunny's area is about 0.056: some 5600 strands.
    hairgen(
        &format!(
            "fur --mesh {} --density 100000 --length 0.008 --gravity 0.3 --clumps 300 --seed 1",
            bunny.display()
        ),
        &out,
    );
    let curves = curves(&out);
    assert!((5000..6500).contains(&curves.len()), "{}", curves.len());
    // Most strands grow away from the bunny's middle (it is convex enough).
    let n = curves.len() as f64;
    let mut center = [0.0; 3];
    for c in &curves {
        center = [0, 1, 2].map(|i| center[i] + c.points[0][i] / n);
    }
    let outward = curves
        .iter()
        .filter(|c| dot(sub(c.points[1], c.points[0]), sub(c.points[0], center)) > 0.0)
        .count();
    assert!(outward as f64 > 0.8 * n, "{outward} of {n} grow outwards");
    let loaded = rpbrt::scene::load_fragment(&out).expect("loads");
    assert_eq!(
        loaded.scene.shape_counts().get("curve"),
        Some(&curves.len())
    );
}
