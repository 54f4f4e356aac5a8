//! What a ray hit: the surface point, its error bound, its geometry and
//! shading frames, and which primitive it belongs to.

use crate::math::{offset_ray_origin, Ray};
use glam::{Vec2, Vec3};

/// The shading geometry (possibly from interpolated normals or a bump map).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Shading {
    pub n: Vec3,
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    pub dndu: Vec3,
    pub dndv: Vec3,
}

/// A ray–surface intersection, in render space.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceInteraction {
    /// The hit point.
    pub p: Vec3,
    /// Absolute error bound of `p`, per axis (for robust ray origins).
    pub p_error: Vec3,
    /// Ray parameter of the hit.
    pub t: f32,
    /// Time of the ray.
    pub time: f32,
    /// Direction towards the ray's origin (−ray.d, normalised).
    pub wo: Vec3,
    /// Geometric normal (unit), on the side pbrt's orientation rules give.
    pub n: Vec3,
    pub uv: Vec2,
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    pub dndu: Vec3,
    pub dndv: Vec3,
    pub shading: Shading,
    /// For curves: the offset across the fibre, −1…1 (pbrt's h = −1 + 2v).
    pub curve_h: f32,
    /// For curves: a direction across the fibre that does not turn with the
    /// view, stable along the strand (orients elliptical fibres; not unit,
    /// and only its part ⟂ the tangent counts); zero for other shapes.
    pub fibre_reference: Vec3,
    /// Index of the primitive hit (into the built scene's primitive list).
    pub primitive: u32,
}

impl SurfaceInteraction {
    /// A ray leaving this point in direction `d`, offset so it cannot hit
    /// the surface it leaves.
    pub fn spawn_ray(&self, d: Vec3) -> Ray {
        Ray::new(
            offset_ray_origin(self.p, self.p_error, self.n, d),
            d,
            self.time,
        )
    }

    /// A ray leaving this point in direction `d` from a point moved along
    /// `d` by the point's error bound, for a hit in the dual hair model's
    /// diffracting ring: a thin shell that light goes through. The usual
    /// offset is along the normal, which on a cylinder curve turns sideways
    /// towards the curve's edges (where the ring is) and is as long as the
    /// curve is wide: it would start the ray up to 1.7 widths to the side,
    /// inside a neighbouring fibre, and tilt a light's direction by more
    /// than the ring's lobe is wide.
    pub fn spawn_ray_through(&self, d: Vec3) -> Ray {
        Ray::new(self.point_through(d), d, self.time)
    }

    /// This point moved along `d` by its error bound (see
    /// [`Self::spawn_ray_through`]).
    pub fn point_through(&self, d: Vec3) -> Vec3 {
        self.p + d.normalize_or_zero() * self.p_error.max_element()
    }

    /// A ray from this point towards `p_to` (the direction is unnormalised,
    /// so that t = 1 − ε is just short of the target).
    pub fn spawn_ray_to(&self, p_to: Vec3) -> Ray {
        let origin = offset_ray_origin(self.p, self.p_error, self.n, p_to - self.p);
        Ray::new(origin, p_to - origin, self.time)
    }

    /// Sets the shading geometry (pbrt-v4's SetShadingGeometry): when
    /// `orientation_is_authoritative`, the geometric normal turns to the
    /// shading normal's side; otherwise the shading normal turns to the
    /// geometric one's.
    pub fn set_shading_geometry(
        &mut self,
        ns: Vec3,
        dpdus: Vec3,
        dpdvs: Vec3,
        dndus: Vec3,
        dndvs: Vec3,
        orientation_is_authoritative: bool,
    ) {
        let mut ns = ns;
        if orientation_is_authoritative {
            if self.n.dot(ns) < 0.0 {
                self.n = -self.n;
            }
        } else if self.n.dot(ns) < 0.0 {
            ns = -ns;
        }
        self.shading = Shading {
            n: ns,
            dpdu: dpdus,
            dpdv: dpdvs,
            dndu: dndus,
            dndv: dndvs,
        };
        // Keep the shading tangent well defined.
        while self.shading.dpdu.length_squared() > 1e16 || self.shading.dpdv.length_squared() > 1e16
        {
            self.shading.dpdu *= 1e-8;
            self.shading.dpdv *= 1e-8;
        }
    }
}
