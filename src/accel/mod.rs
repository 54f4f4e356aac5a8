//! Acceleration structures.

pub mod bvh;
pub mod instance;

pub use bvh::Bvh;
