//! The hair geometry the paper's scenes include, grown by `rpbrt hairgen`
//! from fixed recipes (so every run makes the same files), and the mesh
//! Fig. 13's fur grows on: the Stanford bunny when it is at hand, else a
//! stand-in made here. The paper renders Cem Yuksel's hair models, which
//! are not redistributable with the project; the recipes aim at the same
//! looks (long wavy hair on a head, curly hair, a fur coat).
//!
//! Units: 1 = 10 cm (the head's radius is 1), except the bunny's fur,
//! which is grown in the PLY's metres and scaled by the scene.

use crate::error::{Error, Result};
use crate::tools::io_error;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// How one generated file is made.
pub struct Recipe {
    /// Its name under `scenes/geometry/`.
    pub file: &'static str,
    /// `rpbrt hairgen` arguments (the output and, for fur, the mesh are
    /// added).
    pub hairgen: &'static [&'static str],
    /// Fur grown on the bunny's mesh (`--mesh` is the bunny).
    pub on_bunny: bool,
}

pub const RECIPES: &[Recipe] = &[
    Recipe {
        file: "head.pbrt.gz",
        // Long wavy hair on a scalp (the top 80° of the head), laid down
        // along it and falling.
        hairgen: &[
            "cap",
            "--seed",
            "1",
            "--count",
            "6000",
            "--radius",
            "1",
            "--cap-angle",
            "80",
            "--length",
            "3.5",
            "--length-variation",
            "0.15",
            "--style",
            "wavy",
            "--amplitude",
            "0.05",
            "--period",
            "1.6",
            "--root-width",
            "0.006",
            "--tip-width",
            "0.004",
            "--gravity",
            "0.9",
            "--lean",
            "0,-1,0",
            "--lean-amount",
            "0.85",
            "--spread",
            "4",
            "--clumps",
            "400",
            "--clumping",
            "0.3",
        ],
        on_bunny: false,
    },
    Recipe {
        file: "curly.pbrt.gz",
        // Curly hair: tight helices, shorter, springier.
        hairgen: &[
            "cap",
            "--seed",
            "2",
            "--count",
            "5000",
            "--radius",
            "1",
            "--cap-angle",
            "80",
            "--length",
            "2.6",
            "--length-variation",
            "0.2",
            "--style",
            "curly",
            "--amplitude",
            "0.1",
            "--period",
            "0.35",
            "--root-width",
            "0.006",
            "--tip-width",
            "0.004",
            "--gravity",
            "0.7",
            "--lean",
            "0,-1,0",
            "--lean-amount",
            "0.7",
            "--spread",
            "10",
        ],
        on_bunny: false,
    },
    Recipe {
        file: "lock.pbrt.gz",
        // Fig. 1's lock: hair hanging from a small crown, no head.
        hairgen: &[
            "cap",
            "--seed",
            "5",
            "--count",
            "2500",
            "--radius",
            "0.35",
            "--center",
            "0,2,0",
            "--cap-angle",
            "40",
            "--length",
            "4.2",
            "--length-variation",
            "0.1",
            "--style",
            "wavy",
            "--amplitude",
            "0.04",
            "--period",
            "1.2",
            "--root-width",
            "0.006",
            "--tip-width",
            "0.004",
            "--gravity",
            "1",
            "--lean",
            "0,-1,0",
            "--lean-amount",
            "0.9",
            "--spread",
            "6",
            "--clumps",
            "60",
            "--clumping",
            "0.3",
        ],
        on_bunny: false,
    },
    Recipe {
        file: "ball.pbrt.gz",
        // Fig. 9's ball of fibres: curly strands all over a small sphere.
        hairgen: &[
            "sphere",
            "--seed",
            "3",
            "--count",
            "2500",
            "--radius",
            "0.3",
            "--length",
            "0.7",
            "--style",
            "curly",
            "--amplitude",
            "0.08",
            "--period",
            "0.35",
            "--root-width",
            "0.008",
            "--tip-width",
            "0.008",
            "--spread",
            "40",
        ],
        on_bunny: false,
    },
    Recipe {
        file: "bunny-fur.pbrt.gz",
        // Short fur combed back and down (the bunny's metres: 8 mm hairs).
        hairgen: &[
            "fur",
            "--seed",
            "4",
            "--count",
            "40000",
            "--length",
            "0.008",
            "--length-variation",
            "0.3",
            "--root-width",
            "0.00025",
            "--tip-width",
            "0.0001",
            "--lean",
            "0,-0.5,-1",
            "--lean-amount",
            "0.35",
            "--gravity",
            "0.15",
            "--spread",
            "12",
        ],
        on_bunny: true,
    },
];

/// The mesh Fig. 13's fur grows on.
#[derive(Clone, Debug, PartialEq)]
pub enum BunnyMesh {
    /// A PLY file (the Stanford bunny).
    Ply(PathBuf),
    /// A lumpy ellipsoid of the bunny's size made here, when no bunny is
    /// at hand.
    StandIn,
}

impl BunnyMesh {
    pub fn description(&self) -> String {
        match self {
            BunnyMesh::Ply(path) => format!("the mesh {}", path.display()),
            BunnyMesh::StandIn => "a stand-in mesh (a lumpy ellipsoid of the bunny's size: \
                 the Stanford bunny was not found; pass --bunny FILE.ply)"
                .into(),
        }
    }
}

/// Where the Stanford bunny is, relative to the working directory, when
/// the shared scene data sits beside the project.
const SHARED_BUNNY: &str = "../shared/scenes/stanford-bunny/bun_zipper_res3.ply";

/// `--bunny` if given, else the shared bunny if present, else the stand-in.
pub fn bunny_mesh(arg: Option<&Path>) -> BunnyMesh {
    match arg {
        Some(path) => BunnyMesh::Ply(path.to_path_buf()),
        None if Path::new(SHARED_BUNNY).is_file() => BunnyMesh::Ply(
            std::fs::canonicalize(SHARED_BUNNY).unwrap_or_else(|_| SHARED_BUNNY.into()),
        ),
        None => BunnyMesh::StandIn,
    }
}

/// Makes `scenes/geometry/FILE` unless it is there from the same recipe
/// (its `FILE.recipe` stamp matches).
pub fn make(recipe: &Recipe, scenes: &Path, bunny: &BunnyMesh) -> Result<()> {
    let dir = scenes.join("geometry");
    let out = dir.join(recipe.file);
    let mut args: Vec<String> = recipe.hairgen.iter().map(|s| s.to_string()).collect();
    if recipe.on_bunny {
        let mesh = write_bunny_mesh(&dir, bunny)?;
        args.push("--mesh".into());
        args.push(mesh.display().to_string());
    }
    args.push("--out".into());
    args.push(out.display().to_string());
    let stamp_path = dir.join(format!("{}.recipe", recipe.file));
    let stamp = format!("rpbrt hairgen {}\n", args.join(" "));
    if out.is_file() && std::fs::read_to_string(&stamp_path).ok().as_deref() == Some(&stamp) {
        return Ok(());
    }
    let parsed = parse_hairgen(args)
        .map_err(|e| Error::Usage(format!("hairgen recipe for {}: {e}", recipe.file)))?;
    crate::tools::hairgen::run(&parsed)?;
    std::fs::write(&stamp_path, stamp).map_err(io_error(&stamp_path))
}

/// `rpbrt hairgen`'s arguments from a recipe's command line (without the
/// command's name).
fn parse_hairgen<S: Into<std::ffi::OsString> + Clone>(
    args: impl IntoIterator<Item = S>,
) -> std::result::Result<crate::tools::hairgen::HairgenArgs, clap::Error> {
    #[derive(clap::Parser)]
    struct Hairgen {
        #[command(flatten)]
        args: crate::tools::hairgen::HairgenArgs,
    }
    let argv = std::iter::once(std::ffi::OsString::from("hairgen"))
        .chain(args.into_iter().map(Into::into));
    <Hairgen as clap::Parser>::try_parse_from(argv).map(|h| h.args)
}

/// Writes `geometry/bunny-mesh.pbrt` (the scene includes it) and returns
/// the file the fur grows on: the PLY itself, or the stand-in's pbrt file.
fn write_bunny_mesh(dir: &Path, bunny: &BunnyMesh) -> Result<PathBuf> {
    let include = dir.join("bunny-mesh.pbrt");
    let (text, mesh) = match bunny {
        BunnyMesh::Ply(path) => {
            if !path.is_file() {
                return Err(Error::Usage(format!(
                    "--bunny: \"{}\" is not a file",
                    path.display()
                )));
            }
            let absolute = std::fs::canonicalize(path).map_err(io_error(path))?;
            (
                format!(
                    "# The mesh Fig. 13's fur grows on.\nShape \"plymesh\" \"string filename\" [ \"{}\" ]\n",
                    absolute.display()
                ),
                absolute,
            )
        }
        BunnyMesh::StandIn => (stand_in_mesh(), include.clone()),
    };
    if std::fs::read_to_string(&include).ok().as_deref() != Some(text.as_str()) {
        std::fs::write(&include, &text).map_err(io_error(&include))?;
    }
    Ok(mesh)
}

/// A stand-in for the bunny: an ellipsoid over the bunny's bounding box
/// (metres), with a head-like bulge, as a pbrt `trianglemesh` with normals.
fn stand_in_mesh() -> String {
    const RINGS: usize = 24;
    const SEGMENTS: usize = 48;
    let centre = [-0.017, 0.105, -0.002];
    let radii = [0.07, 0.07, 0.055];
    let mut points = Vec::new();
    let mut normals = Vec::new();
    for i in 0..=RINGS {
        let theta = std::f64::consts::PI * i as f64 / RINGS as f64;
        for j in 0..SEGMENTS {
            let phi = std::f64::consts::TAU * j as f64 / SEGMENTS as f64;
            let d = [
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ];
            // A bulge up and forward, like a head.
            let bulge = 1.0 + 0.25 * (d[1] * 0.7 + d[0] * 0.7).max(0.0).powi(4);
            points.push([0, 1, 2].map(|k| centre[k] + radii[k] * bulge * d[k]));
            // The normal of the unbulged ellipsoid (close enough for fur).
            let n = [0, 1, 2].map(|k| d[k] / radii[k]);
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            normals.push(n.map(|v| v / len));
        }
    }
    let mut indices = Vec::new();
    for i in 0..RINGS {
        for j in 0..SEGMENTS {
            let a = i * SEGMENTS + j;
            let b = i * SEGMENTS + (j + 1) % SEGMENTS;
            let (c, d) = (a + SEGMENTS, b + SEGMENTS);
            // Counter-clockwise seen from outside.
            indices.extend([a, b, c, b, d, c]);
        }
    }
    let mut s = String::from(
        "# A stand-in for the Stanford bunny (not found): an ellipsoid of its size\n\
         # with a bulge for a head, made by rpbrt reproduce.\nShape \"trianglemesh\"\n  \"point3 P\" [",
    );
    for p in &points {
        let _ = write!(s, " {:.5} {:.5} {:.5}", p[0], p[1], p[2]);
    }
    s.push_str(" ]\n  \"normal N\" [");
    for n in &normals {
        let _ = write!(s, " {:.4} {:.4} {:.4}", n[0], n[1], n[2]);
    }
    s.push_str(" ]\n  \"integer indices\" [");
    for i in &indices {
        let _ = write!(s, " {i}");
    }
    s.push_str(" ]\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stand_in_is_a_valid_closed_mesh() {
        let text = stand_in_mesh();
        let loaded =
            crate::scene::load_text(Path::new("stand-in.pbrt"), &format!("WorldBegin\n{text}"))
                .unwrap();
        assert_eq!(loaded.scene.shape_counts()["trianglemesh"], 1);
    }

    #[test]
    fn recipes_parse_as_hairgen_command_lines() {
        for recipe in RECIPES {
            let mut args: Vec<&str> = recipe.hairgen.to_vec();
            if recipe.on_bunny {
                args.extend(["--mesh", "bunny.ply"]);
            }
            args.extend(["--out", "x.pbrt.gz"]);
            if let Err(e) = parse_hairgen(args) {
                panic!("{}: {e}", recipe.file);
            }
        }
    }
}
