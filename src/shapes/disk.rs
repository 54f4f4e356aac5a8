//! pbrt-v4's `disk`: a (partial) annulus in the plane z = height, centred on
//! the object-space z axis.
//!
//! | parameter     | type  | default | meaning                                  |
//! |---------------|-------|---------|------------------------------------------|
//! | `height`      | float | 0       | z of the disk's plane                    |
//! | `radius`      | float | 1       | outer radius                             |
//! | `innerradius` | float | 0       | inner radius (a hole when > 0)           |
//! | `phimax`      | float | 360     | azimuth sweep in degrees (clamped 0–360) |
//!
//! Parametrisation: u = φ/φmax, v = (radius − r)/(radius − innerradius), so
//! v = 0 on the outer rim. The normal is +z in object space, flipped by
//! `ReverseOrientation` XOR a handedness-swapping transform. As in pbrt-v4,
//! area sampling covers the full disk (ignoring the hole and φmax) and the
//! sampled normal is flipped by `ReverseOrientation` only.

use super::object_transform::ObjectTransform;
use super::surface::{surface_interaction, SurfacePoint};
use super::{
    area_sample_to_solid_angle, solid_angle_pdf_of_hit, QuadricHit, ShapeIntersection, ShapeSample,
    ShapeSampleContext,
};
use crate::error::Result;
use crate::interaction::SurfaceInteraction;
use crate::math::sampling::sample_uniform_disk_concentric;
use crate::math::{sqr, Bounds3, Ray, Transform};
use crate::scene_description::params::ParamSet;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// pbrt-v4's `disk` (parameters and conventions: see the module
/// documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Disk {
    transform: ObjectTransform,
    reverse_orientation: bool,
    height: f32,
    radius: f32,
    inner_radius: f32,
    /// In radians.
    phi_max: f32,
}

impl Disk {
    pub fn new(
        render_from_object: &Transform,
        reverse_orientation: bool,
        height: f32,
        radius: f32,
        inner_radius: f32,
        phi_max_degrees: f32,
    ) -> Self {
        Disk {
            transform: ObjectTransform::new(render_from_object),
            reverse_orientation,
            height,
            radius,
            inner_radius,
            phi_max: phi_max_degrees.clamp(0.0, 360.0).to_radians(),
        }
    }

    pub fn from_parameters(
        params: &ParamSet,
        render_from_object: &Transform,
        reverse_orientation: bool,
    ) -> Result<Self> {
        Ok(Disk::new(
            render_from_object,
            reverse_orientation,
            params.float("height", 0.0)? as f32,
            params.float("radius", 1.0)? as f32,
            params.float("innerradius", 0.0)? as f32,
            params.float("phimax", 360.0)? as f32,
        ))
    }

    pub fn bounds(&self) -> Bounds3 {
        let r = self.radius;
        self.transform.bounds_to_render(Bounds3 {
            min: Vec3::new(-r, -r, self.height),
            max: Vec3::new(r, r, self.height),
        })
    }

    pub fn area(&self) -> f32 {
        self.phi_max * 0.5 * (sqr(self.radius) - sqr(self.inner_radius))
    }

    fn basic_intersect(&self, ray: &Ray, t_max: f32) -> Option<QuadricHit> {
        let (o, _, d, _) = self.transform.ray_to_object(ray.origin, ray.direction);
        if d.z == 0.0 {
            return None;
        }
        let t = (self.height - o.z) / d.z;
        if t <= 0.0 || t >= t_max {
            return None;
        }
        let p = o + t * d;
        let distance2 = sqr(p.x) + sqr(p.y);
        if distance2 > sqr(self.radius) || distance2 < sqr(self.inner_radius) {
            return None;
        }
        let mut phi = p.y.atan2(p.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        if phi > self.phi_max {
            return None;
        }
        Some(QuadricHit {
            t,
            p_object: p,
            phi,
        })
    }

    pub fn intersect_p(&self, ray: &Ray, t_max: f32) -> bool {
        self.basic_intersect(ray, t_max).is_some()
    }

    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeIntersection> {
        let hit = self.basic_intersect(ray, t_max)?;
        let mut interaction = self.interaction(&hit, -ray.direction, ray.time);
        interaction.t = hit.t;
        Some(ShapeIntersection {
            interaction,
            t_hit: hit.t,
        })
    }

    fn interaction(&self, hit: &QuadricHit, wo: Vec3, time: f32) -> SurfaceInteraction {
        let mut p = hit.p_object;
        let u = hit.phi / self.phi_max;
        let r_hit = (sqr(p.x) + sqr(p.y)).sqrt();
        let v = (self.radius - r_hit) / (self.radius - self.inner_radius);
        let dpdu = Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0);
        let dpdv = Vec3::new(p.x, p.y, 0.0) * (self.inner_radius - self.radius) / r_hit;
        // On the plane exactly: the object-space point has no error.
        p.z = self.height;
        let object = surface_interaction(
            &SurfacePoint {
                p,
                p_error: Vec3::ZERO,
                uv: Vec2::new(u, v),
                dpdu,
                dpdv,
                dndu: Vec3::ZERO,
                dndv: Vec3::ZERO,
            },
            self.transform.object_from_render.transform_vector3(wo),
            time,
            self.reverse_orientation ^ self.transform.swaps_handedness,
        );
        self.transform.interaction_to_render(&object)
    }

    /// A uniform point on the full disk of radius `radius` (pbrt-v4 ignores
    /// `innerradius` and `phimax` here), density 1/area.
    pub fn sample_area(&self, u: Vec2) -> Option<ShapeSample> {
        let pd = sample_uniform_disk_concentric(u);
        let p_object = Vec3::new(pd.x * self.radius, pd.y * self.radius, self.height);
        let (p, p_error) = self.transform.point_to_render(p_object, Vec3::ZERO);
        let mut n = self.transform.normal_to_render(Vec3::Z).normalize_or_zero();
        if self.reverse_orientation {
            n = -n;
        }
        let mut phi = pd.y.atan2(pd.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let radius_sample = (sqr(p_object.x) + sqr(p_object.y)).sqrt();
        let uv = Vec2::new(
            phi / self.phi_max,
            (self.radius - radius_sample) / (self.radius - self.inner_radius),
        );
        Some(ShapeSample {
            p,
            p_error,
            n,
            uv,
            pdf: 1.0 / self.area(),
        })
    }

    pub fn sample_from(&self, ctx: &ShapeSampleContext, u: Vec2) -> Option<ShapeSample> {
        area_sample_to_solid_angle(self.sample_area(u)?, ctx)
    }

    pub fn pdf_from(&self, ctx: &ShapeSampleContext, wi: Vec3) -> f32 {
        let hit = self.intersect(&ctx.spawn_ray(wi), f32::INFINITY);
        solid_angle_pdf_of_hit(hit.as_ref(), |_| 1.0 / self.area(), ctx, wi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::test_support::{check_solid_angle_sampling, TestRng};
    use crate::shapes::{Shape, ShapeStorage};
    use glam::DVec3;

    #[test]
    fn hits_match_the_analytic_answers() {
        let disk = Disk::new(
            &Transform::translate(DVec3::new(0.0, 0.0, 1.0)),
            false,
            0.5,
            2.0,
            0.5,
            360.0,
        );
        let ray = Ray::new(Vec3::new(0.0, 1.0, 5.0), -Vec3::Z, 0.0);
        let hit = disk.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.t_hit - 3.5).abs() < 1e-6);
        let si = hit.interaction;
        assert_eq!(si.p, Vec3::new(0.0, 1.0, 1.5));
        assert_eq!(si.n, Vec3::Z);
        // φ = 90°, r = 1: u = 1/4, v = (2 − 1)/(2 − 0.5).
        assert!(
            (si.uv - Vec2::new(0.25, 1.0 / 1.5)).abs().max_element() < 1e-6,
            "{}",
            si.uv
        );
        assert!(si.dpdu.cross(si.dpdv).dot(si.n) > 0.0);
        // The hole, the rim, and parallel rays.
        assert!(!disk.intersect_p(
            &Ray::new(Vec3::new(0.2, 0.0, 5.0), -Vec3::Z, 0.0),
            f32::INFINITY
        ));
        assert!(!disk.intersect_p(
            &Ray::new(Vec3::new(2.1, 0.0, 5.0), -Vec3::Z, 0.0),
            f32::INFINITY
        ));
        assert!(!disk.intersect_p(
            &Ray::new(Vec3::new(0.0, 1.0, 1.5), Vec3::X, 0.0),
            f32::INFINITY
        ));
        assert!(!disk.intersect_p(&ray, 3.0));
        // A quarter disk misses φ = 180°.
        let quarter = Disk::new(&Transform::IDENTITY, false, 0.0, 1.0, 0.0, 90.0);
        assert!(!quarter.intersect_p(
            &Ray::new(Vec3::new(-0.5, 0.1, 1.0), -Vec3::Z, 0.0),
            f32::INFINITY
        ));
        assert!(quarter.intersect_p(
            &Ray::new(Vec3::new(0.5, 0.1, 1.0), -Vec3::Z, 0.0),
            f32::INFINITY
        ));
        // Reverse orientation flips the normal.
        let reversed = Disk::new(&Transform::IDENTITY, true, 0.0, 1.0, 0.0, 360.0);
        let hit = reversed.intersect(
            &Ray::new(Vec3::new(0.5, 0.1, 1.0), -Vec3::Z, 0.0),
            f32::INFINITY,
        );
        assert_eq!(hit.unwrap().interaction.n, -Vec3::Z);
    }

    #[test]
    fn spawned_rays_never_rehit_the_disk() {
        let mut rng = TestRng::new(11);
        for case in 0..10_000 {
            let scale = if case % 2 == 0 { 1.0 } else { 1e4 };
            let center = rng.direction().as_dvec3() * scale;
            let axis = rng.direction().as_dvec3();
            let t = Transform::translate(center)
                .then(&Transform::rotate(rng.range(0.0, 6.0) as f64, axis).unwrap());
            let radius = rng.range(0.5, 10.0);
            let disk = Disk::new(&t, case % 3 == 0, rng.range(-1.0, 1.0), radius, 0.0, 360.0);
            let m = t.to_mat4();
            let target_object = (rng.uniform2() * 2.0 - Vec2::ONE) * radius * 0.6;
            let target = m.transform_point3(Vec3::new(target_object.x, target_object.y, 0.0));
            let normal = m.transform_vector3(Vec3::Z).normalize();
            let origin = target + rng.direction_around(normal) * rng.range(0.1, 50.0);
            let Some(hit) = disk.intersect(&Ray::new(origin, target - origin, 0.0), f32::INFINITY)
            else {
                continue;
            };
            let si = hit.interaction;
            for _ in 0..2 {
                let w = rng.direction();
                assert!(
                    disk.intersect(&si.spawn_ray(w), f32::INFINITY).is_none(),
                    "case {case}: re-hit"
                );
            }
        }
    }

    #[test]
    fn sampling_by_area_and_by_solid_angle() {
        let disk = Disk::new(&Transform::IDENTITY, false, 0.0, 1.5, 0.0, 360.0);
        let mut rng = TestRng::new(5);
        for _ in 0..1000 {
            let s = disk.sample_area(rng.uniform2()).unwrap();
            assert!(s.p.z == 0.0 && s.p.truncate().length() <= 1.5 + 1e-6);
            assert!((s.pdf * disk.area() - 1.0).abs() < 1e-6);
            assert_eq!(s.n, Vec3::Z);
        }
        // Seen from the axis at height h: 2π(1 − h/√(h² + r²)).
        let h = 0.8f32;
        let expected = 2.0 * PI * (1.0 - h / (h * h + 1.5 * 1.5).sqrt());
        let ctx = ShapeSampleContext {
            p: Vec3::new(0.0, 0.0, h),
            p_error: Vec3::ZERO,
            n: -Vec3::Z,
            ns: -Vec3::Z,
            time: 0.0,
        };
        let shape = Shape::Disk(Box::new(disk));
        check_solid_angle_sampling(&shape, &ShapeStorage::default(), &ctx, expected, 9);
    }
}
