//! From a scene file to an image file: load, build, render, write.

use crate::cameras::CameraSample;
use crate::error::{Error, Result};
use crate::film::gbuffer::{self, GBufferPixel};
use crate::film::rgb::Pixel;
use crate::film::spectral::SpectralPixel;
use crate::film::splat::SplatBuffer;
use crate::film::{FilmPixel, RgbFilm};
use crate::filters::FilterSample;
use crate::image::pixel_format::count_beyond_half;
use crate::image::{DataWindow, Image};
use crate::integrators::bdpt::bdpt_li;
use crate::integrators::light_path::trace_light_path;
use crate::integrators::visible_surface::visible_surface;
use crate::integrators::{li, RayCounts};
use crate::render::{interrupt_flag, render, RenderOutcome};
use crate::scene::build::{build, BuiltScene, IntegratorKind, RenderOverrides};
use crate::scene_description::ColorSpaceName;
use glam::Vec2;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How a render went.
pub struct RenderReport {
    pub output: PathBuf,
    pub resolution: (u32, u32),
    pub spp_requested: u32,
    /// Samples per pixel every pixel took.
    pub spp_completed: u32,
    /// Samples per pixel taken on average: above `spp_completed` where an
    /// interrupt let the tiles that had started a wave finish it.
    pub spp_mean: f64,
    pub interrupted: bool,
    /// Reading the scene file into a scene description.
    pub parse: Duration,
    /// Building the renderable scene (shapes, lights, BVH) from it.
    pub build: Duration,
    pub render: Duration,
    /// The process's CPU time over the render loop, where known.
    pub render_cpu: Option<Duration>,
    /// Samples whose radiance was NaN or infinite (set to 0, as pbrt-v4).
    pub bad_samples: u64,
    /// Channel values beyond the half-float range, written as ±65504 to a
    /// half EXR (as pbrt-v4's film clamps them).
    pub half_clamped: u64,
    /// Rays the render traced.
    pub rays: RayCounts,
    pub warnings: Vec<String>,
}

/// A thread pool the system would not give (threads it could not start).
fn thread_pool_error(e: rayon::ThreadPoolBuildError) -> Error {
    Error::Io {
        path: "<thread pool>".into(),
        source: std::io::Error::other(e),
    }
}

/// Renders `path` with `threads` threads and writes the image.
pub fn render_file(
    path: &Path,
    overrides: &RenderOverrides,
    threads: usize,
    show_progress: bool,
) -> Result<RenderReport> {
    let start = Instant::now();
    // Nearly every scene converts RGB to spectra through the sRGB table;
    // check its disk cache file (9 MB read through for its checksum; rows
    // are read later, as lookups need them) on another core while this one
    // parses. Another colour space's table is opened when used.
    std::thread::spawn(|| {
        crate::spectrum::color_space::get(ColorSpaceName::Srgb).rgb_to_spectrum_table();
    });
    // `--nthreads` bounds the whole run, as pbrt-v4's does: parsing and
    // the build's parallel phases use the same number of threads as the
    // render, not every core of the machine.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(thread_pool_error)?;
    let loaded = pool.install(|| crate::scene::load(path))?;
    let parse = start.elapsed();
    crate::memory::return_freed_memory("parse");
    let options = loaded.scene.options.clone();
    let built = pool.install(|| build(loaded.scene, overrides))?;
    drop(pool);
    let mut warnings: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    warnings.extend(built.warnings.iter().map(|w| w.to_string()));
    check_window(&built.film, overrides, &mut warnings)?;
    let build_time = start.elapsed() - parse;

    let film = &built.film;
    let spp = built.sampler.samples_per_pixel();
    let bad = AtomicU64::new(0);
    let rays = Mutex::new(RayCounts::default());
    let jitter = Jitter {
        wavelength: !options.disable_wavelength_jitter,
        pixel: !options.disable_pixel_jitter,
    };
    // Light tracing deposits its light on the film anywhere (splats); the
    // other integrators add one sample to their own pixel.
    let splats = matches!(
        built.integrator.kind,
        IntegratorKind::LightPath | IntegratorKind::Bdpt
    )
    .then(|| SplatBuffer::new(film.pixel_bounds));
    let (lo, hi) = film.pixel_bounds;
    let (w, h) = ((hi.x - lo.x) as u32, (hi.y - lo.y) as u32);
    let sampling = Sampling {
        built: &built,
        threads,
        show_progress,
        jitter,
        splats: splats.as_ref(),
        bad: &bad,
        rays: &rays,
    };
    // The image: output RGB, then (spectral film) the buckets' radiance.
    let (outcome, mut channels, data) = match (&film.spectral, &film.gbuffer) {
        (None, None) => {
            let outcome = sampling.sample_pixels(Pixel::default())?;
            let data = film_rgb(&built, &outcome, splats.as_ref());
            (outcome.without_pixels(), Vec::new(), data)
        }
        (None, Some(_)) => {
            let outcome = sampling.sample_pixels(GBufferPixel::default())?;
            let rgb = film_rgb(&built, &outcome, splats.as_ref());
            let mut data = Vec::with_capacity(outcome.pixels.len() * gbuffer::CHANNELS.len());
            for (p, rgb) in outcome.pixels.in_rows().zip(rgb.chunks_exact(3)) {
                data.extend_from_slice(rgb);
                data.extend_from_slice(&p.values());
            }
            let names = gbuffer::CHANNELS[3..]
                .iter()
                .map(|c| c.to_string())
                .collect();
            (outcome.without_pixels(), names, data)
        }
        (Some(buckets), _) => {
            let outcome = sampling.sample_pixels(SpectralPixel::new(buckets))?;
            let rgb = film_rgb(&built, &outcome, splats.as_ref());
            let mut data = Vec::with_capacity(outcome.pixels.len() * (3 + buckets.count));
            for (p, rgb) in outcome.pixels.in_rows().zip(rgb.chunks_exact(3)) {
                data.extend_from_slice(rgb);
                data.extend(p.bucket_values());
            }
            (outcome.without_pixels(), buckets.channel_names(), data)
        }
    };
    channels.splice(0..0, ["R", "G", "B"].map(String::from));
    let io_error = |e: crate::image::ImageError| Error::Io {
        path: film.filename.display().to_string(),
        source: std::io::Error::other(e.to_string()),
    };
    let is_exr = film
        .filename
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    let half_clamped = if is_exr && film.save_fp16 {
        count_beyond_half(&data)
    } else {
        0
    };
    let channel_names: Vec<&str> = channels.iter().map(String::as_str).collect();
    let image = Image::new(w, h, &channel_names, data).map_err(io_error)?;
    if is_exr {
        // A partial render keeps its place in the film (as pbrt-v4 writes
        // it), so `rpbrt imgtool assemble` can put the pieces together.
        let full = film.full_resolution;
        let window = DataWindow {
            full_resolution: (full.x as u32, full.y as u32),
            origin: (lo.x, lo.y),
        };
        // The spectral layout's header entries, as pbrt-v4 writes them.
        let attributes: &[(&str, &str)] = if film.spectral.is_some() {
            &[
                ("spectralLayoutVersion", "1.0"),
                ("emissiveUnits", "W.m^-2.sr^-1"),
            ]
        } else {
            &[]
        };
        image
            .write_exr_with_attributes(&film.filename, film.save_fp16, Some(&window), attributes)
            .map_err(io_error)?;
    } else {
        image.write(&film.filename).map_err(io_error)?;
    }
    Ok(RenderReport {
        output: film.filename.clone(),
        resolution: (w, h),
        spp_requested: spp,
        spp_completed: outcome.samples_completed,
        spp_mean: outcome.samples_mean,
        interrupted: outcome.interrupted,
        parse,
        build: build_time,
        render: outcome.elapsed,
        render_cpu: outcome.cpu,
        bad_samples: bad.into_inner(),
        half_clamped,
        rays: rays.into_inner().unwrap_or_else(|e| e.into_inner()),
        warnings,
    })
}

/// Whether wavelengths and film positions are jittered (pbrt-v4's
/// `disablewavelengthjitter`, `disablepixeljitter` turn them off).
#[derive(Clone, Copy)]
struct Jitter {
    wavelength: bool,
    pixel: bool,
}

/// What taking the pixels' samples needs: the scene, the threads, whether
/// to show progress, the jitter, light tracing's splat buffer, and the
/// counts of bad samples and rays.
struct Sampling<'a> {
    built: &'a BuiltScene,
    threads: usize,
    show_progress: bool,
    jitter: Jitter,
    splats: Option<&'a SplatBuffer>,
    bad: &'a AtomicU64,
    rays: &'a Mutex<RayCounts>,
}

impl Sampling<'_> {
    /// Takes every pixel's samples, accumulating them in pixels of the
    /// film's kind (`empty` is one before any sample), and light tracing's
    /// splats in the splat buffer. NaN or infinite samples are counted and
    /// add nothing.
    fn sample_pixels<P: FilmPixel>(&self, empty: P) -> Result<RenderOutcome<P>> {
        let Sampling {
            built,
            threads,
            show_progress,
            jitter,
            splats,
            bad,
            rays,
        } = *self;
        let film = &built.film;
        let uses_lens = built.camera.uses_lens();
        let has_motion = built.has_motion();
        let light_path_only = built.integrator.kind == IntegratorKind::LightPath;
        render(
            film.pixel_bounds,
            built.sampler.samples_per_pixel(),
            threads,
            show_progress,
            interrupt_flag(),
            empty,
            || (built.sampler.clone(), RayTally::new(rays)),
            |(sampler, tally), pixel, index, acc: &mut P| {
                sampler.start_pixel_sample(pixel, index, 0);
                let lu = sampler.get_1d();
                let mut lambda = film.sample_wavelengths(if jitter.wavelength { lu } else { 0.5 });
                if let (Some(splats), true) = (splats, light_path_only) {
                    trace_light_path(built, &mut lambda, sampler, splats, &mut tally.counts);
                    return;
                }
                // Without jitter (pbrt-v4's `disablewavelengthjitter` and
                // `disablepixeljitter`) the numbers are drawn all the same, so
                // later dimensions stay pbrt-v4's: the wavelengths are those of
                // u = 1/2 (above), and the film point is the pixel's centre,
                // weight 1.
                let mut fs = built.filter.sample(sampler.get_pixel_2d());
                if !jitter.pixel {
                    fs = FilterSample {
                        p: Vec2::ZERO,
                        weight: 1.0,
                    };
                }
                // pbrt-v4 takes a time and a lens point for every camera ray.
                // Without motion the time changes nothing, and without a lens
                // neither does the lens point: their dimensions are skipped,
                // not computed, so later ones stay pbrt-v4's.
                let time = if has_motion {
                    sampler.get_1d()
                } else {
                    sampler.skip(1);
                    0.5
                };
                let p_lens = if uses_lens {
                    sampler.get_2d()
                } else {
                    sampler.skip(2);
                    Vec2::splat(0.5)
                };
                let sample = CameraSample {
                    p_film: pixel.as_vec2() + Vec2::splat(0.5) + fs.p,
                    time,
                    p_lens,
                    filter_weight: fs.weight,
                };
                let Some(camera_ray) = built.camera.generate_ray(&sample, &lambda) else {
                    // A ray the camera cannot make (one a lens blocks)
                    // still counts as a black sample, as in pbrt-v4:
                    // vignetting darkens the pixel instead of vanishing
                    // from it.
                    acc.add_sample(
                        film,
                        crate::spectrum::SampledSpectrum::ZERO,
                        &lambda,
                        sample.filter_weight,
                        None,
                    );
                    return;
                };
                let visible = if P::USES_VISIBLE_SURFACE {
                    visible_surface(built, &camera_ray, &lambda)
                } else {
                    None
                };
                let mut l = match splats {
                    Some(splats) => bdpt_li(
                        built,
                        &camera_ray,
                        &mut lambda,
                        sampler,
                        splats,
                        &mut tally.counts,
                    ),
                    None => li(built, &camera_ray, &mut lambda, sampler, &mut tally.counts),
                } * camera_ray.weight;
                if l.has_nan() || l.0.iter().any(|v| v.is_infinite()) {
                    bad.fetch_add(1, Ordering::Relaxed);
                    l = crate::spectrum::SampledSpectrum::ZERO;
                }
                acc.add_sample(film, l, &lambda, sample.filter_weight, visible.as_ref());
            },
        )
        .map_err(thread_pool_error)
    }
}

/// The film's output RGB of every pixel (interleaved), splats added.
fn film_rgb<P: FilmPixel>(
    built: &BuiltScene,
    outcome: &RenderOutcome<P>,
    splats: Option<&SplatBuffer>,
) -> Vec<f32> {
    let film = &built.film;
    let mut data = Vec::with_capacity(outcome.pixels.len() * 3);
    // Splats are averaged over the samples per pixel (their mean: a path
    // from any tile may splat anywhere), and the filter's weights over its
    // integral, as pbrt-v4's film does.
    let splat_scale = 1.0 / (outcome.samples_mean.max(1.0) as f32 * built.filter.integral());
    for (i, p) in outcome.pixels.in_rows().enumerate() {
        let mut rgb = film.pixel_rgb(p.rgb());
        if let Some(splats) = splats {
            rgb += film.splat_rgb(splats.sum(i) * splat_scale);
        }
        data.extend_from_slice(&[rgb.x, rgb.y, rgb.z]);
    }
    data
}

/// `--pixelbounds` / `--cropwindow` against the image: an error when no
/// pixel of it is left to render, a warning when the bounds reached past it
/// and were clipped, or when both flags were given (the crop window wins),
/// as pbrt-v4.
fn check_window(
    film: &RgbFilm,
    overrides: &RenderOverrides,
    warnings: &mut Vec<String>,
) -> Result<()> {
    let list = |v: &[String]| v.join(",");
    let (flag, requested) = match (overrides.crop_window, overrides.pixel_bounds) {
        (Some(c), pixels) => {
            if pixels.is_some() {
                warnings.push(
                    "warning: both --pixelbounds and --cropwindow were given; using the crop window"
                        .into(),
                );
            }
            ("--cropwindow", list(&c.map(|v| v.to_string())))
        }
        (None, Some(b)) => ("--pixelbounds", list(&b.map(|v| v.to_string()))),
        (None, None) => return Ok(()),
    };
    let (lo, hi) = film.pixel_bounds;
    let full = film.full_resolution;
    if hi.x <= lo.x || hi.y <= lo.y {
        return Err(Error::Usage(format!(
            "{flag} {requested} leaves no pixel of the {}x{} image to render",
            full.x, full.y
        )));
    }
    if let (None, Some([x0, x1, y0, y1])) = (overrides.crop_window, overrides.pixel_bounds) {
        if (lo.x, hi.x, lo.y, hi.y) != (x0, x1, y0, y1) {
            warnings.push(format!(
                "warning: --pixelbounds {requested} reaches outside the {}x{} image; \
                 rendering {},{},{},{}",
                full.x, full.y, lo.x, hi.x, lo.y, hi.y
            ));
        }
    }
    Ok(())
}

/// A render task's ray counts, added to the render's total when the task
/// ends (one lock per task, not per ray).
struct RayTally<'a> {
    counts: RayCounts,
    total: &'a Mutex<RayCounts>,
}

impl<'a> RayTally<'a> {
    fn new(total: &'a Mutex<RayCounts>) -> Self {
        RayTally {
            counts: RayCounts::default(),
            total,
        }
    }
}

impl Drop for RayTally<'_> {
    fn drop(&mut self) {
        *self.total.lock().unwrap_or_else(|e| e.into_inner()) += self.counts;
    }
}
