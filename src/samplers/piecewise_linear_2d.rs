//! A bilinearly interpolated density on [0, 1]², optionally conditioned on
//! N further parameters, with its sample warp and the warp's inverse
//! (pbrt-v4's `PiecewiseLinear2D<Dimension>`, from Mitsuba's `Marginal2D`;
//! Dupuy & Jakob 2018, "An adaptive parameterization for efficient
//! material acquisition and rendering", §5).
//!
//! The table holds `x_size` × `y_size` values per slice at the corners of
//! a regular grid over [0, 1]² (x contiguous), and one slice per
//! combination of the parameters' grid values (the first parameter
//! varying slowest). Between grid points everything is interpolated
//! linearly: the density bilinearly within a patch, the slices
//! multilinearly in the parameters (clamped at the ends).
//!
//! Sampling inverts the marginal in y (a row's integral, trapezoidal
//! between rows) and then the conditional in x, both exactly: within a
//! patch each is linear, so its CDF is a quadratic solved in closed form.
//! `invert` runs the same steps backwards, so `sample(invert(p)) = p`.
//! A measured BRDF uses it for its visible normal distribution and its
//! luminance (sampled, [`Tabulation::Density`]) and for its NDF, projected
//! area and spectra (only interpolated, [`Tabulation::Values`]).

use crate::math::{safe_sqrt, ONE_MINUS_EPSILON};
use glam::Vec2;

/// What a table is built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tabulation {
    /// A density: each slice scaled to integrate to 1 over [0, 1]², with
    /// the cumulative sums that `sample` and `invert` need (pbrt-v4's
    /// `normalize = true, build_cdf = true`).
    Density,
    /// Values only interpolated by `evaluate`, as given (pbrt-v4's
    /// `normalize = false, build_cdf = false`).
    Values,
}

/// Why a table cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    #[error("a table needs at least 2 × 2 values (has {x_size} × {y_size})")]
    TooSmall { x_size: usize, y_size: usize },
    #[error("{len} values for {slices} slices of {x_size} × {y_size}")]
    WrongLength {
        len: usize,
        slices: usize,
        x_size: usize,
        y_size: usize,
    },
    #[error("parameter {index} has no values")]
    EmptyParameter { index: usize },
    #[error("value {index} is {value}: values must be finite")]
    NotFinite { index: usize, value: f32 },
    #[error("slice {slice} integrates to {integral}: a density needs a positive, finite mass")]
    NoMass { slice: usize, integral: f64 },
}

/// A warped point and its density (pbrt-v4's `PLSample`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PLSample {
    pub p: Vec2,
    pub pdf: f32,
}

/// The table; `N` is the number of conditioning parameters.
#[derive(Clone, Debug)]
pub struct PiecewiseLinear2D<const N: usize> {
    x_size: usize,
    y_size: usize,
    /// 1 / (size − 1) and size − 1: a patch's extent in [0, 1]² and its
    /// inverse.
    patch_size: Vec2,
    inv_patch_size: Vec2,
    /// Each parameter's grid values (ascending) and its stride in slices;
    /// a parameter with one value has stride 0 (its one slice serves all).
    param_values: [Vec<f32>; N],
    param_strides: [usize; N],
    /// The values, scaled (see [`Tabulation`]).
    data: Vec<f32>,
    /// Per slice: the marginal CDF over rows (`y_size` entries) and the
    /// conditional CDF along each row (`x_size` per row), both normalised
    /// by the slice's integral. Empty for [`Tabulation::Values`].
    marginal_cdf: Vec<f32>,
    conditional_cdf: Vec<f32>,
}

/// Where a parameter point falls among the slices: the first slice of the
/// enclosing cell and each parameter's two interpolation weights.
struct SliceWeights<const N: usize> {
    slice_offset: usize,
    weights: [[f32; 2]; N],
}

impl<const N: usize> PiecewiseLinear2D<N> {
    /// The table of `data` (`slices` × `y_size` × `x_size`, x fastest),
    /// the slices at the grid values `param_values` (each ascending).
    pub fn new(
        data: &[f32],
        x_size: usize,
        y_size: usize,
        param_values: [&[f32]; N],
        tabulation: Tabulation,
    ) -> Result<Self, TableError> {
        if x_size < 2 || y_size < 2 {
            return Err(TableError::TooSmall { x_size, y_size });
        }
        // Strides from the last parameter (fastest) to the first.
        let mut slices = 1usize;
        let mut param_strides = [0usize; N];
        for i in (0..N).rev() {
            let n = param_values[i].len();
            if n == 0 {
                return Err(TableError::EmptyParameter { index: i });
            }
            param_strides[i] = if n > 1 { slices } else { 0 };
            slices *= n;
        }
        let n_values = x_size * y_size;
        if data.len() != slices * n_values {
            return Err(TableError::WrongLength {
                len: data.len(),
                slices,
                x_size,
                y_size,
            });
        }
        // A NaN or infinity would spread through every interpolation and
        // sample that touches it.
        if let Some(index) = data.iter().position(|v| !v.is_finite()) {
            return Err(TableError::NotFinite {
                index,
                value: data[index],
            });
        }
        let inv_patch_size = Vec2::new((x_size - 1) as f32, (y_size - 1) as f32);
        let mut table = PiecewiseLinear2D {
            x_size,
            y_size,
            patch_size: Vec2::new(1.0 / (x_size - 1) as f32, 1.0 / (y_size - 1) as f32),
            inv_patch_size,
            param_values: param_values.map(<[f32]>::to_vec),
            param_strides,
            data: Vec::with_capacity(data.len()),
            marginal_cdf: Vec::new(),
            conditional_cdf: Vec::new(),
        };
        match tabulation {
            Tabulation::Values => {
                // Scaled down by the patch count here and up again in
                // `evaluate`, as pbrt-v4 does (the same values up to
                // rounding).
                let scale = 1.0 / (inv_patch_size.x * inv_patch_size.y);
                table.data.extend(data.iter().map(|v| v * scale));
            }
            Tabulation::Density => {
                table.marginal_cdf.reserve(slices * y_size);
                table.conditional_cdf.reserve(data.len());
                for (slice, values) in data.chunks_exact(n_values).enumerate() {
                    table.add_density_slice(slice, values)?;
                }
            }
        }
        Ok(table)
    }

    /// Appends one slice's CDFs and normalised values.
    fn add_density_slice(&mut self, slice: usize, values: &[f32]) -> Result<(), TableError> {
        let (nx, ny) = (self.x_size, self.y_size);
        // Trapezoidal running integrals along each row, in grid units, in
        // double precision (as pbrt-v4) so that long rows keep their digits.
        let conditional_start = self.conditional_cdf.len();
        for row in values.chunks_exact(nx) {
            let mut sum = 0.0f64;
            self.conditional_cdf.push(0.0);
            for pair in row.windows(2) {
                sum += 0.5 * (pair[0] as f64 + pair[1] as f64);
                self.conditional_cdf.push(sum as f32);
            }
        }
        let conditional = &mut self.conditional_cdf[conditional_start..];
        // The marginal: trapezoidal between the rows' totals.
        let marginal_start = self.marginal_cdf.len();
        let row_total = |y: usize| conditional[(y + 1) * nx - 1] as f64;
        let mut sum = 0.0f64;
        self.marginal_cdf.push(0.0);
        for y in 0..ny - 1 {
            sum += 0.5 * (row_total(y) + row_total(y + 1));
            self.marginal_cdf.push(sum as f32);
        }
        let integral = self.marginal_cdf[marginal_start + ny - 1];
        if !(integral > 0.0 && integral.is_finite()) {
            return Err(TableError::NoMass {
                slice,
                integral: integral as f64,
            });
        }
        let normalization = 1.0 / integral;
        conditional.iter_mut().for_each(|c| *c *= normalization);
        self.marginal_cdf[marginal_start..]
            .iter_mut()
            .for_each(|c| *c *= normalization);
        self.data.extend(values.iter().map(|v| v * normalization));
        Ok(())
    }

    /// The cell of the parameter grid holding `params` and the weights of
    /// its two ends along each parameter (clamped: outside the grid the
    /// nearest slice is used).
    fn slice_weights(&self, params: [f32; N]) -> SliceWeights<N> {
        let mut slice_offset = 0;
        let mut weights = [[1.0, 0.0]; N];
        for dim in 0..N {
            let values = &self.param_values[dim];
            if values.len() == 1 {
                continue;
            }
            let index = find_interval(values.len(), |i| values[i] <= params[dim]);
            let (p0, p1) = (values[index], values[index + 1]);
            let w1 = ((params[dim] - p0) / (p1 - p0)).clamp(0.0, 1.0);
            weights[dim] = [1.0 - w1, w1];
            slice_offset += self.param_strides[dim] * index;
        }
        SliceWeights {
            slice_offset,
            weights,
        }
    }

    /// `table[index]` interpolated across the slices of the parameter cell:
    /// `index` is in the first slice of the cell, `slice_len` the length of
    /// one slice in `table`. The last parameter is interpolated outermost,
    /// as pbrt-v4 nests it.
    /// The totals of rows `row` and `row + 1` (the last entries of their
    /// conditional cdfs), interpolated across slices.
    fn row_pair_totals(&self, row: usize, slice_size: usize, at: &SliceWeights<N>) -> (f32, f32) {
        let nx = self.x_size;
        let row_offset = row * nx + at.slice_offset * slice_size;
        let r0 = self.lookup(&self.conditional_cdf, row_offset + nx - 1, slice_size, at);
        let r1 = self.lookup(
            &self.conditional_cdf,
            row_offset + 2 * nx - 1,
            slice_size,
            at,
        );
        (r0, r1)
    }

    fn lookup(&self, table: &[f32], index: usize, slice_len: usize, at: &SliceWeights<N>) -> f32 {
        self.lookup_dims(table, index, slice_len, &at.weights, N)
    }

    fn lookup_dims(
        &self,
        table: &[f32],
        index: usize,
        slice_len: usize,
        weights: &[[f32; 2]; N],
        dims: usize,
    ) -> f32 {
        if dims == 0 {
            return table.get(index).copied().unwrap_or(0.0);
        }
        let far = index + self.param_strides[dims - 1] * slice_len;
        let [w0, w1] = weights[dims - 1];
        let v0 = self.lookup_dims(table, index, slice_len, weights, dims - 1);
        let v1 = self.lookup_dims(table, far, slice_len, weights, dims - 1);
        v0 * w0 + v1 * w1
    }

    fn slice_size(&self) -> usize {
        self.x_size * self.y_size
    }

    /// Warps a uniform sample `u` ∈ [0, 1)² to a point distributed as the
    /// density at `params`, and the density there. A table built as
    /// [`Tabulation::Values`] has no CDFs and returns a zero density.
    pub fn sample(&self, u: Vec2, params: [f32; N]) -> PLSample {
        if self.marginal_cdf.is_empty() {
            return PLSample { p: u, pdf: 0.0 };
        }
        // Keep away from the ends, where the quadratics degenerate.
        let lo = 1.0 - ONE_MINUS_EPSILON;
        let mut sample = Vec2::new(
            u.x.clamp(lo, ONE_MINUS_EPSILON),
            u.y.clamp(lo, ONE_MINUS_EPSILON),
        );
        let at = self.slice_weights(params);
        let (nx, ny) = (self.x_size, self.y_size);
        let slice_size = self.slice_size();

        // The row, from the marginal CDF.
        let marginal_offset = at.slice_offset * ny;
        let marginal = |i: usize| self.lookup(&self.marginal_cdf, marginal_offset + i, ny, &at);
        let row = find_interval(ny, |i| marginal(i) < sample.y);
        sample.y -= marginal(row);

        // Within the row pair the marginal density is linear from r0 to r1
        // (the two rows' totals): solve r0 t + (r1 − r0) t²/2 = u.
        let (r0, r1) = self.row_pair_totals(row, slice_size, &at);
        sample.y = solve_linear_cdf(r0, r1, sample.y);
        let row_offset = row * nx + at.slice_offset * slice_size;

        // The column: the conditional CDF interpolated between the rows.
        sample.x *= (1.0 - sample.y) * r0 + sample.y * r1;
        let conditional = |i: usize| {
            let v0 = self.lookup(&self.conditional_cdf, row_offset + i, slice_size, &at);
            let v1 = self.lookup(&self.conditional_cdf, row_offset + nx + i, slice_size, &at);
            (1.0 - sample.y) * v0 + sample.y * v1
        };
        let col = find_interval(nx, |i| conditional(i) < sample.x);
        sample.x -= conditional(col);

        let offset = row_offset + col;
        let v00 = self.lookup(&self.data, offset, slice_size, &at);
        let v10 = self.lookup(&self.data, offset + 1, slice_size, &at);
        let v01 = self.lookup(&self.data, offset + nx, slice_size, &at);
        let v11 = self.lookup(&self.data, offset + nx + 1, slice_size, &at);
        let c0 = (1.0 - sample.y) * v00 + sample.y * v01;
        let c1 = (1.0 - sample.y) * v10 + sample.y * v11;
        sample.x = solve_linear_cdf(c0, c1, sample.x);

        PLSample {
            p: Vec2::new(
                (col as f32 + sample.x) * self.patch_size.x,
                (row as f32 + sample.y) * self.patch_size.y,
            ),
            pdf: ((1.0 - sample.x) * c0 + sample.x * c1) * self.inv_patch_size.element_product(),
        }
    }

    /// The uniform sample that [`Self::sample`] warps to `p`, and the
    /// density at `p`. Zero density for a [`Tabulation::Values`] table.
    pub fn invert(&self, p: Vec2, params: [f32; N]) -> PLSample {
        if self.marginal_cdf.is_empty() {
            return PLSample { p, pdf: 0.0 };
        }
        let at = self.slice_weights(params);
        let (nx, ny) = (self.x_size, self.y_size);
        let slice_size = self.slice_size();

        // The patch holding p, and p within it.
        let (col, row, mut sample) = self.patch(p);
        let offset = col + row * nx + at.slice_offset * slice_size;

        // The x component: the conditional CDF up to the patch plus the
        // integral of the bilinear density across the patch to p.
        let v00 = self.lookup(&self.data, offset, slice_size, &at);
        let v10 = self.lookup(&self.data, offset + 1, slice_size, &at);
        let v01 = self.lookup(&self.data, offset + nx, slice_size, &at);
        let v11 = self.lookup(&self.data, offset + nx + 1, slice_size, &at);
        let (w1, w0) = (sample, Vec2::ONE - sample);
        let c0 = w0.y * v00 + w1.y * v01;
        let c1 = w0.y * v10 + w1.y * v11;
        let pdf = w0.x * c0 + w1.x * c1;

        sample.x *= c0 + 0.5 * sample.x * (c1 - c0);
        let v0 = self.lookup(&self.conditional_cdf, offset, slice_size, &at);
        let v1 = self.lookup(&self.conditional_cdf, offset + nx, slice_size, &at);
        sample.x += (1.0 - sample.y) * v0 + sample.y * v1;

        let (r0, r1) = self.row_pair_totals(row, slice_size, &at);
        sample.x /= (1.0 - sample.y) * r0 + sample.y * r1;

        // The y component: the marginal CDF up to the row plus the linear
        // marginal density's integral to p.
        sample.y *= r0 + 0.5 * sample.y * (r1 - r0);
        let marginal_offset = row + at.slice_offset * ny;
        sample.y += self.lookup(&self.marginal_cdf, marginal_offset, ny, &at);

        PLSample {
            p: sample,
            pdf: pdf * self.inv_patch_size.element_product(),
        }
    }

    /// The table's value at `p` (bilinear within its patch, multilinear in
    /// the parameters): the density for a [`Tabulation::Density`] table,
    /// the interpolated value for a [`Tabulation::Values`] one.
    pub fn evaluate(&self, p: Vec2, params: [f32; N]) -> f32 {
        let at = self.slice_weights(params);
        let nx = self.x_size;
        let slice_size = self.slice_size();
        let (col, row, w1) = self.patch(p);
        let w0 = Vec2::ONE - w1;
        let index = col + row * nx + at.slice_offset * slice_size;
        let v00 = self.lookup(&self.data, index, slice_size, &at);
        let v10 = self.lookup(&self.data, index + 1, slice_size, &at);
        let v01 = self.lookup(&self.data, index + nx, slice_size, &at);
        let v11 = self.lookup(&self.data, index + nx + 1, slice_size, &at);
        (w0.y * (w0.x * v00 + w1.x * v10) + w1.y * (w0.x * v01 + w1.x * v11))
            * self.inv_patch_size.element_product()
    }

    /// The patch (column, row) holding `p` and `p`'s position within it
    /// (the last patch extends past 1; negative and NaN coordinates fall in
    /// the first).
    fn patch(&self, p: Vec2) -> (usize, usize, Vec2) {
        let scaled = p * self.inv_patch_size;
        // `as usize` truncates towards zero and saturates (NaN → 0), as
        // pbrt-v4's conversion to integers does for in-range values.
        let col = (scaled.x as usize).min(self.x_size - 2);
        let row = (scaled.y as usize).min(self.y_size - 2);
        (col, row, scaled - Vec2::new(col as f32, row as f32))
    }
}

/// t ∈ [0, 1] with ∫₀ᵗ ((1 − s) a + s b) ds = u (a linear density from a
/// to b; u is at most its integral (a + b)/2), and the plain 2u/(a + b)
/// where the density is constant to 10⁻⁴ (the quadratic's cancellation).
fn solve_linear_cdf(a: f32, b: f32, u: f32) -> f32 {
    if (a - b).abs() < 1e-4 * (a + b) {
        2.0 * u / (a + b)
    } else {
        (a - safe_sqrt(a * a - 2.0 * u * (a - b))) / (a - b)
    }
}

/// The largest index i in [0, size − 2] with `pred(i)` true, for a
/// predicate true then false along the index (0 where it is never true):
/// pbrt-v4's `FindInterval`, a bisection.
fn find_interval(size: usize, pred: impl Fn(usize) -> bool) -> usize {
    if size < 2 {
        return 0;
    }
    let (mut first, mut len) = (1usize, size - 2);
    while len > 0 {
        let half = len / 2;
        let middle = first + half;
        if pred(middle) {
            first = middle + 1;
            len -= half + 1;
        } else {
            len = half;
        }
    }
    (first - 1).min(size - 2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bxdfs::test_support::{chi2_survival, Pcg32Source};

    /// A smooth positive function of (x, y) and two parameters, tabulated
    /// on a grid: every slice differs, so interpolation across slices is
    /// exercised.
    fn smooth_table(nx: usize, ny: usize, a: &[f32], b: &[f32]) -> Vec<f32> {
        let mut data = Vec::new();
        for &pa in a {
            for &pb in b {
                for y in 0..ny {
                    for x in 0..nx {
                        let (fx, fy) = (x as f32 / (nx - 1) as f32, y as f32 / (ny - 1) as f32);
                        let bump = (-((fx - 0.3 - 0.2 * pa).powi(2) + (fy - 0.6 * pb).powi(2))
                            * 8.0)
                            .exp();
                        data.push(0.05 + bump + 0.3 * fx * fy);
                    }
                }
            }
        }
        data
    }

    const A: [f32; 3] = [0.0, 0.5, 1.0];
    const B: [f32; 2] = [-1.0, 2.0];

    fn conditioned() -> PiecewiseLinear2D<2> {
        let data = smooth_table(7, 5, &A, &B);
        PiecewiseLinear2D::new(&data, 7, 5, [&A, &B], Tabulation::Density).unwrap()
    }

    /// ∫ over [0, 1]² by the midpoint rule on an n × n grid.
    fn integrate(f: impl Fn(Vec2) -> f32, n: usize) -> f64 {
        let h = 1.0 / n as f64;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let p = Vec2::new(((i as f64 + 0.5) * h) as f32, ((j as f64 + 0.5) * h) as f32);
                sum += f(p) as f64;
            }
        }
        sum * h * h
    }

    #[test]
    fn the_density_integrates_to_one_at_and_between_the_slices() {
        let table = conditioned();
        for params in [
            [0.0, -1.0],
            [0.25, 0.3],
            [1.0, 2.0],
            [-3.0, 9.0],
            [0.7, 1.9],
        ] {
            let integral = integrate(|p| table.evaluate(p, params), 420);
            assert!((integral - 1.0).abs() < 1e-3, "{params:?}: {integral}");
        }
        let plain = PiecewiseLinear2D::<0>::new(
            &smooth_table(4, 9, &[0.0], &[0.0]),
            4,
            9,
            [],
            Tabulation::Density,
        )
        .unwrap();
        let integral = integrate(|p| plain.evaluate(p, []), 360);
        assert!((integral - 1.0).abs() < 1e-3, "{integral}");
    }

    #[test]
    fn sample_and_invert_are_inverses_with_the_same_density() {
        let table = conditioned();
        let mut rng = Pcg32Source::new(7);
        for i in 0..4000 {
            let params = [rng.next_f32() * 1.4 - 0.2, rng.next_f32() * 3.5 - 1.2];
            let u = rng.next_vec2();
            let s = table.sample(u, params);
            assert!(
                s.p.x >= 0.0 && s.p.x <= 1.0 && s.p.y >= 0.0 && s.p.y <= 1.0,
                "{s:?}"
            );
            let back = table.invert(s.p, params);
            assert!(
                (back.p - u).abs().max_element() < 2e-4,
                "{i}: {u} → {} → {}",
                s.p,
                back.p
            );
            let eval = table.evaluate(s.p, params);
            for pdf in [back.pdf, eval] {
                assert!(
                    (pdf - s.pdf).abs() <= 1e-4 * s.pdf.max(1.0),
                    "{i}: {pdf} vs {}",
                    s.pdf
                );
            }
        }
    }

    /// Pearson's χ² p-value of points sampled at `sampled` against the
    /// density at `judged`, integrated over each cell of a 16 × 16 grid.
    fn chi2_p_value(
        table: &PiecewiseLinear2D<2>,
        sampled: [f32; 2],
        judged: [f32; 2],
        rng: &mut Pcg32Source,
    ) -> f64 {
        const CELLS: usize = 16;
        const SAMPLES: usize = 200_000;
        let mut observed = vec![0.0f64; CELLS * CELLS];
        for _ in 0..SAMPLES {
            let p = table.sample(rng.next_vec2(), sampled).p;
            let i = ((p.x * CELLS as f32) as usize).min(CELLS - 1);
            let j = ((p.y * CELLS as f32) as usize).min(CELLS - 1);
            observed[j * CELLS + i] += 1.0;
        }
        let mut statistic = 0.0;
        for j in 0..CELLS {
            for i in 0..CELLS {
                let origin = Vec2::new(i as f32, j as f32) / CELLS as f32;
                let mass = integrate(|q| table.evaluate(origin + q / CELLS as f32, judged), 12)
                    / (CELLS * CELLS) as f64;
                let expected = mass * SAMPLES as f64;
                statistic += (observed[j * CELLS + i] - expected).powi(2) / expected;
            }
        }
        chi2_survival(statistic, CELLS * CELLS - 1)
    }

    #[test]
    fn sampled_points_follow_the_density() {
        let table = conditioned();
        let mut rng = Pcg32Source::new(11);
        for params in [[0.0, -1.0], [0.4, 0.8], [0.9, 1.7]] {
            let p = chi2_p_value(&table, params, params, &mut rng);
            assert!(p > 1e-3, "{params:?}: χ² p = {p}");
        }
        // Negative control: points of one slice judged against another's
        // density are rejected.
        let p = chi2_p_value(&table, [1.0, 2.0], [0.0, -1.0], &mut rng);
        assert!(p < 1e-6, "χ² p = {p}");
    }

    #[test]
    fn values_are_interpolated_as_given() {
        let data = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let table = PiecewiseLinear2D::<0>::new(&data, 3, 2, [], Tabulation::Values).unwrap();
        assert!((table.evaluate(Vec2::new(0.0, 0.0), []) - 1.0).abs() < 1e-6);
        assert!((table.evaluate(Vec2::new(1.0, 1.0), []) - 6.0).abs() < 1e-6);
        assert!((table.evaluate(Vec2::new(0.25, 0.5), []) - 3.0).abs() < 1e-6);
        // Along a parameter: halfway between slices of 1 and 3.
        let slices = [1.0f32; 4]
            .iter()
            .chain(&[3.0f32; 4])
            .copied()
            .collect::<Vec<_>>();
        let table =
            PiecewiseLinear2D::<1>::new(&slices, 2, 2, [&[400.0, 500.0]], Tabulation::Values)
                .unwrap();
        assert!((table.evaluate(Vec2::splat(0.3), [450.0]) - 2.0).abs() < 1e-6);
        assert!((table.evaluate(Vec2::splat(0.3), [300.0]) - 1.0).abs() < 1e-6);
        assert!((table.evaluate(Vec2::splat(0.3), [900.0]) - 3.0).abs() < 1e-6);
        assert_eq!(table.sample(Vec2::splat(0.5), [450.0]).pdf, 0.0);
    }

    #[test]
    fn malformed_tables_are_refused() {
        let too_small = PiecewiseLinear2D::<0>::new(&[1.0, 1.0], 2, 1, [], Tabulation::Values);
        assert_eq!(
            too_small.unwrap_err(),
            TableError::TooSmall {
                x_size: 2,
                y_size: 1
            }
        );
        let short = PiecewiseLinear2D::<1>::new(&[1.0; 4], 2, 2, [&[1.0, 2.0]], Tabulation::Values);
        assert!(matches!(
            short,
            Err(TableError::WrongLength {
                len: 4,
                slices: 2,
                ..
            })
        ));
        let empty = PiecewiseLinear2D::<1>::new(&[], 2, 2, [&[]], Tabulation::Values);
        assert!(matches!(
            empty,
            Err(TableError::EmptyParameter { index: 0 })
        ));
        let zero = PiecewiseLinear2D::<0>::new(&[0.0; 4], 2, 2, [], Tabulation::Density);
        assert!(matches!(zero, Err(TableError::NoMass { slice: 0, .. })));
        let nan =
            PiecewiseLinear2D::<0>::new(&[1.0, 1.0, f32::NAN, 1.0], 2, 2, [], Tabulation::Values);
        assert!(matches!(nan, Err(TableError::NotFinite { index: 2, .. })));
        let inf = PiecewiseLinear2D::<0>::new(&[f32::INFINITY; 4], 2, 2, [], Tabulation::Density);
        assert!(matches!(inf, Err(TableError::NotFinite { index: 0, .. })));
    }

    #[test]
    fn find_interval_brackets_as_pbrt() {
        let v = [0.0f32, 1.0, 2.0, 3.0];
        for (x, want) in [
            (-1.0, 0),
            (0.0, 0),
            (0.5, 0),
            (1.0, 1),
            (2.5, 2),
            (3.0, 2),
            (7.0, 2),
        ] {
            assert_eq!(find_interval(v.len(), |i| v[i] <= x), want, "{x}");
        }
        assert_eq!(find_interval(2, |_| true), 0);
    }
}
