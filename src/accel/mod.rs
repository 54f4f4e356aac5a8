//! Acceleration structures.

pub mod bvh;
pub mod instance;
pub mod parallel_build;
pub mod prefetch;

pub use bvh::Bvh;
pub use prefetch::prefetch;
