//! rpbrt: a renderer for pbrt-v4 scenes, built for hair.
//!
//! Data flows one way: scene text → directives (the `pbrt-parser` crate) →
//! scene description ([`scene`]) → built scene → integrator → film → image.
//! See `docs/architecture.md`.

pub mod accel;
pub mod bxdfs;
pub mod cameras;
pub mod error;
pub mod image;
pub mod interaction;
pub mod math;
// pending merge: pub mod film;
// pending merge: pub mod integrators;
// pending merge: pub mod lights;
// pending merge: pub mod materials;
// pending merge: pub mod pipeline;
// pending merge: pub mod render;
pub mod samplers;
pub mod scene;
pub mod shapes;
// pending merge: pub mod textures;
pub mod spectrum;
pub mod tools;

pub use error::{Error, Result};
