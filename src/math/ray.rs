//! Rays and robust ray origins.

use glam::Vec3;

/// A ray `o + t d` at a time in the shutter interval. `d` need not be
/// normalised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub direction: Vec3,
    pub time: f32,
}

impl Ray {
    pub fn new(origin: Vec3, direction: Vec3, time: f32) -> Self {
        Ray {
            origin,
            direction,
            time,
        }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.direction
    }
}

/// Moves a ray origin `p` (with absolute error bound `p_error` per axis)
/// off the surface with geometric normal `n`, to the side `w` points to,
/// far enough that the ray cannot hit the surface it leaves (pbrt-v4's
/// OffsetRayOrigin: offset along the normal by the error bound's
/// projection, then round away from `p`).
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(p_error);
    let mut offset = d * n;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let mut po = p + offset;
    for i in 0..3 {
        if offset[i] > 0.0 {
            po[i] = next_float_up(po[i]);
        } else if offset[i] < 0.0 {
            po[i] = next_float_down(po[i]);
        }
    }
    po
}

/// The next representable f32 above `v`.
pub fn next_float_up(v: f32) -> f32 {
    if v.is_infinite() && v > 0.0 {
        return v;
    }
    let v = if v == -0.0 { 0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v >= 0.0 { bits + 1 } else { bits - 1 };
    f32::from_bits(bits)
}

/// The next representable f32 below `v`.
pub fn next_float_down(v: f32) -> f32 {
    if v.is_infinite() && v < 0.0 {
        return v;
    }
    let v = if v == 0.0 { -0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v > 0.0 { bits - 1 } else { bits + 1 };
    f32::from_bits(bits)
}

/// pbrt's γ(n) = nε/(1−nε), the relative error bound of n floating-point
/// operations.
pub const fn gamma(n: i32) -> f32 {
    let e = f32::EPSILON * 0.5;
    (n as f32 * e) / (1.0 - n as f32 * e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_floats() {
        assert!(next_float_up(1.0) > 1.0);
        assert!(next_float_down(1.0) < 1.0);
        assert!(next_float_up(0.0) > 0.0);
        assert!(next_float_down(0.0) < 0.0);
        assert!(next_float_up(-1.0) > -1.0);
    }

    #[test]
    fn offset_goes_to_the_side_of_w() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let e = Vec3::splat(1e-6);
        let n = Vec3::Z;
        assert!(offset_ray_origin(p, e, n, Vec3::Z).z > 3.0);
        assert!(offset_ray_origin(p, e, n, -Vec3::Z).z < 3.0);
    }
}
