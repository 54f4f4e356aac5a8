//! `rpbrt reproduce`: renders the figures of Benamira & Pattanaik 2021
//! ("A combined scattering and diffraction model for elliptical hair
//! rendering") from the scenes in `pbrt-scenes/paper/` and writes a page
//! of results.
//!
//! | option | default | meaning |
//! |---|---|---|
//! | `--out DIR` | (required) | where everything goes (below) |
//! | `--quality draft\|preview\|full` | `preview` | `draft`: a quarter of the scenes' resolution in each axis, 4 samples per pixel (a first look); `preview`: half the resolution and 64 samples per pixel (256 for Fig. 4, whose difference is small); `full`: the scenes as written (480 × 480, 256 spp) |
//! | `--only FIG[,FIG…]` | all | just these figures (`fig01`, `fig04`, `fig07`, `fig09`–`fig16`) |
//! | `--nthreads N` | all cores | render threads |
//! | `--bunny FILE.ply` | `../shared/scenes/stanford-bunny/bun_zipper_res3.ply` if present | the mesh Fig. 13's fur grows on; without one a stand-in made here (a lumpy ellipsoid) is used and the page says so |
//!
//! Steps: the scene files (built into the binary) are written to
//! `DIR/scenes/`; the hair geometry they include is grown there with
//! `rpbrt hairgen` (deterministic recipes in [`geometry`]); each panel is
//! rendered to `DIR/FIG/PANEL.exr` with a small record of how
//! (`PANEL.txt`: quality, a hash of the scene and geometry, the render
//! time); then `DIR/FIG.png` shows the panels side by side with their
//! parameters (one exposure per figure), and `DIR/index.md` and
//! `DIR/index.html` give the images, the paper's claims, per-panel
//! measurements and Table 2 (render time, reference model against dual
//! model). It resumes: a panel whose record matches the requested quality
//! and the current scene is not rendered again.

mod compose;
mod figures;
mod geometry;
mod page;

pub use figures::{Figure, Model, Work, FIGURES};

use crate::error::{Error, Result};
use crate::scene::build::RenderOverrides;
use crate::tools::io_error;
use indicatif::ProgressBar;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// How finely to render.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quality {
    /// A quarter of the resolution in each axis, 4 samples per pixel: a
    /// first look in a minute or two.
    Draft,
    /// Half the resolution in each axis, 64 samples per pixel (more for
    /// Fig. 4).
    Preview,
    /// The scenes as written.
    Full,
}

impl Quality {
    fn name(self) -> &'static str {
        match self {
            Quality::Draft => "draft",
            Quality::Preview => "preview",
            Quality::Full => "full",
        }
    }

    /// `preview_spp`: the figure's samples per pixel in a preview.
    fn overrides(self, outfile: PathBuf, preview_spp: u32) -> RenderOverrides {
        let (spp, resolution_divisor) = match self {
            Quality::Draft => (Some(DRAFT_SPP), Some(4)),
            Quality::Preview => (Some(preview_spp), Some(2)),
            Quality::Full => (None, None),
        };
        RenderOverrides {
            spp,
            outfile: Some(outfile),
            resolution_divisor,
            ..Default::default()
        }
    }
}

/// Samples per pixel of a draft.
const DRAFT_SPP: u32 = 4;

/// Renders the paper's figures and writes a page of results.
#[derive(clap::Args, Debug)]
pub struct ReproduceArgs {
    /// Output folder (scenes, geometry, images, index.md, index.html).
    #[arg(long)]
    pub out: PathBuf,
    #[arg(long, value_enum, default_value = "preview")]
    pub quality: Quality,
    /// Only these figures, comma-separated (fig01, fig04, fig07, fig09,
    /// fig10, fig11, fig12, fig13, fig14, fig15, fig16).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// Render threads (default: all cores).
    #[arg(long)]
    pub nthreads: Option<usize>,
    /// The PLY mesh Fig. 13's fur grows on (default: the Stanford bunny in
    /// ../shared/scenes/stanford-bunny/ when present, else a stand-in).
    #[arg(long)]
    pub bunny: Option<PathBuf>,
}

/// How one panel was rendered (its `PANEL.txt`).
#[derive(Clone, Debug, PartialEq)]
pub struct PanelRecord {
    pub quality: String,
    /// Hash of the scene text, the files it includes and the geometry
    /// recipes: a change renders the panel again.
    pub inputs: u64,
    /// Render-loop wall time, seconds.
    pub render_seconds: f64,
    pub threads: usize,
    pub resolution: (u32, u32),
    pub spp: u32,
}

impl PanelRecord {
    fn to_text(&self) -> String {
        format!(
            "quality {}\ninputs {:016x}\nrender_seconds {:.3}\nthreads {}\nresolution {} {}\nspp {}\n",
            self.quality,
            self.inputs,
            self.render_seconds,
            self.threads,
            self.resolution.0,
            self.resolution.1,
            self.spp
        )
    }

    /// The record in `text`, or `None` if it is not one (then the panel is
    /// rendered again).
    fn parse(text: &str) -> Option<PanelRecord> {
        let mut fields = std::collections::HashMap::new();
        for line in text.lines() {
            let (key, value) = line.split_once(' ')?;
            fields.insert(key, value);
        }
        let resolution = fields.get("resolution")?.split_once(' ')?;
        Some(PanelRecord {
            quality: fields.get("quality")?.to_string(),
            inputs: u64::from_str_radix(fields.get("inputs")?, 16).ok()?,
            render_seconds: fields.get("render_seconds")?.parse().ok()?,
            threads: fields.get("threads")?.parse().ok()?,
            resolution: (resolution.0.parse().ok()?, resolution.1.parse().ok()?),
            spp: fields.get("spp")?.parse().ok()?,
        })
    }
}

/// Measurements of one rendered panel, for the page.
#[derive(Clone, Debug)]
pub struct PanelResult {
    pub scene: &'static str,
    pub label: &'static str,
    pub model: Model,
    pub record: PanelRecord,
    /// Whether this run rendered it (else it was kept from an earlier run).
    pub rendered_now: bool,
    /// Mean luminance (linear) over each of the figure's regions.
    pub region_luminance: Vec<f64>,
    /// Mean saturation (max − min) / max over the first region's lit
    /// pixels.
    pub saturation: f64,
    /// The rendered image: width, height, linear RGB (read once, for the
    /// measurements and the figure).
    pub rgb: (usize, usize, Vec<f32>),
}

/// A figure's outcome.
pub struct FigureResult {
    pub figure: &'static Figure,
    /// `FIG.png`, relative to the output folder.
    pub image: String,
    pub panels: Vec<PanelResult>,
}

pub fn run(args: &ReproduceArgs) -> Result<()> {
    let selected = select(&args.only)?;
    let scenes = args.out.join("scenes");
    std::fs::create_dir_all(scenes.join("geometry")).map_err(io_error(&scenes))?;
    write_scene_files(&scenes)?;
    let threads = args
        .nthreads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let interactive = std::io::stderr().is_terminal();

    // Geometry the selected figures include.
    let needed: Vec<&geometry::Recipe> = geometry::RECIPES
        .iter()
        .filter(|r| selected.iter().any(|f| figure_uses(f, r.file)))
        .collect();
    let bunny = geometry::bunny_mesh(args.bunny.as_deref());
    for recipe in &needed {
        eprintln!("geometry: {}", recipe.file);
        geometry::make(recipe, &scenes, &bunny)?;
    }

    let panels_total: u64 = selected
        .iter()
        .map(|f| match &f.work {
            Work::Render { panels, .. } => panels.len() as u64,
            Work::Plot { .. } => 1,
        })
        .sum();
    let bar = super::progress_bar(
        panels_total,
        "{bar:30} {pos}/{len} panels, {elapsed} {msg}",
        interactive,
    );
    let mut results = Vec::new();
    for figure in &selected {
        let result = match &figure.work {
            Work::Render {
                panels,
                exposure,
                difference,
                difference_scale,
                preview_spp,
            } => {
                let mut done = Vec::new();
                for panel in *panels {
                    bar.set_message(panel.scene);
                    let inputs = inputs_hash(panel.scene, &needed, &bunny);
                    let job = PanelJob {
                        figure,
                        panel,
                        scenes: &scenes,
                        inputs,
                        threads,
                        preview_spp: *preview_spp,
                    };
                    let result = render_panel(args, &job, &bar)?;
                    done.push(result);
                    bar.inc(1);
                }
                let image = compose_figure(
                    &args.out,
                    figure,
                    &done,
                    *exposure,
                    *difference,
                    *difference_scale,
                )?;
                FigureResult {
                    figure,
                    image,
                    panels: done,
                }
            }
            Work::Plot {
                bcsdf_args,
                caption,
            } => {
                bar.set_message(figure.id);
                let image = format!("{}.png", figure.id);
                plot(figure.title, bcsdf_args, caption, &args.out.join(&image))?;
                bar.inc(1);
                FigureResult {
                    figure,
                    image,
                    panels: Vec::new(),
                }
            }
        };
        let line = format!(
            "{}: wrote {}",
            figure.id,
            args.out.join(&result.image).display()
        );
        if interactive {
            bar.println(line);
        } else {
            eprintln!("{line}");
        }
        results.push(result);
    }
    bar.finish_and_clear();
    let context = page::Context {
        quality: args.quality.name(),
        threads,
        bunny: bunny.description(),
    };
    page::write(&args.out, &results, &context)?;
    eprintln!(
        "wrote {} and {}",
        args.out.join("index.md").display(),
        args.out.join("index.html").display()
    );
    Ok(())
}

/// The figures `--only` names (all when empty), in the paper's order.
fn select(only: &[String]) -> Result<Vec<&'static Figure>> {
    for id in only {
        if figures::figure(id).is_none() {
            let known: Vec<&str> = FIGURES.iter().map(|f| f.id).collect();
            return Err(Error::Usage(format!(
                "--only: no figure \"{id}\" (figures: {})",
                known.join(", ")
            )));
        }
    }
    Ok(FIGURES
        .iter()
        .filter(|f| only.is_empty() || only.iter().any(|id| id == f.id))
        .collect())
}

/// Writes the built-in scene files, leaving files that are already the
/// same untouched.
fn write_scene_files(dir: &Path) -> Result<()> {
    for (name, text) in figures::SCENE_FILES {
        let path = dir.join(name);
        if std::fs::read_to_string(&path).ok().as_deref() != Some(*text) {
            std::fs::write(&path, text).map_err(io_error(&path))?;
        }
    }
    Ok(())
}

/// The text of a built-in scene file.
fn scene_text(name: &str) -> &'static str {
    figures::SCENE_FILES
        .iter()
        .find(|(n, _)| *n == name)
        .map_or("", |(_, text)| text)
}

/// The built-in scene `name` and everything it includes, recursively
/// (built-in files only; generated geometry is named, not read).
fn scene_closure(name: &str, out: &mut Vec<&'static str>) {
    let text = scene_text(name);
    out.push(text);
    for line in text.lines() {
        if let Some(rest) = line.trim().strip_prefix("Include \"") {
            if let Some(included) = rest.split('"').next() {
                scene_closure(included, out);
            }
        }
    }
}

/// Whether a panel of `figure` includes the generated file `geometry`.
fn figure_uses(figure: &Figure, geometry: &str) -> bool {
    let Work::Render { panels, .. } = &figure.work else {
        return false;
    };
    panels.iter().any(|p| {
        let mut texts = Vec::new();
        scene_closure(p.scene, &mut texts);
        texts
            .iter()
            .any(|t| t.contains(&format!("\"geometry/{geometry}\"")))
    })
}

/// Hash of what a panel's image depends on: its scene files, the recipes
/// of the geometry it includes and the mesh the fur grows on.
fn inputs_hash(scene: &str, recipes: &[&geometry::Recipe], bunny: &geometry::BunnyMesh) -> u64 {
    let mut texts = Vec::new();
    scene_closure(scene, &mut texts);
    let mut all = texts.concat();
    for recipe in recipes {
        if texts
            .iter()
            .any(|t| t.contains(&format!("\"geometry/{}\"", recipe.file)))
        {
            all.push_str(&recipe.hairgen.join(" "));
            if recipe.on_bunny {
                all.push_str(&bunny.description());
            }
        }
    }
    all.push_str(env!("CARGO_PKG_VERSION"));
    crate::math::hash::murmur_hash_64a(all.as_bytes(), 0)
}

/// One panel to render.
struct PanelJob<'a> {
    figure: &'static Figure,
    panel: &'static figures::Panel,
    /// The folder the scene files are in.
    scenes: &'a Path,
    /// [`inputs_hash`] of the panel.
    inputs: u64,
    threads: usize,
    preview_spp: u32,
}

/// Renders one panel unless its record says it is already there at this
/// quality from the same inputs.
fn render_panel(args: &ReproduceArgs, job: &PanelJob, bar: &ProgressBar) -> Result<PanelResult> {
    let PanelJob {
        figure,
        panel,
        scenes,
        inputs,
        threads,
        preview_spp,
    } = *job;
    let dir = args.out.join(figure.id);
    std::fs::create_dir_all(&dir).map_err(io_error(&dir))?;
    let stem = panel.scene.trim_end_matches(".pbrt");
    let exr = dir.join(format!("{stem}.exr"));
    let record_path = dir.join(format!("{stem}.txt"));
    let kept = std::fs::read_to_string(&record_path)
        .ok()
        .and_then(|t| PanelRecord::parse(&t))
        .filter(|r| {
            r.quality == args.quality.name()
                && r.inputs == inputs
                && match args.quality {
                    Quality::Draft => r.spp == DRAFT_SPP,
                    Quality::Preview => r.spp == preview_spp,
                    Quality::Full => true,
                }
                && exr.exists()
        });
    let (record, rendered_now) = match kept {
        Some(record) => (record, false),
        None => {
            let overrides = args.quality.overrides(exr.clone(), preview_spp);
            let report = crate::pipeline::render_file(
                &scenes.join(panel.scene),
                &overrides,
                threads,
                false,
            )?;
            for warning in &report.warnings {
                bar.println(format!("{}: {warning}", panel.scene));
            }
            if report.interrupted {
                return Err(Error::Usage(format!(
                    "{}: interrupted; run the command again to go on",
                    panel.scene
                )));
            }
            let record = PanelRecord {
                quality: args.quality.name().into(),
                inputs,
                render_seconds: report.render.as_secs_f64(),
                threads,
                resolution: report.resolution,
                spp: report.spp_completed,
            };
            std::fs::write(&record_path, record.to_text()).map_err(io_error(&record_path))?;
            (record, true)
        }
    };
    let (width, height, rgb) = crate::tools::imgtool::read_rgb(&exr)?;
    let stats: Vec<(f64, f64)> = figure
        .regions
        .iter()
        .map(|r| region_stats(width, height, &rgb, r.bounds))
        .collect();
    let region_luminance = stats.iter().map(|s| s.0).collect();
    let saturation = stats.first().map_or(0.0, |s| s.1);
    Ok(PanelResult {
        scene: panel.scene,
        label: panel.label,
        model: panel.model,
        record,
        rendered_now,
        region_luminance,
        saturation,
        rgb: (width, height, rgb),
    })
}

/// Mean luminance over `region` (fractions of the image), and the mean
/// saturation (max − min) / max of its pixels brighter than 1 % of that
/// mean (dark pixels have no colour to speak of).
pub fn region_stats(width: usize, height: usize, rgb: &[f32], region: [f32; 4]) -> (f64, f64) {
    let x0 = (region[0] * width as f32) as usize;
    let x1 = ((region[2] * width as f32) as usize).clamp(x0 + 1, width.max(1));
    let y0 = (region[1] * height as f32) as usize;
    let y1 = ((region[3] * height as f32) as usize).clamp(y0 + 1, height.max(1));
    let pixels = || {
        (y0..y1)
            .flat_map(move |y| (x0..x1).map(move |x| (y * width + x) * 3))
            .filter_map(|i| rgb.get(i..i + 3))
    };
    let count = pixels().count().max(1) as f64;
    let mean = pixels().map(|p| compose::luminance(p) as f64).sum::<f64>() / count;
    let (mut saturation, mut lit) = (0.0, 0usize);
    for p in pixels() {
        if (compose::luminance(p) as f64) > 0.01 * mean {
            let max = p[0].max(p[1]).max(p[2]) as f64;
            let min = p[0].min(p[1]).min(p[2]) as f64;
            if max > 0.0 {
                saturation += (max - min) / max;
                lit += 1;
            }
        }
    }
    (mean, saturation / lit.max(1) as f64)
}

/// `DIR/FIG.png`: the panels side by side, each captioned with its label
/// and measurements.
fn compose_figure(
    out: &Path,
    figure: &Figure,
    panels: &[PanelResult],
    exposure: f32,
    difference: Option<(usize, usize)>,
    difference_scale: f32,
) -> Result<String> {
    let images: Vec<&(usize, usize, Vec<f32>)> = panels.iter().map(|p| &p.rgb).collect();
    let difference_pixels = match difference {
        Some((a, b)) if images[a].0 == images[b].0 && images[a].1 == images[b].1 => Some((
            images[a].0,
            images[a].1,
            compose::difference_panel(
                images[a].0,
                images[a].1,
                &images[a].2,
                &images[b].2,
                difference_scale,
            ),
            a,
            b,
        )),
        _ => None,
    };
    let mut composed: Vec<compose::Panel> = panels
        .iter()
        .zip(&images)
        .map(|(p, (w, h, rgb))| compose::Panel {
            width: *w,
            height: *h,
            rgb,
            caption: vec![
                p.label.to_string(),
                format!(
                    "{:.1} s, mean {:.4}",
                    p.record.render_seconds,
                    p.region_luminance.first().copied().unwrap_or(0.0)
                ),
            ],
        })
        .collect();
    let difference_exposure_fix;
    if let Some((w, h, pixels, a, b)) = &difference_pixels {
        // The difference panel is shown as is: undo the figure's exposure.
        difference_exposure_fix = pixels.iter().map(|v| v / exposure).collect::<Vec<_>>();
        composed.push(compose::Panel {
            width: *w,
            height: *h,
            rgb: &difference_exposure_fix,
            caption: vec![
                format!("|{} - {}| / {}", b + 1, a + 1, a + 1),
                format!("red = {:.0} %", difference_scale * 100.0),
            ],
        });
    }
    let image = compose::side_by_side(figure.title, &composed, exposure)?;
    let name = format!("{}.png", figure.id);
    image.write_png(out.join(&name))?;
    Ok(name)
}

/// A Fig. 7 or Fig. 10 plot from `rpbrt bcsdf`, framed with the figure's
/// title and `caption`.
fn plot(title: &str, bcsdf_args: &[&str], caption: &str, png: &Path) -> Result<()> {
    #[derive(clap::Parser)]
    struct Bcsdf {
        #[command(flatten)]
        args: crate::tools::bcsdf::BcsdfArgs,
    }
    let png_arg = png.display().to_string();
    let argv = ["bcsdf"]
        .into_iter()
        .chain(bcsdf_args.iter().copied())
        .chain(["--png", png_arg.as_str()]);
    let parsed = <Bcsdf as clap::Parser>::try_parse_from(argv)
        .map_err(|e| Error::Usage(format!("bcsdf arguments: {e}")))?;
    crate::tools::bcsdf::run(&parsed.args).map_err(Error::Usage)?;
    let (width, height, rgb) = crate::tools::imgtool::read_rgb(png)?;
    let framed = compose::side_by_side(
        title,
        &[compose::Panel {
            width,
            height,
            rgb: &rgb,
            caption: vec![caption.to_string()],
        }],
        1.0,
    )?;
    Ok(framed.write_png(png)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_read_back() {
        let record = PanelRecord {
            quality: "preview".into(),
            inputs: 0x0123_4567_89ab_cdef,
            render_seconds: 12.5,
            threads: 2,
            resolution: (240, 200),
            spp: 16,
        };
        assert_eq!(PanelRecord::parse(&record.to_text()), Some(record));
        assert_eq!(PanelRecord::parse("quality preview\n"), None);
        assert_eq!(PanelRecord::parse("garbage"), None);
    }

    #[test]
    fn unknown_figures_are_refused_and_order_is_the_papers() {
        let err = select(&["fig99".into()]).err().unwrap().to_string();
        assert!(err.contains("fig99") && err.contains("fig12"), "{err}");
        let picked = select(&["fig16".into(), "fig01".into()]).unwrap();
        assert_eq!(
            picked.iter().map(|f| f.id).collect::<Vec<_>>(),
            ["fig01", "fig16"]
        );
        assert_eq!(select(&[]).unwrap().len(), FIGURES.len());
    }

    #[test]
    fn region_stats_measure_brightness_and_colour() {
        // 2 × 1: a grey pixel and a pure red one.
        let rgb = [0.5, 0.5, 0.5, 1.0, 0.0, 0.0];
        let (mean, saturation) = region_stats(2, 1, &rgb, [0.0, 0.0, 1.0, 1.0]);
        assert!((mean - (0.5 + 0.2126) / 2.0).abs() < 1e-6);
        assert!((saturation - 0.5).abs() < 1e-6);
        let (left, _) = region_stats(2, 1, &rgb, [0.0, 0.0, 0.5, 1.0]);
        assert!((left - 0.5).abs() < 1e-6);
    }

    #[test]
    fn inputs_hash_follows_the_included_files() {
        let bunny = geometry::BunnyMesh::StandIn;
        let recipes: Vec<&geometry::Recipe> = geometry::RECIPES.iter().collect();
        let a = inputs_hash("fig12-d1.pbrt", &recipes, &bunny);
        assert_eq!(a, inputs_hash("fig12-d1.pbrt", &recipes, &bunny));
        assert_ne!(a, inputs_hash("fig12-d0.pbrt", &recipes, &bunny));
        // Figures sharing scene files but not materials differ.
        assert_ne!(
            inputs_hash("fig14-dual.pbrt", &recipes, &bunny),
            inputs_hash("fig16-d02.pbrt", &recipes, &bunny)
        );
    }
}
