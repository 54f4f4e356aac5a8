//! Pixel reconstruction filters (pbrt-v4's `Filter`s): each sample's film
//! position is offset from the pixel centre by a draw from the filter, and
//! weighted so the film's weighted average reconstructs the filtered image.
//!
//! Box and triangle filters are sampled exactly, with weight 1. Gaussian,
//! Mitchell and Lanczos-sinc filters are sampled from a table of the
//! filter's values ([`FilterSampler`]), the weight being the tabulated
//! value over the density: its expectation is the filter's integral, and
//! negative lobes give negative weights. Either way the film's ratio
//! Σ w·L / Σ w estimates ∫ f·L / ∫ f.

mod box_filter;
mod error_function;
mod filter_sampler;
mod gaussian;
mod lanczos_sinc;
mod mitchell;
mod triangle;

pub use box_filter::BoxFilter;
pub use filter_sampler::FilterSampler;
pub use gaussian::GaussianFilter;
pub use lanczos_sinc::LanczosSincFilter;
pub use mitchell::MitchellFilter;
pub use triangle::TriangleFilter;

use crate::error::{scene_error, Result};
use crate::scene_description::Entity;
use filter_sampler::{table_size, MAX_TABLE_CELLS};
use glam::Vec2;

/// A filter offset from the pixel centre and its weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSample {
    pub p: Vec2,
    pub weight: f32,
}

/// A filter of any pbrt-v4 type.
#[derive(Clone, Debug)]
pub enum Filter {
    Box(BoxFilter),
    Gaussian(GaussianFilter),
    Mitchell(MitchellFilter),
    LanczosSinc(LanczosSincFilter),
    Triangle(TriangleFilter),
}

/// Dispatches a method call to the filter inside.
macro_rules! dispatch {
    ($filter:expr, $f:ident => $call:expr) => {
        match $filter {
            Filter::Box($f) => $call,
            Filter::Gaussian($f) => $call,
            Filter::Mitchell($f) => $call,
            Filter::LanczosSinc($f) => $call,
            Filter::Triangle($f) => $call,
        }
    };
}

impl Filter {
    /// The filter a `PixelFilter` directive describes (`"box"`,
    /// `"gaussian"`, `"mitchell"`, `"sinc"`, `"triangle"`), with pbrt-v4's
    /// defaults.
    pub fn create(entity: &Entity) -> Result<Filter> {
        let params = &entity.params;
        let location = &entity.location.0;
        let kind = entity.kind.as_str();
        let default_radius = match kind {
            "box" => BoxFilter::DEFAULT_RADIUS,
            "gaussian" => GaussianFilter::DEFAULT_RADIUS,
            "mitchell" => MitchellFilter::DEFAULT_RADIUS,
            "sinc" => LanczosSincFilter::DEFAULT_RADIUS,
            "triangle" => TriangleFilter::DEFAULT_RADIUS,
            other => return scene_error(format!("\"{other}\": filter type unknown"), location),
        };
        let float = |name: &str, default: f32| -> Result<f32> {
            Ok(params.float(name, f64::from(default))? as f32)
        };
        let positive = |name: &str, value: f32| -> Result<f32> {
            if value > 0.0 && value.is_finite() {
                Ok(value)
            } else {
                scene_error(
                    format!("filter \"{kind}\": \"{name}\" must be positive, not {value}"),
                    location,
                )
            }
        };
        let radius = Vec2::new(
            positive("xradius", float("xradius", default_radius)?)?,
            positive("yradius", float("yradius", default_radius)?)?,
        );
        let tabulated = matches!(kind, "gaussian" | "mitchell" | "sinc");
        let cells = table_size(radius);
        if tabulated && cells.x as usize * cells.y as usize > MAX_TABLE_CELLS {
            return scene_error(
                format!(
                    "filter \"{kind}\": radius {} x {} is too large to tabulate for sampling",
                    radius.x, radius.y
                ),
                location,
            );
        }
        let filter = match kind {
            "box" => Filter::Box(BoxFilter::new(radius)),
            "gaussian" => {
                let sigma = positive("sigma", float("sigma", GaussianFilter::DEFAULT_SIGMA)?)?;
                Filter::Gaussian(GaussianFilter::new(radius, sigma))
            }
            "mitchell" => {
                let b = float("B", MitchellFilter::DEFAULT_B)?;
                let c = float("C", MitchellFilter::DEFAULT_C)?;
                Filter::Mitchell(MitchellFilter::new(radius, b, c))
            }
            "sinc" => {
                let tau = positive("tau", float("tau", LanczosSincFilter::DEFAULT_TAU)?)?;
                Filter::LanczosSinc(LanczosSincFilter::new(radius, tau))
            }
            _ => Filter::Triangle(TriangleFilter::new(radius)),
        };
        params.report_unused(|| format!("filter \"{kind}\""))?;
        Ok(filter)
    }

    /// The half-widths of the filter's support.
    pub fn radius(&self) -> Vec2 {
        dispatch!(self, f => f.radius())
    }

    /// The filter's value at offset `p` from the pixel centre.
    pub fn evaluate(&self, p: Vec2) -> f32 {
        dispatch!(self, f => f.evaluate(p))
    }

    /// ∫ f over its support.
    pub fn integral(&self) -> f32 {
        dispatch!(self, f => f.integral())
    }

    /// An offset drawn with `u` in [0, 1)² (the sampler's film sample) and
    /// its weight.
    pub fn sample(&self, u: Vec2) -> FilterSample {
        dispatch!(self, f => f.sample(u))
    }
}

#[cfg(test)]
mod tests;
