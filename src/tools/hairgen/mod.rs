//! `rpbrt hairgen sphere|cap|fur [options] --out FILE`: hair or fur grown
//! from a recipe and written as pbrt-v4 curves, the same bytes for the
//! same recipe and seed ([docs/hairgen.md](../../../docs/hairgen.md)).
//!
//! | option | default | meaning |
//! |---|---|---|
//! | `--out FILE` | required | `.pbrt`, or `.pbrt.gz` (gzip) |
//! | `--seed S` | 0 | random seed |
//! | `--count N` | 5000 (sphere, cap); fur: from `--density`, else 20000 | strands |
//! | `--density D` | (fur) | strands per unit area of the mesh (instead of `--count`) |
//! | `--radius R`, `--center X,Y,Z` | 1, 0,0,0 | the sphere (sphere, cap) |
//! | `--cap-angle DEG` | 70 | cap: roots within this angle of the top (the pole opposite `--down`) |
//! | `--mesh FILE` | required (fur) | a `.ply`, or a `.pbrt` whose meshes are read (see `mesh.rs`) |
//! | `--flip-normals` | off | fur: grow from the other side of the mesh |
//! | `--length L` | sphere 0.5·R, cap 1.5·R, fur 5 % of the mesh's bounding-box diagonal | length along the strand's axis |
//! | `--length-variation V` | 0.2 | lengths uniform in [(1 − V)·L, L] (at least L/100) |
//! | `--style` | straight | `straight`, `wavy` (planar sine), `curly` (helix) |
//! | `--amplitude A` | L/20 | the wave's amplitude, the helix's radius |
//! | `--period P` | L/5 | the wave's or helix's period along the axis |
//! | `--root-width W`, `--tip-width W` | L/200, root/4 | curve width at the root and tip (linear taper) |
//! | `--gravity G` | 0 | in [0, 1]: how far the tip turns towards `--down` |
//! | `--down X,Y,Z` | 0,-1,0 | gravity's direction (and the cap's bottom) |
//! | `--lean X,Y,Z`, `--lean-amount A` | 0,0,0, 0 | comb direction, tilt A·90° from the normal towards it |
//! | `--spread DEG` | 0 | random tilt of each strand within this cone |
//! | `--clumps K`, `--clumping C` | 0, 0.5 | K clumps; C in [0, 1]: tips pulled C of the way to their clump's guide |
//! | `--segments N` | auto | Bézier segments per strand: 1 for straight strands that do not bend, 4 when they bend, at least six per period for wavy and curly (≥ 4, ≤ 1000) |
//!
//! Files: `strand.rs` (one strand's shape), `roots.rs` (roots and growth
//! directions, random streams), `mesh.rs` (reading the fur's mesh),
//! `clump.rs` (clump guides), `write.rs` (the pbrt text).

mod clump;
mod mesh;
mod roots;
mod strand;
mod write;

pub use strand::Style;

use crate::error::{Error, Result};
use glam::DVec3;
use roots::{Lean, Random, Surface, TriangleSet};
use std::fmt::Write as _;
use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};
use strand::{Recipe, Samples, Strand};

/// Grows hair or fur and writes it as pbrt-v4 curves.
#[derive(clap::Args, Debug)]
pub struct HairgenArgs {
    #[command(subcommand)]
    pub surface: HairgenSurface,
}

/// What the strands grow on.
#[derive(clap::Subcommand, Debug)]
pub enum HairgenSurface {
    /// Strands all over a sphere.
    Sphere(SphereArgs),
    /// Strands on a head-like cap: the top of a sphere, a scalp.
    Cap(CapArgs),
    /// Fur on a triangle mesh (a PLY, or the meshes of a pbrt file).
    Fur(FurArgs),
}

/// `hairgen sphere`.
#[derive(clap::Args, Debug)]
pub struct SphereArgs {
    /// Number of strands.
    #[arg(long, default_value_t = 5000)]
    pub count: u64,
    /// The sphere's radius.
    #[arg(long, default_value_t = 1.0)]
    pub radius: f64,
    /// The sphere's center, X,Y,Z.
    #[arg(long, default_value = "0,0,0", value_parser = parse_vector, allow_hyphen_values = true)]
    pub center: DVec3,
    #[command(flatten)]
    pub strands: StrandArgs,
}

/// `hairgen cap`.
#[derive(clap::Args, Debug)]
pub struct CapArgs {
    /// Number of strands.
    #[arg(long, default_value_t = 5000)]
    pub count: u64,
    /// The sphere's radius.
    #[arg(long, default_value_t = 1.0)]
    pub radius: f64,
    /// The sphere's center, X,Y,Z.
    #[arg(long, default_value = "0,0,0", value_parser = parse_vector, allow_hyphen_values = true)]
    pub center: DVec3,
    /// Roots lie within this angle (degrees) of the sphere's top, the pole
    /// opposite --down.
    #[arg(long, default_value_t = 70.0)]
    pub cap_angle: f64,
    #[command(flatten)]
    pub strands: StrandArgs,
}

/// `hairgen fur`.
#[derive(clap::Args, Debug)]
pub struct FurArgs {
    /// The mesh: a .ply (or .ply.gz), or a .pbrt (or .pbrt.gz) whose
    /// trianglemesh, plymesh and bilinearmesh shapes are read with their
    /// transforms.
    #[arg(long)]
    pub mesh: PathBuf,
    /// Number of strands [default: 20000 unless --density is given].
    #[arg(long, conflicts_with = "density")]
    pub count: Option<u64>,
    /// Strands per unit area of the mesh.
    #[arg(long, allow_hyphen_values = true)]
    pub density: Option<f64>,
    /// Grow from the other side of the mesh's faces.
    #[arg(long)]
    pub flip_normals: bool,
    #[command(flatten)]
    pub strands: StrandArgs,
}

/// Options every surface shares.
#[derive(clap::Args, Debug)]
pub struct StrandArgs {
    /// The file to write: .pbrt, or .pbrt.gz (gzip-compressed).
    #[arg(long, short)]
    pub out: PathBuf,
    /// Random seed: the same recipe and seed write the same bytes.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Strand length along its axis [default: sphere 0.5·radius, cap
    /// 1.5·radius, fur 5% of the mesh's bounding-box diagonal].
    #[arg(long, allow_hyphen_values = true)]
    pub length: Option<f64>,
    /// Lengths are uniform in [(1 − V)·length, length], V in [0, 1].
    #[arg(long, default_value_t = 0.2, allow_hyphen_values = true)]
    pub length_variation: f64,
    #[arg(long, value_enum, default_value_t = Style::Straight)]
    pub style: Style,
    /// The wave's amplitude / the helix's radius [default: length/20].
    #[arg(long, allow_hyphen_values = true)]
    pub amplitude: Option<f64>,
    /// The wave's / helix's period along the strand [default: length/5].
    #[arg(long, allow_hyphen_values = true)]
    pub period: Option<f64>,
    /// Width at the root [default: length/200].
    #[arg(long, allow_hyphen_values = true)]
    pub root_width: Option<f64>,
    /// Width at the tip [default: root width/4].
    #[arg(long, allow_hyphen_values = true)]
    pub tip_width: Option<f64>,
    /// In [0, 1]: how far the strand turns towards --down by its tip.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub gravity: f64,
    /// Gravity's direction, X,Y,Z (also the bottom of the cap).
    #[arg(long, default_value = "0,-1,0", value_parser = parse_vector, allow_hyphen_values = true)]
    pub down: DVec3,
    /// Comb direction X,Y,Z, projected onto the surface's tangent plane.
    #[arg(long, default_value = "0,0,0", value_parser = parse_vector, allow_hyphen_values = true)]
    pub lean: DVec3,
    /// In [0, 1]: the tilt from the normal towards --lean, as a fraction of 90°.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub lean_amount: f64,
    /// Random tilt of each strand's direction within a cone of this
    /// half-angle (degrees, 0 to 90).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub spread: f64,
    /// Number of clumps (0: none).
    #[arg(long, default_value_t = 0)]
    pub clumps: u64,
    /// In [0, 1]: how far strand tips are pulled to their clump's guide.
    #[arg(long, default_value_t = 0.5, allow_hyphen_values = true)]
    pub clumping: f64,
    /// Bézier segments per strand [default: 1 for straight strands that do
    /// not bend, 4 when they bend; wavy and curly: at least six per period].
    #[arg(long)]
    pub segments: Option<usize>,
}

/// "X,Y,Z" (commas or spaces) as a vector.
fn parse_vector(text: &str) -> std::result::Result<DVec3, String> {
    let values: Vec<f64> = text
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| format!("\"{text}\": {e} (expected X,Y,Z)"))?;
    match values[..] {
        [x, y, z] if values.iter().all(|v| v.is_finite()) => Ok(DVec3::new(x, y, z)),
        _ => Err(format!("\"{text}\": expected three finite numbers X,Y,Z")),
    }
}

/// The most strands (or clumps) one run writes.
const MAX_COUNT: u64 = 100_000_000;
/// The most segments per strand.
const MAX_SEGMENTS: usize = 10_000;
/// Longer runs show a progress bar (on a terminal).
const PROGRESS_ABOVE: u64 = 100_000;

/// A default derived from other values, to six significant digits (so the
/// header's recipe, which prints it, gives the same strands again).
fn rounded(value: f64) -> f64 {
    write::short(value).parse().unwrap_or(value)
}

fn usage<T>(message: String) -> Result<T> {
    Err(Error::Usage(format!("hairgen: {message}")))
}

fn positive(option: &str, value: f64) -> Result<f64> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        usage(format!("{option} must be a positive number (got {value})"))
    }
}

fn unit_interval(option: &str, value: f64) -> Result<f64> {
    if (0.0..=1.0).contains(&value) {
        Ok(value)
    } else {
        usage(format!("{option} must be in [0, 1] (got {value})"))
    }
}

fn count(option: &str, value: u64) -> Result<u64> {
    if value == 0 || value > MAX_COUNT {
        usage(format!("{option} must be 1 to {MAX_COUNT} (got {value})"))
    } else {
        Ok(value)
    }
}

fn center(option: &str, value: DVec3) -> Result<DVec3> {
    if value.is_finite() {
        Ok(value)
    } else {
        usage(format!("{option} must be finite (got {value})"))
    }
}

/// Everything a run needs, checked, with every default filled in.
struct Plan {
    surface: Surface,
    count: u64,
    seed: u64,
    length: f64,
    length_variation: f64,
    recipe: Recipe,
    widths: (f64, f64),
    lean: Lean,
    clumps: u64,
    clumping: f64,
    segments: usize,
    /// The recipe as a command line (the header).
    command: String,
    /// The strands' source, for the header.
    what: String,
}

/// Checks the shared options; `default_length` is the surface's.
fn plan_strands(
    args: &StrandArgs,
    surface: Surface,
    count: u64,
    default_length: f64,
    mut command: String,
    what: String,
) -> Result<Plan> {
    let length = positive("--length", args.length.unwrap_or(rounded(default_length)))?;
    let length_variation = unit_interval("--length-variation", args.length_variation)?;
    let amplitude = args.amplitude.unwrap_or(rounded(length / 20.0));
    if !(amplitude >= 0.0 && amplitude.is_finite()) {
        return usage(format!(
            "--amplitude must be zero or positive (got {amplitude})"
        ));
    }
    let period = positive("--period", args.period.unwrap_or(rounded(length / 5.0)))?;
    let root_width = positive(
        "--root-width",
        args.root_width.unwrap_or(rounded(length / 200.0)),
    )?;
    let tip_width = positive(
        "--tip-width",
        args.tip_width.unwrap_or(rounded(root_width / 4.0)),
    )?;
    let gravity = unit_interval("--gravity", args.gravity)?;
    let Some(down) = args.down.try_normalize() else {
        return usage(format!(
            "--down must be a non-zero finite vector (got {})",
            args.down
        ));
    };
    let lean_amount = unit_interval("--lean-amount", args.lean_amount)?;
    if !args.lean.is_finite() || (lean_amount > 0.0 && args.lean.length() == 0.0) {
        return usage(format!(
            "--lean must be a non-zero finite vector when --lean-amount is above 0 (got {})",
            args.lean
        ));
    }
    if !(0.0..=90.0).contains(&args.spread) {
        return usage(format!(
            "--spread must be 0 to 90 degrees (got {})",
            args.spread
        ));
    }
    let clumping = unit_interval("--clumping", args.clumping)?;
    if args.clumps > count {
        return usage(format!(
            "--clumps must be at most the number of strands, {count} (got {})",
            args.clumps
        ));
    }
    let bends = gravity > 0.0 || (args.clumps > 0 && clumping > 0.0);
    let segments = match args.segments {
        Some(n) if n == 0 || n > MAX_SEGMENTS => {
            return usage(format!("--segments must be 1 to {MAX_SEGMENTS} (got {n})"))
        }
        Some(n) => n,
        None => match args.style {
            Style::Straight if !bends => 1,
            Style::Straight => 4,
            Style::Wavy | Style::Curly => ((6.0 * length / period).ceil() as usize).clamp(4, 1000),
        },
    };
    let _ = write!(
        command,
        " --seed {} --length {length} --length-variation {length_variation} --style {} \
         --amplitude {amplitude} --period {period} --root-width {root_width} --tip-width {tip_width} \
         --gravity {gravity} --down {},{},{} --lean {},{},{} --lean-amount {lean_amount} --spread {} \
         --clumps {} --clumping {clumping} --segments {segments}",
        args.seed,
        args.style.name(),
        args.down.x,
        args.down.y,
        args.down.z,
        args.lean.x,
        args.lean.y,
        args.lean.z,
        args.spread,
        args.clumps,
    );
    Ok(Plan {
        surface,
        count,
        seed: args.seed,
        length,
        length_variation,
        recipe: Recipe {
            style: args.style,
            amplitude,
            period,
            gravity,
            down,
        },
        widths: (root_width, tip_width),
        lean: Lean {
            towards: args.lean,
            amount: lean_amount,
            spread: args.spread.to_radians(),
        },
        clumps: args.clumps,
        clumping,
        segments,
        command,
        what,
    })
}

fn plan_sphere(args: &SphereArgs) -> Result<Plan> {
    let count = count("--count", args.count)?;
    let radius = positive("--radius", args.radius)?;
    let c = center("--center", args.center)?;
    let command = format!(
        "rpbrt hairgen sphere --count {count} --radius {radius} --center {},{},{}",
        c.x, c.y, c.z
    );
    plan_strands(
        &args.strands,
        Surface::Sphere { center: c, radius },
        count,
        0.5 * radius,
        command,
        format!(
            "a sphere of radius {radius} about ({}, {}, {})",
            c.x, c.y, c.z
        ),
    )
}

fn plan_cap(args: &CapArgs) -> Result<Plan> {
    let count = count("--count", args.count)?;
    let radius = positive("--radius", args.radius)?;
    let c = center("--center", args.center)?;
    if !(args.cap_angle > 0.0 && args.cap_angle <= 180.0) {
        return usage(format!(
            "--cap-angle must be above 0 and at most 180 degrees (got {})",
            args.cap_angle
        ));
    }
    let Some(down) = args.strands.down.try_normalize() else {
        return usage(format!(
            "--down must be a non-zero finite vector (got {})",
            args.strands.down
        ));
    };
    let command = format!(
        "rpbrt hairgen cap --count {count} --radius {radius} --center {},{},{} --cap-angle {}",
        c.x, c.y, c.z, args.cap_angle
    );
    plan_strands(
        &args.strands,
        Surface::Cap {
            center: c,
            radius,
            up: -down,
            cos_max: args.cap_angle.to_radians().cos(),
        },
        count,
        1.5 * radius,
        command,
        format!(
            "a cap of {}° on a sphere of radius {radius} about ({}, {}, {})",
            args.cap_angle, c.x, c.y, c.z
        ),
    )
}

fn plan_fur(args: &FurArgs) -> Result<Plan> {
    if let Some(density) = args.density {
        positive("--density", density)?;
    }
    if let Some(n) = args.count {
        count("--count", n)?;
    }
    let triangles = mesh::load(&args.mesh, args.flip_normals)?;
    let triangle_count = triangles.len();
    let Some(set) = TriangleSet::new(triangles) else {
        return Err(Error::Usage(format!(
            "--mesh {}: no triangles of positive area",
            args.mesh.display()
        )));
    };
    let area = set.area;
    let surface = Surface::Mesh(set);
    let strands = match (args.count, args.density) {
        (Some(n), _) => n,
        (None, Some(density)) => {
            let n = (density * area).round();
            if n < 1.0 || n > MAX_COUNT as f64 {
                return usage(format!(
                    "--density {density} on an area of {area:.6} makes {n} strands (1 to {MAX_COUNT} allowed)"
                ));
            }
            n as u64
        }
        (None, None) => 20_000,
    };
    let (lo, hi) = surface.bounds();
    let diagonal = (hi - lo).length();
    let command = format!(
        "rpbrt hairgen fur --mesh {} --count {strands}{}",
        args.mesh.display(),
        if args.flip_normals {
            " --flip-normals"
        } else {
            ""
        }
    );
    plan_strands(
        &args.strands,
        surface,
        strands,
        0.05 * diagonal,
        command,
        format!(
            "fur on {} ({triangle_count} triangles, area {area:.6})",
            args.mesh.display()
        ),
    )
}

/// Grows the strands and writes them.
pub fn run(args: &HairgenArgs) -> Result<()> {
    let (plan, out) = match &args.surface {
        HairgenSurface::Sphere(a) => (plan_sphere(a)?, &a.strands.out),
        HairgenSurface::Cap(a) => (plan_cap(a)?, &a.strands.out),
        HairgenSurface::Fur(a) => (plan_fur(a)?, &a.strands.out),
    };
    generate(&plan, out)?;
    eprintln!(
        "hairgen: {} strands of {} Bézier segments written to {}",
        plan.count,
        plan.segments,
        out.display()
    );
    Ok(())
}

/// Strand (or guide, `kind` 1) `index`: its root, direction, length, phases.
fn grow(plan: &Plan, kind: u64, index: u64) -> Strand {
    let mut random = Random::new(plan.seed, kind, index);
    let root = plan.surface.sample(&mut random);
    let direction = plan.lean.direction(root.normal, &mut random);
    let length = plan.length * (1.0 - plan.length_variation * random.uniform()).max(0.01);
    Strand {
        root: root.point,
        direction,
        length,
        phase: std::f64::consts::TAU * random.uniform(),
        azimuth: std::f64::consts::TAU * random.uniform(),
    }
}

fn generate(plan: &Plan, out: &Path) -> Result<()> {
    let guides: Option<(clump::NearestRoot, Vec<Samples>)> =
        (plan.clumps > 0 && plan.clumping > 0.0).then(|| {
            let strands: Vec<Strand> = (0..plan.clumps).map(|k| grow(plan, 1, k)).collect();
            let roots = strands.iter().map(|s| s.root).collect();
            let samples = strands
                .iter()
                .map(|s| strand::sample(s, &plan.recipe, plan.segments))
                .collect();
            (clump::NearestRoot::new(roots), samples)
        });
    let (lo, hi) = plan.surface.bounds();
    let decimals = write::decimals_for((hi - lo).length() + 2.0 * plan.length);

    let mut sink = write::Sink::create(out)?;
    match write_strands(plan, guides.as_ref(), decimals, &mut sink) {
        Ok(()) => sink.finish(),
        Err(e) => {
            sink.abandon();
            Err(e)
        }
    }
}

/// The header and every strand.
fn write_strands(
    plan: &Plan,
    guides: Option<&(clump::NearestRoot, Vec<Samples>)>,
    decimals: usize,
    sink: &mut write::Sink,
) -> Result<()> {
    let mut text = String::new();
    let _ = writeln!(text, "# pbrt-v4 curves written by rpbrt hairgen");
    let _ = writeln!(text, "# {}", plan.command);
    let _ = writeln!(text, "# {}", plan.what);
    let _ = writeln!(
        text,
        "# seed {}, {} strands, {} cubic Bézier segments each ({} control points)",
        plan.seed,
        plan.count,
        plan.segments,
        3 * plan.segments + 1
    );
    let _ = writeln!(
        text,
        "# Include this file inside the world block, under the hair's material.\n"
    );
    sink.write(&text)?;

    let bar = super::progress_bar(
        plan.count,
        "{bar:40} {pos}/{len} strands, {elapsed} (eta {eta})",
        plan.count > PROGRESS_ABOVE && std::io::stderr().is_terminal(),
    );
    for i in 0..plan.count {
        let s = grow(plan, 0, i);
        let mut samples = strand::sample(&s, &plan.recipe, plan.segments);
        if let Some((nearest, guides)) = guides {
            if let Some(guide) = guides.get(nearest.nearest(s.root)) {
                strand::clump(&mut samples, guide, plan.clumping);
            }
        }
        text.clear();
        write::push_curve(&mut text, &strand::bezier(&samples), plan.widths, decimals);
        sink.write(&text)?;
        if i % 4096 == 0 {
            bar.set_position(i);
        }
    }
    bar.finish_and_clear();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(clap::Parser, Debug)]
    struct Cli {
        #[command(flatten)]
        args: HairgenArgs,
    }

    fn parse(line: &str) -> std::result::Result<HairgenArgs, clap::Error> {
        let words = std::iter::once("hairgen").chain(line.split_whitespace());
        Cli::try_parse_from(words).map(|c| c.args)
    }

    fn plan_error(line: &str) -> String {
        let args = parse(line).unwrap();
        let result = match &args.surface {
            HairgenSurface::Sphere(a) => plan_sphere(a),
            HairgenSurface::Cap(a) => plan_cap(a),
            HairgenSurface::Fur(a) => plan_fur(a),
        };
        match result {
            Ok(_) => panic!("{line}: accepted"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn bad_values_are_refused_naming_the_option() {
        for (line, option) in [
            ("sphere --out x --count 0", "--count"),
            ("sphere --out x --radius 0", "--radius"),
            ("sphere --out x --radius nan", "--radius"),
            ("sphere --out x --length -1", "--length"),
            (
                "sphere --out x --length-variation 1.5",
                "--length-variation",
            ),
            ("sphere --out x --amplitude -0.1", "--amplitude"),
            ("sphere --out x --period 0", "--period"),
            ("sphere --out x --root-width 0", "--root-width"),
            ("sphere --out x --tip-width -1", "--tip-width"),
            ("sphere --out x --gravity 2", "--gravity"),
            ("sphere --out x --down 0,0,0", "--down"),
            ("sphere --out x --lean-amount 0.5", "--lean"),
            (
                "sphere --out x --lean-amount 1.5 --lean 1,0,0",
                "--lean-amount",
            ),
            ("sphere --out x --spread 100", "--spread"),
            ("sphere --out x --clumping -0.5 --clumps 3", "--clumping"),
            ("sphere --out x --count 10 --clumps 11", "--clumps"),
            ("sphere --out x --segments 0", "--segments"),
            ("cap --out x --cap-angle 0", "--cap-angle"),
            ("cap --out x --cap-angle 200", "--cap-angle"),
            (
                "fur --out x --mesh /nonexistent/bunny.ply",
                "/nonexistent/bunny.ply",
            ),
            (
                "fur --out x --mesh /nonexistent/m.ply --density -3",
                "--density",
            ),
            ("fur --out x --mesh /nonexistent/m.ply --count 0", "--count"),
        ] {
            let e = plan_error(line);
            assert!(e.contains(option), "{line}: {e}");
        }
    }

    #[test]
    fn malformed_arguments_are_refused_by_the_parser() {
        assert!(parse("sphere --out x --center 1,2").is_err());
        assert!(parse("sphere --out x --style frizzy").is_err());
        assert!(parse("sphere --count 5").is_err(), "--out is required");
        assert!(parse("fur --out x").is_err(), "--mesh is required");
        assert!(parse("fur --out x --mesh m.ply --count 5 --density 3").is_err());
        let a = parse("sphere --out x --center -1,2e-1,3 --down 0,0,-1").unwrap();
        let HairgenSurface::Sphere(a) = a.surface else {
            panic!()
        };
        assert_eq!(a.center, DVec3::new(-1.0, 0.2, 3.0));
        assert_eq!(a.strands.down, DVec3::NEG_Z);
    }

    #[test]
    fn defaults_follow_the_surface() {
        let args = parse("cap --out x --radius 2 --style curly").unwrap();
        let HairgenSurface::Cap(a) = &args.surface else {
            panic!()
        };
        let plan = plan_cap(a).unwrap();
        assert_eq!(plan.length, 3.0);
        assert_eq!(plan.recipe.period, 0.6);
        assert_eq!(plan.recipe.amplitude, 0.15);
        assert_eq!(plan.widths, (0.015, 0.00375));
        assert_eq!(plan.segments, 30);
        assert!(plan.command.contains("--style curly"));
    }
}
