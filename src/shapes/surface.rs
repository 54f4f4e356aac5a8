//! Building a [`SurfaceInteraction`] the way pbrt-v4's shapes do: the
//! geometric normal from the parametric partial derivatives, flipped for
//! reverse orientation / handedness, and the shading frame set with pbrt's
//! orientation rule.
//!
//! (`SurfaceInteraction::set_shading_geometry` in `crate::interaction` flips
//! the opposite normal to pbrt-v4 for the `orientation_is_authoritative`
//! flag, so the shapes use [`set_shading_geometry`] here instead.)

use super::numeric::difference_of_products;
use crate::interaction::{Shading, SurfaceInteraction};
use glam::{Vec2, Vec3};

/// What a shape knows about a surface point before the shading frame is
/// refined: position and error bound, (u,v), and the partial derivatives.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    pub p: Vec3,
    pub p_error: Vec3,
    pub uv: Vec2,
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    pub dndu: Vec3,
    pub dndv: Vec3,
}

/// pbrt's SurfaceInteraction constructor: `n = normalize(dpdu × dpdv)`,
/// negated when `flip_normal` (reverse orientation XOR handedness swap),
/// and the shading geometry equal to the true geometry.
pub fn surface_interaction(
    point: &SurfacePoint,
    wo: Vec3,
    time: f32,
    flip_normal: bool,
) -> SurfaceInteraction {
    let mut n = point.dpdu.cross(point.dpdv).normalize_or_zero();
    if flip_normal {
        n = -n;
    }
    SurfaceInteraction {
        p: point.p,
        p_error: point.p_error,
        t: 0.0,
        time,
        wo: wo.normalize_or_zero(),
        n,
        uv: point.uv,
        dpdu: point.dpdu,
        dpdv: point.dpdv,
        dndu: point.dndu,
        dndv: point.dndv,
        shading: Shading {
            n,
            dpdu: point.dpdu,
            dpdv: point.dpdv,
            dndu: point.dndu,
            dndv: point.dndv,
        },
        curve_h: 0.0,
        fibre_reference: Vec3::ZERO,
        primitive: 0,
    }
}

/// pbrt-v4's SetShadingGeometry: when `orientation_is_authoritative`, the
/// geometric normal is flipped to the shading normal's hemisphere;
/// otherwise the shading normal is flipped to the geometric normal's.
/// Very long shading tangents are scaled down (keeps later products finite).
pub fn set_shading_geometry(
    interaction: &mut SurfaceInteraction,
    shading_normal: Vec3,
    dpdu: Vec3,
    dpdv: Vec3,
    dndu: Vec3,
    dndv: Vec3,
    orientation_is_authoritative: bool,
) {
    let mut ns = shading_normal;
    if orientation_is_authoritative {
        interaction.n = face_forward(interaction.n, ns);
    } else {
        ns = face_forward(ns, interaction.n);
    }
    let mut shading = Shading {
        n: ns,
        dpdu,
        dpdv,
        dndu,
        dndv,
    };
    while shading.dpdu.length_squared() > 1e16 || shading.dpdv.length_squared() > 1e16 {
        shading.dpdu /= 1e8;
        shading.dpdv /= 1e8;
    }
    interaction.shading = shading;
}

/// `v`, negated if it points away from `towards`.
pub fn face_forward(v: Vec3, towards: Vec3) -> Vec3 {
    if v.dot(towards) < 0.0 {
        -v
    } else {
        v
    }
}

/// The change of the unit normal along u and v from the first and second
/// fundamental forms (Weingarten equations), given the second derivatives
/// of the surface.
pub fn weingarten_normal_derivatives(
    dpdu: Vec3,
    dpdv: Vec3,
    d2p_duu: Vec3,
    d2p_duv: Vec3,
    d2p_dvv: Vec3,
) -> (Vec3, Vec3) {
    let e_upper = dpdu.dot(dpdu);
    let f_upper = dpdu.dot(dpdv);
    let g_upper = dpdv.dot(dpdv);
    let n = dpdu.cross(dpdv).normalize_or_zero();
    let e = n.dot(d2p_duu);
    let f = n.dot(d2p_duv);
    let g = n.dot(d2p_dvv);
    let egf2 = difference_of_products(e_upper, g_upper, f_upper, f_upper);
    let inv_egf2 = if egf2 == 0.0 { 0.0 } else { 1.0 / egf2 };
    let dndu = (f * f_upper - e * g_upper) * inv_egf2 * dpdu
        + (e * f_upper - f * e_upper) * inv_egf2 * dpdv;
    let dndv = (g * f_upper - f * g_upper) * inv_egf2 * dpdu
        + (f * f_upper - g * e_upper) * inv_egf2 * dpdv;
    (dndu, dndv)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point() -> SurfacePoint {
        SurfacePoint {
            p: Vec3::ZERO,
            p_error: Vec3::ZERO,
            uv: Vec2::ZERO,
            dpdu: Vec3::X,
            dpdv: Vec3::Y,
            dndu: Vec3::ZERO,
            dndv: Vec3::ZERO,
        }
    }

    #[test]
    fn normal_is_dpdu_cross_dpdv_and_flips() {
        let si = surface_interaction(&point(), Vec3::Z, 0.0, false);
        assert_eq!(si.n, Vec3::Z);
        assert_eq!(si.shading.n, Vec3::Z);
        let flipped = surface_interaction(&point(), Vec3::Z, 0.0, true);
        assert_eq!(flipped.n, -Vec3::Z);
        assert_eq!(flipped.shading.n, -Vec3::Z);
    }

    #[test]
    fn authoritative_shading_normal_moves_the_geometric_normal() {
        let mut si = surface_interaction(&point(), Vec3::Z, 0.0, false);
        set_shading_geometry(
            &mut si,
            -Vec3::Z,
            Vec3::X,
            Vec3::Y,
            Vec3::ZERO,
            Vec3::ZERO,
            true,
        );
        assert_eq!(si.n, -Vec3::Z);
        assert_eq!(si.shading.n, -Vec3::Z);
        let mut si = surface_interaction(&point(), Vec3::Z, 0.0, false);
        set_shading_geometry(
            &mut si,
            -Vec3::Z,
            Vec3::X,
            Vec3::Y,
            Vec3::ZERO,
            Vec3::ZERO,
            false,
        );
        assert_eq!(si.n, Vec3::Z);
        assert_eq!(si.shading.n, Vec3::Z);
    }
}
