//! Malformed scenes: each gives its own error message at the right
//! line:col, and nothing panics.

use rpbrt::scene;
use std::path::{Path, PathBuf};

/// (scene text, expected line:col, text the message must contain)
const CASES: &[(&str, &str, &str)] = &[
    // Tokens.
    ("WorldBegin\nShapee \"sphere\"", "2:1", "unknown directive \"Shapee\""),
    ("WorldBegin\n  Shape \"sphere", "2:9", "unterminated string"),
    ("WorldBegin\nShape \"sphere\" \"float radius\" [ 1.2.3 ]", "2:33", "bad number \"1.2.3\""),
    ("WorldBegin\nShape \"sphere\" \"float radius\" 2x", "2:31", "bad number \"2x\""),
    ("Translate 1 2 nan", "1:1", "expected 3 numbers, found 2"),
    ("WorldBegin\n[ 1 2 ]", "2:1", "expected a directive, found \"[\""),
    ("WorldBegin\nShape \"sphere\" \"float radius\" [ 1 2", "2:31", "'[' is never closed: the file ends at line 2, column 36 with no ']'"),
    ("WorldBegin\nShape \"sphere\" \"float radius\" [ 1\n\n", "2:31", "'[' is never closed: the file ends at line 4, column 1"),
    ("WorldBegin\nShape \"sphere\" \"float radius\" [ 1\n\nAttributeBegin\n", "4:1", "expected a value or ']', found \"AttributeBegin\" (in the list that '[' opens at line 2, column 31)"),
    ("WorldBegin\nShape \"x\" \"string a\" [ \"b\"\n  \"float r\" [ 1 ]", "3:13", "found \"[\" (in the list that '[' opens at line 2, column 22)"),
    ("Translate [ 1 2 3\nWorldBegin", "2:1", "expected a number or ']', found \"WorldBegin\" (in the list that '[' opens at line 1, column 11)"),
    ("LookAt [ 0 0 1  0 0 0  0 1 0\n", "1:8", "'[' is never closed: the file ends at line 2, column 1"),
    // Parameter declarations and values.
    ("WorldBegin\nShape \"sphere\" \"float\" 1", "2:16", "malformed parameter declaration \"float\""),
    ("WorldBegin\nShape \"sphere\" \"floaty radius\" 1", "2:16", "unknown parameter type \"floaty\""),
    ("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 ]", "2:22", "4 values given, expected a multiple of 3"),
    ("WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [ .5 .5 ]", "2:20", "2 values given, expected a multiple of 3"),
    ("WorldBegin\nShape \"trianglemesh\" \"integer indices\" [ 0 1 2.5 ]", "2:22", "2.5 is not an integer"),
    ("WorldBegin\nShape \"sphere\" \"float radius\" [ 1 \"two\" ]", "2:35", "mixed values in one list"),
    ("WorldBegin\nShape \"sphere\" \"float radius\" \"one\"", "2:16", "expected numeric values"),
    ("WorldBegin\nLightSource \"infinite\" \"spectrum L\" [ 300 1 400 ]", "2:24", "3 values given, expected a multiple of 2"),
    ("Option \"bool disablepixeljitter\" 1\nWorldBegin", "1:8", "expected bool (true or false) values"),
    ("Transform [ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 ]\nWorldBegin", "1:1", "expected 16 numbers, found 15"),
    ("ActiveTransform Sometimes\nWorldBegin", "1:17", "expected StartTime, EndTime or All"),
    // Blocks and nesting.
    ("Shape \"sphere\"\nWorldBegin", "1:1", "\"Shape\" is only allowed inside the world block"),
    ("WorldBegin\nCamera \"perspective\"", "2:1", "\"Camera\" is not allowed after WorldBegin"),
    ("Import \"geometry.pbrt\"\nWorldBegin", "1:1", "Import is only allowed inside the world block"),
    ("WorldBegin\nAttributeEnd", "2:1", "unmatched AttributeEnd"),
    ("WorldBegin\nObjectEnd", "2:1", "ObjectEnd outside an object definition"),
    ("WorldBegin\nObjectBegin \"a\"\nObjectBegin \"b\"", "3:1", "objects cannot nest"),
    ("Camera \"perspective\"", "1:1", "end of file before WorldBegin"),
    // Types and parameters.
    ("WorldBegin\nShape \"spheer\"", "2:1", "unknown shape type \"spheer\""),
    ("WorldBegin\nShape \"sphere\"\n    \"float raduis\" 1", "3:5", "\"float raduis\": unused parameter"),
    ("WorldBegin\nShape \"sphere\" \"integer radius\" 1", "2:16", "\"integer radius\": parameter \"radius\" has the wrong type; expected float"),
    // The check of a shape like the one before is skipped; one that differs in a type,
    // a name or an attribute is checked.
    ("WorldBegin\nShape \"sphere\" \"float radius\" 1\nShape \"sphere\" \"float radius\" 2\nShape \"sphere\" \"integer radius\" 1", "4:16", "\"integer radius\": parameter \"radius\" has the wrong type; expected float"),
    ("WorldBegin\nShape \"sphere\" \"float radius\" 1\nShape \"sphere\" \"float radius\" 2\nShape \"sphere\" \"float radius\" 1 \"float raduis\" 1", "4:33", "\"float raduis\": unused parameter"),
    ("WorldBegin\nShape \"sphere\" \"float radius\" 1\nAttribute \"shape\" \"integer radius\" 1\nShape \"sphere\" \"float zmin\" 1", "3:19", "\"integer radius\": parameter \"radius\" has the wrong type; expected float"),
    ("WorldBegin\nShape \"sphere\" \"float zmax\" 1\nShape \"disk\" \"float zmax\" 1", "3:14", "\"float zmax\": unused parameter (not a parameter of shape \"disk\")"),
    // Parameters pbrt-v4 has for some types of a family but not this one.
    ("Sampler \"independent\" \"integer randomization\" 2\nWorldBegin", "1:23", "\"integer randomization\": unused parameter (not a parameter of sampler \"independent\")"),
    ("Sampler \"stratified\"\n  \"integer pixelsamples\" 4\nWorldBegin", "2:3", "\"integer pixelsamples\": unused parameter"),
    ("Integrator \"ambientocclusion\" \"integer maxdepth\" 5\nWorldBegin", "1:31", "\"integer maxdepth\": unused parameter"),
    ("WorldBegin\nLightSource \"distant\" \"float power\" 2", "2:23", "\"float power\": unused parameter"),
    ("WorldBegin\nTexture \"t\" \"float\" \"constant\" \"float uscale\" 2", "2:32", "\"float uscale\": unused parameter (not a parameter of texture \"constant\")"),
    ("WorldBegin\nTexture \"t\" \"float\" \"checkerboard\" \"integer dimension\" 3 \"float vscale\" 2", "2:58", "\"float vscale\": unused parameter"),
    ("WorldBegin\nTexture \"t\" \"spectrum\" \"imagemap\" \"string mapping\" \"spherical\"\n    \"float udelta\" 0.5", "3:5", "\"float udelta\": unused parameter"),
    ("WorldBegin\nTexture \"t\" \"float\" \"imagemap\" \"vector3 v1\" [ 1 0 0 ]", "2:32", "\"vector3 v1\": unused parameter"),
    ("WorldBegin\nShape \"bilinearmesh\" \"vector3 S\" [ 1 0 0 ]", "2:22", "\"vector3 S\": unused parameter"),
    ("WorldBegin\nMakeNamedMaterial \"m\" \"rgb reflectance\" [ 1 1 1 ]", "2:1", "\"string type\" not provided"),
    ("WorldBegin\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\"\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\"", "3:1", "named material \"m\" redefined"),
    ("WorldBegin\nTexture \"t\" \"colour\" \"constant\"", "2:1", "texture type \"colour\" unknown"),
    ("WorldBegin\nAttribute \"camera\" \"float fov\" 30", "2:1", "unknown Attribute target \"camera\""),
    ("Option \"bogus\" 3\nWorldBegin", "1:8", "unknown option \"bogus\""),
    ("WorldBegin\nRotate 30 0 0 0", "2:1", "Rotate needs a non-zero axis"),
    ("LookAt 0 0 1  0 0 0  0 0 1\nWorldBegin", "1:1", "up vector is parallel"),
    ("ColorSpace \"srgbb\"\nWorldBegin", "1:1", "unknown colour space \"srgbb\""),
    // References resolved at the end.
    ("WorldBegin\nNamedMaterial \"nothing\"\nShape \"sphere\"", "3:1", "NamedMaterial \"nothing\" is not defined"),
    ("WorldBegin\nObjectInstance \"nothing\"", "2:1", "object \"nothing\" is not defined"),
    ("WorldBegin\nMaterial \"diffuse\" \"texture reflectance\" \"nothing\"", "2:20", "texture \"nothing\" is not defined"),
    ("WorldBegin\nMediumInterface \"fog\" \"\"\nShape \"sphere\"", "3:1", "medium \"fog\" is not defined"),
];

/// Checks one case; a description of what is wrong, if anything.
fn try_case(name: &Path, text: &str, at: &str, message: &str) -> Result<(), String> {
    let result = std::panic::catch_unwind(|| scene::load_text(name, text));
    let Ok(result) = result else {
        return Err(format!("panicked on {text:?}"));
    };
    let Err(error) = result else {
        return Err(format!("no error for {text:?}"));
    };
    let printed = error.to_string();
    let first = printed.lines().next().unwrap_or("");
    let expected_location = format!("{}:{at}:", name.display());
    if !first.starts_with(&expected_location) {
        return Err(format!(
            "{text:?}: expected the error at {expected_location}, got:\n{printed}"
        ));
    }
    if !first.contains(message) {
        return Err(format!("{text:?}: expected \"{message}\" in:\n{printed}"));
    }
    // The offending line is shown with a caret under the column.
    let mut lines = printed.lines();
    lines.next();
    if !(lines.next().is_some() && lines.next().is_some_and(|l| l.trim_end().ends_with('^'))) {
        return Err(format!("no caret excerpt in:\n{printed}"));
    }
    Ok(())
}

fn check(name: &Path, text: &str, at: &str, message: &str) {
    if let Err(e) = try_case(name, text, at, message) {
        panic!("{e}");
    }
}

#[test]
fn each_malformed_input_gives_its_error_at_its_location() {
    assert!(CASES.len() >= 25);
    let failures: Vec<String> = CASES
        .iter()
        .filter_map(|(text, at, message)| try_case(Path::new("bad.pbrt"), text, at, message).err())
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n\n{}",
        failures.len(),
        CASES.len(),
        failures.join("\n\n")
    );
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rpbrt-malformed-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn missing_and_cyclic_includes() {
    let dir = temp_dir("includes");
    let main = dir.join("main.pbrt");
    check(
        &main,
        "WorldBegin\n  Include \"absent.pbrt\"",
        "2:3",
        "cannot read",
    );
    std::fs::write(dir.join("a.pbrt"), "Include \"b.pbrt\"\n").unwrap();
    std::fs::write(dir.join("b.pbrt"), "\n\nInclude \"a.pbrt\"\n").unwrap();
    let b = dir.join("b.pbrt");
    let error = scene::load_text(&main, "WorldBegin\nInclude \"a.pbrt\"")
        .err()
        .unwrap()
        .to_string();
    assert!(
        error.starts_with(&format!("{}:3:1:", b.display())),
        "{error}"
    );
    assert!(error.contains("cyclic"), "{error}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn errors_inside_gzipped_includes_point_into_them() {
    use std::io::Write;
    let dir = temp_dir("gz");
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    gz.write_all(b"Shape \"sphere\"\n Shape \"sphere\" \"float radius\" [ 1 oops ]\n")
        .unwrap();
    std::fs::write(dir.join("geometry.pbrt.gz"), gz.finish().unwrap()).unwrap();
    let error = scene::load_text(
        &dir.join("main.pbrt"),
        "WorldBegin\nInclude \"geometry.pbrt.gz\"",
    )
    .err()
    .unwrap()
    .to_string();
    assert!(
        error.contains("geometry.pbrt.gz:2:36: expected a value or ']', found \"oops\""),
        "{error}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The error for a scene that names a file the system will not read: its
/// first line, or why the scene did not fail.
fn unreadable_file_error(path: &Path, text: &str) -> Result<String, String> {
    std::fs::write(path, text).map_err(|e| e.to_string())?;
    let built = std::panic::catch_unwind(|| {
        let loaded = scene::load(path)?;
        scene::build::build(loaded.scene, &Default::default()).map(|_| ())
    })
    .map_err(|_| format!("panicked on {text:?}"))?;
    match built {
        Ok(()) => Err(format!("no error for {text:?}")),
        Err(e) => Ok(e.to_string().lines().next().unwrap_or("").to_string()),
    }
}

/// Every kind of file a scene names (PLY meshes, image textures,
/// environment maps, spectrum files), missing or a directory, is reported
/// at the parameter that names it, with the path and the system's reason.
#[test]
fn unreadable_files_are_reported_where_the_scene_names_them() {
    let dir = temp_dir("files");
    std::fs::create_dir_all(dir.join("folder.ply")).unwrap();
    std::fs::create_dir_all(dir.join("folder.png")).unwrap();
    let header = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n\
                  Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4\nWorldBegin\n";
    // (world text, line:col, file named, text the first line must contain)
    let cases = [
        ("Shape \"plymesh\" \"string filename\" \"nowhere.ply\"", "5:17", "nowhere.ply", "No such file"),
        ("AttributeBegin\n  Shape \"plymesh\"\n    \"string filename\" \"nowhere.ply.gz\"", "7:5", "nowhere.ply.gz", "No such file"),
        ("Shape \"plymesh\" \"string filename\" \"folder.ply\"", "5:17", "folder.ply", "directory"),
        ("Texture \"t\" \"spectrum\" \"imagemap\"\n  \"string filename\" \"nowhere.png\"\nMaterial \"diffuse\" \"texture reflectance\" \"t\"\nShape \"sphere\"", "6:3", "nowhere.png", "No such file"),
        ("Texture \"t\" \"float\" \"imagemap\" \"string filename\" \"folder.png\"\nShape \"sphere\" \"texture alpha\" \"t\"", "5:32", "folder.png", "directory"),
        ("LightSource \"infinite\" \"string filename\" \"nowhere.exr\"", "5:24", "nowhere.exr", "No such file"),
        ("Material \"conductor\" \"spectrum eta\" \"nowhere.spd\" \"spectrum k\" \"metal-Cu-k\"\nShape \"sphere\"", "5:22", "nowhere.spd", "No such file"),
        ("LightSource \"point\" \"spectrum I\" \"nowhere.spd\"", "5:21", "nowhere.spd", "No such file"),
    ];
    let path = dir.join("scene.pbrt");
    let failures: Vec<String> = cases
        .iter()
        .filter_map(|(world, at, file, reason)| {
            let first = match unreadable_file_error(&path, &format!("{header}{world}\n")) {
                Ok(first) => first,
                Err(e) => return Some(e),
            };
            let at = format!("{}:{at}:", path.display());
            let named = dir.join(file).display().to_string();
            let ok = first.starts_with(&at) && first.contains(&named) && first.contains(reason);
            (!ok).then(|| {
                format!("{world:?}: expected {at} ... {named} ... {reason}, got:\n{first}")
            })
        })
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    std::fs::remove_dir_all(&dir).ok();
}
