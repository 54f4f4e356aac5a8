//! One strand's shape: from its root, growth direction and length, the
//! style (straight, wavy, curly), gravity and clumping, sampled at n + 1
//! points with their exact derivatives and written as n cubic Béziers.
//!
//! | parameter   | meaning                                                                 |
//! |-------------|-------------------------------------------------------------------------|
//! | `length`    | length along the strand's axis (a wavy or curly strand's fibre is longer) |
//! | `style`     | `straight`; `wavy`: a planar sine across the axis, in a random plane; `curly`: a helix about the axis |
//! | `amplitude` | the sine's amplitude / the helix's radius                              |
//! | `period`    | the wave's / helix's period along the axis                             |
//! | `gravity`   | g in [0, 1]: the axis turns towards `down` by g·(2x − x²) of its angle to `down` (x = 0 at the root, 1 at the tip), so at the tip it has turned g of the way |
//! | `clumping`  | c in [0, 1]: each point moves c·x² of the way to the clump guide's point at the same x |
//!
//! The axis starts along the growth direction; gravity rotates it about
//! the fixed axis `direction × down`, so the frame carrying the wave or
//! helix turns with it (a parallel transport in closed form). The wave and
//! helix start from zero at the root (a smoothstep over the first quarter
//! period), so the root stays on the surface and the first tangent is the
//! growth direction. The curve is the cubic Hermite interpolation of the
//! samples with their derivatives: C1 across segments, and close to the
//! exact shape (a helix sampled six times a turn stays within 0.5 % of its
//! radius).

use glam::DVec3;
use std::f64::consts::TAU;

/// How a strand winds about its axis.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    Straight,
    /// A planar sine across the axis.
    Wavy,
    /// A helix about the axis.
    Curly,
}

impl Style {
    pub fn name(self) -> &'static str {
        match self {
            Style::Straight => "straight",
            Style::Wavy => "wavy",
            Style::Curly => "curly",
        }
    }
}

/// What all strands of one run share.
#[derive(Clone, Copy, Debug)]
pub struct Recipe {
    pub style: Style,
    pub amplitude: f64,
    pub period: f64,
    /// In [0, 1].
    pub gravity: f64,
    /// Unit vector.
    pub down: DVec3,
}

/// One strand before sampling.
#[derive(Clone, Copy, Debug)]
pub struct Strand {
    pub root: DVec3,
    /// Unit growth direction at the root.
    pub direction: DVec3,
    pub length: f64,
    /// The wave's or helix's phase (radians).
    pub phase: f64,
    /// Turns the wave's plane (or the helix's start) about the axis (radians).
    pub azimuth: f64,
}

/// Points at x = i/n, i = 0..=n, and their derivatives d/dx.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    pub points: Vec<DVec3>,
    pub derivatives: Vec<DVec3>,
}

/// A unit vector perpendicular to the unit vector `d`.
pub fn perpendicular(d: DVec3) -> DVec3 {
    let other = if d.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    d.cross(other).normalize()
}

/// `v` rotated by `angle` about the unit `axis` (Rodrigues).
pub fn rotate(v: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    v * c + axis.cross(v) * s + axis * axis.dot(v) * (1.0 - c)
}

/// The fraction of its bend the axis has made at x.
fn bend_profile(x: f64) -> f64 {
    2.0 * x - x * x
}

/// Smoothstep from 0 at the root to 1 at arclength `ramp`.
fn ramp(s: f64, ramp: f64) -> f64 {
    let t = (s / ramp).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The strand's frame and bend, fixed per strand.
struct Frame {
    /// Across the axis at the root: the wave's direction, the helix's start.
    u: DVec3,
    v: DVec3,
    /// Gravity's rotation axis (unit) and the total bend at the tip.
    axis: DVec3,
    bend: f64,
}

impl Frame {
    fn new(strand: &Strand, recipe: &Recipe) -> Self {
        let d = strand.direction;
        let u0 = perpendicular(d);
        let v0 = d.cross(u0);
        let (s, c) = strand.azimuth.sin_cos();
        let u = u0 * c + v0 * s;
        let v = d.cross(u);
        let cos_to_down = d.dot(recipe.down).clamp(-1.0, 1.0);
        let angle = cos_to_down.acos();
        let cross = d.cross(recipe.down);
        // Growing straight up (or down): fall towards the strand's own u.
        let axis = if cross.length() > 1e-9 {
            cross.normalize()
        } else {
            d.cross(u).normalize()
        };
        Frame {
            u,
            v,
            axis,
            bend: angle * recipe.gravity,
        }
    }

    fn angle(&self, x: f64) -> f64 {
        self.bend * bend_profile(x)
    }
}

/// The wave's or helix's offset from the axis at x.
fn offset(strand: &Strand, recipe: &Recipe, frame: &Frame, x: f64) -> DVec3 {
    if recipe.style == Style::Straight || recipe.amplitude == 0.0 {
        return DVec3::ZERO;
    }
    let s = x * strand.length;
    let r = recipe.amplitude * ramp(s, 0.25 * recipe.period.min(strand.length));
    let angle = frame.angle(x);
    let u = rotate(frame.u, frame.axis, angle);
    let t = TAU * s / recipe.period + strand.phase;
    match recipe.style {
        Style::Straight => DVec3::ZERO,
        Style::Wavy => u * (r * t.sin()),
        Style::Curly => {
            let v = rotate(frame.v, frame.axis, angle);
            (u * t.cos() + v * t.sin()) * r
        }
    }
}

/// The strand at x = i/n, i = 0..=n: points and derivatives d/dx.
pub fn sample(strand: &Strand, recipe: &Recipe, n: usize) -> Samples {
    let frame = Frame::new(strand, recipe);
    let tangent = |x: f64| rotate(strand.direction, frame.axis, frame.angle(x)) * strand.length;
    let step = 1.0 / n as f64;
    let h = 1e-5;
    let mut axis_point = strand.root;
    let mut samples = Samples {
        points: Vec::with_capacity(n + 1),
        derivatives: Vec::with_capacity(n + 1),
    };
    for i in 0..=n {
        let x = i as f64 * step;
        if i > 0 {
            // Simpson's rule over [x − step, x] (two halves).
            let a = x - step;
            let q = 0.25 * step;
            axis_point += (tangent(a)
                + 4.0 * tangent(a + q)
                + 2.0 * tangent(a + 2.0 * q)
                + 4.0 * tangent(a + 3.0 * q)
                + tangent(x))
                * (step / 12.0);
        }
        let o = offset(strand, recipe, &frame, x);
        let o_derivative = (offset(strand, recipe, &frame, x + h)
            - offset(strand, recipe, &frame, x - h))
            / (2.0 * h);
        samples.points.push(axis_point + o);
        samples.derivatives.push(tangent(x) + o_derivative);
    }
    samples
}

/// Pulls `strand` towards `guide` (sampled at the same x): each point moves
/// `clumping`·x² of the way to the guide's.
pub fn clump(strand: &mut Samples, guide: &Samples, clumping: f64) {
    let n = strand.points.len().saturating_sub(1).max(1) as f64;
    for (i, (p, d)) in strand
        .points
        .iter_mut()
        .zip(strand.derivatives.iter_mut())
        .enumerate()
    {
        let (Some(q), Some(dq)) = (guide.points.get(i), guide.derivatives.get(i)) else {
            break;
        };
        let x = i as f64 / n;
        let f = clumping * x * x;
        let df = clumping * 2.0 * x;
        let gap = *q - *p;
        *d += gap * df + (*dq - *d) * f;
        *p += gap * f;
    }
}

/// The 3n + 1 Bézier control points of the Hermite curve through the
/// samples: C1 across segments.
pub fn bezier(samples: &Samples) -> Vec<DVec3> {
    let n = samples.points.len().saturating_sub(1);
    let mut out = Vec::with_capacity(3 * n + 1);
    let third = 1.0 / (3.0 * n.max(1) as f64);
    for i in 0..n {
        let (p0, p1) = (samples.points[i], samples.points[i + 1]);
        let (d0, d1) = (samples.derivatives[i], samples.derivatives[i + 1]);
        out.push(p0);
        out.push(p0 + d0 * third);
        out.push(p1 - d1 * third);
    }
    if let Some(last) = samples.points.last() {
        out.push(*last);
    }
    out
}

/// A cubic Bézier segment's point at t.
#[cfg(test)]
pub fn bezier_point(b: &[DVec3], t: f64) -> DVec3 {
    let s = 1.0 - t;
    b[0] * (s * s * s) + b[1] * (3.0 * s * s * t) + b[2] * (3.0 * s * t * t) + b[3] * (t * t * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recipe(style: Style, gravity: f64) -> Recipe {
        Recipe {
            style,
            amplitude: 0.05,
            period: 0.2,
            gravity,
            down: DVec3::NEG_Y,
        }
    }

    fn strand(direction: DVec3) -> Strand {
        Strand {
            root: DVec3::new(1.0, 2.0, 3.0),
            direction,
            length: 1.0,
            phase: 0.7,
            azimuth: 1.3,
        }
    }

    fn curve_points(b: &[DVec3]) -> Vec<DVec3> {
        let mut out = Vec::new();
        for segment in b.windows(4).step_by(3) {
            for k in 0..=16 {
                out.push(bezier_point(segment, k as f64 / 16.0));
            }
        }
        out
    }

    #[test]
    fn a_straight_strand_is_a_segment_of_its_length() {
        let s = strand(DVec3::X);
        let b = bezier(&sample(&s, &recipe(Style::Straight, 0.0), 4));
        assert_eq!(b.len(), 13);
        assert!((b[0] - s.root).length() < 1e-12);
        assert!((b[12] - (s.root + DVec3::X)).length() < 1e-9);
        for p in curve_points(&b) {
            let rel = p - s.root;
            assert!(rel.y.abs() < 1e-9 && rel.z.abs() < 1e-9);
        }
    }

    #[test]
    fn curly_stays_within_its_amplitude_of_the_axis() {
        let s = strand(DVec3::Z);
        let r = recipe(Style::Curly, 0.0);
        let b = bezier(&sample(&s, &r, 30));
        let mut widest: f64 = 0.0;
        for p in curve_points(&b) {
            let rel = p - s.root;
            let off_axis = (rel - DVec3::Z * rel.z).length();
            widest = widest.max(off_axis);
        }
        assert!(widest <= r.amplitude * 1.01, "{widest}");
        assert!(widest >= r.amplitude * 0.95, "{widest}");
    }

    #[test]
    fn the_first_tangent_is_the_growth_direction() {
        for style in [Style::Straight, Style::Wavy, Style::Curly] {
            let d = DVec3::new(1.0, 1.0, 0.0).normalize();
            let s = strand(d);
            let b = bezier(&sample(&s, &recipe(style, 0.8), 12));
            let t = (b[1] - b[0]).normalize();
            assert!(t.dot(d) > 1.0 - 1e-6, "{style:?}: {t}");
        }
    }

    #[test]
    fn full_gravity_turns_the_tip_down() {
        for d in [DVec3::X, DVec3::Y, DVec3::new(0.0, 0.6, 0.8)] {
            let s = strand(d);
            let samples = sample(&s, &recipe(Style::Straight, 1.0), 8);
            let tip = samples.derivatives[8].normalize();
            assert!(tip.dot(DVec3::NEG_Y) > 1.0 - 1e-9, "{d}: {tip}");
            // The axis keeps its length (unit speed along x · length).
            for d in &samples.derivatives {
                assert!((d.length() - 1.0).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn full_clumping_brings_the_tip_to_the_guide() {
        let r = recipe(Style::Wavy, 0.3);
        let mut a = sample(&strand(DVec3::Y), &r, 6);
        let mut other = strand(DVec3::X);
        other.root = DVec3::ZERO;
        let g = sample(&other, &r, 6);
        let root = a.points[0];
        clump(&mut a, &g, 1.0);
        assert!((a.points[6] - g.points[6]).length() < 1e-12);
        assert!((a.points[0] - root).length() < 1e-12);
    }
}
