//! Scattering functions (BxDFs) with pbrt-v4's semantics, and the BSDF that
//! places one in a surface's shading frame.
//!
//! All BxDF methods work in the local shading frame (z is the shading
//! normal) with ωo and ωi both pointing away from the surface. The family
//! is a closed enum dispatched by `match`, so a BxDF is created per
//! intersection by value, with no heap allocation.

mod bsdf_sample;
mod flags;
pub mod fresnel;
pub mod geometry;
mod transport_mode;

pub use bsdf_sample::BSDFSample;
pub use flags::{BxDFFlags, BxDFReflTransFlags};
pub use transport_mode::TransportMode;
