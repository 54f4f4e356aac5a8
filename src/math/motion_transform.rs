//! A transform that moves during the shutter interval (pbrt-v4's
//! `AnimatedTransform`): motion blur of shapes, instances and the camera.
//!
//! The start and end matrices are each split into translation T, rotation
//! R and the rest S (scale and shear) by polar decomposition, M = T R S.
//! At a time between the two, T and S are interpolated linearly and R by
//! spherical interpolation of its quaternion (the shorter way round), and
//! the matrix is put back together. Before the start time the start
//! matrix holds, after the end time the end one, as in pbrt-v4.
//!
//! Bounds over the whole motion ([`MotionTransform::motion_bounds`]) are
//! conservative: each corner's path is sampled, and the distance between
//! the path and its samples' polygon is bounded from its curvature (see
//! there), instead of pbrt-v4's closed-form extrema of the same path.

use super::{Bounds3, Transform};
use glam::{DMat3, DMat4, DQuat, DVec3};

/// Start and end transforms with their times, decomposed for
/// interpolation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionTransform {
    start: Transform,
    end: Transform,
    start_time: f32,
    end_time: f32,
    translation: [DVec3; 2],
    rotation: [DQuat; 2],
    /// What is left once the rotation is taken out (scale and shear).
    stretch: [DMat3; 2],
}

/// Polar decomposition of an affine matrix: (translation, rotation,
/// stretch) with M = T · R · S. A reflection is left in S, so that R is a
/// proper rotation (a quaternion can represent it).
fn decompose(m: &DMat4) -> (DVec3, DQuat, DMat3) {
    let translation = m.w_axis.truncate();
    let linear = DMat3::from_mat4(*m);
    // Averaging a matrix with its inverse transpose converges to the
    // orthogonal factor of its polar decomposition.
    let mut rotation = linear;
    for _ in 0..100 {
        let next = (rotation + rotation.inverse().transpose()) * 0.5;
        let change = (next - rotation).abs();
        rotation = next;
        let row_sums = change.x_axis + change.y_axis + change.z_axis;
        if row_sums.max_element() <= 1e-12 {
            break;
        }
    }
    if rotation.determinant() < 0.0 {
        rotation = -rotation;
    }
    let stretch = rotation.transpose() * linear;
    (
        translation,
        DQuat::from_mat3(&rotation).normalize(),
        stretch,
    )
}

impl MotionTransform {
    /// `start` at `start_time` moving to `end` at `end_time`.
    pub fn new(start: Transform, start_time: f32, end: Transform, end_time: f32) -> Self {
        let (t0, r0, s0) = decompose(&start.matrix);
        let (t1, mut r1, s1) = decompose(&end.matrix);
        // The shorter way round.
        if r0.dot(r1) < 0.0 {
            r1 = -r1;
        }
        MotionTransform {
            start,
            end,
            start_time,
            end_time,
            translation: [t0, t1],
            rotation: [r0, r1],
            stretch: [s0, s1],
        }
    }

    /// The transform at the start time and before.
    pub fn start(&self) -> &Transform {
        &self.start
    }

    /// The transform at the end time and after.
    pub fn end(&self) -> &Transform {
        &self.end
    }

    /// Whether the transform changes at all.
    pub fn is_animated(&self) -> bool {
        self.start != self.end
    }

    /// The transform at `time`.
    pub fn at(&self, time: f32) -> Transform {
        if !self.is_animated() || time <= self.start_time {
            return self.start;
        }
        if time >= self.end_time {
            return self.end;
        }
        let s = ((time - self.start_time) / (self.end_time - self.start_time)) as f64;
        self.interpolated(s)
    }

    /// The transform a fraction `s` ∈ [0, 1] of the way from start to end.
    fn interpolated(&self, s: f64) -> Transform {
        let translation = self.translation[0].lerp(self.translation[1], s);
        let rotation = self.rotation[0].slerp(self.rotation[1], s);
        let stretch = self.stretch[0] * (1.0 - s) + self.stretch[1] * s;
        let linear = DMat3::from_quat(rotation) * stretch;
        let matrix = DMat4::from_cols(
            linear.x_axis.extend(0.0),
            linear.y_axis.extend(0.0),
            linear.z_axis.extend(0.0),
            translation.extend(1.0),
        );
        // An interpolated stretch can only be singular where the ends'
        // differ in sign (a mirror that turns inside out): then the
        // nearer end stands in.
        Transform::from_matrix(matrix).unwrap_or(if s < 0.5 { self.start } else { self.end })
    }

    /// The angle R turns through from start to end, in radians.
    fn rotation_angle(&self) -> f64 {
        2.0 * self.rotation[0].dot(self.rotation[1]).abs().min(1.0).acos()
    }

    /// Bounds of `b` over the whole motion.
    ///
    /// Without rotation a point moves along a straight line (T and S are
    /// linear in time), so the start and end boxes suffice. With rotation,
    /// each corner's path is sampled at `SAMPLES + 1` times; between two
    /// samples h apart, the path f(s) = T(s) + R(s)·S(s)·p strays from the
    /// chord by at most h²/8 · max|f''|, and |f''| ≤ θ²·|S p| + 2θ·|ΔS p|
    /// (R turns at the constant rate θ, S changes at the constant rate
    /// ΔS, T's second derivative is zero). The boxes are padded by that.
    pub fn motion_bounds(&self, b: Bounds3) -> Bounds3 {
        if b.is_empty() {
            return b;
        }
        if !self.is_animated() {
            return b.transformed(&self.start.to_mat4());
        }
        let theta = self.rotation_angle();
        if theta == 0.0 {
            return b
                .transformed(&self.start.to_mat4())
                .union(b.transformed(&self.end.to_mat4()));
        }
        const SAMPLES: usize = 64;
        let h = 1.0 / SAMPLES as f64;
        let transforms: Vec<Transform> = (0..=SAMPLES)
            .map(|i| self.interpolated(i as f64 * h))
            .collect();
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for corner in b.corners() {
            let p = corner.as_dvec3();
            let stretched = [self.stretch[0] * p, self.stretch[1] * p];
            let radius = stretched[0].length().max(stretched[1].length());
            let change = (stretched[1] - stretched[0]).length();
            let pad = h * h / 8.0 * (theta * theta * radius + 2.0 * theta * change);
            for t in &transforms {
                let q = t.point(p);
                min = min.min(q - pad);
                max = max.max(q + pad);
            }
        }
        // Outward past f32 rounding.
        let round = (min.abs().max(max.abs())).max_element() * 1e-6;
        Bounds3 {
            min: (min - round).as_vec3(),
            max: (max + round).as_vec3(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use std::f64::consts::PI;

    fn close(a: &DMat4, b: &DMat4, tolerance: f64) -> bool {
        (*a - *b)
            .to_cols_array()
            .iter()
            .all(|d| d.abs() <= tolerance)
    }

    #[test]
    fn decomposition_puts_the_matrix_back_together() {
        let m = Transform::translate(DVec3::new(1.0, -2.0, 3.0))
            .then(&Transform::rotate(0.7, DVec3::new(1.0, 2.0, 0.5)).unwrap())
            .then(&Transform::scale(DVec3::new(2.0, -0.5, 3.0)).unwrap());
        let (t, r, s) = decompose(&m.matrix);
        assert!((DMat3::from_quat(r).determinant() - 1.0).abs() < 1e-12);
        let linear = DMat3::from_quat(r) * s;
        let back = DMat4::from_cols(
            linear.x_axis.extend(0.0),
            linear.y_axis.extend(0.0),
            linear.z_axis.extend(0.0),
            t.extend(1.0),
        );
        assert!(close(&back, &m.matrix, 1e-9), "{back} vs {}", m.matrix);
    }

    #[test]
    fn ends_and_outside_times_give_the_ends_exactly() {
        let a = Transform::translate(DVec3::new(1.0, 0.0, 0.0));
        let b = Transform::rotate(1.0, DVec3::Z)
            .unwrap()
            .then(&Transform::translate(DVec3::new(1.5, 0.0, 0.0)));
        let m = MotionTransform::new(a, 0.0, b, 2.0);
        assert_eq!(m.at(-1.0), a);
        assert_eq!(m.at(0.0), a);
        assert_eq!(m.at(2.0), b);
        assert_eq!(m.at(5.0), b);
    }

    #[test]
    fn translation_is_linear_and_rotation_turns_at_a_constant_rate() {
        let a = Transform::translate(DVec3::new(1.0, 0.0, 0.0));
        let b = Transform::translate(DVec3::new(1.5, 0.25, 0.0));
        let m = MotionTransform::new(a, 0.0, b, 1.0);
        let p = m.at(0.3).point(DVec3::ZERO);
        assert!((p - DVec3::new(1.15, 0.075, 0.0)).length() < 1e-6, "{p}");
        // A quarter turn about z: at s, the point (1, 0, 0) is at angle
        // s·π/2.
        let turn = Transform::rotate(PI / 2.0, DVec3::Z).unwrap();
        let m = MotionTransform::new(Transform::IDENTITY, 0.0, turn, 1.0);
        for s in [0.25f32, 0.5, 0.8] {
            let p = m.at(s).point(DVec3::X);
            let angle = s as f64 * PI / 2.0;
            assert!(
                (p - DVec3::new(angle.cos(), angle.sin(), 0.0)).length() < 1e-6,
                "{s}: {p}"
            );
        }
        // Scale interpolates linearly, with the rotation.
        let grow = turn.then(&Transform::scale(DVec3::splat(3.0)).unwrap());
        let m = MotionTransform::new(Transform::IDENTITY, 0.0, grow, 1.0);
        let p = m.at(0.5).point(DVec3::X);
        let expected = 2.0 * DVec3::new((PI / 4.0).cos(), (PI / 4.0).sin(), 0.0);
        assert!((p - expected).length() < 1e-6, "{p}");
    }

    #[test]
    fn mirrored_ends_interpolate_without_a_reflection_in_the_rotation() {
        let a = Transform::scale(DVec3::new(1.0, 1.0, -1.0)).unwrap();
        let b = Transform::rotate(0.5, DVec3::Y).unwrap().then(&a);
        let m = MotionTransform::new(a, 0.0, b, 1.0);
        let mid = m.at(0.5);
        let expected = Transform::rotate(0.25, DVec3::Y).unwrap().then(&a);
        assert!(close(&mid.matrix, &expected.matrix, 1e-9), "{}", mid.matrix);
    }

    #[test]
    fn motion_bounds_hold_every_position_of_a_turning_box() {
        let b = Bounds3 {
            min: Vec3::new(1.0, -0.5, -0.2),
            max: Vec3::new(2.0, 0.5, 0.3),
        };
        let cases = [
            (
                Transform::IDENTITY,
                Transform::rotate(3.0, DVec3::new(0.3, 1.0, 0.2)).unwrap(),
            ),
            (
                Transform::translate(DVec3::new(-1.0, 2.0, 0.0)),
                Transform::rotate(PI / 2.0, DVec3::Z)
                    .unwrap()
                    .then(&Transform::scale(DVec3::new(2.0, 1.0, 0.5)).unwrap()),
            ),
            (
                Transform::translate(DVec3::new(1.0, 0.0, 0.0)),
                Transform::translate(DVec3::new(1.5, 0.0, 0.0)),
            ),
        ];
        for (start, end) in cases {
            let m = MotionTransform::new(start, 0.0, end, 1.0);
            let bounds = m.motion_bounds(b);
            let mut reached = Bounds3::EMPTY;
            for i in 0..=2000 {
                let t = m.at(i as f32 / 2000.0).to_mat4();
                for c in b.corners() {
                    let q = t.transform_point3(c);
                    reached = reached.with_point(q);
                    assert!(
                        q.cmpge(bounds.min).all() && q.cmple(bounds.max).all(),
                        "{q} outside {bounds:?}"
                    );
                }
            }
            // And not much bigger than the motion needs.
            let slack = (bounds.diagonal() - reached.diagonal()).max_element();
            assert!(slack < 0.01 * reached.diagonal().max_element(), "{slack}");
        }
    }
}
