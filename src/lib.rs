//! rpbrt: a renderer for pbrt-v4 scenes, built for hair.
//!
//! Data flows one way: scene text → directives (the `pbrt-parser` crate) →
//! scene description ([`scene`]) → built scene → integrator → film → image.
//! See `docs/architecture.md`.

pub mod error;
pub mod filters;
pub mod interaction;
pub mod math;
pub mod samplers;
pub mod scene;
pub mod spectrum;
pub mod tools;

pub use error::{Error, Result};
