//! Affine/projective transforms as pbrt builds them from scene directives.
//!
//! Matrices are f64 while the scene is described (long chains of
//! `ConcatTransform` lose little), and are converted to f32 when built.

use glam::{DMat4, DVec3};

/// A transform and its inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub matrix: DMat4,
    pub inverse: DMat4,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform = Transform {
        matrix: DMat4::IDENTITY,
        inverse: DMat4::IDENTITY,
    };

    /// From a matrix; `None` when it cannot be inverted.
    pub fn from_matrix(matrix: DMat4) -> Option<Self> {
        let det = matrix.determinant();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        Some(Transform {
            matrix,
            inverse: matrix.inverse(),
        })
    }

    /// The matrix of `Transform`/`ConcatTransform`: the 16 numbers are the
    /// matrix column by column (pbrt reads them row-major and transposes).
    pub fn from_pbrt_array(values: &[f64; 16]) -> Option<Self> {
        Self::from_matrix(DMat4::from_cols_array(values))
    }

    pub fn translate(delta: DVec3) -> Self {
        Transform {
            matrix: DMat4::from_translation(delta),
            inverse: DMat4::from_translation(-delta),
        }
    }

    /// `None` for a zero scale factor.
    pub fn scale(s: DVec3) -> Option<Self> {
        if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 {
            return None;
        }
        Some(Transform {
            matrix: DMat4::from_scale(s),
            inverse: DMat4::from_scale(s.recip()),
        })
    }

    /// Rotation by `angle_radians` about `axis` (normalised here); `None`
    /// for a zero axis.
    pub fn rotate(angle_radians: f64, axis: DVec3) -> Option<Self> {
        let axis = axis.try_normalize()?;
        let matrix = DMat4::from_axis_angle(axis, angle_radians);
        Some(Transform {
            matrix,
            inverse: matrix.transpose(),
        })
    }

    /// pbrt's `LookAt`: camera-from-world for a camera at `eye` looking at
    /// `look` (pbrt's left-handed camera space: +z forward, +y up).
    /// `None` when `up` is parallel to the viewing direction.
    pub fn look_at(eye: DVec3, look: DVec3, up: DVec3) -> Option<Self> {
        let dir = (look - eye).try_normalize()?;
        let right = up.try_normalize()?.cross(dir).try_normalize()?;
        let new_up = dir.cross(right);
        let world_from_camera = DMat4::from_cols(
            right.extend(0.0),
            new_up.extend(0.0),
            dir.extend(0.0),
            eye.extend(1.0),
        );
        Some(Transform {
            matrix: world_from_camera.inverse(),
            inverse: world_from_camera,
        })
    }

    pub fn inverse(&self) -> Self {
        Transform {
            matrix: self.inverse,
            inverse: self.matrix,
        }
    }

    /// `self` applied after `other` (`self * other`).
    pub fn then(&self, other: &Transform) -> Self {
        Transform {
            matrix: self.matrix * other.matrix,
            inverse: other.inverse * self.inverse,
        }
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.matrix.project_point3(p)
    }

    /// The matrix in f32, for rendering.
    pub fn to_mat4(&self) -> glam::Mat4 {
        self.matrix.as_mat4()
    }

    /// The inverse matrix in f32.
    pub fn inverse_mat4(&self) -> glam::Mat4 {
        self.inverse.as_mat4()
    }

    /// Whether the transform flips handedness.
    pub fn swaps_handedness(&self) -> bool {
        glam::DMat3::from_mat4(self.matrix).determinant() < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pbrt_array_is_column_major() {
        let mut v = [0.0; 16];
        v[0] = 1.0;
        v[5] = 1.0;
        v[10] = 1.0;
        v[15] = 1.0;
        v[12] = 3.0; // translation x, as pbrt writes it
        let t = Transform::from_pbrt_array(&v).unwrap();
        assert_eq!(t.point(DVec3::ZERO), DVec3::new(3.0, 0.0, 0.0));
    }

    #[test]
    fn look_at_puts_the_target_on_plus_z() {
        let t = Transform::look_at(DVec3::new(0., 0., 5.), DVec3::ZERO, DVec3::Y).unwrap();
        let p = t.point(DVec3::ZERO);
        assert!((p - DVec3::new(0., 0., 5.)).length() < 1e-12, "{p}");
        // pbrt's camera space is left-handed: +x is to the right on screen.
        let right = t.point(DVec3::new(-1., 0., 0.));
        assert!(right.x > 0.0, "{right}");
        assert!(Transform::look_at(DVec3::ZERO, DVec3::Y, DVec3::Y).is_none());
    }

    #[test]
    fn rotate_matches_the_right_hand_rule() {
        let t = Transform::rotate(std::f64::consts::FRAC_PI_2, DVec3::Z).unwrap();
        assert!((t.point(DVec3::X) - DVec3::Y).length() < 1e-12);
        assert!(Transform::rotate(1.0, DVec3::ZERO).is_none());
    }
}
