//! A reference direction across each curve that does not depend on the
//! viewing ray, so an elliptical fibre keeps its orientation from every
//! view (pbrt's curve frame faces the ray and would turn the ellipse with
//! the camera).
//!
//! Ribbons have one: their normal. Other curves get one of [`FibreFrame`]:
//! a scene direction projected across the fibre, or a rotation-minimising
//! (parallel-transported) frame computed once per strand at build time by
//! the double-reflection method (Wang, Jüttler, Zheng & Liu 2008), started
//! from a direction fixed by the first tangent (turned by an angle drawn
//! per strand for `Turned`), sampled at each segment's ends and carried
//! across segments, so it is continuous and twist-free along the strand.
//! A strand is a `Shape "curve"`, or one strand of a `cyhair` shape's file
//! (`CurveSegment::strand_start` marks where each begins).
//! At a hit it is interpolated (`CurveSegment::reference_at`); the
//! material takes its part across the fibre.

use super::splines::evaluate_bezier;
use super::CurveSegment;
use crate::math::frame::coordinate_system;
use glam::Vec3;

/// Steps of the transport per segment (the frame is smooth; the tangent
/// turns little over a step).
const STEPS: usize = 8;

/// Where a non-ribbon strand's reference across the fibre comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FibreFrame {
    /// Transported from a direction that the first tangent fixes: steady
    /// along the strand, but its start means nothing to a scene's author.
    Transported,
    /// A direction (render space) projected across the fibre at each
    /// point: `vector3 ellipse_reference`.
    Toward(Vec3),
    /// Transported from a start turned about the first tangent by this
    /// angle (radians), drawn per strand: real hair's fibres are not lined
    /// up.
    Turned(f32),
}

/// An angle in [0, 2π) drawn for strand `strand` of the shape whose
/// `Shape` directive starts at byte `offset` of its file (deterministic,
/// independent of the build's order). A `Shape "curve"` is strand 0; a
/// `cyhair` shape's strands are numbered in file order.
pub fn strand_angle(offset: usize, strand: usize) -> f32 {
    // SplitMix64's finaliser: consecutive offsets give unrelated angles.
    // Strand 0 hashes the offset alone (the angles of `Shape "curve"`s
    // stay what they were); the strand index is spread by an odd 64-bit
    // constant so that a file's strands do not land on the offsets of
    // shapes a few bytes further on.
    let key = (offset as u64).wrapping_add((strand as u64).wrapping_mul(0xd1b5_4a32_d192_ed03));
    let mut z = key.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32 * std::f32::consts::TAU
}

/// Sets `reference` at both ends of the strand's consecutive segments.
pub fn set_frame(segments: &mut [CurveSegment], frame: FibreFrame) {
    match frame {
        FibreFrame::Transported => transport(segments, 0.0),
        FibreFrame::Turned(angle) => transport(segments, angle),
        FibreFrame::Toward(direction) => {
            for seg in segments.iter_mut() {
                for (k, u) in [(0, 0.0), (1, 1.0)] {
                    seg.reference[k] = orthogonal(direction, point_and_tangent(seg, u).1);
                }
            }
        }
    }
}

/// The transported frame, its start turned by `angle` about the first
/// tangent.
fn transport(segments: &mut [CurveSegment], angle: f32) {
    let Some(first) = segments.first() else {
        return;
    };
    let t0 = point_and_tangent(first, 0.0).1;
    let (a, b) = coordinate_system(t0);
    let mut r = a * angle.cos() + b * angle.sin();
    for seg in segments.iter_mut() {
        // Segments may meet at a kink: start ⟂ this segment's tangent.
        let (mut x, mut t) = point_and_tangent(seg, 0.0);
        r = orthogonal(r, t);
        seg.reference[0] = r;
        for k in 1..=STEPS {
            let (x1, t1) = point_and_tangent(seg, k as f32 / STEPS as f32);
            r = double_reflection(x, t, r, x1, t1);
            (x, t) = (x1, t1);
        }
        seg.reference[1] = r;
    }
}

fn point_and_tangent(seg: &CurveSegment, u: f32) -> (Vec3, Vec3) {
    let (p, d) = evaluate_bezier(&seg.cp, u);
    (p, d.try_normalize().unwrap_or(Vec3::Z))
}

/// One step of the double-reflection method: reflect (r, t) in the plane
/// bisecting x0→x1, then in the plane that maps the reflected tangent to t1.
fn double_reflection(x0: Vec3, t0: Vec3, r0: Vec3, x1: Vec3, t1: Vec3) -> Vec3 {
    let v1 = x1 - x0;
    let c1 = v1.length_squared();
    if c1 < 1e-20 {
        return orthogonal(r0, t1);
    }
    let rl = r0 - (2.0 / c1) * v1.dot(r0) * v1;
    let tl = t0 - (2.0 / c1) * v1.dot(t0) * v1;
    let v2 = t1 - tl;
    let c2 = v2.length_squared();
    let r1 = if c2 < 1e-20 {
        rl
    } else {
        rl - (2.0 / c2) * v2.dot(rl) * v2
    };
    orthogonal(r1, t1)
}

/// `r` made unit and orthogonal to unit `t` (any perpendicular if r ∥ t).
fn orthogonal(r: Vec3, t: Vec3) -> Vec3 {
    (r - t * t.dot(r))
        .try_normalize()
        .unwrap_or_else(|| coordinate_system(t).0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::curve::CurveType;

    fn segment(cp: [Vec3; 4]) -> CurveSegment {
        CurveSegment {
            cp,
            width: [0.1, 0.1],
            kind: CurveType::Cylinder,
            normals: [Vec3::Z; 2],
            normal_angle: 0.0,
            inv_sin_normal_angle: 0.0,
            flip_normal: false,
            reference: [Vec3::ZERO; 2],
            fibre_frame: false,
            strand_start: false,
        }
    }

    /// Along a helix-like strand of several segments the reference stays
    /// unit, ⟂ the tangent, continuous across segments, and does not
    /// depend on any ray (it is fixed at build time); along a straight
    /// strand it does not turn at all.
    #[test]
    fn transported_frame_is_orthogonal_continuous_and_twist_free() {
        let mut segs: Vec<CurveSegment> = (0..6)
            .map(|i| {
                // A C1 helix: Hermite ends as Bézier control points.
                let p = |a: f32| Vec3::new(a.cos(), a.sin(), 0.3 * a);
                let dp = |a: f32| Vec3::new(-a.sin(), a.cos(), 0.3);
                let (a0, a1) = (0.8 * i as f32, 0.8 * (i + 1) as f32);
                let k = (a1 - a0) / 3.0;
                segment([p(a0), p(a0) + k * dp(a0), p(a1) - k * dp(a1), p(a1)])
            })
            .collect();
        transport(&mut segs, 0.0);
        for w in segs.windows(2) {
            assert!((w[0].reference[1] - w[1].reference[0]).length() < 1e-6);
        }
        for s in &segs {
            for (k, u) in [(0, 0.0f32), (1, 1.0)] {
                let (_, d) = evaluate_bezier(&s.cp, u);
                let r = s.reference[k];
                assert!((r.length() - 1.0).abs() < 1e-4 && r.dot(d.normalize()).abs() < 1e-3);
            }
            // Between the ends the interpolated reference keeps a part
            // across the tangent far from degenerate (the material takes
            // that part's direction), though a segment here turns 46°.
            let r = s.reference_at(0.4, Vec3::ZERO);
            let t = evaluate_bezier(&s.cp, 0.4).1.normalize();
            let across = (r - t * t.dot(r)).length();
            assert!(across > 0.9, "{across}");
        }
        let mut straight = vec![segment([Vec3::ZERO, Vec3::X, 2.0 * Vec3::X, 3.0 * Vec3::X]); 3];
        transport(&mut straight, 0.0);
        assert!((straight[0].reference[0] - straight[2].reference[1]).length() < 1e-6);
    }

    /// `Toward`: at each end the reference is the direction's part across
    /// the tangent, whatever the strand's shape.
    #[test]
    fn reference_direction_is_projected_across_the_fibre() {
        let mut bent = vec![segment([
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
        ])];
        set_frame(&mut bent, FibreFrame::Toward(Vec3::new(0.0, 1.0, 1.0)));
        // Tangent +x at the start: (0, 1, 1) is already across it.
        let s = std::f32::consts::FRAC_1_SQRT_2;
        assert!((bent[0].reference[0] - Vec3::new(0.0, s, s)).length() < 1e-5);
        // Tangent +y at the end: only z is across it.
        assert!((bent[0].reference[1] - Vec3::Z).length() < 1e-5);
    }

    /// `Turned`: the start turns about the first tangent by the angle, and
    /// strands' angles are spread over the circle.
    #[test]
    fn turned_frames_start_at_their_angle() {
        let straight = segment([Vec3::ZERO, Vec3::X, 2.0 * Vec3::X, 3.0 * Vec3::X]);
        let mut a = vec![straight.clone()];
        let mut b = vec![straight];
        set_frame(&mut a, FibreFrame::Turned(0.0));
        set_frame(&mut b, FibreFrame::Turned(1.0));
        let cos = a[0].reference[0].dot(b[0].reference[0]);
        assert!((cos - 1.0f32.cos()).abs() < 1e-5, "{cos}");
        // Over shapes, and over the strands of one shape.
        let shapes: Vec<f32> = (0..4000).map(|i| strand_angle(100 * i, 0)).collect();
        let strands: Vec<f32> = (0..4000).map(|i| strand_angle(1234, i)).collect();
        for angles in [shapes, strands] {
            for quarter in 0..4 {
                let lo = quarter as f32 * std::f32::consts::FRAC_PI_2;
                let n = angles
                    .iter()
                    .filter(|&&x| x >= lo && x < lo + std::f32::consts::FRAC_PI_2)
                    .count();
                assert!((900..1100).contains(&n), "{quarter}: {n}");
            }
        }
    }
}
