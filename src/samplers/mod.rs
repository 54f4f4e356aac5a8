//! Samplers: the per-pixel-sample streams of [0, 1) values a renderer turns
//! into film positions, lens positions, wavelengths, light and BSDF
//! choices. Each mirrors a pbrt-v4 sampler value for value (but `pmj02bn`,
//! whose tables rpbrt does not ship: see its file): what a sampler
//! returns depends only on (pixel, sample index, dimension, seed), never on
//! threads or rendering order, so a sampler is cloned per thread.
//!
//! # Dimension conventions
//!
//! A pixel sample starts with [`Sampler::start_pixel_sample`] (dimension 0
//! for a camera path) and then reads values in pbrt-v4's order; every
//! [`Sampler::get_1d`] takes one dimension, every [`Sampler::get_2d`] and
//! [`Sampler::get_pixel_2d`] two. pbrt-v4's integrators read, per camera
//! sample:
//!
//! 1. `get_1d`: the wavelength sample (0.5 under `--disable-wavelength-jitter`);
//! 2. `get_pixel_2d`: the film position within the pixel, fed to
//!    [`crate::filters::Filter::sample`] (under `--disable-pixel-jitter`
//!    it is still drawn, and the filter offset is then 0 with weight 1);
//! 3. `get_1d`: the time;
//! 4. `get_2d`: the lens position;
//!
//! then the integrator's own requests (light choice, light position, BSDF
//! lobe and direction, Russian roulette, ...) in its order.
//!
//! Where that lands in each sampler's sequence:
//!
//! | sampler          | `get_pixel_2d`                                  | other requests                          |
//! |------------------|-------------------------------------------------|-----------------------------------------|
//! | `halton`         | reserved dimensions 0, 1 (bases 2, 3)           | from dimension 2, wrap to 2 after 999   |
//! | `sobol`          | reserved dimensions 0, 1 (unscrambled)          | from dimension 2, wrap to 2 after 1023  |
//! | `zsobol`         | like `get_2d` (takes the next two dimensions)   | from the start dimension, no limit      |
//! | `paddedsobol`    | like `get_2d`                                   | from the start dimension, no limit      |
//! | `independent`    | like `get_2d`                                   | from the start dimension                |
//! | `stratified`     | like `get_2d`                                   | from the start dimension                |
//! | `pmj02bn`        | like `get_2d`                                   | from the start dimension, no limit      |
//!
//! So for `halton` and `sobol` the wavelength is dimension 2, the time 3
//! and the lens 4–5; for the others the wavelength is dimension 0, the film
//! position 1–2, the time 3 and the lens 4–5.

mod bits;
mod digit_permutation;
pub mod distribution;
mod halton;
mod independent;
mod padded_sobol;
mod permutation;
mod pmj02bn;
mod primes;
mod radical_inverse;
pub(crate) use radical_inverse::radical_inverse;
pub mod piecewise_linear_2d;
mod randomize_strategy;
mod sobol;
mod sobol_interval;
mod sobol_matrices;
mod sobol_sample;
mod stratified;
pub mod summed_area_table;
pub mod windowed_distribution;
mod zsobol;

pub use distribution::{Domain2D, PiecewiseConstant1D, PiecewiseConstant2D};
pub use halton::HaltonSampler;
pub use independent::IndependentSampler;
pub use padded_sobol::PaddedSobolSampler;
pub use permutation::permutation_element;
pub use pmj02bn::Pmj02bnSampler;
pub use randomize_strategy::RandomizeStrategy;
pub use sobol::SobolSampler;
pub use sobol_matrices::SOBOL_DIMENSIONS;
pub use stratified::StratifiedSampler;
pub use windowed_distribution::WindowedPiecewiseConstant2D;
pub use zsobol::ZSobolSampler;

use crate::error::{scene_error, Result};
use crate::scene_description::Entity;
use glam::{IVec2, Vec2};

/// Image sides beyond this are refused (the `sobol` sampler's pixel grid
/// stops at 2^25; the others index pixels in 32-bit integers).
const MAX_RESOLUTION: i32 = 1 << 25;

/// A sampler of any pbrt-v4 type.
#[derive(Clone, Debug)]
pub enum Sampler {
    Independent(IndependentSampler),
    Stratified(StratifiedSampler),
    Halton(HaltonSampler),
    Sobol(SobolSampler),
    PaddedSobol(PaddedSobolSampler),
    ZSobol(ZSobolSampler),
    Pmj02bn(Pmj02bnSampler),
}

/// Dispatches a method call to the sampler inside.
macro_rules! dispatch {
    ($sampler:expr, $s:ident => $call:expr) => {
        match $sampler {
            Sampler::Independent($s) => $call,
            Sampler::Stratified($s) => $call,
            Sampler::Halton($s) => $call,
            Sampler::Sobol($s) => $call,
            Sampler::PaddedSobol($s) => $call,
            Sampler::ZSobol($s) => $call,
            Sampler::Pmj02bn($s) => $call,
        }
    };
}

impl Sampler {
    /// The sampler a `Sampler` directive describes, as pbrt-v4 makes it.
    ///
    /// `seed` is the `--seed` option (the default of the `"seed"`
    /// parameter), `full_resolution` the film's full resolution, and
    /// `spp_override` the `--spp` option, which replaces the samples per
    /// pixel (for `stratified`, split into the most nearly square
    /// `xsamples × ysamples`).
    pub fn create(
        entity: &Entity,
        seed: i32,
        full_resolution: IVec2,
        spp_override: Option<u32>,
    ) -> Result<Sampler> {
        let location = &entity.location.0;
        let params = &entity.params;
        if full_resolution.min_element() < 1 || full_resolution.max_element() > MAX_RESOLUTION {
            return scene_error(
                format!(
                    "sampler \"{}\": image resolution {}x{} is not supported",
                    entity.kind, full_resolution.x, full_resolution.y
                ),
                location,
            );
        }
        let positive = |name: &str, value: i32| -> Result<u32> {
            if value < 1 {
                return scene_error(
                    format!(
                        "sampler \"{}\": \"{name}\" must be at least 1, not {value}",
                        entity.kind
                    ),
                    location,
                );
            }
            Ok(value as u32)
        };
        let pixel_samples = |default: i32| -> Result<u32> {
            let from_scene = params.int("pixelsamples", default)?;
            match spp_override {
                Some(0) => scene_error("--spp must be at least 1", location),
                Some(n) => Ok(n),
                None => positive("pixelsamples", from_scene),
            }
        };
        let randomization =
            |default: &str, allowed: &[RandomizeStrategy]| -> Result<RandomizeStrategy> {
                let name = params.string("randomization", default)?;
                match RandomizeStrategy::from_name(&name) {
                    Some(strategy) if allowed.contains(&strategy) => Ok(strategy),
                    Some(_) => scene_error(
                        format!(
                            "sampler \"{}\": \"{name}\" randomization is not supported",
                            entity.kind
                        ),
                        location,
                    ),
                    None => scene_error(
                        format!(
                            "sampler \"{}\": unknown randomization strategy \"{name}\"",
                            entity.kind
                        ),
                        location,
                    ),
                }
            };
        use RandomizeStrategy as R;
        let all_strategies = [R::None, R::PermuteDigits, R::FastOwen, R::Owen];
        let sampler = match entity.kind.as_str() {
            "independent" => {
                let samples = pixel_samples(4)?;
                let seed = params.int("seed", seed)?;
                Sampler::Independent(IndependentSampler::new(samples, seed))
            }
            "stratified" => {
                let jitter = params.bool("jitter", true)?;
                let mut x_samples = positive("xsamples", params.int("xsamples", 4)?)?;
                let mut y_samples = positive("ysamples", params.int("ysamples", 4)?)?;
                match spp_override {
                    Some(0) => return scene_error("--spp must be at least 1", location),
                    Some(n) => (x_samples, y_samples) = nearly_square_factors(n),
                    None => {}
                }
                let seed = params.int("seed", seed)?;
                Sampler::Stratified(StratifiedSampler::new(x_samples, y_samples, jitter, seed))
            }
            "halton" => {
                let samples = pixel_samples(16)?;
                let seed = params.int("seed", seed)?;
                let randomize =
                    randomization("permutedigits", &[R::None, R::PermuteDigits, R::Owen])?;
                Sampler::Halton(HaltonSampler::new(
                    samples,
                    full_resolution,
                    randomize,
                    seed,
                ))
            }
            "sobol" => {
                let samples = pixel_samples(16)?;
                let seed = params.int("seed", seed)?;
                let randomize = randomization("fastowen", &all_strategies)?;
                Sampler::Sobol(SobolSampler::new(samples, full_resolution, randomize, seed))
            }
            "paddedsobol" => {
                let samples = pixel_samples(16)?;
                let seed = params.int("seed", seed)?;
                let randomize = randomization("fastowen", &all_strategies)?;
                Sampler::PaddedSobol(PaddedSobolSampler::new(samples, randomize, seed))
            }
            "zsobol" => {
                let samples = pixel_samples(16)?;
                let seed = params.int("seed", seed)?;
                let randomize = randomization("fastowen", &all_strategies)?;
                Sampler::ZSobol(ZSobolSampler::new(
                    samples,
                    full_resolution,
                    randomize,
                    seed,
                ))
            }
            "pmj02bn" => {
                let samples = pixel_samples(16)?;
                let seed = params.int("seed", seed)?;
                Sampler::Pmj02bn(Pmj02bnSampler::new(samples, seed))
            }
            other => return scene_error(format!("\"{other}\": sampler type unknown"), location),
        };
        params.report_unused(|| format!("sampler \"{}\"", entity.kind))?;
        Ok(sampler)
    }

    /// Samples per pixel (for `zsobol`, the power of two actually used).
    pub fn samples_per_pixel(&self) -> u32 {
        dispatch!(self, s => s.samples_per_pixel())
    }

    /// Starts sample `sample_index` of `pixel`, at `dimension` of its
    /// sequence (0 for a camera path).
    pub fn start_pixel_sample(&mut self, pixel: IVec2, sample_index: u32, dimension: u32) {
        dispatch!(self, s => s.start_pixel_sample(pixel, sample_index, dimension))
    }

    /// The next value in [0, 1).
    pub fn get_1d(&mut self) -> f32 {
        dispatch!(self, s => s.get_1d())
    }

    /// The next two values, as a point of [0, 1)².
    pub fn get_2d(&mut self) -> Vec2 {
        dispatch!(self, s => s.get_2d())
    }

    /// The film position within the pixel, in [0, 1)².
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        dispatch!(self, s => s.get_pixel_2d())
    }

    /// Moves past the `count` (1 or 2) dimensions one `get_1d` or `get_2d`
    /// would take, without computing their values: for a value the scene
    /// does not use (the camera's time without motion, its lens point
    /// without a lens), so that later requests get the dimensions pbrt-v4
    /// gives them. Samplers that draw from a random stream draw and discard.
    pub fn skip(&mut self, count: usize) {
        match self {
            Sampler::Halton(s) => s.skip(count),
            Sampler::Sobol(s) => s.skip(count),
            Sampler::PaddedSobol(s) => s.skip(count),
            Sampler::ZSobol(s) => s.skip(count),
            Sampler::Pmj02bn(s) => s.skip(count),
            Sampler::Independent(_) | Sampler::Stratified(_) => {
                if count == 1 {
                    self.get_1d();
                } else {
                    self.get_2d();
                }
            }
        }
    }
}

/// `n` as `x · y` with `y` the largest divisor of `n` not above √n (pbrt-v4's
/// split of `--spp` for the stratified sampler).
fn nearly_square_factors(n: u32) -> (u32, u32) {
    let mut divisor = ((n as f64).sqrt() as u32).max(1);
    while n % divisor != 0 {
        divisor -= 1;
    }
    let x = n / divisor;
    (x, n / x)
}

#[cfg(test)]
mod tests;

/// Takes the next `count` sample dimensions of a sampler with a table of
/// `table_size` dimensions (Halton, Sobol): the first one taken; past the
/// table's end it starts again at 2 (0 and 1 are the pixel's), as pbrt-v4.
pub(crate) fn take_dimensions(dimension: &mut usize, count: usize, table_size: usize) -> usize {
    if *dimension + count > table_size {
        *dimension = 2;
    }
    let first = *dimension;
    *dimension += count;
    first
}
