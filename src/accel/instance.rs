//! Object instancing as a two-level structure (pbrt-v4's
//! `TransformedPrimitive` over a per-object `BVHAggregate`).
//!
//! Each object (`ObjectBegin` … `ObjectEnd`) has its own [`Bvh`] over its
//! primitives, built once in the space the object was defined in (pbrt's
//! "instance space": render space as the object's shapes were written).
//! A top-level BVH holds the instances, each with its render-from-instance
//! transform and its bounds in render space. A ray is taken to instance
//! space, traced through the object's BVH, and the hit is brought back:
//! point with its error bound, normals by the inverse transpose, as
//! pbrt-v4's `Transform::operator()(SurfaceInteraction)`.
//!
//! An instance may move during the shutter interval (pbrt-v4's
//! `AnimatedPrimitive`): its render-from-instance is then interpolated
//! at each ray's time, and its box in the top-level BVH holds the whole
//! motion.
//!
//! The objects' primitives live in the scene's one primitive array; an
//! object's BVH reports indices into it (see [`Bvh::build_from`]). No heap
//! hop and no trait object per ray: an instance is a transform and an
//! object index.

use super::bvh::BuildBox;
use super::Bvh;
use crate::interaction::SurfaceInteraction;
use crate::math::{Bounds3, MotionTransform, Ray};
use crate::shapes::object_transform::{transform_point_with_error, ObjectTransform};
use std::ops::Range;

/// One use of an object (`ObjectInstance`, or a moving shape).
#[derive(Clone, Debug)]
pub struct Instance {
    /// Index into the objects' BVHs.
    pub object: u32,
    pub placement: Placement,
}

/// Where an instance is.
#[derive(Clone, Debug)]
pub enum Placement {
    /// render-from-instance and its inverse (f32).
    Fixed(ObjectTransform),
    /// render-from-instance over the shutter interval.
    Moving(Box<MotionTransform>),
}

impl Instance {
    /// `f` with render-from-instance at `time`.
    #[inline]
    fn with_transform_at<R>(&self, time: f32, f: impl FnOnce(&ObjectTransform) -> R) -> R {
        match &self.placement {
            Placement::Fixed(transform) => f(transform),
            Placement::Moving(motion) => f(&ObjectTransform::new(&motion.at(time))),
        }
    }
}

/// The instances of a scene: the objects' BVHs and the top-level BVH over
/// the instances (in its leaf order).
pub struct InstanceAccel {
    objects: Vec<Bvh>,
    instances: Vec<Instance>,
    top: Bvh,
}

/// A render-space ray in instance space, as pbrt-v4's
/// `Transform::ApplyInverse(Ray)`: the origin carries the transform's
/// rounding error, so it is moved to the far edge of its error box along
/// the direction; `dt` is how far (in units of the direction), to be taken
/// off `t_max` and added back to hit distances.
fn ray_to_instance(transform: &ObjectTransform, ray: &Ray) -> (Ray, f32) {
    let (mut origin, error) =
        transform_point_with_error(&transform.object_from_render, ray.origin, glam::Vec3::ZERO);
    let direction = transform
        .object_from_render
        .transform_vector3(ray.direction);
    let length_squared = direction.length_squared();
    let mut dt = 0.0;
    if length_squared > 0.0 {
        dt = direction.abs().dot(error) / length_squared;
        origin += direction * dt;
    }
    (Ray::new(origin, direction, ray.time), dt)
}

impl InstanceAccel {
    /// No instances.
    pub fn empty() -> Self {
        InstanceAccel {
            objects: Vec::new(),
            instances: Vec::new(),
            top: Bvh::build(&[]).0,
        }
    }

    /// `objects`: each object's BVH (reporting indices into the scene's
    /// primitive array); `instances`: (object, render-from-instance).
    pub fn build(objects: Vec<Bvh>, instances: &[(u32, MotionTransform)]) -> Self {
        let placed: Vec<Instance> = instances
            .iter()
            .map(|(object, motion)| Instance {
                object: *object,
                placement: if motion.is_animated() {
                    Placement::Moving(Box::new(*motion))
                } else {
                    Placement::Fixed(ObjectTransform::new(motion.start()))
                },
            })
            .collect();
        let bounds: Vec<Bounds3> = placed
            .iter()
            .zip(instances)
            .map(|(i, (_, motion))| motion.motion_bounds(objects[i.object as usize].bounds()))
            .collect();
        let (top, order) = Bvh::build(&bounds);
        let instances = order.iter().map(|&i| placed[i as usize].clone()).collect();
        InstanceAccel {
            objects,
            instances,
            top,
        }
    }

    pub fn len(&self) -> usize {
        self.instances.len()
    }

    pub fn is_empty(&self) -> bool {
        self.instances.is_empty()
    }

    /// Whether any instance moves (motion blur).
    pub fn has_motion(&self) -> bool {
        self.instances
            .iter()
            .any(|i| matches!(i.placement, Placement::Moving(_)))
    }

    /// Render-space bounds of all instances.
    pub fn bounds(&self) -> Bounds3 {
        self.top.bounds()
    }

    /// The closest instance hit before `t_max`, in render space.
    /// `intersect(object_bvh, instance_ray, t_max)` finds the closest hit
    /// in an object (its interaction in instance space, `t` set).
    pub fn intersect(
        &self,
        ray: &Ray,
        t_max: f32,
        mut intersect: impl FnMut(&Bvh, &Ray, f32) -> Option<SurfaceInteraction>,
    ) -> Option<SurfaceInteraction> {
        let mut best: Option<(SurfaceInteraction, usize)> = None;
        self.top.closest_hit(ray, t_max, |i, t_max| {
            let instance = &self.instances[i];
            let si = instance.with_transform_at(ray.time, |transform| {
                let (local, dt) = ray_to_instance(transform, ray);
                let local_t_max = t_max - dt;
                if local_t_max <= 0.0 {
                    return None;
                }
                let mut si =
                    intersect(&self.objects[instance.object as usize], &local, local_t_max)?;
                si.t += dt;
                Some(si)
            })?;
            // (Rounding of t + dt must not let a farther hit replace a
            // nearer one.)
            if si.t >= t_max {
                return None;
            }
            let t = si.t;
            best = Some((si, i));
            Some(t)
        })?;
        let (si, i) = best?;
        let mut out = self.instances[i]
            .with_transform_at(ray.time, |transform| transform.interaction_to_render(&si));
        out.t = si.t;
        Some(out)
    }

    /// Whether any instance is hit before `t_max`;
    /// `intersect_p(object_bvh, instance_ray, t_max)` tests one object.
    pub fn intersect_p(
        &self,
        ray: &Ray,
        t_max: f32,
        mut intersect_p: impl FnMut(&Bvh, &Ray, f32) -> bool,
    ) -> bool {
        self.top.any_hit(ray, t_max, |i, t_max| {
            let instance = &self.instances[i];
            instance.with_transform_at(ray.time, |transform| {
                let (local, dt) = ray_to_instance(transform, ray);
                let local_t_max = t_max - dt;
                local_t_max > 0.0
                    && intersect_p(&self.objects[instance.object as usize], &local, local_t_max)
            })
        })
    }
}

/// BVHs over a primitive array laid out as `[top level | object 0 | object
/// 1 | …]`: one over `0..top_count`, one per object range, from the
/// primitives' boxes ([`super::bvh::build_box`]). Returns the top-level
/// BVH, the objects' BVHs (reporting indices into the array) and the new
/// order of the whole array (each range reordered in place).
pub fn build_levels(
    boxes: &[BuildBox],
    top_count: usize,
    object_ranges: &[Range<usize>],
) -> (Bvh, Vec<Bvh>, Vec<u32>) {
    let (top, top_order) = Bvh::build_from_boxes(&boxes[..top_count], 0);
    let mut order = top_order;
    let mut objects = Vec::with_capacity(object_ranges.len());
    for range in object_ranges {
        let first = range.start as u32;
        let (bvh, local) = Bvh::build_from_boxes(&boxes[range.clone()], first);
        order.extend(local.iter().map(|&i| first + i));
        objects.push(bvh);
    }
    (top, objects, order)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Transform;
    use crate::shapes::{Shape, ShapeStorage, Sphere};
    use glam::{DVec3, Vec3};

    /// A unit sphere at the origin of instance space, placed by `t`.
    fn one_sphere_instance(t: &Transform) -> (InstanceAccel, ShapeStorage, Shape) {
        let storage = ShapeStorage::default();
        let sphere = Shape::Sphere(Box::new(Sphere::new(
            &Transform::IDENTITY,
            false,
            1.0,
            -1.0,
            1.0,
            360.0,
        )));
        let (bvh, _) = Bvh::build_from(&[sphere.bounds(&storage)], 0);
        (
            InstanceAccel::build(vec![bvh], &[(0, MotionTransform::new(*t, 0.0, *t, 1.0))]),
            storage,
            sphere,
        )
    }

    fn intersect(
        accel: &InstanceAccel,
        storage: &ShapeStorage,
        sphere: &Shape,
        ray: &Ray,
    ) -> Option<SurfaceInteraction> {
        accel.intersect(ray, f32::INFINITY, |bvh, r, t_max| {
            let mut best = None;
            bvh.closest_hit(r, t_max, |_, t_max| {
                let hit = sphere.intersect(storage, r, t_max)?;
                best = Some(hit.interaction);
                Some(hit.t_hit)
            })?;
            best
        })
    }

    #[test]
    fn instance_space_hits_come_back_to_render_space() {
        // Scaled by 2 and moved to (10, 0, 0): a sphere of radius 2.
        let t = Transform::translate(DVec3::new(10.0, 0.0, 0.0))
            .then(&Transform::scale(DVec3::splat(2.0)).unwrap());
        let (accel, storage, sphere) = one_sphere_instance(&t);
        // Off the pole (pbrt nudges a hit exactly on the axis by 1e-5 r).
        let ray = Ray::new(Vec3::new(10.5, 0.0, -10.0), Vec3::Z, 0.0);
        let si = intersect(&accel, &storage, &sphere, &ray).expect("hit");
        let z = (1.0f64 - 0.0625).sqrt();
        let exact = [10.5, 0.0, -2.0 * z];
        assert!(
            (si.t as f64 - (10.0 - 2.0 * z)).abs() < 1e-5,
            "t = {}",
            si.t
        );
        assert!(
            (si.n - Vec3::new(0.25, 0.0, -z as f32)).length() < 1e-5,
            "n = {}",
            si.n
        );
        // The error bound covers the point's distance from the exact one.
        for (axis, exact) in exact.iter().enumerate() {
            let off = (si.p[axis] as f64 - exact).abs();
            assert!(
                off <= si.p_error[axis] as f64,
                "{axis}: {} ± {}",
                si.p,
                si.p_error
            );
        }
        // An oblique ray: the hit lies on the radius-2 sphere, its normal
        // radial; t in units of the render-space direction.
        let d = Vec3::new(0.1, 0.05, 1.0);
        let ray = Ray::new(Vec3::new(9.0, 0.0, -10.0), d, 0.0);
        let si = intersect(&accel, &storage, &sphere, &ray).expect("hit");
        let radial = si.p - Vec3::new(10.0, 0.0, 0.0);
        assert!((radial.length() - 2.0).abs() < 1e-4);
        assert!((si.n - radial / 2.0).length() < 1e-4);
        assert!((ray.at(si.t) - si.p).length() < 1e-3);
        // A non-uniform scale: normals through the inverse transpose.
        let t = Transform::scale(DVec3::new(1.0, 4.0, 1.0)).unwrap();
        let (accel, storage, sphere) = one_sphere_instance(&t);
        let target = Vec3::new(0.6, 4.0 * 0.8, 0.0);
        let ray = Ray::new(target * 3.0, -target * 2.0, 0.0);
        let si = intersect(&accel, &storage, &sphere, &ray).expect("hit");
        assert!((si.t - 1.0).abs() < 1e-4, "t = {}", si.t);
        let expected_n = Vec3::new(0.6, 0.8 / 4.0, 0.0).normalize();
        assert!((si.n - expected_n).length() < 1e-4, "n = {}", si.n);
        // Misses and t_max.
        let miss = Ray::new(Vec3::new(5.0, 0.0, -10.0), Vec3::Z, 0.0);
        assert!(intersect(&accel, &storage, &sphere, &miss).is_none());
        assert!(!accel.intersect_p(&ray, 0.9, |bvh, r, t_max| {
            bvh.any_hit(r, t_max, |_, t| sphere.intersect_p(&storage, r, t))
        }));
        assert!(accel.intersect_p(&ray, 1.1, |bvh, r, t_max| {
            bvh.any_hit(r, t_max, |_, t| sphere.intersect_p(&storage, r, t))
        }));
    }
}
