//! The box that bounds a grid or procedural medium: `p0`–`p1` in the
//! medium's space, placed in render space by the medium's transform.

use super::MajorantSegment;
use crate::math::{Ray, Transform};
use crate::spectrum::SampledSpectrum;
use glam::{DVec3, Mat4, Vec3};

#[derive(Clone, Debug)]
pub struct Cuboid {
    medium_from_render: Mat4,
    min: Vec3,
    max: Vec3,
}

impl Cuboid {
    pub fn new(render_from_medium: &Transform, p0: DVec3, p1: DVec3) -> Self {
        Cuboid {
            medium_from_render: render_from_medium.inverse_mat4(),
            min: p0.min(p1).as_vec3(),
            max: p0.max(p1).as_vec3(),
        }
    }

    /// The majorant segment of a medium filling this box: the stretch of
    /// `ray` inside it (as [`Cuboid::clip`]), with the bound `sigma_maj`
    /// on σt there (evaluated only where the ray meets the box).
    pub fn majorant(
        &self,
        ray: &Ray,
        t_max: f32,
        sigma_maj: impl FnOnce() -> SampledSpectrum,
    ) -> Option<MajorantSegment> {
        let (t_min, t_max) = self.clip(ray, t_max)?;
        Some(MajorantSegment {
            t_min,
            t_max,
            sigma_maj: sigma_maj(),
        })
    }

    /// The stretch of `ray` (render space) inside the box, clipped to
    /// `0..t_max`; the ray's t is kept (the transform is affine).
    pub fn clip(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32)> {
        let o = self.medium_from_render.transform_point3(ray.origin);
        let d = self.medium_from_render.transform_vector3(ray.direction);
        let (mut t0, mut t1) = (0.0f32, t_max);
        for i in 0..3 {
            let inv = 1.0 / d[i];
            let (mut near, mut far) = ((self.min[i] - o[i]) * inv, (self.max[i] - o[i]) * inv);
            if near > far {
                std::mem::swap(&mut near, &mut far);
            }
            // A ray along the slab's plane gives NaN: then the test is
            // whether the origin lies between the planes.
            if near.is_nan() || far.is_nan() {
                if o[i] < self.min[i] || o[i] > self.max[i] {
                    return None;
                }
                continue;
            }
            t0 = t0.max(near);
            t1 = t1.min(far);
            if t0 > t1 {
                return None;
            }
        }
        Some((t0, t1))
    }

    /// Render-space `p` in the medium's space.
    pub fn medium_point(&self, p: Vec3) -> Vec3 {
        self.medium_from_render.transform_point3(p)
    }

    /// Render-space `p` in the box's own coordinates, 0…1 on each axis
    /// (pbrt's `Bounds3::Offset`).
    pub fn unit(&self, p: Vec3) -> Vec3 {
        let q = self.medium_from_render.transform_point3(p);
        let extent = self.max - self.min;
        Vec3::from_array(std::array::from_fn(|i| {
            if extent[i] > 0.0 {
                (q[i] - self.min[i]) / extent[i]
            } else {
                q[i] - self.min[i]
            }
        }))
    }
}
