//! Cubic Bézier splines, as pbrt-v4's `util/splines.h`: evaluation,
//! blossoming and subdivision of a segment, and the conversions of the
//! other bases a curve may be given in (B-splines, quadratic Béziers, and
//! a HAIR file's polylines and Catmull-Rom strands) to cubic Béziers.
//!
//! The conversions work in f64 (a scene's control points, before their
//! transform to render space), each written as pbrt-v4 writes it.

use glam::{DVec3, Vec2, Vec3};

/// Point and derivative of a cubic Bézier at u (de Casteljau), in 3D or
/// in a plane.
pub fn evaluate_bezier<V: BezierPoint>(cp: &[V; 4], u: f32) -> (V, V) {
    let a = [
        cp[0].lerp(cp[1], u),
        cp[1].lerp(cp[2], u),
        cp[2].lerp(cp[3], u),
    ];
    let b = [a[0].lerp(a[1], u), a[1].lerp(a[2], u)];
    let deriv = if (b[1] - b[0]).length_squared() > 0.0 {
        (b[1] - b[0]) * 3.0
    } else {
        // A degenerate end (repeated control points): use the chord.
        cp[3] - cp[0]
    };
    (b[0].lerp(b[1], u), deriv)
}

/// What [`evaluate_bezier`] needs of a point: glam's `Vec3` and `Vec2`.
pub trait BezierPoint:
    Copy + std::ops::Sub<Output = Self> + std::ops::Mul<f32, Output = Self>
{
    fn lerp(self, other: Self, t: f32) -> Self;
    fn length_squared(self) -> f32;
}

macro_rules! bezier_point {
    ($($point:ty),*) => {$(
        impl BezierPoint for $point {
            #[inline]
            fn lerp(self, other: Self, t: f32) -> Self {
                <$point>::lerp(self, other, t)
            }
            #[inline]
            fn length_squared(self) -> f32 {
                <$point>::length_squared(self)
            }
        }
    )*};
}

bezier_point!(Vec2, Vec3);

/// The control points of the sub-curve over [u0, u1] (blossoming).
pub fn blossom_piece(cp: &[Vec3; 4], u0: f32, u1: f32) -> [Vec3; 4] {
    let blossom = |u: [f32; 3]| {
        let a = [
            cp[0].lerp(cp[1], u[0]),
            cp[1].lerp(cp[2], u[0]),
            cp[2].lerp(cp[3], u[0]),
        ];
        let b = [a[0].lerp(a[1], u[1]), a[1].lerp(a[2], u[1])];
        b[0].lerp(b[1], u[2])
    };
    [
        blossom([u0, u0, u0]),
        blossom([u0, u0, u1]),
        blossom([u0, u1, u1]),
        blossom([u1, u1, u1]),
    ]
}

/// The two halves of a cubic Bézier (de Casteljau at ½).
pub fn split_in_half(c: &[Vec3; 4]) -> ([Vec3; 4], [Vec3; 4]) {
    let a = [
        c[0].midpoint(c[1]),
        c[1].midpoint(c[2]),
        c[2].midpoint(c[3]),
    ];
    let b = [a[0].midpoint(a[1]), a[1].midpoint(a[2])];
    let m = b[0].midpoint(b[1]);
    ([c[0], a[0], b[0], m], [m, b[1], a[2], c[3]])
}

/// `a + (b − a)·t`, the interpolation the conversions are written with.
fn lerp(t: f64, a: DVec3, b: DVec3) -> DVec3 {
    a + (b - a) * t
}

/// A quadratic Bézier segment as the same curve in cubic form (pbrt-v4's
/// `ElevateQuadraticBezierToCubic`).
pub fn elevate_quadratic_bezier(p: [DVec3; 3]) -> [DVec3; 4] {
    [
        p[0],
        lerp(2.0 / 3.0, p[0], p[1]),
        lerp(1.0 / 3.0, p[1], p[2]),
        p[2],
    ]
}

/// The cubic Bézier of the uniform cubic B-spline segment over control
/// points `p` (pbrt-v4's `CubicBSplineToBezier`, with its point names).
pub fn cubic_bspline_to_bezier(p: [DVec3; 4]) -> [DVec3; 4] {
    let [p012, p123, p234, p345] = p;
    let p122 = lerp(2.0 / 3.0, p012, p123);
    let p223 = lerp(1.0 / 3.0, p123, p234);
    let p233 = lerp(2.0 / 3.0, p123, p234);
    let p334 = lerp(1.0 / 3.0, p234, p345);
    [lerp(0.5, p122, p223), p223, p233, lerp(0.5, p233, p334)]
}

/// The cubic Bézier of the uniform quadratic B-spline segment over
/// control points `p` (pbrt-v4's `QuadraticBSplineToBezier`, then
/// [`elevate_quadratic_bezier`]).
pub fn quadratic_bspline_to_bezier(p: [DVec3; 3]) -> [DVec3; 4] {
    let [p01, p12, p23] = p;
    let p11 = lerp(0.5, p01, p12);
    let p22 = lerp(0.5, p12, p23);
    elevate_quadratic_bezier([p11, p12, p22])
}

/// The straight segment from `p0` to `p1` as a cubic Bézier (a HAIR
/// file's polyline strands): inner control points at its thirds.
pub fn line_to_cubic_bezier(p0: DVec3, p1: DVec3) -> [DVec3; 4] {
    [p0, lerp(1.0 / 3.0, p0, p1), lerp(2.0 / 3.0, p0, p1), p1]
}

/// The cubic Bézier of the Catmull-Rom segment from `p0` to `p1`, whose
/// neighbours are `before` and `after`: the tangents are the central
/// differences, halved.
pub fn catmull_rom_to_bezier(before: DVec3, p0: DVec3, p1: DVec3, after: DVec3) -> [DVec3; 4] {
    let t0 = (p1 - before) * 0.5;
    let t1 = (after - p0) * 0.5;
    [p0, p0 + t0 / 3.0, p1 - t1 / 3.0, p1]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    /// Each conversion gives a Bézier that starts and ends where its basis
    /// puts the segment's ends, with the basis's end tangents.
    #[test]
    fn conversions_keep_the_segment_ends_and_tangents() {
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(3.0, 2.0, 1.0),
            DVec3::new(4.0, 0.0, 2.0),
        ];
        // Uniform cubic B-spline: ends (p0 + 4p1 + p2)/6, tangents (p2 − p0)/2.
        let b = cubic_bspline_to_bezier(p);
        assert!(close(b[0], (p[0] + 4.0 * p[1] + p[2]) / 6.0));
        assert!(close(b[3], (p[1] + 4.0 * p[2] + p[3]) / 6.0));
        assert!(close(3.0 * (b[1] - b[0]), (p[2] - p[0]) / 2.0));
        // Uniform quadratic B-spline: ends at the legs' midpoints.
        let q = quadratic_bspline_to_bezier([p[0], p[1], p[2]]);
        assert!(close(q[0], (p[0] + p[1]) / 2.0) && close(q[3], (p[1] + p[2]) / 2.0));
        assert!(close(3.0 * (q[1] - q[0]), p[1] - p[0]));
        // A quadratic Bézier elevated: same ends, tangents 2(p1 − p0).
        let e = elevate_quadratic_bezier([p[0], p[1], p[2]]);
        assert!(close(e[0], p[0]) && close(e[3], p[2]));
        assert!(close(3.0 * (e[1] - e[0]), 2.0 * (p[1] - p[0])));
        // A line: evenly spaced control points.
        let l = line_to_cubic_bezier(p[0], p[3]);
        assert!(close(l[1] - l[0], l[2] - l[1]) && close(l[3] - l[2], l[2] - l[1]));
        // Catmull-Rom: through p1 and p2, tangents the halved central differences.
        let c = catmull_rom_to_bezier(p[0], p[1], p[2], p[3]);
        assert!(close(c[0], p[1]) && close(c[3], p[2]));
        assert!(close(3.0 * (c[1] - c[0]), (p[2] - p[0]) / 2.0));
        assert!(close(3.0 * (c[3] - c[2]), (p[3] - p[1]) / 2.0));
    }
}
