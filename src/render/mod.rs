//! The render loop: waves of samples over tiles, in parallel, with a
//! progress bar and a clean stop on Ctrl-C.
//!
//! Every pixel sample is a pure function of (pixel, sample index, seed), and
//! each pixel is accumulated by one task in sample order, so the image is
//! identical at any thread count. Samples are taken in waves (1, 1, 2, 4, …
//! up to 64 samples per pixel over the whole image) so that an interrupted
//! render is evenly converged rather than half finished: a tile takes a
//! wave whole or not at all, and after Ctrl-C only the tiles already
//! started finish the wave.

mod tiled_pixels;

pub use tiled_pixels::{Tile, TiledPixels};

use crate::film::rgb::Pixel;
use glam::IVec2;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// What the loop did.
pub struct RenderOutcome<P = Pixel> {
    /// Pixel sums over the pixel bounds.
    pub pixels: TiledPixels<P>,
    /// Samples per pixel completed in every pixel.
    pub samples_completed: u32,
    /// Samples per pixel taken, averaged over the pixels: above
    /// `samples_completed` where an interrupt let some tiles finish a wave
    /// that others did not start.
    pub samples_mean: f64,
    pub interrupted: bool,
    pub elapsed: Duration,
    /// The process's CPU time over the loop (user + system, all threads;
    /// None where the system does not tell). Unlike `elapsed` it leaves out
    /// time the hypervisor stole and time other programs ran, which makes
    /// it the steadier figure to compare two renders by.
    pub cpu: Option<Duration>,
}

impl<P> RenderOutcome<P> {
    /// The outcome's figures, its pixels dropped (once they are made into
    /// an image).
    pub fn without_pixels(self) -> RenderOutcome<()> {
        RenderOutcome {
            pixels: TiledPixels::empty(),
            samples_completed: self.samples_completed,
            samples_mean: self.samples_mean,
            interrupted: self.interrupted,
            elapsed: self.elapsed,
            cpu: self.cpu,
        }
    }
}

/// Renders `spp` samples for every pixel in `[bounds.0, bounds.1)`.
/// `make_state` makes per-task state (a sampler, scratch buffers);
/// `evaluate(state, pixel, sample_index, accumulator)` takes one sample.
/// Every pixel's accumulator starts as `empty_pixel` (the film's kind:
/// RGB sums, or RGB and spectral buckets).
#[allow(clippy::too_many_arguments)]
pub fn render<S, M, F, P>(
    bounds: (IVec2, IVec2),
    spp: u32,
    threads: usize,
    show_progress: bool,
    interrupt: &AtomicBool,
    empty_pixel: P,
    make_state: M,
    evaluate: F,
) -> Result<RenderOutcome<P>, rayon::ThreadPoolBuildError>
where
    M: Fn() -> S + Sync,
    F: Fn(&mut S, IVec2, u32, &mut P) + Sync,
    P: Clone + Send + Sync,
{
    let start = Instant::now();
    let cpu_start = process_cpu_time();
    let mut pixels = TiledPixels::new(bounds, empty_pixel);
    let waves = waves(spp);
    let total: u64 = waves.iter().map(|(a, b)| (b - a) as u64).sum::<u64>() * pixels.len() as u64;
    let bar = if show_progress {
        let bar = ProgressBar::new(total.max(1));
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent}% (ETA {eta})",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    } else {
        ProgressBar::hidden()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    // Each tile's slice of the accumulators, so no pixel is shared between
    // tasks, and the samples per pixel it has taken.
    let mut tiles: Vec<(Tile, &mut [P], u32)> = pixels
        .tiles_mut()
        .into_iter()
        .map(|(tile, slice)| (tile, slice, 0))
        .collect();
    let mut interrupted = false;
    for (first, end) in waves {
        pool.install(|| {
            tiles
                .par_iter_mut()
                // One tile per job: rayon's adaptive splitting otherwise
                // hands out runs of tiles whose cost differs widely (hair
                // covers some tiles only), leaving a thread idle for up to a
                // quarter of every wave.
                .with_max_len(1)
                .for_each_init(&make_state, |state, (tile, acc, taken)| {
                    if interrupt.load(Ordering::Relaxed) {
                        return;
                    }
                    let mut k = 0;
                    for y in tile.lo.y..tile.hi.y {
                        for x in tile.lo.x..tile.hi.x {
                            for s in first..end {
                                evaluate(state, IVec2::new(x, y), s, &mut acc[k]);
                            }
                            k += 1;
                        }
                    }
                    *taken = end;
                    bar.inc(((end - first) as usize * tile.pixel_count()) as u64);
                });
        });
        if interrupt.load(Ordering::Relaxed) {
            // Tiles not started keep the samples of the waves before.
            interrupted = true;
            break;
        }
    }
    bar.finish_and_clear();
    let taken: Vec<(usize, u32)> = tiles
        .iter()
        .map(|(tile, _, taken)| (tile.pixel_count(), *taken))
        .collect();
    drop(tiles);
    let samples_completed = taken.iter().map(|t| t.1).min().unwrap_or(spp);
    let samples_mean = if pixels.is_empty() {
        samples_completed as f64
    } else {
        let sum: f64 = taken.iter().map(|&(n, t)| n as f64 * t as f64).sum();
        sum / pixels.len() as f64
    };
    Ok(RenderOutcome {
        pixels,
        samples_completed,
        samples_mean,
        interrupted,
        elapsed: start.elapsed(),
        cpu: process_cpu_time()
            .zip(cpu_start)
            .map(|(end, start)| end.saturating_sub(start)),
    })
}

/// This process's CPU time so far (user + system, all threads; the
/// kernel's run-time clock, which leaves out time stolen by a hypervisor),
/// to the nanosecond.
#[cfg(unix)]
fn process_cpu_time() -> Option<Duration> {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid, writable timespec for the call's duration.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    (status == 0).then(|| Duration::new(t.tv_sec as u64, t.tv_nsec as u32))
}

#[cfg(not(unix))]
fn process_cpu_time() -> Option<Duration> {
    None
}

/// Sample-index ranges of the waves: 1, 1, 2, 4, … up to 64 per wave.
fn waves(spp: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut size = 1;
    while start < spp {
        let end = (start + size).min(spp);
        out.push((start, end));
        start = end;
        if start >= 2 {
            size = (size * 2).min(64);
        }
    }
    out
}

/// Installs a Ctrl-C handler that sets the returned flag (once per
/// process; later calls return the same flag).
pub fn interrupt_flag() -> &'static AtomicBool {
    static FLAG: AtomicBool = AtomicBool::new(false);
    static INSTALLED: std::sync::Once = std::sync::Once::new();
    INSTALLED.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            if FLAG.swap(true, Ordering::SeqCst) {
                // A second Ctrl-C: stop at once.
                std::process::exit(130);
            }
            eprintln!("\ninterrupted: finishing the current wave's tiles and writing the image (Ctrl-C again to quit now)");
        });
    });
    &FLAG
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[cfg(unix)]
    fn process_cpu_time_advances_with_work() {
        let start = process_cpu_time().unwrap();
        let mut x = 1.0f64;
        for i in 0..2_000_000 {
            x = (x + i as f64).sqrt();
        }
        std::hint::black_box(x);
        assert!(process_cpu_time().unwrap() > start);
    }

    #[test]
    fn waves_cover_every_sample_once() {
        for spp in [1, 2, 3, 16, 100, 1000] {
            let w = waves(spp);
            assert_eq!(w.first().unwrap().0, 0);
            assert_eq!(w.last().unwrap().1, spp);
            assert!(w.windows(2).all(|p| p[0].1 == p[1].0));
        }
    }

    #[test]
    fn identical_at_any_thread_count() {
        let bounds = (IVec2::new(3, 5), IVec2::new(70, 41));
        let run = |threads| {
            let flag = AtomicBool::new(false);
            render(
                bounds,
                7,
                threads,
                false,
                &flag,
                Pixel::default(),
                || 0u64,
                |calls, p, s, px| {
                    *calls += 1;
                    // A deterministic function of (pixel, sample).
                    let v = ((p.x * 31 + p.y * 17 + s as i32 * 7) % 13) as f64;
                    px.rgb_sum[0] += v;
                    px.weight_sum += 1.0;
                },
            )
            .unwrap()
        };
        let a = run(1);
        let b = run(2);
        assert_eq!(a.samples_completed, 7);
        assert_eq!(a.samples_mean, 7.0);
        assert!(a
            .pixels
            .in_rows()
            .zip(b.pixels.in_rows())
            .all(|(x, y)| x.rgb_sum == y.rgb_sum && x.weight_sum == y.weight_sum));
        // Each pixel's sum is its own (pixel, sample) values, in its place.
        let (lo, hi) = bounds;
        let pixels: Vec<IVec2> = (lo.y..hi.y)
            .flat_map(|y| (lo.x..hi.x).map(move |x| IVec2::new(x, y)))
            .collect();
        for (p, px) in pixels.iter().zip(a.pixels.in_rows()) {
            let sum: f64 = (0..7)
                .map(|s| ((p.x * 31 + p.y * 17 + s * 7) % 13) as f64)
                .sum();
            assert_eq!((px.rgb_sum[0], px.weight_sum), (sum, 7.0), "{p}");
        }
    }

    #[test]
    fn an_interrupt_keeps_whole_waves() {
        let flag = AtomicBool::new(false);
        let bounds = (IVec2::ZERO, IVec2::new(40, 40));
        let out = render(
            bounds,
            64,
            2,
            false,
            &flag,
            Pixel::default(),
            || (),
            |_, p, s, px| {
                if s == 5 && p == IVec2::new(20, 20) {
                    flag.store(true, Ordering::Relaxed);
                }
                px.weight_sum += 1.0;
            },
        )
        .unwrap();
        assert!(out.interrupted);
        let n = out.samples_completed;
        assert!(n < 64);
        // Every tile holds whole waves: the completed ones, and the
        // interrupted one where the tile had started it. The tile that
        // raised the flag (at sample 5, in the wave of samples 4..8) had.
        let next = waves(64).into_iter().find(|w| w.0 == n).unwrap().1;
        let counts: Vec<f64> = out.pixels.in_rows().map(|p| p.weight_sum).collect();
        assert!(counts.iter().all(|&c| c == n as f64 || c == next as f64));
        assert_eq!(counts[20 * 40 + 20], 8.0);
        let mean = counts.iter().sum::<f64>() / counts.len() as f64;
        assert_eq!(out.samples_mean, mean);
        // The pixels of one tile took the same samples.
        let mut tiled = out.pixels;
        for (_, slice) in tiled.tiles_mut() {
            assert!(slice.iter().all(|p| p.weight_sum == slice[0].weight_sum));
        }
    }
}
