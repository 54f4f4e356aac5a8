//! Piecewise-constant distributions in 1D and 2D: sampling a tabulated
//! function in proportion to its absolute value (pbrt-v4's
//! `PiecewiseConstant1D` and `PiecewiseConstant2D`). Used by the filters'
//! tabulated sampling, and meant for image lights as well.

use glam::{UVec2, Vec2};

/// A rectangle `[min, max]` a 2D distribution is defined over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain2D {
    pub min: Vec2,
    pub max: Vec2,
}

impl Domain2D {
    /// [0, 1]².
    pub const UNIT: Domain2D = Domain2D {
        min: Vec2::ZERO,
        max: Vec2::ONE,
    };

    pub fn new(min: Vec2, max: Vec2) -> Self {
        Domain2D { min, max }
    }

    /// Where `p` lies, as a fraction of the extent along each axis.
    pub fn offset(&self, p: Vec2) -> Vec2 {
        let extent = self.max - self.min;
        let mut o = p - self.min;
        if extent.x > 0.0 {
            o.x /= extent.x;
        }
        if extent.y > 0.0 {
            o.y /= extent.y;
        }
        o
    }

    /// The point at fraction `t` of the extent along each axis.
    pub fn lerp(&self, t: Vec2) -> Vec2 {
        (Vec2::ONE - t) * self.min + t * self.max
    }
}

/// One step of a tabulated function: the normalized running integral at
/// its start and |f| on it, side by side so that a sample reads both from
/// one cache line.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Step {
    cdf: f32,
    value: f32,
}

/// Guide entry k of a table: `first`, the interval u = k / n falls in,
/// with that interval's step and the next step's cdf. A sample u that
/// falls in it (most do) reads nothing but this entry.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
struct Cut {
    first: u32,
    cdf: f32,
    value: f32,
    next_cdf: f32,
}

/// A table's guide: for each bucket k = 0…n, the interval u = k / n falls
/// in. The 1D tables keep [`Cut`]s (the interval's step beside its index);
/// the rows of a 2D table keep the index alone, in 2 bytes where the rows
/// are narrow enough (an image light's two distributions would otherwise
/// hold 16 bytes a texel each for their guides: 8 MB for a 512² image).
trait Guide {
    /// The first interval of bucket `k`, its step and the next step's cdf.
    fn cut(&self, steps: &[Step], k: usize) -> (usize, Step, f32);
    /// The first interval of bucket `k`.
    fn first(&self, k: usize) -> usize;
    /// Starts loading bucket `k`'s entry.
    fn prefetch(&self, k: usize);
}

impl Guide for [Cut] {
    #[inline]
    fn cut(&self, _: &[Step], k: usize) -> (usize, Step, f32) {
        let cut = self[k];
        let step = Step {
            cdf: cut.cdf,
            value: cut.value,
        };
        (cut.first as usize, step, cut.next_cdf)
    }

    #[inline]
    fn first(&self, k: usize) -> usize {
        self[k].first as usize
    }

    #[inline]
    fn prefetch(&self, k: usize) {
        crate::accel::prefetch(&self[k]);
    }
}

/// A guide of interval indices alone (`u16` or `u32`).
macro_rules! index_guide {
    ($index:ty) => {
        impl Guide for [$index] {
            #[inline]
            fn cut(&self, steps: &[Step], k: usize) -> (usize, Step, f32) {
                let first = self[k] as usize;
                (first, steps[first], steps[first + 1].cdf)
            }

            #[inline]
            fn first(&self, k: usize) -> usize {
                self[k] as usize
            }

            #[inline]
            fn prefetch(&self, k: usize) {
                crate::accel::prefetch(&self[k]);
            }
        }
    };
}
index_guide!(u16);
index_guide!(u32);

/// The tables of one step function: `steps` (n + 1 entries, the last one
/// holding cdf 1 and no value) and `guide` (n + 1 entries, k = 0…n). A
/// sample u in [k/n, (k+1)/n) lies in an interval between `guide[k]`'s
/// first and `guide[k + 1]`'s, so it searches there: one or two steps on
/// average instead of log₂ n dependent loads, with exactly the interval
/// the full search finds (the cutpoint method of Chen and Asau 1974).
struct Tables<'a, G: ?Sized> {
    steps: &'a [Step],
    guide: &'a G,
}

impl<G: ?Sized> Clone for Tables<'_, G> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<G: ?Sized> Copy for Tables<'_, G> {}

/// Appends the steps of `|function|` on equal steps over `[min, max]` to
/// `steps` (an all-zero function gets a uniform cdf); returns the integral
/// of |f|.
fn tabulate_steps(function: &[f32], min: f32, max: f32, steps: &mut Vec<Step>) -> f32 {
    let n = function.len();
    let first = steps.len();
    let mut cdf = 0.0f32;
    for &f in function {
        let value = f.abs();
        steps.push(Step { cdf, value });
        cdf += value * (max - min) / n as f32;
    }
    steps.push(Step { cdf, value: 0.0 });
    let table = &mut steps[first..];
    let integral = cdf;
    for (i, step) in table.iter_mut().enumerate().skip(1) {
        step.cdf = if integral == 0.0 {
            i as f32 / n as f32
        } else {
            step.cdf / integral
        };
    }
    integral
}

/// The first interval of each guide bucket k = 0…n of a table's steps.
fn guide_intervals(table: &[Step]) -> impl Iterator<Item = usize> + '_ {
    let n = table.len() - 1;
    (0..=n).map(move |k| find_interval(table, k as f32 / n as f32))
}

/// Appends the tables of `|function|` on equal steps over `[min, max]` to
/// `steps` and `guide` (an all-zero function gets a uniform cdf); returns
/// the integral of |f|.
fn tabulate(
    function: &[f32],
    min: f32,
    max: f32,
    steps: &mut Vec<Step>,
    guide: &mut Vec<Cut>,
) -> f32 {
    let first = steps.len();
    let integral = tabulate_steps(function, min, max, steps);
    let table = &steps[first..];
    guide.extend(guide_intervals(table).map(|first| Cut {
        first: first as u32,
        cdf: table[first].cdf,
        value: table[first].value,
        next_cdf: table[first + 1].cdf,
    }));
    integral
}

impl<G: Guide + ?Sized> Tables<'_, G> {
    /// Number of steps.
    fn size(&self) -> usize {
        self.steps.len() - 1
    }

    /// The guide bucket `u` falls in (rounding of u · n may put it one
    /// off; [`Tables::locate`] allows for that).
    #[inline]
    fn bucket(&self, u: f32) -> usize {
        let n = self.size();
        ((u * n as f32) as usize).min(n - 1)
    }

    /// Starts loading the guide entry [`Tables::locate`] reads first.
    #[inline]
    fn prefetch(&self, u: f32) {
        self.guide.prefetch(self.bucket(u));
    }

    /// The interval `u` falls in (the last i ≤ n − 1 with cdf[i] ≤ u, as
    /// [`find_interval`] finds it), its step and the next step's cdf.
    #[inline]
    fn locate(&self, u: f32) -> (usize, Step, f32) {
        let n = self.size();
        let k = self.bucket(u);
        let (first, step, next_cdf) = self.guide.cut(self.steps, k);
        // cdf[i] ≤ u < cdf[i + 1] makes i the last interval with cdf ≤ u,
        // whichever bucket rounding put u in.
        if step.cdf <= u && u < next_cdf {
            return (first, step, next_cdf);
        }
        let cdf = |i: usize| self.steps[i].cdf;
        let (mut lo, mut hi) = (first, self.guide.first(k + 1));
        // Rounding of u · n may have put u one bucket off: widen to it.
        while lo > 0 && cdf(lo) > u {
            lo -= 1;
        }
        while hi < n - 1 && cdf(hi + 1) <= u {
            hi += 1;
        }
        // The last i in [lo, hi] with cdf[i] ≤ u (cdf[lo] ≤ u here unless
        // lo = 0, the answer then).
        while lo < hi {
            let middle = (lo + hi).div_ceil(2);
            if cdf(middle) <= u {
                lo = middle;
            } else {
                hi = middle - 1;
            }
        }
        (lo, self.steps[lo], cdf(lo + 1))
    }

    /// Samples with `u` in [0, 1) a function with integral `integral` over
    /// `[min, max]`: the point, its density, and the index of the step it
    /// lies in.
    #[inline]
    fn sample(&self, u: f32, integral: f32, min: f32, max: f32) -> (f32, f32, usize) {
        let (offset, step, next_cdf) = self.locate(u);
        let mut du = u - step.cdf;
        let step_mass = next_cdf - step.cdf;
        if step_mass > 0.0 {
            du /= step_mass;
        }
        let pdf = if integral > 0.0 {
            step.value / integral
        } else {
            0.0
        };
        let t = (offset as f32 + du) / self.size() as f32;
        ((1.0 - t) * min + t * max, pdf, offset)
    }
}

/// A step function on `[min, max]` with equal-width steps, and the means to
/// sample it in proportion to its absolute value.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant1D {
    steps: Vec<Step>,
    guide: Vec<Cut>,
    min: f32,
    max: f32,
    /// ∫|f| over [min, max].
    integral: f32,
}

impl PiecewiseConstant1D {
    /// The distribution of `|function|`, its values on equal steps over
    /// `[min, max]`. An all-zero function samples uniformly (with pdf 0);
    /// an empty one is taken as a single zero step.
    pub fn new(function: &[f32], min: f32, max: f32) -> Self {
        let function = if function.is_empty() {
            &[0.0][..]
        } else {
            function
        };
        let (mut steps, mut guide) = (Vec::new(), Vec::new());
        let integral = tabulate(function, min, max, &mut steps, &mut guide);
        PiecewiseConstant1D {
            steps,
            guide,
            min,
            max,
            integral,
        }
    }

    fn tables(&self) -> Tables<'_, [Cut]> {
        Tables {
            steps: &self.steps,
            guide: &self.guide[..],
        }
    }

    /// ∫|f| over the domain.
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Number of steps.
    pub fn size(&self) -> usize {
        self.tables().size()
    }

    /// |f| on step `i`.
    pub fn value(&self, i: usize) -> f32 {
        self.steps[i].value
    }

    /// Samples with `u` in [0, 1): the point, its density, and the index of
    /// the step it lies in.
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        self.tables().sample(u, self.integral, self.min, self.max)
    }
}

/// The last index `i` in `0..steps.len() - 1` with `steps[i].cdf <= u`
/// (clamped to that range), by binary search: the step `u` falls in.
fn find_interval(steps: &[Step], u: f32) -> usize {
    let last = steps.len().saturating_sub(2);
    let mut size = steps.len().saturating_sub(2);
    let mut first = 1usize;
    while size > 0 {
        let half = size >> 1;
        let middle = first + half;
        if steps[middle].cdf <= u {
            first = middle + 1;
            size -= half + 1;
        } else {
            size = half;
        }
    }
    first.saturating_sub(1).min(last)
}

/// A 2D step function on a grid over a rectangle, sampled in proportion to
/// its absolute value: a marginal distribution over rows (v) and a
/// conditional one within each row (u). The rows' tables lie end to end in
/// two arrays, so a sample reads no per-row header: 10 bytes a cell where
/// rows have fewer than 65,536 steps (pbrt-v4's tables hold 8: each step's
/// value and cdf).
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant2D {
    domain: Domain2D,
    /// Steps per row.
    nu: usize,
    /// Row v's steps at `v (nu + 1) .. (v + 1)(nu + 1)`.
    steps: Vec<Step>,
    /// Row v's guide at the same place.
    guides: RowGuides,
    /// The distribution over rows of each row's integral (its values are
    /// the rows' integrals).
    marginal: PiecewiseConstant1D,
}

/// The rows' guides: interval indices within the row, in 2 bytes where
/// they fit.
#[derive(Clone, Debug, PartialEq)]
enum RowGuides {
    Narrow(Vec<u16>),
    Wide(Vec<u32>),
}

impl PiecewiseConstant2D {
    /// The distribution of `|function|`, given row by row (`nu` values per
    /// row, u fastest, `nv` rows) over `domain`. Missing values count as 0;
    /// `nu` and `nv` are taken as at least 1.
    pub fn new(function: &[f32], nu: usize, nv: usize, domain: Domain2D) -> Self {
        let (nu, nv) = (nu.max(1), nv.max(1));
        let mut steps = Vec::with_capacity(nv * (nu + 1));
        // An interval index is at most nu - 1.
        let mut guides = if nu <= usize::from(u16::MAX) {
            RowGuides::Narrow(Vec::with_capacity(nv * (nu + 1)))
        } else {
            RowGuides::Wide(Vec::with_capacity(nv * (nu + 1)))
        };
        let mut row = Vec::with_capacity(nu);
        let row_integrals: Vec<f32> = (0..nv)
            .map(|v| {
                row.clear();
                row.extend((0..nu).map(|u| function.get(v * nu + u).copied().unwrap_or(0.0)));
                let first = steps.len();
                let integral = tabulate_steps(&row, domain.min.x, domain.max.x, &mut steps);
                let intervals = guide_intervals(&steps[first..]);
                match &mut guides {
                    RowGuides::Narrow(g) => g.extend(intervals.map(|i| i as u16)),
                    RowGuides::Wide(g) => g.extend(intervals.map(|i| i as u32)),
                }
                integral
            })
            .collect();
        let marginal = PiecewiseConstant1D::new(&row_integrals, domain.min.y, domain.max.y);
        PiecewiseConstant2D {
            domain,
            nu,
            steps,
            guides,
            marginal,
        }
    }

    /// Where row `v`'s tables lie.
    fn row_range(&self, v: usize) -> std::ops::Range<usize> {
        v * (self.nu + 1)..(v + 1) * (self.nu + 1)
    }

    /// Samples row `v` with `u`: the point, its density within the row,
    /// and the step's index.
    #[inline]
    fn sample_row(&self, v: usize, u: f32) -> (f32, f32, usize) {
        let range = self.row_range(v);
        let steps = &self.steps[range.clone()];
        let (integral, min, max) = (self.marginal.value(v), self.domain.min.x, self.domain.max.x);
        match &self.guides {
            RowGuides::Narrow(g) => Tables {
                steps,
                guide: &g[range],
            }
            .sample(u, integral, min, max),
            RowGuides::Wide(g) => Tables {
                steps,
                guide: &g[range],
            }
            .sample(u, integral, min, max),
        }
    }

    pub fn domain(&self) -> Domain2D {
        self.domain
    }

    /// ∫|f| over the domain.
    pub fn integral(&self) -> f32 {
        self.marginal.integral()
    }

    /// Samples with `u` in [0, 1)²: the point and its density.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (p, pdf, _) = self.sample_with_cell(u);
        (p, pdf)
    }

    /// Samples with `u` in [0, 1)²: the point, its density, and the grid
    /// cell (column, row) it lies in.
    pub fn sample_with_cell(&self, u: Vec2) -> (Vec2, f32, UVec2) {
        let (y, pdf_y, row) = self.marginal.sample(u.y);
        let (x, pdf_x, column) = self.sample_row(row, u.x);
        (
            Vec2::new(x, y),
            pdf_x * pdf_y,
            UVec2::new(column as u32, row as u32),
        )
    }

    /// Starts loading the guide entry `sample_with_cell(u)` will read in
    /// its row (the marginal table is small and cached).
    #[inline]
    pub fn prefetch(&self, u: Vec2) {
        let (_, _, row) = self.marginal.sample(u.y);
        let range = self.row_range(row);
        let steps = &self.steps[range.clone()];
        match &self.guides {
            RowGuides::Narrow(g) => Tables {
                steps,
                guide: &g[range],
            }
            .prefetch(u.x),
            RowGuides::Wide(g) => Tables {
                steps,
                guide: &g[range],
            }
            .prefetch(u.x),
        }
    }

    /// The density of sampling `p` (a point of the domain).
    pub fn pdf(&self, p: Vec2) -> f32 {
        let o = self.domain.offset(p);
        let nu = self.nu;
        let nv = self.marginal.size();
        let column = ((o.x * nu as f32) as i64).clamp(0, nu as i64 - 1) as usize;
        let row = ((o.y * nv as f32) as i64).clamp(0, nv as i64 - 1) as usize;
        let integral = self.marginal.integral();
        if integral == 0.0 {
            return 0.0;
        }
        self.steps[self.row_range(row)][column].value / integral
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_dimensional_sampling_follows_the_function() {
        let d = PiecewiseConstant1D::new(&[1.0, -3.0, 0.0, 4.0], 0.0, 2.0);
        assert_eq!(d.integral(), 4.0);
        let (x, pdf, offset) = d.sample(0.0);
        assert_eq!((x, pdf, offset), (0.0, 0.25, 0));
        // The second step holds cdf mass 3/8 starting at 1/8.
        let (x, pdf, offset) = d.sample(0.125 + 0.375 / 2.0);
        assert_eq!(offset, 1);
        assert!((x - 0.75).abs() < 1e-6);
        assert_eq!(pdf, 0.75);
        // Zero steps are never chosen.
        for i in 0..1000 {
            let (_, _, offset) = d.sample(i as f32 / 1000.0);
            assert_ne!(offset, 2);
        }
        let (_, _, offset) = d.sample(ONE_BELOW_ONE);
        assert_eq!(offset, 3);
    }

    const ONE_BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

    /// The guided search finds the interval the full binary search finds,
    /// for functions with zero runs, single spikes and smooth parts, at
    /// random u, at every cdf value and bucket boundary and next to them.
    #[test]
    fn guided_search_finds_the_binary_search_interval() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        for case in 0..60 {
            let n = 1 + (rnd() * 300.0) as usize;
            let function: Vec<f32> = (0..n)
                .map(|i| match case % 4 {
                    0 => rnd(),
                    1 => {
                        if rnd() < 0.7 {
                            0.0
                        } else {
                            rnd() * 10.0
                        }
                    }
                    2 => {
                        if i == n / 3 {
                            1e6
                        } else {
                            rnd() * 1e-3
                        }
                    }
                    _ => (i as f32 * 0.1).sin().abs() * ((i % 17 == 0) as u8 as f32),
                })
                .collect();
            let d = PiecewiseConstant1D::new(&function, 0.0, 1.0);
            let mut us: Vec<f32> = (0..2000).map(|_| rnd()).collect();
            // Neighbouring floats (u > 0 here, so ± 1 ulp in the bits).
            let around = |x: f32| {
                [
                    x,
                    f32::from_bits(x.to_bits().saturating_sub(1)),
                    f32::from_bits(x.to_bits() + 1),
                ]
            };
            for step in &d.steps {
                us.extend(around(step.cdf));
            }
            for k in 0..=n {
                us.extend(around(k as f32 / n as f32));
            }
            us.extend([0.0, ONE_BELOW_ONE]);
            for u in us.into_iter().filter(|u| (0.0..1.0).contains(u)) {
                let i = find_interval(&d.steps, u);
                assert_eq!(
                    d.tables().locate(u),
                    (i, d.steps[i], d.steps[i + 1].cdf),
                    "case {case} n {n} u {u}"
                );
            }
        }
    }

    /// A 2D table's rows, with their guides of indices (2 bytes, or 4 for
    /// rows of 65,536 steps and more), find the interval the full binary
    /// search finds.
    #[test]
    fn row_guides_find_the_binary_search_interval() {
        let mut rng = crate::shapes::test_support::TestRng::new(0x9e37_79b9_7f4a_7c15);
        let mut rnd = || rng.uniform();
        for (nu, nv) in [(1, 1), (7, 5), (300, 3), (70_000, 1)] {
            let function: Vec<f32> = (0..nu * nv)
                .map(|i| {
                    if i % 11 < 4 {
                        0.0
                    } else {
                        rnd() * (1 + i % 3) as f32
                    }
                })
                .collect();
            let d = PiecewiseConstant2D::new(&function, nu, nv, Domain2D::UNIT);
            assert_eq!(matches!(d.guides, RowGuides::Wide(_)), nu > 65_535);
            for v in 0..nv {
                let steps = &d.steps[d.row_range(v)];
                let mut us: Vec<f32> = (0..500).map(|_| rnd()).collect();
                us.extend(steps.iter().map(|s| s.cdf).filter(|&c| c < 1.0));
                us.extend((0..nu).map(|k| k as f32 / nu as f32));
                for u in us {
                    let i = find_interval(steps, u);
                    let (_, _, column) = d.sample_row(v, u);
                    assert_eq!(column, i, "{nu}×{nv} row {v} u {u}");
                }
            }
        }
    }

    #[test]
    fn zero_function_samples_uniformly() {
        let d = PiecewiseConstant1D::new(&[0.0, 0.0], -1.0, 1.0);
        let (x, pdf, _) = d.sample(0.75);
        assert_eq!((x, pdf), (0.5, 0.0));
        let empty = PiecewiseConstant1D::new(&[], 0.0, 1.0);
        assert_eq!(empty.sample(0.5).0, 0.5);
    }

    #[test]
    fn two_dimensional_pdf_integrates_to_one_and_matches_sampling() {
        let nu = 4;
        let nv = 3;
        let function: Vec<f32> = (0..nu * nv).map(|i| (i % 5) as f32 - 1.0).collect();
        let domain = Domain2D::new(Vec2::new(-1.0, 0.0), Vec2::new(1.0, 3.0));
        let d = PiecewiseConstant2D::new(&function, nu, nv, domain);
        let cell_area = (2.0 / nu as f32) * (3.0 / nv as f32);
        let mut total = 0.0;
        for v in 0..nv {
            for u in 0..nu {
                let p = domain.lerp(Vec2::new(
                    (u as f32 + 0.5) / nu as f32,
                    (v as f32 + 0.5) / nv as f32,
                ));
                total += d.pdf(p) * cell_area;
            }
        }
        assert!((total - 1.0).abs() < 1e-5);
        for i in 0..50 {
            for j in 0..50 {
                let u = Vec2::new((i as f32 + 0.5) / 50.0, (j as f32 + 0.5) / 50.0);
                let (p, pdf, cell) = d.sample_with_cell(u);
                assert!((d.pdf(p) - pdf).abs() < 1e-5);
                assert!(pdf > 0.0);
                assert_ne!(function[cell.y as usize * nu + cell.x as usize], 0.0);
            }
        }
    }
}
