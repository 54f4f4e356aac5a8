//! Trigonometry of unit directions in the local shading frame, where the
//! shading normal is +z, plus reflection and refraction about a normal.
//! Every BxDF works in this frame, so θ is measured from z and φ from x.

use crate::math::safe_sqrt;
use glam::Vec3;

#[inline]
pub fn cos_theta(w: Vec3) -> f32 {
    w.z
}

#[inline]
pub fn cos2_theta(w: Vec3) -> f32 {
    w.z * w.z
}

#[inline]
pub fn abs_cos_theta(w: Vec3) -> f32 {
    w.z.abs()
}

#[inline]
pub fn sin2_theta(w: Vec3) -> f32 {
    (1.0 - cos2_theta(w)).max(0.0)
}

#[inline]
pub fn sin_theta(w: Vec3) -> f32 {
    sin2_theta(w).sqrt()
}

/// tan²θ; infinite for directions in the tangent plane.
#[inline]
pub fn tan2_theta(w: Vec3) -> f32 {
    sin2_theta(w) / cos2_theta(w)
}

/// cos φ, taken as 1 at the pole where φ is undefined.
#[inline]
pub fn cos_phi(w: Vec3) -> f32 {
    let sin_theta = sin_theta(w);
    if sin_theta == 0.0 {
        1.0
    } else {
        (w.x / sin_theta).clamp(-1.0, 1.0)
    }
}

/// sin φ, taken as 0 at the pole where φ is undefined.
#[inline]
pub fn sin_phi(w: Vec3) -> f32 {
    let sin_theta = sin_theta(w);
    if sin_theta == 0.0 {
        0.0
    } else {
        (w.y / sin_theta).clamp(-1.0, 1.0)
    }
}

/// Whether two directions are on the same side of the surface (a pair
/// with one direction exactly in the tangent plane counts as not).
#[inline]
pub fn same_hemisphere(w: Vec3, wp: Vec3) -> bool {
    w.z * wp.z > 0.0
}

/// `v` flipped, if needed, to lie in the hemisphere around `reference`.
#[inline]
pub fn face_forward(v: Vec3, reference: Vec3) -> Vec3 {
    if v.dot(reference) < 0.0 {
        -v
    } else {
        v
    }
}

/// Mirror direction of `wo` about `n` (both pointing away from the surface).
#[inline]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    -wo + 2.0 * wo.dot(n) * n
}

/// Refracted direction of `wi` through a boundary with normal `n`, where
/// `eta` is η on the side `n` points away from (below) over η on its side
/// (above). Works from either side: a `wi` below the boundary flips the
/// normal and inverts `eta`. Returns the direction and the relative index
/// actually used, or `None` for total internal reflection.
#[inline]
pub fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_theta_i = n.dot(wi);
    let (mut n, mut eta) = (n, eta);
    if cos_theta_i < 0.0 {
        eta = 1.0 / eta;
        cos_theta_i = -cos_theta_i;
        n = -n;
    }
    let sin2_theta_i = (1.0 - cos_theta_i * cos_theta_i).max(0.0);
    let sin2_theta_t = sin2_theta_i / (eta * eta);
    if sin2_theta_t >= 1.0 {
        return None;
    }
    let cos_theta_t = safe_sqrt(1.0 - sin2_theta_t);
    let wt = -wi / eta + (cos_theta_i / eta - cos_theta_t) * n;
    Some((wt, eta))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refraction_obeys_snell_from_both_sides() {
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let (wt, etap) = refract(wi, Vec3::Z, 1.5).unwrap();
        assert_eq!(etap, 1.5);
        assert!(wt.z < 0.0 && (wt.length() - 1.0).abs() < 1e-6);
        assert!((sin_theta(wi) - 1.5 * sin_theta(wt)).abs() < 1e-6);
        // Back out again: the original direction, with the index inverted.
        let (back, etap) = refract(wt, Vec3::Z, 1.5).unwrap();
        assert!((etap - 1.0 / 1.5).abs() < 1e-7);
        assert!((back - wi).length() < 1e-5);
        // Grazing from inside: total internal reflection.
        assert!(refract(Vec3::new(0.9, 0.0, -0.435_889_9), Vec3::Z, 1.5).is_none());
    }

    #[test]
    fn reflection_mirrors_about_the_normal() {
        let wo = Vec3::new(0.3, -0.4, 0.866_025_4);
        assert!((reflect(wo, Vec3::Z) - Vec3::new(-0.3, 0.4, 0.866_025_4)).length() < 1e-6);
        assert_eq!(cos_phi(Vec3::Z), 1.0);
        assert_eq!(sin_phi(Vec3::Z), 0.0);
        assert!(tan2_theta(Vec3::X).is_infinite());
    }
}
