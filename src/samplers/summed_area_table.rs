//! A summed-area table of a piecewise-constant function on [0, 1]²: the
//! integral of the function over any axis-aligned rectangle in constant
//! time (pbrt-v4's `SummedAreaTable`). Backs
//! [`super::windowed_distribution::WindowedPiecewiseConstant2D`], which
//! samples within a rectangle chosen per lookup.

use glam::Vec2;

/// Running integrals of a `width` × `height` grid of values, each value
/// constant over its cell of [0, 1]².
#[derive(Clone, Debug)]
pub struct SummedAreaTable {
    /// `sums[y * width + x]`: the integral over [0, (x+1)/width] ×
    /// [0, (y+1)/height]. Double precision, since a large table's sums
    /// are differenced to integrate small rectangles.
    sums: Vec<f64>,
    width: usize,
    height: usize,
}

impl SummedAreaTable {
    /// The table of `values` (row-major, `width` × `height`, both ≥ 1).
    pub fn new(values: &[f32], width: usize, height: usize) -> Self {
        debug_assert_eq!(values.len(), width * height);
        let cell_area = 1.0 / (width * height) as f64;
        let mut sums = vec![0.0f64; width * height];
        for y in 0..height {
            let mut row = 0.0f64;
            for x in 0..width {
                row += values[y * width + x] as f64 * cell_area;
                let below = if y > 0 {
                    sums[(y - 1) * width + x]
                } else {
                    0.0
                };
                sums[y * width + x] = row + below;
            }
        }
        SummedAreaTable {
            sums,
            width,
            height,
        }
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// The integral over [0, x/width] × [0, y/height] for grid corner
    /// (x, y); corners beyond the far edges read the edge.
    fn corner(&self, x: usize, y: usize) -> f64 {
        if x == 0 || y == 0 {
            return 0.0;
        }
        let x = (x - 1).min(self.width - 1);
        let y = (y - 1).min(self.height - 1);
        self.sums[y * self.width + x]
    }

    /// The integral over [0, p.x] × [0, p.y]. Within a cell the running
    /// integral is bilinear in (x, y), so interpolating the cell's corners
    /// is exact.
    fn cumulative(&self, p: Vec2) -> f64 {
        let x = (p.x.max(0.0) as f64) * self.width as f64;
        let y = (p.y.max(0.0) as f64) * self.height as f64;
        let (x0, y0) = (x as usize, y as usize);
        let (dx, dy) = (x - x0 as f64, y - y0 as f64);
        (1.0 - dx) * (1.0 - dy) * self.corner(x0, y0)
            + dx * (1.0 - dy) * self.corner(x0 + 1, y0)
            + (1.0 - dx) * dy * self.corner(x0, y0 + 1)
            + dx * dy * self.corner(x0 + 1, y0 + 1)
    }

    /// The integral over the rectangle [min, max] (never negative: round-off
    /// in the differences is clamped away).
    pub fn integral(&self, min: Vec2, max: Vec2) -> f64 {
        let sum = (self.cumulative(max) - self.cumulative(Vec2::new(min.x, max.y)))
            + (self.cumulative(min) - self.cumulative(Vec2::new(max.x, min.y)));
        sum.max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Integrals over rectangles that cut cells partly agree with the
    /// cell-by-cell sum of the covered areas.
    #[test]
    fn integral_over_a_rectangle_matches_the_covered_cells() {
        let (w, h) = (5, 3);
        let values: Vec<f32> = (0..w * h).map(|i| (i * 7 % 11) as f32 + 0.5).collect();
        let table = SummedAreaTable::new(&values, w, h);
        let rectangles = [
            (Vec2::ZERO, Vec2::ONE),
            (Vec2::new(0.13, 0.2), Vec2::new(0.77, 0.91)),
            (Vec2::new(0.4, 0.34), Vec2::new(0.41, 0.35)),
        ];
        for (min, max) in rectangles {
            let mut expected = 0.0f64;
            for y in 0..h {
                for x in 0..w {
                    let overlap_x = ((max.x as f64).min((x + 1) as f64 / w as f64)
                        - (min.x as f64).max(x as f64 / w as f64))
                    .max(0.0);
                    let overlap_y = ((max.y as f64).min((y + 1) as f64 / h as f64)
                        - (min.y as f64).max(y as f64 / h as f64))
                    .max(0.0);
                    expected += values[y * w + x] as f64 * overlap_x * overlap_y;
                }
            }
            let got = table.integral(min, max);
            assert!(
                (got - expected).abs() < 1e-6 * expected.max(1e-3),
                "{min} {max}: {got} vs {expected}"
            );
        }
    }
}
