//! Geometry helpers on top of glam. Rendering works in f32 (as pbrt does);
//! the scene description keeps f64 transforms.

pub mod bounds;
pub mod equal_area;
pub mod exp4;
pub mod fast_atan2;
pub mod frame;
pub mod hash;
pub mod motion_transform;
pub mod pcg32;
pub mod ray;
pub mod sampling;
pub mod transform;

pub use bounds::Bounds3;
pub use frame::Frame;
pub use motion_transform::MotionTransform;
pub use ray::{offset_ray_origin, Ray};
pub use transform::Transform;

/// The largest f32 below 1 (pbrt-v4's `OneMinusEpsilon`): sample values
/// are clamped to it so they stay in [0, 1).
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Clamped square root (0 for the small negative values rounding gives).
#[inline]
pub fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// acos with its argument clamped to [−1, 1].
#[inline]
pub fn safe_acos(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).acos()
}

/// asin with its argument clamped to [−1, 1].
#[inline]
pub fn safe_asin(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).asin()
}

#[inline]
pub fn lerp(t: f32, a: f32, b: f32) -> f32 {
    (1.0 - t) * a + t * b
}

#[inline]
pub fn sqr(x: f32) -> f32 {
    x * x
}
