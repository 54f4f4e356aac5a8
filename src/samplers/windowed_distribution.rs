//! A piecewise-constant distribution on [0, 1]² sampled within a window
//! chosen per sample (pbrt-v4's `WindowedPiecewiseConstant2D`): the
//! function restricted to an axis-aligned rectangle, normalised over it.
//! A portal light samples the part of its image visible through the
//! portal from the point being lit; that rectangle changes from point to
//! point, so the marginal and conditional integrals come from a
//! [`SummedAreaTable`] rather than precomputed cdfs.

use super::distribution::Domain2D;
use super::summed_area_table::SummedAreaTable;
use glam::Vec2;

/// Bisection steps before giving up on narrowing to one cell (f32 round-off
/// could otherwise keep two bounds straddling a cell edge forever).
const MAX_BISECTION_STEPS: usize = 64;

#[derive(Clone, Debug)]
pub struct WindowedPiecewiseConstant2D {
    table: SummedAreaTable,
    /// The function's values, row-major, negative ones as 0.
    values: Vec<f32>,
}

impl WindowedPiecewiseConstant2D {
    /// The distribution of `values` (row-major, `width` × `height` cells
    /// over [0, 1]²). Negative values count as 0: a density cannot be
    /// negative.
    pub fn new(values: &[f32], width: usize, height: usize) -> Self {
        let values: Vec<f32> = values.iter().map(|&v| v.max(0.0)).collect();
        WindowedPiecewiseConstant2D {
            table: SummedAreaTable::new(&values, width, height),
            values,
        }
    }

    /// The function's value in the cell holding `p`.
    fn value(&self, p: Vec2) -> f32 {
        let (w, h) = (self.table.width(), self.table.height());
        let x = ((p.x.max(0.0) * w as f32) as usize).min(w - 1);
        let y = ((p.y.max(0.0) * h as f32) as usize).min(h - 1);
        self.values[y * w + x]
    }

    /// A point of `window` with density proportional to the function there,
    /// and that density (with respect to area in [0, 1]²). `None` where the
    /// function is zero over the whole window.
    pub fn sample(&self, u: Vec2, window: Domain2D) -> Option<(Vec2, f32)> {
        let total = self.table.integral(window.min, window.max);
        if total <= 0.0 {
            return None;
        }
        // The marginal in x: the integral over [min.x, x] × the window's
        // height, as a fraction of the window's.
        let nx = self.table.width();
        let marginal = |x: f32| self.table.integral(window.min, Vec2::new(x, window.max.y)) / total;
        let x = invert_cdf(marginal, u.x, window.min.x, window.max.x, nx);

        // The conditional in y: within the column holding x (the function
        // is constant across it, so the whole column's width serves).
        let cell = x * nx as f32;
        let mut column_min_x = cell.floor() / nx as f32;
        let mut column_max_x = cell.ceil() / nx as f32;
        if column_min_x == column_max_x {
            column_max_x += 1.0 / nx as f32;
        }
        column_min_x = column_min_x.max(0.0);
        let column_total = self.table.integral(
            Vec2::new(column_min_x, window.min.y),
            Vec2::new(column_max_x, window.max.y),
        );
        if column_total <= 0.0 {
            // A window narrower than round-off can leave x in an empty
            // column.
            return None;
        }
        let conditional = |y: f32| {
            self.table.integral(
                Vec2::new(column_min_x, window.min.y),
                Vec2::new(column_max_x, y),
            ) / column_total
        };
        let y = invert_cdf(
            conditional,
            u.y,
            window.min.y,
            window.max.y,
            self.table.height(),
        );

        let p = Vec2::new(x, y);
        let pdf = self.pdf(p, window);
        (pdf > 0.0).then_some((p, pdf))
    }

    /// The density with which [`Self::sample`] picks `p` within `window`
    /// (0 outside it, and where the function is zero over the window).
    pub fn pdf(&self, p: Vec2, window: Domain2D) -> f32 {
        let inside = p.x >= window.min.x
            && p.x <= window.max.x
            && p.y >= window.min.y
            && p.y <= window.max.y;
        if !inside {
            return 0.0;
        }
        let total = self.table.integral(window.min, window.max);
        if total <= 0.0 {
            return 0.0;
        }
        (self.value(p) as f64 / total) as f32
    }
}

/// The t in [min, max] where the increasing, piecewise-linear `cdf`
/// (linear within each of the `n` cells of [0, 1]) reaches `u`: bisection
/// down to one cell, then linear interpolation, exact within it.
fn invert_cdf(cdf: impl Fn(f32) -> f64, u: f32, min: f32, max: f32, n: usize) -> f32 {
    let (mut low, mut high) = (min, max);
    let n = n as f32;
    let u = u as f64;
    let mut steps = 0;
    while (n * high).ceil() - (n * low).floor() > 1.0 && steps < MAX_BISECTION_STEPS {
        let mid = (low + high) / 2.0;
        if cdf(mid) > u {
            high = mid;
        } else {
            low = mid;
        }
        steps += 1;
    }
    let (cdf_low, cdf_high) = (cdf(low), cdf(high));
    let t = if cdf_high > cdf_low {
        ((u - cdf_low) / (cdf_high - cdf_low)) as f32
    } else {
        0.5
    };
    (low + t * (high - low)).clamp(low, high)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 7 × 5 function with a zero column and a zero cell.
    fn distribution() -> (WindowedPiecewiseConstant2D, usize, usize) {
        let (w, h) = (7, 5);
        let values: Vec<f32> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                if x == 2 || (x, y) == (4, 3) {
                    0.0
                } else {
                    1.0 + ((x * 3 + y * 5) % 7) as f32
                }
            })
            .collect();
        (WindowedPiecewiseConstant2D::new(&values, w, h), w, h)
    }

    fn windows() -> [Domain2D; 3] {
        [
            Domain2D::UNIT,
            Domain2D::new(Vec2::new(0.21, 0.33), Vec2::new(0.83, 0.71)),
            Domain2D::new(Vec2::new(0.05, 0.5), Vec2::new(0.12, 0.52)),
        ]
    }

    /// Samples fall inside the window, never in zero cells, and carry the
    /// density `pdf` gives them.
    #[test]
    fn samples_stay_inside_the_window_with_their_pdf() {
        let (d, _, _) = distribution();
        for window in windows() {
            let m = 64;
            for j in 0..m * m {
                let u = Vec2::new(
                    ((j % m) as f32 + 0.5) / m as f32,
                    ((j / m) as f32 + 0.5) / m as f32,
                );
                let (p, pdf) = d.sample(u, window).expect("a sample");
                assert!(
                    p.cmpge(window.min).all() && p.cmple(window.max).all(),
                    "{p} outside {window:?}"
                );
                assert!(pdf > 0.0);
                let again = d.pdf(p, window);
                assert!((again - pdf).abs() <= 1e-5 * pdf, "{again} vs {pdf}");
            }
        }
    }

    /// The density integrates to 1 over the window (midpoint rule on a
    /// fine grid) and is 0 outside it.
    #[test]
    fn pdf_integrates_to_one_over_the_window() {
        let (d, _, _) = distribution();
        for window in windows() {
            let m = 700;
            let extent = window.max - window.min;
            let mut sum = 0.0f64;
            for j in 0..m * m {
                let t = Vec2::new(
                    ((j % m) as f32 + 0.5) / m as f32,
                    ((j / m) as f32 + 0.5) / m as f32,
                );
                sum += d.pdf(window.lerp(t), window) as f64;
            }
            let integral = sum * (extent.x * extent.y) as f64 / (m * m) as f64;
            assert!((integral - 1.0).abs() < 1e-2, "{window:?}: {integral}");
            let outside = Vec2::new(window.max.x + 0.01, window.min.y);
            if outside.x < 1.0 {
                assert_eq!(d.pdf(outside, window), 0.0);
            }
        }
    }

    /// Sample counts per cell follow the function (a χ²-like check on
    /// the full window), so sampling and density are the same
    /// distribution.
    #[test]
    fn sample_histogram_follows_the_function() {
        let (d, w, h) = distribution();
        // Hammersley points: evenly spread in u.x and, within any range
        // of u.x, in u.y too.
        let count: u32 = 1 << 17;
        let mut counts = vec![0usize; w * h];
        for j in 0..count {
            let u = Vec2::new(
                (j as f32 + 0.5) / count as f32,
                (j.reverse_bits() as f64 / 2f64.powi(32)) as f32,
            );
            let (p, _) = d.sample(u, Domain2D::UNIT).expect("a sample");
            let x = ((p.x * w as f32) as usize).min(w - 1);
            let y = ((p.y * h as f32) as usize).min(h - 1);
            counts[y * w + x] += 1;
        }
        let total: f32 = d.values.iter().sum();
        for (i, (&value, &got)) in d.values.iter().zip(&counts).enumerate() {
            let expected = value / total * count as f32;
            let got = got as f32;
            assert!(
                (got - expected).abs() <= 0.01 * expected + 2.0,
                "cell {i}: {got} vs {expected}"
            );
        }
    }

    /// A window over zeros only has nothing to sample.
    #[test]
    fn a_window_over_zeros_samples_nothing() {
        let (d, _, _) = distribution();
        let column_two = Domain2D::new(Vec2::new(2.1 / 7.0, 0.0), Vec2::new(2.9 / 7.0, 1.0));
        assert!(d.sample(Vec2::splat(0.5), column_two).is_none());
        assert_eq!(d.pdf(Vec2::new(0.35, 0.5), column_two), 0.0);
    }
}
