//! Geometry helpers on top of glam.

pub mod transform;

pub use transform::Transform;
