//! Orthonormal frames (local shading coordinates: z is the normal).

use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub x: Vec3,
    pub y: Vec3,
    pub z: Vec3,
}

impl Frame {
    /// A frame around the unit vector `z` (Duff et al. 2017's branchless
    /// construction).
    pub fn from_z(z: Vec3) -> Self {
        let (x, y) = coordinate_system(z);
        Frame { x, y, z }
    }

    /// A frame with `x` and `z` given (orthonormal).
    pub fn from_xz(x: Vec3, z: Vec3) -> Self {
        Frame {
            x,
            y: z.cross(x),
            z,
        }
    }

    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    pub fn from_local(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }
}

/// Two unit vectors completing `v` (unit) to an orthonormal basis.
pub fn coordinate_system(v: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(v.z);
    let a = -1.0 / (sign + v.z);
    let b = v.x * v.y * a;
    (
        Vec3::new(1.0 + sign * v.x * v.x * a, sign * b, -sign * v.x),
        Vec3::new(b, sign + v.y * v.y * a, -v.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal() {
        for z in [Vec3::Z, -Vec3::Z, Vec3::new(0.3, -0.4, 0.1).normalize()] {
            let f = Frame::from_z(z);
            assert!(f.x.dot(f.y).abs() < 1e-6 && f.x.dot(f.z).abs() < 1e-6);
            assert!((f.x.length() - 1.0).abs() < 1e-6 && (f.y.length() - 1.0).abs() < 1e-6);
            let v = Vec3::new(0.2, 0.5, -0.7);
            assert!((f.from_local(f.to_local(v)) - v).length() < 1e-6);
        }
    }
}
