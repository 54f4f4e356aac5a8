//! Acceleration structures.

pub mod bvh;
pub mod instance;
pub mod prefetch;

pub use bvh::Bvh;
pub use prefetch::prefetch;
