//! A quadric's render-from-object transform (f32, with its inverse), and
//! the conservative floating-point error bounds pbrt-v4 carries through it:
//! a point transformed by a 4×4 matrix picks up a relative error of γ(3)
//! per row, plus (1+γ(3)) times its own error bound carried through |M|.

use crate::interaction::SurfaceInteraction;
use crate::math::ray::gamma;
use crate::math::{Bounds3, Transform};
use crate::shapes::interval::Interval;
use crate::shapes::surface::face_forward;
use glam::{Mat4, Vec3, Vec4Swizzles};

/// render-from-object and object-from-render, in f32.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectTransform {
    pub render_from_object: Mat4,
    pub object_from_render: Mat4,
    /// Whether the transform's 3×3 part has a negative determinant.
    pub swaps_handedness: bool,
}

/// A point or vector with an interval per component.
#[derive(Clone, Copy, Debug)]
pub struct Vec3Interval {
    pub x: Interval,
    pub y: Interval,
    pub z: Interval,
}

impl Vec3Interval {
    pub fn new(value: Vec3, error: Vec3) -> Self {
        Vec3Interval {
            x: Interval::from_value_and_error(value.x, error.x),
            y: Interval::from_value_and_error(value.y, error.y),
            z: Interval::from_value_and_error(value.z, error.z),
        }
    }
}

impl ObjectTransform {
    pub fn new(render_from_object: &Transform) -> Self {
        ObjectTransform {
            render_from_object: render_from_object.to_mat4(),
            object_from_render: render_from_object.inverse_mat4(),
            swaps_handedness: render_from_object.swaps_handedness(),
        }
    }

    /// Object-space bounds taken to render space.
    pub fn bounds_to_render(&self, object_bounds: Bounds3) -> Bounds3 {
        let mut out = Bounds3::EMPTY;
        for corner in 0..8 {
            let p = Vec3::new(
                if corner & 1 == 0 {
                    object_bounds.min.x
                } else {
                    object_bounds.max.x
                },
                if corner & 2 == 0 {
                    object_bounds.min.y
                } else {
                    object_bounds.max.y
                },
                if corner & 4 == 0 {
                    object_bounds.min.z
                } else {
                    object_bounds.max.z
                },
            );
            out = out.with_point(transform_point(&self.render_from_object, p));
        }
        out
    }

    /// A render-space ray origin and direction in object space, as
    /// intervals (the transform's rounding error bounded).
    pub fn ray_to_object(
        &self,
        origin: Vec3,
        direction: Vec3,
    ) -> (Vec3, Vec3Interval, Vec3, Vec3Interval) {
        let (o, o_error) = transform_point_with_error(&self.object_from_render, origin, Vec3::ZERO);
        let (d, d_error) = transform_vector_with_error(&self.object_from_render, direction);
        (
            o,
            Vec3Interval::new(o, o_error),
            d,
            Vec3Interval::new(d, d_error),
        )
    }

    /// An object-space point and its error bound, in render space.
    pub fn point_to_render(&self, p: Vec3, p_error: Vec3) -> (Vec3, Vec3) {
        transform_point_with_error(&self.render_from_object, p, p_error)
    }

    pub fn point_to_object(&self, p: Vec3) -> Vec3 {
        transform_point(&self.object_from_render, p)
    }

    /// An object-space normal in render space (inverse transpose; not
    /// normalised).
    pub fn normal_to_render(&self, n: Vec3) -> Vec3 {
        transform_normal(&self.object_from_render, n)
    }

    /// An object-space surface interaction in render space, as pbrt-v4's
    /// `Transform::operator()(SurfaceInteraction)`: the point with its error
    /// bound, normals through the inverse transpose (renormalised), tangents
    /// through the matrix, and the shading normal turned to the geometric
    /// normal's side.
    pub fn interaction_to_render(&self, object: &SurfaceInteraction) -> SurfaceInteraction {
        let m = &self.render_from_object;
        let inverse = &self.object_from_render;
        let (p, p_error) = self.point_to_render(object.p, object.p_error);
        let n = transform_normal(inverse, object.n).normalize_or_zero();
        let mut shading_n = transform_normal(inverse, object.shading.n).normalize_or_zero();
        shading_n = face_forward(shading_n, n);
        let mut out = *object;
        out.p = p;
        out.p_error = p_error;
        out.n = n;
        out.wo = m.transform_vector3(object.wo).normalize_or_zero();
        out.dpdu = m.transform_vector3(object.dpdu);
        out.dpdv = m.transform_vector3(object.dpdv);
        out.dndu = transform_normal(inverse, object.dndu);
        out.dndv = transform_normal(inverse, object.dndv);
        out.shading.n = shading_n;
        out.shading.dpdu = m.transform_vector3(object.shading.dpdu);
        out.shading.dpdv = m.transform_vector3(object.shading.dpdv);
        out.shading.dndu = transform_normal(inverse, object.shading.dndu);
        out.shading.dndv = transform_normal(inverse, object.shading.dndv);
        // A direction across the fibre, as dpdv (the material projects it
        // onto the plane across the fibre, so a shear needs no more).
        out.fibre_reference = m.transform_vector3(object.fibre_reference);
        out
    }
}

/// `m · (p, 1)` with the homogeneous divide (pbrt allows projective shape
/// transforms).
pub fn transform_point(m: &Mat4, p: Vec3) -> Vec3 {
    let h = *m * p.extend(1.0);
    if h.w == 1.0 {
        h.xyz()
    } else {
        h.xyz() / h.w
    }
}

/// A normal through the inverse transpose of the matrix whose inverse is
/// `inverse`.
pub fn transform_normal(inverse: &Mat4, n: Vec3) -> Vec3 {
    Vec3::new(
        inverse.x_axis.xyz().dot(n),
        inverse.y_axis.xyz().dot(n),
        inverse.z_axis.xyz().dot(n),
    )
}

/// `m · (p, 1)` and the error bound of the result, given the error bound of
/// `p` (pbrt-v4's Point3fi transform).
pub fn transform_point_with_error(m: &Mat4, p: Vec3, p_error: Vec3) -> (Vec3, Vec3) {
    let h = *m * p.extend(1.0);
    let a = m.abs();
    let magnitude = a.x_axis.xyz() * p.x.abs()
        + a.y_axis.xyz() * p.y.abs()
        + a.z_axis.xyz() * p.z.abs()
        + a.w_axis.xyz();
    let mut error = gamma(3) * magnitude;
    if p_error != Vec3::ZERO {
        let carried =
            a.x_axis.xyz() * p_error.x + a.y_axis.xyz() * p_error.y + a.z_axis.xyz() * p_error.z;
        error += (gamma(3) + 1.0) * carried;
    }
    if h.w == 1.0 {
        (h.xyz(), error)
    } else {
        (h.xyz() / h.w, error / h.w.abs())
    }
}

/// `m · (v, 0)` and the error bound of the result for an exact `v`.
pub fn transform_vector_with_error(m: &Mat4, v: Vec3) -> (Vec3, Vec3) {
    let a = m.abs();
    let magnitude =
        a.x_axis.xyz() * v.x.abs() + a.y_axis.xyz() * v.y.abs() + a.z_axis.xyz() * v.z.abs();
    (m.transform_vector3(v), gamma(3) * magnitude)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn transformed_points_carry_their_error() {
        let t = Transform::translate(DVec3::new(1e4, 0.0, 0.0))
            .then(&Transform::scale(DVec3::new(3.0, 3.0, 3.0)).unwrap());
        let xf = ObjectTransform::new(&t);
        let p = Vec3::new(0.1, 0.2, 0.3);
        let (q, e) = xf.point_to_render(p, Vec3::splat(1e-7));
        let exact = t.point(DVec3::new(0.1f32 as f64, 0.2f32 as f64, 0.3f32 as f64));
        for i in 0..3 {
            assert!((q[i] as f64 - exact[i]).abs() <= e[i] as f64, "axis {i}");
            assert!(e[i] > 0.0);
        }
        // The inverse transform brings the point back within the bounds.
        let back = xf.point_to_object(q);
        assert!((back - p).abs().max_element() < 1e-3);
    }

    #[test]
    fn normals_use_the_inverse_transpose() {
        let t = Transform::scale(DVec3::new(1.0, 4.0, 1.0)).unwrap();
        let xf = ObjectTransform::new(&t);
        // A 45° normal in object space leans towards x after stretching y.
        let n = xf
            .normal_to_render(Vec3::new(1.0, 1.0, 0.0).normalize())
            .normalize();
        let tangent = xf
            .render_from_object
            .transform_vector3(Vec3::new(1.0, -1.0, 0.0));
        assert!(n.dot(tangent).abs() < 1e-6);
        assert!(n.x > n.y);
    }

    /// An instanced fibre's reference direction turns with the instance
    /// (it was left in object space, so an instanced elliptical strand kept
    /// its object-space orientation whatever the instance's rotation).
    #[test]
    fn fibre_reference_turns_with_the_instance() {
        let t = Transform::rotate(std::f64::consts::FRAC_PI_2, DVec3::Z).unwrap();
        let xf = ObjectTransform::new(&t);
        let si = SurfaceInteraction {
            fibre_reference: Vec3::X,
            ..Default::default()
        };
        let out = xf.interaction_to_render(&si);
        assert!(
            (out.fibre_reference - Vec3::Y).length() < 1e-6,
            "{}",
            out.fibre_reference
        );
    }
}
