//! pbrt-v4's `sphere`: a (partial) sphere about the object-space origin.
//!
//! | parameter | type  | default   | meaning                                  |
//! |-----------|-------|-----------|------------------------------------------|
//! | `radius`  | float | 1         | radius                                   |
//! | `zmin`    | float | −radius   | lower z clipping plane (clamped to ±r)   |
//! | `zmax`    | float | radius    | upper z clipping plane (clamped to ±r)   |
//! | `phimax`  | float | 360       | azimuth sweep in degrees (clamped 0–360) |
//!
//! Parametrisation: u = φ/φmax, v = (θ − θ(zmin)) / (θ(zmax) − θ(zmin)),
//! θ measured from +z. The normal points outwards, flipped by
//! `ReverseOrientation` XOR a handedness-swapping transform.
//!
//! As in pbrt-v4, area sampling covers the whole sphere even when it is
//! clipped (with density 1/area of the clipped part), sampled normals are
//! flipped by `ReverseOrientation` only, and solid-angle sampling from
//! outside uses the object-space radius (scaling transforms are not
//! accounted for).

use super::first_unclipped;
use super::interval::{solve_quadric, Interval};
use super::numeric::clamp;
use super::object_transform::ObjectTransform;
use super::spherical::spherical_direction;
use super::surface::{surface_interaction, weingarten_normal_derivatives, SurfacePoint};
use super::{
    area_sample_to_solid_angle, solid_angle_pdf_of_hit, QuadricHit, ShapeIntersection, ShapeSample,
    ShapeSampleContext,
};
use crate::error::Result;
use crate::math::ray::gamma;
use crate::math::sampling::sample_uniform_sphere;
use crate::math::{safe_acos, safe_sqrt, sqr, Bounds3, Frame, Ray, Transform};
use crate::scene_description::params::ParamSet;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// sin²(1.5°): below it, cone sampling uses Taylor expansions.
const SMALL_CONE_SIN2: f32 = 0.000_685_23;

/// pbrt-v4's `sphere` (parameters and conventions: see the module
/// documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    transform: ObjectTransform,
    reverse_orientation: bool,
    radius: f32,
    z_min: f32,
    z_max: f32,
    theta_z_min: f32,
    theta_z_max: f32,
    /// In radians.
    phi_max: f32,
}

impl Sphere {
    /// `phi_max_degrees` is clamped to [0, 360] and the z range to ±radius.
    pub fn new(
        render_from_object: &Transform,
        reverse_orientation: bool,
        radius: f32,
        z_min: f32,
        z_max: f32,
        phi_max_degrees: f32,
    ) -> Self {
        let (low, high) = (z_min.min(z_max), z_min.max(z_max));
        Sphere {
            transform: ObjectTransform::new(render_from_object),
            reverse_orientation,
            radius,
            z_min: clamp(low, -radius, radius),
            z_max: clamp(high, -radius, radius),
            theta_z_min: clamp(low / radius, -1.0, 1.0).acos(),
            theta_z_max: clamp(high / radius, -1.0, 1.0).acos(),
            phi_max: phi_max_degrees.clamp(0.0, 360.0).to_radians(),
        }
    }

    pub fn from_parameters(
        params: &ParamSet,
        render_from_object: &Transform,
        reverse_orientation: bool,
    ) -> Result<Self> {
        let radius = params.float("radius", 1.0)?;
        let z_min = params.float("zmin", -radius)?;
        let z_max = params.float("zmax", radius)?;
        let phi_max = params.float("phimax", 360.0)?;
        Ok(Sphere::new(
            render_from_object,
            reverse_orientation,
            radius as f32,
            z_min as f32,
            z_max as f32,
            phi_max as f32,
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
        self.phi_max * self.radius * (self.z_max - self.z_min)
    }

    fn is_clipped(&self, p: Vec3, phi: f32) -> bool {
        (self.z_min > -self.radius && p.z < self.z_min)
            || (self.z_max < self.radius && p.z > self.z_max)
            || phi > self.phi_max
    }

    /// The point at `t`, pushed onto the sphere, and its azimuth.
    fn hit_point(&self, origin: Vec3, direction: Vec3, t: f32) -> (Vec3, f32) {
        let mut p = origin + t * direction;
        p *= self.radius / p.length();
        if p.x == 0.0 && p.y == 0.0 {
            p.x = 1e-5 * self.radius;
        }
        let mut phi = p.y.atan2(p.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        (p, phi)
    }

    /// The object-space hit: the quadratic solved on intervals, so a root is
    /// only taken when its whole error interval lies in (0, t_max).
    fn basic_intersect(&self, ray: &Ray, t_max: f32) -> Option<QuadricHit> {
        // Most rays that reach the sphere's box pass well clear of it: the
        // line's squared distance from the centre, in plain floats, with a
        // margin far above its rounding (the cancellation is of order
        // 10⁻⁶ |o|²), rejects them before the transform with error bounds
        // and the interval arithmetic.
        let to_object = &self.transform.object_from_render;
        let (o, d) = (
            to_object.transform_point3(ray.origin),
            to_object.transform_vector3(ray.direction),
        );
        let (o2, od, d2) = (o.length_squared(), o.dot(d), d.length_squared());
        if o2 - od * od / d2 > 1.01 * self.radius * self.radius + 1e-4 * o2 {
            return None;
        }
        let (o, oi, d, di) = self.transform.ray_to_object(ray.origin, ray.direction);
        let radius = Interval::exact(self.radius);
        let a = di.x.squared() + di.y.squared() + di.z.squared();
        let b = (di.x * oi.x + di.y * oi.y + di.z * oi.z).scaled(2.0);
        let c = oi.x.squared() + oi.y.squared() + oi.z.squared() - radius.squared();

        // Discriminant as 4a(r + |v|)(r − |v|), v the ray point closest to
        // the centre: far more accurate than b² − 4ac.
        let f = b / a.scaled(2.0);
        let vx = oi.x - f * di.x;
        let vy = oi.y - f * di.y;
        let vz = oi.z - f * di.z;
        let length = (vx.squared() + vy.squared() + vz.squared()).sqrt();
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

    fn interaction(
        &self,
        hit: &QuadricHit,
        wo: Vec3,
        time: f32,
    ) -> crate::interaction::SurfaceInteraction {
        let p = hit.p_object;
        let phi = hit.phi;
        let u = phi / self.phi_max;
        let cos_theta = p.z / self.radius;
        let theta = safe_acos(cos_theta);
        let theta_range = self.theta_z_max - self.theta_z_min;
        let v = (theta - self.theta_z_min) / theta_range;

        let z_radius = (sqr(p.x) + sqr(p.y)).sqrt();
        let (cos_phi, sin_phi) = (p.x / z_radius, p.y / z_radius);
        let dpdu = Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0);
        let sin_theta = safe_sqrt(1.0 - sqr(cos_theta));
        let dpdv = theta_range * Vec3::new(p.z * cos_phi, p.z * sin_phi, -self.radius * sin_theta);

        let d2p_duu = -self.phi_max * self.phi_max * Vec3::new(p.x, p.y, 0.0);
        let d2p_duv = theta_range * p.z * self.phi_max * Vec3::new(-sin_phi, cos_phi, 0.0);
        let d2p_dvv = -sqr(theta_range) * p;
        let (dndu, dndv) = weingarten_normal_derivatives(dpdu, dpdv, d2p_duu, d2p_duv, d2p_dvv);

        let object = surface_interaction(
            &SurfacePoint {
                p,
                p_error: gamma(5) * p.abs(),
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

    fn uv_of_object_point(&self, p: Vec3) -> Vec2 {
        let theta = safe_acos(p.z / self.radius);
        let mut phi = p.y.atan2(p.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        Vec2::new(
            phi / self.phi_max,
            (theta - self.theta_z_min) / (self.theta_z_max - self.theta_z_min),
        )
    }

    /// A uniform point on the whole sphere (pbrt-v4 ignores the clipping
    /// here), density 1/area.
    pub fn sample_area(&self, u: Vec2) -> Option<ShapeSample> {
        let mut p_object = self.radius * sample_uniform_sphere(u);
        p_object *= self.radius / p_object.length();
        let p_object_error = gamma(5) * p_object.abs();
        let mut n = self
            .transform
            .normal_to_render(p_object)
            .normalize_or_zero();
        if self.reverse_orientation {
            n = -n;
        }
        let (p, p_error) = self.transform.point_to_render(p_object, p_object_error);
        Some(ShapeSample {
            p,
            p_error,
            n,
            uv: self.uv_of_object_point(p_object),
            pdf: 1.0 / self.area(),
        })
    }

    fn center(&self) -> Vec3 {
        self.transform
            .render_from_object
            .transform_point3(Vec3::ZERO)
    }

    /// Whether the (offset) reference point is inside the sphere, where
    /// pbrt samples by area instead of by cone.
    fn is_inside(&self, ctx: &ShapeSampleContext) -> bool {
        let center = self.center();
        ctx.offset_origin(center - ctx.p).distance_squared(center) <= sqr(self.radius)
    }

    /// From outside: a direction uniform in the cone the sphere subtends,
    /// and the point it first hits. From inside: area sampling converted to
    /// solid angle.
    pub fn sample_from(&self, ctx: &ShapeSampleContext, u: Vec2) -> Option<ShapeSample> {
        if self.is_inside(ctx) {
            return area_sample_to_solid_angle(self.sample_area(u)?, ctx);
        }
        let center = self.center();
        let sin_theta_max = self.radius / ctx.p.distance(center);
        let sin2_theta_max = sqr(sin_theta_max);
        let cos_theta_max = safe_sqrt(1.0 - sin2_theta_max);
        let mut one_minus_cos_theta_max = 1.0 - cos_theta_max;

        let mut cos_theta = (cos_theta_max - 1.0) * u.x + 1.0;
        let mut sin2_theta = 1.0 - sqr(cos_theta);
        if sin2_theta_max < SMALL_CONE_SIN2 {
            sin2_theta = sin2_theta_max * u.x;
            cos_theta = (1.0 - sin2_theta).sqrt();
            one_minus_cos_theta_max = sin2_theta_max / 2.0;
        }

        // The angle at the centre between the axis and the sampled point.
        let cos_alpha = sin2_theta / sin_theta_max
            + cos_theta * safe_sqrt(1.0 - sin2_theta / sqr(sin_theta_max));
        let sin_alpha = safe_sqrt(1.0 - sqr(cos_alpha));
        let phi = u.y * 2.0 * PI;
        let w = spherical_direction(sin_alpha, cos_alpha, phi);
        let frame = Frame::from_z((center - ctx.p).normalize());
        let mut n = frame.from_local(-w);
        let p = center + self.radius * n;
        if self.reverse_orientation {
            n = -n;
        }
        if one_minus_cos_theta_max == 0.0 {
            return None;
        }
        Some(ShapeSample {
            p,
            p_error: gamma(5) * p.abs(),
            n,
            uv: self.uv_of_object_point(self.transform.point_to_object(p)),
            pdf: 1.0 / (2.0 * PI * one_minus_cos_theta_max),
        })
    }

    pub fn pdf_from(&self, ctx: &ShapeSampleContext, wi: Vec3) -> f32 {
        if self.is_inside(ctx) {
            let hit = self.intersect(&ctx.spawn_ray(wi), f32::INFINITY);
            return solid_angle_pdf_of_hit(hit.as_ref(), |_| 1.0 / self.area(), ctx, wi);
        }
        let sin2_theta_max = sqr(self.radius) / ctx.p.distance_squared(self.center());
        let cos_theta_max = safe_sqrt(1.0 - sin2_theta_max);
        let one_minus_cos_theta_max = if sin2_theta_max < SMALL_CONE_SIN2 {
            sin2_theta_max / 2.0
        } else {
            1.0 - cos_theta_max
        };
        1.0 / (2.0 * PI * one_minus_cos_theta_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::test_support::{check_solid_angle_sampling, TestRng};
    use crate::shapes::{Shape, ShapeStorage};
    use glam::DVec3;

    fn sphere_at(center: DVec3, radius: f32) -> Sphere {
        Sphere::new(
            &Transform::translate(center),
            false,
            radius,
            -radius,
            radius,
            360.0,
        )
    }

    fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
        (a - b).abs().max_element() <= tolerance
    }

    #[test]
    fn hits_match_the_analytic_answers() {
        let s = sphere_at(DVec3::new(1.0, 2.0, 3.0), 2.0);
        // Along −x onto the equator at φ = 0.
        let ray = Ray::new(Vec3::new(11.0, 2.0, 3.0), -Vec3::X, 0.5);
        let hit = s.intersect(&ray, f32::INFINITY).unwrap();
        assert!((hit.t_hit - 8.0).abs() < 1e-5);
        let si = hit.interaction;
        assert!(close(si.p, Vec3::new(3.0, 2.0, 3.0), 1e-5));
        assert!(close(si.n, Vec3::X, 1e-6));
        assert!(close(si.wo, Vec3::X, 1e-6));
        assert!(
            (si.uv - Vec2::new(0.0, 0.5)).abs().max_element() < 1e-5,
            "{}",
            si.uv
        );
        assert_eq!(si.time, 0.5);
        // Along −y onto φ = 90°, above the equator: u = 1/4.
        let ray = Ray::new(Vec3::new(1.0, 12.0, 4.0), -Vec3::Y, 0.0);
        let si = s.intersect(&ray, f32::INFINITY).unwrap().interaction;
        let expected_p = Vec3::new(1.0, 2.0 + 3.0f32.sqrt(), 4.0);
        assert!(close(si.p, expected_p, 1e-5));
        assert!(close(
            si.n,
            (expected_p - Vec3::new(1.0, 2.0, 3.0)) / 2.0,
            1e-5
        ));
        let theta = (0.5f32).acos();
        assert!((si.uv.x - 0.25).abs() < 1e-5 && (si.uv.y - (PI - theta) / PI).abs() < 1e-5);
        // dpdu × dpdv points along the outward normal.
        assert!(si.dpdu.cross(si.dpdv).normalize().dot(si.n) > 0.999);
        // t_max and rays pointing away.
        assert!(s.intersect(&ray, 8.0).is_none());
        assert!(!s.intersect_p(
            &Ray::new(Vec3::new(1.0, 12.0, 4.0), Vec3::Y, 0.0),
            f32::INFINITY
        ));
        // From inside, the hit is the far side and the normal still points out.
        let inside = s
            .intersect(
                &Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::Z, 0.0),
                f32::INFINITY,
            )
            .unwrap();
        assert!((inside.t_hit - 2.0).abs() < 1e-5 && close(inside.interaction.n, Vec3::Z, 1e-5));
    }

    #[test]
    fn orientation_flips_with_reverse_orientation_xor_handedness() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, 0.0);
        let normal = |reverse: bool, mirror: bool| {
            let t = if mirror {
                Transform::scale(DVec3::new(-1.0, 1.0, 1.0)).unwrap()
            } else {
                Transform::IDENTITY
            };
            let s = Sphere::new(&t, reverse, 1.0, -1.0, 1.0, 360.0);
            let si = s.intersect(&ray, f32::INFINITY).unwrap().interaction;
            assert_eq!(si.n, si.shading.n);
            si.n.z
        };
        assert!(normal(false, false) > 0.99);
        assert!(normal(true, false) < -0.99);
        assert!(normal(false, true) < -0.99);
        assert!(normal(true, true) > 0.99);
    }

    #[test]
    fn clipping_lets_rays_through_to_the_far_side() {
        // Cut off above z = 0.5: a ray down the axis enters through the hole
        // and hits the bottom from inside.
        let s = Sphere::new(&Transform::IDENTITY, false, 1.0, -1.0, 0.5, 360.0);
        let hit = s
            .intersect(
                &Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, 0.0),
                f32::INFINITY,
            )
            .unwrap();
        assert!((hit.t_hit - 6.0).abs() < 1e-5, "{}", hit.t_hit);
        assert!(hit.interaction.n.z < -0.99);
        // Half sphere (φ ≤ 180°): a ray hitting y < 0 first meets the far wall.
        let half = Sphere::new(&Transform::IDENTITY, false, 1.0, -1.0, 1.0, 180.0);
        let hit = half
            .intersect(
                &Ray::new(Vec3::new(0.3, -5.0, 0.0), Vec3::Y, 0.0),
                f32::INFINITY,
            )
            .unwrap();
        assert!(hit.interaction.p.y > 0.9);
        assert!((half.area() - 2.0 * PI).abs() < 1e-5);
        // Both crossings clipped: a miss.
        assert!(s
            .intersect(
                &Ray::new(Vec3::new(0.0, -5.0, 0.8), Vec3::Y, 0.0),
                f32::INFINITY
            )
            .is_none());
    }

    #[test]
    fn spawned_rays_never_rehit_the_sphere() {
        let mut rng = TestRng::new(7);
        let mut far_side_hits = 0;
        for case in 0..10_000 {
            let scale = if case % 2 == 0 { 1.0 } else { 1e4 };
            let center = DVec3::new(
                rng.range(-1.0, 1.0) as f64,
                rng.range(-1.0, 1.0) as f64,
                rng.range(-1.0, 1.0) as f64,
            ) * scale as f64;
            let radius = if scale == 1.0 {
                rng.range(0.01, 10.0)
            } else {
                rng.range(1.0, 100.0)
            };
            let axis = rng.direction().as_dvec3();
            let rotation = Transform::rotate(rng.range(0.0, 6.0) as f64, axis).unwrap();
            let t = Transform::translate(center).then(&rotation);
            let s = Sphere::new(&t, false, radius, -radius, radius, 360.0);
            let c = center.as_vec3();
            let origin = c + rng.direction() * radius * rng.range(1.5, 100.0);
            let target = c + rng.direction() * radius * 0.9;
            let ray = Ray::new(origin, target - origin, 0.0);
            let Some(hit) = s.intersect(&ray, f32::INFINITY) else {
                panic!("case {case}: the ray towards the inside missed");
            };
            let si = hit.interaction;
            let out = rng.direction_around(si.n);
            assert!(
                s.intersect(&si.spawn_ray(out), f32::INFINITY).is_none(),
                "case {case}: outgoing ray re-hit"
            );
            let inward = rng.direction_around(-si.n);
            if let Some(again) = s.intersect(&si.spawn_ray(inward), f32::INFINITY) {
                assert!(
                    again.interaction.p.distance(si.p) > 1e-3 * radius,
                    "case {case}: inward ray hit its own origin"
                );
                far_side_hits += 1;
            }
        }
        assert!(far_side_hits > 9_000);
    }

    #[test]
    fn area_samples_are_uniform_on_the_sphere() {
        let s = sphere_at(DVec3::new(0.0, 0.0, 2.0), 1.5);
        let mut rng = TestRng::new(3);
        let n = 20_000;
        let mut bins = [0usize; 4];
        for _ in 0..n {
            let ss = s.sample_area(rng.uniform2()).unwrap();
            assert!((ss.p.distance(Vec3::new(0.0, 0.0, 2.0)) - 1.5).abs() < 1e-5);
            assert!((ss.pdf * s.area() - 1.0).abs() < 1e-6);
            assert!(ss.n.dot(ss.p - Vec3::new(0.0, 0.0, 2.0)) > 0.0);
            // Archimedes: z is uniform over a sphere.
            let z = (ss.p.z - 2.0) / 1.5;
            bins[(((z + 1.0) * 2.0) as usize).min(3)] += 1;
        }
        for count in bins {
            assert!((count as f32 / n as f32 - 0.25).abs() < 0.015, "{bins:?}");
        }
    }

    #[test]
    fn solid_angle_sampling_from_outside_and_inside() {
        let storage = ShapeStorage::default();
        let s = sphere_at(DVec3::new(0.5, -0.25, 4.0), 1.0);
        let shape = Shape::Sphere(Box::new(s.clone()));
        let d = Vec3::new(0.5, -0.25, 4.0).length();
        let expected = 2.0 * PI * (1.0 - (1.0 - 1.0 / (d * d)).sqrt());
        let outside = ShapeSampleContext {
            p: Vec3::ZERO,
            p_error: Vec3::ZERO,
            n: Vec3::Z,
            ns: Vec3::Z,
            time: 0.0,
        };
        check_solid_angle_sampling(&shape, &storage, &outside, expected, 1);
        // A tiny, far sphere (the small-angle Taylor branch).
        let far = Shape::Sphere(Box::new(sphere_at(DVec3::new(0.0, 0.0, 100.0), 1.0)));
        let expected_far = 2.0 * PI * (1.0 - (1.0f64 - 1e-4).sqrt()) as f32;
        check_solid_angle_sampling(&far, &storage, &outside, expected_far, 2);
        // From inside the whole sphere is seen.
        let inside = ShapeSampleContext::in_medium(Vec3::new(0.6, -0.2, 4.3), 0.0);
        check_solid_angle_sampling(&shape, &storage, &inside, 4.0 * PI, 3);
    }
}
