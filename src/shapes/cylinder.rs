//! pbrt-v4's `cylinder`: an open (partial) cylinder around the object-space
//! z axis.
//!
//! | parameter | type  | default | meaning                                  |
//! |-----------|-------|---------|------------------------------------------|
//! | `radius`  | float | 1       | radius                                   |
//! | `zmin`    | float | −1      | lower end (swapped with zmax if greater) |
//! | `zmax`    | float | 1       | upper end                                |
//! | `phimax`  | float | 360     | azimuth sweep in degrees (clamped 0–360) |
//!
//! Parametrisation: u = φ/φmax, v = (z − zmin)/(zmax − zmin). The normal
//! points away from the axis, flipped by `ReverseOrientation` XOR a
//! handedness-swapping transform (sampled normals: `ReverseOrientation`
//! only, as in pbrt-v4).

use super::first_unclipped;
use super::interval::{solve_quadric, Interval};
use super::object_transform::ObjectTransform;
use super::surface::{surface_interaction, weingarten_normal_derivatives, SurfacePoint};
use super::{
    area_sample_to_solid_angle, solid_angle_pdf_of_hit, QuadricHit, ShapeIntersection, ShapeSample,
    ShapeSampleContext,
};
use crate::error::Result;
use crate::interaction::SurfaceInteraction;
use crate::math::ray::gamma;
use crate::math::{lerp, sqr, Bounds3, Ray, Transform};
use crate::scene_description::params::ParamSet;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// pbrt-v4's `cylinder` (parameters and conventions: see the module
/// documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    transform: ObjectTransform,
    reverse_orientation: bool,
    radius: f32,
    z_min: f32,
    z_max: f32,
    /// In radians.
    phi_max: f32,
}

impl Cylinder {
    pub fn new(
        render_from_object: &Transform,
        reverse_orientation: bool,
        radius: f32,
        z_min: f32,
        z_max: f32,
        phi_max_degrees: f32,
    ) -> Self {
        Cylinder {
            transform: ObjectTransform::new(render_from_object),
            reverse_orientation,
            radius,
            z_min: z_min.min(z_max),
            z_max: z_min.max(z_max),
            phi_max: phi_max_degrees.clamp(0.0, 360.0).to_radians(),
        }
    }

    pub fn from_parameters(
        params: &ParamSet,
        render_from_object: &Transform,
        reverse_orientation: bool,
    ) -> Result<Self> {
        Ok(Cylinder::new(
            render_from_object,
            reverse_orientation,
            params.float("radius", 1.0)? as f32,
            params.float("zmin", -1.0)? as f32,
            params.float("zmax", 1.0)? as f32,
            params.float("phimax", 360.0)? as f32,
        ))
    }

    pub fn bounds(&self) -> Bounds3 {
        let r = self.radius;
        self.transform.bounds_to_render(Bounds3 {
            min: Vec3::new(-r, -r, self.z_min),
            max: Vec3::new(r, r, self.z_max),
        })
    }

    pub fn area(&self) -> f32 {
        (self.z_max - self.z_min) * self.radius * self.phi_max
    }

    fn is_clipped(&self, p: Vec3, phi: f32) -> bool {
        p.z < self.z_min || p.z > self.z_max || phi > self.phi_max
    }

    /// The point at `t`, pushed onto the cylinder, and its azimuth.
    fn hit_point(&self, origin: Vec3, direction: Vec3, t: f32) -> (Vec3, f32) {
        let mut p = origin + t * direction;
        let hit_radius = (sqr(p.x) + sqr(p.y)).sqrt();
        p.x *= self.radius / hit_radius;
        p.y *= self.radius / hit_radius;
        let mut phi = p.y.atan2(p.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        (p, phi)
    }

    fn basic_intersect(&self, ray: &Ray, t_max: f32) -> Option<QuadricHit> {
        let (o, oi, d, di) = self.transform.ray_to_object(ray.origin, ray.direction);
        let radius = Interval::exact(self.radius);
        let a = di.x.squared() + di.y.squared();
        let b = (di.x * oi.x + di.y * oi.y).scaled(2.0);
        let c = oi.x.squared() + oi.y.squared() - radius.squared();

        let f = b / a.scaled(2.0);
        let vx = oi.x - f * di.x;
        let vy = oi.y - f * di.y;
        let length = (vx.squared() + vy.squared()).sqrt();
        let (t_hit, t1) = solve_quadric(a, b, c, radius, length, t_max)?;

        first_unclipped(
            t_hit,
            t1,
            t_max,
            |t| self.hit_point(o, d, t),
            |p, phi| self.is_clipped(p, phi),
        )
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
        let p = hit.p_object;
        let u = hit.phi / self.phi_max;
        let v = (p.z - self.z_min) / (self.z_max - self.z_min);
        let dpdu = Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0);
        let dpdv = Vec3::new(0.0, 0.0, self.z_max - self.z_min);
        let d2p_duu = -self.phi_max * self.phi_max * Vec3::new(p.x, p.y, 0.0);
        let (dndu, dndv) =
            weingarten_normal_derivatives(dpdu, dpdv, d2p_duu, Vec3::ZERO, Vec3::ZERO);
        let object = surface_interaction(
            &SurfacePoint {
                p,
                p_error: gamma(3) * Vec3::new(p.x, p.y, 0.0).abs(),
                uv: Vec2::new(u, v),
                dpdu,
                dpdv,
                dndu,
                dndv,
            },
            self.transform.object_from_render.transform_vector3(wo),
            time,
            self.reverse_orientation ^ self.transform.swaps_handedness,
        );
        self.transform.interaction_to_render(&object)
    }

    /// A uniform point on the (partial) cylinder, density 1/area.
    pub fn sample_area(&self, u: Vec2) -> Option<ShapeSample> {
        let z = lerp(u.x, self.z_min, self.z_max);
        let phi = u.y * self.phi_max;
        let mut p_object = Vec3::new(self.radius * phi.cos(), self.radius * phi.sin(), z);
        let hit_radius = (sqr(p_object.x) + sqr(p_object.y)).sqrt();
        p_object.x *= self.radius / hit_radius;
        p_object.y *= self.radius / hit_radius;
        let p_object_error = gamma(3) * Vec3::new(p_object.x, p_object.y, 0.0).abs();
        let (p, p_error) = self.transform.point_to_render(p_object, p_object_error);
        let mut n = self
            .transform
            .normal_to_render(Vec3::new(p_object.x, p_object.y, 0.0))
            .normalize_or_zero();
        if self.reverse_orientation {
            n = -n;
        }
        Some(ShapeSample {
            p,
            p_error,
            n,
            uv: Vec2::new(
                phi / self.phi_max,
                (p_object.z - self.z_min) / (self.z_max - self.z_min),
            ),
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
    use crate::shapes::test_support::{mean_and_error, TestRng};
    use glam::DVec3;

    #[test]
    fn hits_match_the_analytic_answers() {
        let c = Cylinder::new(
            &Transform::translate(DVec3::new(0.0, 0.0, 1.0)),
            false,
            2.0,
            -1.0,
            3.0,
            360.0,
        );
        let ray = Ray::new(Vec3::new(10.0, 0.0, 2.0), -Vec3::X, 0.0);
        let hit = c.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.t_hit - 8.0).abs() < 1e-5);
        let si = hit.interaction;
        assert!((si.p - Vec3::new(2.0, 0.0, 2.0)).abs().max_element() < 1e-5);
        assert!((si.n - Vec3::X).abs().max_element() < 1e-6);
        // z = 1 in object space: v = (1 − (−1))/4.
        assert!(
            (si.uv - Vec2::new(0.0, 0.5)).abs().max_element() < 1e-6,
            "{}",
            si.uv
        );
        // Along the axis: no hit; past the ends: no hit; from inside: far wall.
        assert!(!c.intersect_p(
            &Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 0.0),
            f32::INFINITY
        ));
        assert!(!c.intersect_p(
            &Ray::new(Vec3::new(10.0, 0.0, 4.5), -Vec3::X, 0.0),
            f32::INFINITY
        ));
        let inside = c
            .intersect(
                &Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::Y, 0.0),
                f32::INFINITY,
            )
            .unwrap();
        assert!((inside.t_hit - 2.0).abs() < 1e-5);
        assert!((inside.interaction.uv.x - 0.25).abs() < 1e-6);
        assert!((inside.interaction.n - Vec3::Y).abs().max_element() < 1e-6);
        // A half cylinder (φ ≤ 180°) lets a ray into y < 0 through to the far wall.
        let half = Cylinder::new(&Transform::IDENTITY, true, 1.0, -1.0, 1.0, 180.0);
        let hit = half
            .intersect(
                &Ray::new(Vec3::new(0.0, -5.0, 0.0), Vec3::Y, 0.0),
                f32::INFINITY,
            )
            .unwrap();
        assert!((hit.interaction.p.y - 1.0).abs() < 1e-6);
        // Reversed: the normal points at the axis.
        assert!((hit.interaction.n + Vec3::Y).abs().max_element() < 1e-6);
    }

    #[test]
    fn spawned_rays_never_rehit_the_cylinder_outside() {
        let mut rng = TestRng::new(13);
        for case in 0..10_000 {
            let scale = if case % 2 == 0 { 1.0 } else { 1e4 };
            let center = rng.direction().as_dvec3() * scale;
            let axis = rng.direction().as_dvec3();
            let t = Transform::translate(center)
                .then(&Transform::rotate(rng.range(0.0, 6.0) as f64, axis).unwrap());
            let radius = if scale == 1.0 {
                rng.range(0.05, 10.0)
            } else {
                rng.range(1.0, 100.0)
            };
            let c = Cylinder::new(&t, false, radius, -radius, radius, 360.0);
            let m = t.to_mat4();
            let phi = rng.range(0.0, 2.0 * PI);
            let z = rng.range(-0.8, 0.8) * radius;
            let target = m.transform_point3(Vec3::new(radius * phi.cos(), radius * phi.sin(), z));
            let outward = m.transform_vector3(Vec3::new(phi.cos(), phi.sin(), 0.0));
            let origin = target + (outward + 0.5 * rng.direction()) * radius * rng.range(1.0, 10.0);
            let Some(hit) = c.intersect(&Ray::new(origin, target - origin, 0.0), f32::INFINITY)
            else {
                continue;
            };
            let si = hit.interaction;
            // Leaving on the outside of a convex surface: never a hit.
            let out = rng.direction_around(si.n);
            if out.dot(si.n) > 0.0 {
                assert!(
                    c.intersect(&si.spawn_ray(out), f32::INFINITY).is_none(),
                    "case {case}: re-hit"
                );
            }
            // Going in: any hit is elsewhere on the cylinder.
            if let Some(again) = c.intersect(&si.spawn_ray(-out), f32::INFINITY) {
                assert!(
                    again.interaction.p.distance(si.p) > 1e-3 * radius,
                    "case {case}: self-hit"
                );
            }
        }
    }

    #[test]
    fn area_samples_are_uniform_and_the_pdf_integrates_to_one() {
        let c = Cylinder::new(&Transform::IDENTITY, false, 0.5, 0.0, 2.0, 270.0);
        let mut rng = TestRng::new(17);
        let mut zs = Vec::new();
        for _ in 0..20_000 {
            let s = c.sample_area(rng.uniform2()).unwrap();
            assert!((s.p.truncate().length() - 0.5).abs() < 1e-6);
            let mut phi = s.p.y.atan2(s.p.x);
            if phi < 0.0 {
                phi += 2.0 * PI;
            }
            assert!(phi <= 1.5 * PI + 1e-5);
            assert!((s.pdf * c.area() - 1.0).abs() < 1e-6);
            zs.push(s.p.z as f64);
        }
        let (mean_z, error) = mean_and_error(&zs);
        assert!((mean_z - 1.0).abs() < 4.0 * error);
        // ∫ pdf dA over the surface = pdf · area, with the surface measured
        // by the (u,v) Jacobian |dpdu × dpdv| on a grid.
        let n = 64;
        let mut integral = 0.0;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let phi = u.x * 1.5 * PI;
                let p = Vec3::new(0.5 * phi.cos(), 0.5 * phi.sin(), 2.0 * u.y);
                let ray = Ray::new(
                    p * Vec3::new(3.0, 3.0, 1.0),
                    p * Vec3::new(-2.0, -2.0, 0.0),
                    0.0,
                );
                let si = c.intersect(&ray, f32::INFINITY).unwrap().interaction;
                integral += si.dpdu.cross(si.dpdv).length() / (n * n) as f32 * (1.0 / c.area());
            }
        }
        assert!((integral - 1.0).abs() < 1e-3, "{integral}");
    }
}
