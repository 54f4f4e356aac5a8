//! Sampling a filter by tabulation (pbrt-v4's `FilterSampler`), for
//! filters with no closed-form sampling: the filter's values at the centres
//! of a grid of 32 cells per unit of radius, sampled in proportion to their
//! absolute value, each sample weighted by the tabulated value over its
//! density (so negative lobes give negative weights).

use super::FilterSample;
use crate::samplers::{Domain2D, PiecewiseConstant2D};
use glam::{UVec2, Vec2};

/// Tabulated cells per unit of filter radius, along each axis.
const CELLS_PER_UNIT_RADIUS: f32 = 32.0;

/// The most table cells allowed (about 16 MB of floats per table).
pub const MAX_TABLE_CELLS: usize = 1 << 22;

/// Table size along each axis for `radius` (at least one cell).
pub fn table_size(radius: Vec2) -> UVec2 {
    UVec2::new(
        ((CELLS_PER_UNIT_RADIUS * radius.x) as u32).max(1),
        ((CELLS_PER_UNIT_RADIUS * radius.y) as u32).max(1),
    )
}

/// A filter's tabulated values and the distribution of their magnitude.
#[derive(Clone, Debug)]
pub struct FilterSampler {
    size: UVec2,
    /// Filter values at cell centres, row by row.
    values: Vec<f32>,
    distribution: PiecewiseConstant2D,
}

impl FilterSampler {
    /// Tabulates `evaluate` over [-radius, radius]. The table must not
    /// exceed [`MAX_TABLE_CELLS`] (checked when filters are made).
    pub fn new(radius: Vec2, evaluate: impl Fn(Vec2) -> f32) -> Self {
        let size = table_size(radius);
        let domain = Domain2D::new(-radius, radius);
        let mut values = Vec::with_capacity(size.x as usize * size.y as usize);
        for y in 0..size.y {
            for x in 0..size.x {
                let t = Vec2::new(
                    (x as f32 + 0.5) / size.x as f32,
                    (y as f32 + 0.5) / size.y as f32,
                );
                values.push(evaluate(domain.lerp(t)));
            }
        }
        let distribution =
            PiecewiseConstant2D::new(&values, size.x as usize, size.y as usize, domain);
        FilterSampler {
            size,
            values,
            distribution,
        }
    }

    /// A filter offset drawn with `u` in [0, 1)², weighted by the tabulated
    /// value over the density.
    pub fn sample(&self, u: Vec2) -> FilterSample {
        let (p, pdf, cell) = self.distribution.sample_with_cell(u);
        let value = self.values[(cell.y * self.size.x + cell.x) as usize];
        let weight = if pdf > 0.0 { value / pdf } else { 0.0 };
        FilterSample { p, weight }
    }
}
