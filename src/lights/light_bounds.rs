//! Spatial and directional bounds of a light's emission, for the BVH light
//! sampler (pbrt-v4's `LightBounds`, `DirectionCone` and the lights'
//! `Bounds()` methods; Conty Estevez & Kulla 2018, as pbrt-v4 §12.6.3).

use super::Light;
use crate::math::{safe_acos, safe_sqrt, sqr, Bounds3};
use crate::shapes::{Shape, ShapeStorage};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// A cone of directions: axis `w` and the cosine of its half-angle
/// (pbrt-v4's `DirectionCone`; cos θ = −1 is the whole sphere).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionCone {
    pub w: Vec3,
    pub cos_theta: f32,
}

impl DirectionCone {
    pub const ENTIRE_SPHERE: DirectionCone = DirectionCone {
        w: Vec3::Z,
        cos_theta: -1.0,
    };

    /// A single direction.
    pub fn of(w: Vec3) -> Self {
        DirectionCone {
            w: w.normalize_or_zero(),
            cos_theta: 1.0,
        }
    }

    /// The cone of directions from `p` towards the box (its bounding
    /// sphere); the whole sphere from inside it.
    pub fn subtended_by(bounds: &Bounds3, p: Vec3) -> Self {
        let (center, radius) = bounds.bounding_sphere();
        let d2 = p.distance_squared(center);
        if d2 < sqr(radius) {
            return Self::ENTIRE_SPHERE;
        }
        DirectionCone {
            w: (center - p).normalize_or_zero(),
            cos_theta: safe_sqrt(1.0 - sqr(radius) / d2),
        }
    }

    /// The smallest cone holding both (pbrt-v4's `Union(DirectionCone,
    /// DirectionCone)`).
    pub fn union(self, b: DirectionCone) -> DirectionCone {
        let a = self;
        let theta_a = safe_acos(a.cos_theta);
        let theta_b = safe_acos(b.cos_theta);
        let theta_d = angle_between(a.w, b.w);
        if (theta_d + theta_b).min(PI) <= theta_a {
            return a;
        }
        if (theta_d + theta_a).min(PI) <= theta_b {
            return b;
        }
        let theta_o = (theta_a + theta_d + theta_b) / 2.0;
        if theta_o >= PI {
            return Self::ENTIRE_SPHERE;
        }
        // Rotate a's axis towards b's by θo − θa.
        let theta_r = theta_o - theta_a;
        let axis = a.w.cross(b.w);
        if axis.length_squared() == 0.0 {
            return Self::ENTIRE_SPHERE;
        }
        let w = glam::Quat::from_axis_angle(axis.normalize(), theta_r) * a.w;
        DirectionCone {
            w,
            cos_theta: theta_o.cos(),
        }
    }
}

/// The angle between unit vectors, accurate near 0 and π.
fn angle_between(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) < 0.0 {
        PI - 2.0 * ((a + b).length() / 2.0).clamp(-1.0, 1.0).asin()
    } else {
        2.0 * ((b - a).length() / 2.0).clamp(-1.0, 1.0).asin()
    }
}

/// Where a light emits and how: its box, the cone of its surface normals
/// (axis `w`, cos θo), the spread of emission about them (cos θe), its
/// power bound `phi`, and whether it emits on both sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    pub bounds: Bounds3,
    pub w: Vec3,
    pub phi: f32,
    pub cos_theta_o: f32,
    pub cos_theta_e: f32,
    pub two_sided: bool,
}

impl Default for LightBounds {
    fn default() -> Self {
        LightBounds {
            bounds: Bounds3::EMPTY,
            w: Vec3::Z,
            phi: 0.0,
            cos_theta_o: 1.0,
            cos_theta_e: 1.0,
            two_sided: false,
        }
    }
}

/// cos(π/2) as f32 arithmetic gives it (pbrt-v4 writes `std::cos(Pi / 2)`).
fn cos_half_pi() -> f32 {
    (PI / 2.0).cos()
}

impl LightBounds {
    pub fn centroid(&self) -> Vec3 {
        (self.bounds.min + self.bounds.max) / 2.0
    }

    /// Bounds of both lights (pbrt-v4's `Union(LightBounds, LightBounds)`).
    pub fn union(self, b: LightBounds) -> LightBounds {
        if self.phi == 0.0 {
            return b;
        }
        if b.phi == 0.0 {
            return self;
        }
        let cone = DirectionCone {
            w: self.w,
            cos_theta: self.cos_theta_o,
        }
        .union(DirectionCone {
            w: b.w,
            cos_theta: b.cos_theta_o,
        });
        LightBounds {
            bounds: self.bounds.union(b.bounds),
            w: cone.w,
            phi: self.phi + b.phi,
            cos_theta_o: cone.cos_theta,
            cos_theta_e: self.cos_theta_e.min(b.cos_theta_e),
            two_sided: self.two_sided || b.two_sided,
        }
    }

    /// How much the lights inside may contribute at `p` with surface
    /// normal `n` (zero for a point in a medium): pbrt-v4's
    /// `LightBounds::Importance` — power over clamped squared distance,
    /// times the cosine of the smallest angle between the emission cone
    /// and the direction to `p` (zero outside θo + θe), times the smallest
    /// incident cosine at `p` over the box.
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        let pc = self.centroid();
        let d2 = p
            .distance_squared(pc)
            .max(self.bounds.diagonal().length() / 2.0);
        // cos(a − b) and sin(a − b), clamped to 1 and 0 when a < b.
        let cos_sub_clamped = |sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32| {
            if cos_a > cos_b {
                1.0
            } else {
                cos_a * cos_b + sin_a * sin_b
            }
        };
        let sin_sub_clamped = |sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32| {
            if cos_a > cos_b {
                0.0
            } else {
                sin_a * cos_b - cos_a * sin_b
            }
        };
        let wi = (p - pc).normalize();
        let mut cos_w = self.w.dot(wi);
        if self.two_sided {
            cos_w = cos_w.abs();
        }
        let sin_w = safe_sqrt(1.0 - sqr(cos_w));
        let cos_b = DirectionCone::subtended_by(&self.bounds, p).cos_theta;
        let sin_b = safe_sqrt(1.0 - sqr(cos_b));
        let sin_o = safe_sqrt(1.0 - sqr(self.cos_theta_o));
        let cos_x = cos_sub_clamped(sin_w, cos_w, sin_o, self.cos_theta_o);
        let sin_x = sin_sub_clamped(sin_w, cos_w, sin_o, self.cos_theta_o);
        let cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
        if cos_p <= self.cos_theta_e {
            return 0.0;
        }
        let mut importance = self.phi * cos_p / d2;
        if n != Vec3::ZERO {
            let cos_i = wi.dot(n).abs();
            let sin_i = safe_sqrt(1.0 - sqr(cos_i));
            importance *= cos_sub_clamped(sin_i, cos_i, sin_b, cos_b);
        }
        // Also 0 for NaN (p at the centre of a point light).
        if importance > 0.0 {
            importance
        } else {
            0.0
        }
    }

    /// The bounds as pbrt-v4's `CompactLightBounds` stores them: the box
    /// quantised to 16 bits per axis within `all` (rounded outwards), the
    /// cosines to 15 bits (rounded down, so cones only widen). The BVH
    /// sampler evaluates importance on these, as pbrt-v4 does.
    pub fn quantized(&self, all: &Bounds3) -> LightBounds {
        let quantize_cos = |c: f32| {
            let q = (32767.0 * ((c.clamp(-1.0, 1.0) + 1.0) / 2.0)).floor();
            2.0 * (q / 32767.0) - 1.0
        };
        let quantize = |c: f32, min: f32, max: f32, round: fn(f32) -> f32| {
            if min == max {
                return min;
            }
            let q = round(65535.0 * ((c - min) / (max - min)).clamp(0.0, 1.0));
            crate::math::lerp(q / 65535.0, min, max)
        };
        let mut bounds = self.bounds;
        for axis in 0..3 {
            let (lo, hi) = (all.min[axis], all.max[axis]);
            bounds.min[axis] = quantize(self.bounds.min[axis], lo, hi, f32::floor);
            bounds.max[axis] = quantize(self.bounds.max[axis], lo, hi, f32::ceil);
        }
        LightBounds {
            bounds,
            w: self.w.normalize_or_zero(),
            cos_theta_o: quantize_cos(self.cos_theta_o),
            cos_theta_e: quantize_cos(self.cos_theta_e),
            ..*self
        }
    }
}

/// The light's bounds, or `None` for lights at infinity (distant,
/// infinite), which the BVH sampler samples separately.
pub fn light_bounds(light: &Light, shapes: &ShapeStorage) -> Option<LightBounds> {
    match light {
        // pbrt-v4 PointLight::Bounds: isotropic, φ = 4π · scale · max I.
        Light::Point(l) => Some(LightBounds {
            bounds: Bounds3::from_point(l.position),
            w: Vec3::Z,
            phi: 4.0 * PI * l.scale * l.intensity.max_value(),
            cos_theta_o: PI.cos(),
            cos_theta_e: cos_half_pi(),
            two_sided: false,
        }),
        // SpotLight::Bounds: φ as an isotropic point (the cone is in the
        // importance), θo the full-intensity cone, θe the falloff.
        Light::Spot(l) => {
            let mut cos_theta_e = (l.cos_falloff_end.acos() - l.cos_falloff_start.acos()).cos();
            // pbrt-v4's slack for round-off in the importance's cos θ'.
            if cos_theta_e == 1.0 && l.cos_falloff_end != l.cos_falloff_start {
                cos_theta_e = 0.999;
            }
            Some(LightBounds {
                bounds: Bounds3::from_point(l.position),
                w: l.axis,
                phi: 4.0 * PI * l.scale * l.intensity.max_value(),
                cos_theta_o: l.cos_falloff_start,
                cos_theta_e,
                two_sided: false,
            })
        }
        // GoniometricLight::Bounds: an isotropic point whose φ is the
        // total power with the spectrum's maximum.
        Light::Goniometric(l) => Some(LightBounds {
            bounds: Bounds3::from_point(l.position),
            w: Vec3::Z,
            phi: 4.0 * PI * l.scale * l.intensity.max_value() * l.image_mean(),
            cos_theta_o: PI.cos(),
            cos_theta_e: cos_half_pi(),
            two_sided: false,
        }),
        // ProjectionLight::Bounds: the axis, emission out to the frustum's
        // corner, and pbrt-v4's φ (the image's mean largest channel).
        Light::Projection(l) => Some(LightBounds {
            bounds: Bounds3::from_point(l.position),
            w: l.axis,
            phi: l.bounds_phi(),
            cos_theta_o: 1.0,
            cos_theta_e: l.cos_total_width(),
            two_sided: false,
        }),
        // DiffuseAreaLight::Bounds: φ = π · area · scale · max L (or the
        // image's mean channel value; not doubled when two-sided: the
        // importance accounts for both sides), the shape's normal cone,
        // emission over the hemisphere.
        Light::DiffuseArea(l) => {
            let normals = normal_bounds(&l.shape, shapes);
            Some(LightBounds {
                bounds: l.shape.bounds(shapes),
                w: normals.w,
                phi: l.bounds_radiance() * l.scale * l.area * PI,
                cos_theta_o: normals.cos_theta,
                cos_theta_e: cos_half_pi(),
                two_sided: l.two_sided,
            })
        }
        Light::Distant(_)
        | Light::UniformInfinite(_)
        | Light::ImageInfinite(_)
        | Light::PortalInfinite(_) => None,
    }
}

/// The cone of a shape's geometric normals, oriented as its hits are
/// (pbrt-v4's `Shape::NormalBounds`).
pub fn normal_bounds(shape: &Shape, shapes: &ShapeStorage) -> DirectionCone {
    let face_forward = |n: Vec3, towards: Vec3| if n.dot(towards) < 0.0 { -n } else { n };
    match shape {
        Shape::Sphere(_) | Shape::Cylinder(_) | Shape::Curve(_) => DirectionCone::ENTIRE_SPHERE,
        // A disk's normal is the same everywhere; its samples carry it.
        Shape::Disk(_) => shape
            .sample_area(shapes, Vec2::splat(0.5))
            .map_or(DirectionCone::ENTIRE_SPHERE, |s| DirectionCone::of(s.n)),
        Shape::Triangle(t) => {
            let mesh = t.mesh_of(shapes);
            let v = mesh.triangle(t.index);
            let p = v.map(|i| mesh.positions[i]);
            let mut n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            if !mesh.normals.is_empty() {
                n = face_forward(n, v.iter().map(|&i| mesh.normals[i]).sum());
            } else if mesh.reverse_orientation ^ mesh.transform_swaps_handedness {
                n = -n;
            }
            DirectionCone::of(n)
        }
        Shape::BilinearPatch(b) => {
            let mesh = b.mesh_of(shapes);
            let v = mesh.patch(b.index);
            let [p00, p10, p01, p11] = v.map(|i| mesh.positions[i]);
            let flip = mesh.reverse_orientation ^ mesh.transform_swaps_handedness;
            let orient = |n: Vec3, vertex: usize| {
                if !mesh.normals.is_empty() {
                    face_forward(n, mesh.normals[v[vertex]])
                } else if flip {
                    -n
                } else {
                    n
                }
            };
            // A degenerate patch (a triangle) has one normal.
            if p00 == p10 || p10 == p11 || p11 == p01 || p01 == p00 {
                let dpdu = p10.lerp(p11, 0.5) - p00.lerp(p01, 0.5);
                let dpdv = p01.lerp(p11, 0.5) - p00.lerp(p10, 0.5);
                let mut n = dpdu.cross(dpdv).normalize_or_zero();
                if !mesh.normals.is_empty() {
                    n = face_forward(n, v.iter().map(|&i| mesh.normals[i]).sum());
                } else if flip {
                    n = -n;
                }
                return DirectionCone::of(n);
            }
            let n00 = orient((p10 - p00).cross(p01 - p00).normalize_or_zero(), 0);
            let n10 = orient((p11 - p10).cross(p00 - p10).normalize_or_zero(), 1);
            let n01 = orient((p00 - p01).cross(p11 - p01).normalize_or_zero(), 2);
            let n11 = orient((p01 - p11).cross(p10 - p11).normalize_or_zero(), 3);
            let n = (n00 + n10 + n01 + n11).normalize_or_zero();
            let cos_theta = n.dot(n00).min(n.dot(n01)).min(n.dot(n10)).min(n.dot(n11));
            DirectionCone {
                w: n,
                cos_theta: cos_theta.clamp(-1.0, 1.0),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_union_holds_both_cones() {
        let a = DirectionCone {
            w: Vec3::Z,
            cos_theta: 0.9,
        };
        let b = DirectionCone {
            w: Vec3::X,
            cos_theta: 0.95,
        };
        let u = a.union(b);
        for cone in [a, b] {
            // The cone's edge towards the other lies inside the union.
            let angle = safe_acos(cone.cos_theta);
            for k in 0..16 {
                let phi = k as f32 / 16.0 * 2.0 * PI;
                let frame = crate::math::Frame::from_z(cone.w);
                let d = frame.from_local(Vec3::new(
                    angle.sin() * phi.cos(),
                    angle.sin() * phi.sin(),
                    angle.cos(),
                ));
                assert!(d.dot(u.w) >= u.cos_theta - 1e-5);
            }
        }
        // Opposite single directions give the whole sphere.
        let opposite = DirectionCone::of(Vec3::Z).union(DirectionCone::of(-Vec3::Z));
        assert!(opposite.cos_theta <= -1.0 + 1e-6);
    }

    #[test]
    fn importance_is_zero_behind_a_one_sided_emitter() {
        let quad = LightBounds {
            bounds: Bounds3 {
                min: Vec3::new(-0.5, -0.5, 0.0),
                max: Vec3::new(0.5, 0.5, 0.0),
            },
            w: Vec3::Z,
            phi: 1.0,
            cos_theta_o: 1.0,
            cos_theta_e: cos_half_pi(),
            two_sided: false,
        };
        let above = quad.importance(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO);
        let below = quad.importance(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO);
        assert!(above > 0.0);
        assert_eq!(below, 0.0);
        let two_sided = LightBounds {
            two_sided: true,
            ..quad
        };
        assert!(two_sided.importance(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO) > 0.0);
        // Farther is less important; a surface facing away from the light
        // along its normal cone's edge still counts (bounded cosine).
        assert!(quad.importance(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO) < above);
    }
}
