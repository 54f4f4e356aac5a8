//! `Shape "cyhair"` and `rpbrt cyhair2pbrt`: a converted file (plain and
//! gzip) gives the same curve segments as the shape, bit for bit, and the
//! same image byte for byte (both bases, constant and varying thickness,
//! every optional array present and absent, 20,000 strands); the
//! converter's errors; each strand of a cyhair file its own fibre frame.
mod common;
use common::rpbrt;

use rpbrt::scene::build::{build, BuiltScene, RenderOverrides};
use rpbrt::shapes::curve::CurveSegment;
use rpbrt::shapes::cyhair::{hair_bytes, HairFile};
use std::path::{Path, PathBuf};

fn temp_dir(name: &str) -> PathBuf {
    common::fresh_dir("cyhair-it", name)
}

/// A small deterministic generator (no dependency for tests).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// `strands` wavy strands of `segments` segments each (or 1 to
/// `segments`, and some of a single point, when `varying_segments`) in
/// about [-1, 1]³, with a thickness array of varying values when
/// `varying_thickness` (else the header's default), and the other
/// optional arrays when `extras`.
fn make_hair(
    strands: usize,
    segments: u32,
    varying_segments: bool,
    varying_thickness: bool,
    extras: bool,
    seed: u64,
) -> HairFile {
    let mut rng = Rng(seed);
    let mut hair = HairFile {
        segments: Vec::new(),
        points: Vec::new(),
        thickness: None,
        default_thickness: 0.03,
        transparency: None,
        default_transparency: 0.5,
        colour: None,
        default_colour: [0.4, 0.3, 0.2],
    };
    let mut thickness = Vec::new();
    for k in 0..strands {
        let n = if varying_segments {
            // Every 7th strand a single point (it draws nothing).
            if k % 7 == 3 {
                0
            } else {
                1 + (rng.uniform() * segments as f32) as u32 % segments
            }
        } else {
            segments
        };
        hair.segments.push(n);
        let root = [
            2.0 * rng.uniform() - 1.0,
            -1.0 + 0.2 * rng.uniform(),
            2.0 * rng.uniform() - 1.0,
        ];
        let phase = 6.0 * rng.uniform();
        for i in 0..=n {
            let t = i as f32 / segments as f32;
            hair.points.push([
                root[0] + 0.15 * (phase + 5.0 * t).sin(),
                root[1] + 1.8 * t,
                root[2] + 0.15 * (phase + 5.0 * t).cos(),
            ]);
            thickness.push(0.02 + 0.03 * rng.uniform());
        }
    }
    let n = hair.points.len();
    if varying_thickness {
        hair.thickness = Some(thickness);
    }
    if extras {
        hair.transparency = Some((0..n).map(|i| (i % 10) as f32 / 10.0).collect());
        hair.colour = Some((0..n).map(|i| [(i % 3) as f32 / 3.0, 0.5, 0.25]).collect());
    }
    hair
}

fn write_hair(path: &Path, hair: &HairFile, segments_array: bool) {
    std::fs::write(path, hair_bytes(hair, segments_array).unwrap()).unwrap();
}

/// Runs `rpbrt cyhair2pbrt IN OUT OPTIONS…`; its stdout.
fn convert(input: &Path, output: &Path, options: &[&str]) -> String {
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "cyhair2pbrt".as_ref(),
        input.as_os_str(),
        output.as_os_str(),
    ];
    args.extend(options.iter().map(std::ffi::OsStr::new));
    let out = rpbrt(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

const HEADER: &str = "LookAt 0.3 0.2 4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n\
Film \"rgb\" \"integer xresolution\" 48 \"integer yresolution\" 32 \"string filename\" \"out.exr\"\n\
Sampler \"zsobol\"\nWorldBegin\nLightSource \"infinite\" \"rgb L\" [0.8 0.9 1]\n\
LightSource \"distant\" \"point3 from\" [1 2 3] \"blackbody L\" 5500 \"float scale\" 3\n";

/// A scene of `geometry` (a `Shape` line or an `Include`) under `material`
/// and a transform, written in `dir` as `name`.
fn scene_file(dir: &Path, name: &str, material: &str, geometry: &str) -> PathBuf {
    let text =
        format!("{HEADER}AttributeBegin\n{material}\nRotate 20 0 1 0\nScale 1.1 0.9 1.0\n{geometry}\nAttributeEnd\n");
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn built(path: &Path) -> BuiltScene {
    let loaded = rpbrt::scene::load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    build(loaded.scene, &RenderOverrides::default())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The segments' control points, widths and type, bit for bit (not their
/// strand starts: a file written a curve per segment starts a strand at
/// each).
fn assert_same_segments(a: &[CurveSegment], b: &[CurveSegment], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: segment counts");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        let bits = |s: &CurveSegment| {
            (
                s.cp.map(|p| p.to_array().map(f32::to_bits)),
                s.width.map(f32::to_bits),
            )
        };
        assert_eq!(bits(x), bits(y), "{what}: segment {i}");
        assert_eq!(
            (x.kind, x.flip_normal),
            (y.kind, y.flip_normal),
            "{what}: {i}"
        );
    }
}

fn render(scene: &Path, out: &Path) -> Vec<u8> {
    let overrides = RenderOverrides {
        spp: Some(4),
        outfile: Some(out.to_path_buf()),
        ..Default::default()
    };
    let report = rpbrt::pipeline::render_file(scene, &overrides, 2, false).unwrap();
    assert_eq!(report.bad_samples, 0);
    std::fs::read(out).unwrap()
}

/// Both bases, constant and varying thickness (one curve per strand, and
/// a curve per segment), a width override and the cylinder type: the
/// `cyhair` shape and the converted file (plain and gzip) give the same
/// segments bit for bit and the same image byte for byte.
#[test]
fn converted_files_render_what_the_shape_renders() {
    let dir = temp_dir("roundtrip");
    let material = "Material \"hair\" \"float eumelanin\" 0.8";
    for (case, (basis, varying, options)) in [
        ("catmullrom", false, ""),
        ("polyline", false, ""),
        ("catmullrom", true, ""),
        ("polyline", true, " --type cylinder --scale 1.3"),
        ("catmullrom", true, " --width 0.04 --scale 0.9"),
    ]
    .into_iter()
    .enumerate()
    {
        let hair = make_hair(40, 6, varying, varying, varying, 11 + case as u64);
        let input = dir.join(format!("h{case}.hair"));
        write_hair(&input, &hair, varying);
        let mut args = vec!["--basis", basis];
        args.extend(options.split_whitespace());
        let plain = dir.join(format!("h{case}.pbrt"));
        let gz = dir.join(format!("h{case}.pbrt.gz"));
        let summary = convert(&input, &plain, &args);
        convert(&input, &gz, &args);
        // Constant widths: one curve per strand; a varying thickness (no
        // override) needs a curve per segment.
        let whole = !varying || options.contains("--width");
        assert_eq!(
            summary.contains(" 0 a curve per segment"),
            whole,
            "{case}: {summary}"
        );
        let text = std::fs::read_to_string(&plain).unwrap();
        assert!(
            text.starts_with("# ") && text.contains(&format!("basis {basis}")),
            "{text:.300}"
        );
        assert!(text.contains("\"string basis\" [ \"bezier\" ]"));

        // The shape with the same parameters.
        let value = |flag: &str| {
            options
                .split_whitespace()
                .skip_while(|o| *o != flag)
                .nth(1)
                .map(str::to_string)
        };
        let mut params =
            format!("\"string filename\" \"h{case}.hair\" \"string basis\" \"{basis}\"");
        if let Some(kind) = value("--type") {
            params += &format!(" \"string type\" \"{kind}\"");
        }
        if let Some(scale) = value("--scale") {
            params += &format!(" \"float scale\" {scale}");
        }
        if let Some(width) = value("--width") {
            params += &format!(" \"float width\" {width}");
        }
        let shape = scene_file(
            &dir,
            "shape.pbrt",
            material,
            &format!("Shape \"cyhair\" {params}"),
        );
        let included = scene_file(
            &dir,
            "plain.pbrt",
            material,
            &format!("Include \"h{case}.pbrt\""),
        );
        let included_gz = scene_file(
            &dir,
            "gz.pbrt",
            material,
            &format!("Include \"h{case}.pbrt.gz\""),
        );
        let reference = built(&shape);
        assert!(!reference.shapes.curve_segments.is_empty());
        for other in [&included, &included_gz] {
            assert_same_segments(
                &reference.shapes.curve_segments,
                &built(other).shapes.curve_segments,
                &format!("{case} {basis} {options}"),
            );
        }
        if case < 4 {
            let a = render(&shape, &dir.join("shape.exr"));
            let b = render(&included_gz, &dir.join("gz.exr"));
            assert!(a == b, "{case}: the images differ");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// 20,000 strands, with and without the segments array and every other
/// optional array: the converted file has the shape's segments.
#[test]
fn big_files_with_and_without_optional_arrays_convert() {
    let dir = temp_dir("big");
    for (k, (segments_array, thickness, extras)) in [(false, false, false), (true, true, true)]
        .into_iter()
        .enumerate()
    {
        let hair = make_hair(20_000, 3, segments_array, thickness, extras, 5 + k as u64);
        let input = dir.join(format!("big{k}.hair"));
        write_hair(&input, &hair, segments_array);
        let output = dir.join(format!("big{k}.pbrt.gz"));
        convert(&input, &output, &["--basis", "polyline"]);
        let material = "Material \"hair\"";
        let shape = scene_file(
            &dir,
            "shape.pbrt",
            material,
            &format!("Shape \"cyhair\" \"string filename\" \"big{k}.hair\" \"string basis\" \"polyline\""),
        );
        let included = scene_file(
            &dir,
            "inc.pbrt",
            material,
            &format!("Include \"big{k}.pbrt.gz\""),
        );
        let a = built(&shape);
        let b = built(&included);
        let expected: u32 = hair.segments.iter().sum();
        assert_eq!(a.shapes.curve_segments.len(), expected as usize);
        assert_same_segments(&a.shapes.curve_segments, &b.shapes.curve_segments, "big");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A missing or broken input names the file and the byte and writes
/// nothing; an unwritable output names the output; bad options are
/// refused.
#[test]
fn converter_errors_are_located_and_leave_no_file() {
    let dir = temp_dir("errors");
    let hair = make_hair(3, 2, false, true, false, 3);
    let good = hair_bytes(&hair, true).unwrap();
    let broken = dir.join("broken.hair");
    std::fs::write(&broken, &good[..good.len() - 5]).unwrap();
    let output = dir.join("out.pbrt");
    let run = |input: &Path, output: &Path, extra: &[&str]| {
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "cyhair2pbrt".as_ref(),
            input.as_os_str(),
            output.as_os_str(),
        ];
        args.extend(extra.iter().map(std::ffi::OsStr::new));
        let out = rpbrt(&args);
        assert!(!out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let e = run(&broken, &output, &[]);
    assert!(
        e.contains("broken.hair")
            && e.contains("byte ")
            && e.contains("inside the thickness array"),
        "{e}"
    );
    let e = run(&dir.join("missing.hair"), &output, &[]);
    assert!(
        e.contains("missing.hair") && e.contains("cannot read"),
        "{e}"
    );
    let good_path = dir.join("good.hair");
    std::fs::write(&good_path, &good).unwrap();
    let nowhere = dir.join("no-such-directory").join("out.pbrt");
    let e = run(&good_path, &nowhere, &[]);
    assert!(e.contains("no-such-directory/out.pbrt"), "{e}");
    let e = run(&good_path, &output, &["--scale", "0"]);
    assert!(e.contains("\"scale\" must be > 0"), "{e}");
    let e = run(&good_path, &output, &["--type", "ribbon"]);
    assert!(e.contains("ribbon"), "{e}");
    // Nothing written, no temporary left.
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("pbrt"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two strands in one cyhair file get the frames two `Shape "curve"`s get
/// (each transported from its own first tangent); with `ellipse_random`
/// each strand is turned by its own angle, `strand_angle(offset, k)`.
#[test]
fn each_strand_of_a_cyhair_file_has_its_own_fibre_frame() {
    use rpbrt::shapes::curve::frame::strand_angle;
    let dir = temp_dir("frames");
    let hair = make_hair(2, 5, false, false, false, 9);
    write_hair(&dir.join("two.hair"), &hair, true);
    convert(&dir.join("two.hair"), &dir.join("two.pbrt"), &[]);
    let text = std::fs::read_to_string(dir.join("two.pbrt")).unwrap();
    assert_eq!(text.matches("Shape \"curve\"").count(), 2);
    let elliptical = "Material \"hair\" \"float ellipse_a\" 30 \"float ellipse_b\" 20";
    let shape = "Shape \"cyhair\" \"string filename\" \"two.hair\"";
    let references = |material: &str, geometry: &str| {
        let scene = built(&scene_file(&dir, "frames.pbrt", material, geometry));
        let segments = scene.shapes.curve_segments;
        assert_eq!(segments.len(), 10);
        assert!(segments.iter().all(|s| s.fibre_frame));
        segments
    };
    let cyhair = references(elliptical, shape);
    let curves = references(elliptical, "Include \"two.pbrt\"");
    let bits = |s: &CurveSegment| s.reference.map(|r| r.to_array().map(f32::to_bits));
    for (i, (a, b)) in cyhair.iter().zip(&curves).enumerate() {
        assert_eq!(bits(a), bits(b), "segment {i}");
    }
    // The second strand starts afresh: its first reference is not the
    // first strand's last carried on.
    assert_eq!(
        cyhair.iter().map(|s| s.strand_start).collect::<Vec<_>>(),
        [true, false, false, false, false, true, false, false, false, false]
    );

    // ellipse_random: strand k's start is the transported one turned by
    // its angle.
    let random = format!("{elliptical} \"bool ellipse_random\" true");
    let turned = references(&random, shape);
    let offset = std::fs::read_to_string(dir.join("frames.pbrt"))
        .unwrap()
        .find(shape)
        .unwrap();
    let mut cosines = Vec::new();
    for (k, first) in [0, 5].into_iter().enumerate() {
        let cos = turned[first].reference[0].dot(cyhair[first].reference[0]);
        let expected = strand_angle(offset, k).cos();
        assert!(
            (cos - expected).abs() < 1e-4,
            "strand {k}: {cos} {expected}"
        );
        cosines.push(cos);
    }
    assert!((cosines[0] - cosines[1]).abs() > 1e-3, "{cosines:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The dual model's diffracting ring needs a curve: a cyhair shape is one.
#[test]
fn a_diffracting_ring_accepts_cyhair_strands() {
    let dir = temp_dir("ring");
    write_hair(
        &dir.join("ring.hair"),
        &make_hair(2, 3, false, false, false, 1),
        true,
    );
    let scene = built(&scene_file(
        &dir,
        "ring.pbrt",
        "Material \"hair\" \"float ellipse_a\" 30 \"float ellipse_b\" 20 \"float d_diff\" 0.4",
        "Shape \"cyhair\" \"string filename\" \"ring.hair\"",
    ));
    // Widened by 1 + d_diff.
    let w = scene.shapes.curve_segments[0].width[0];
    assert!(
        (w - 0.03 * 1.4 * 1.1f32.powf(1.0 / 3.0) * 0.9f32.powf(1.0 / 3.0)).abs() < 1e-4,
        "{w}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
