//! rpbrt: a renderer for pbrt-v4 scenes, built for hair.
//!
//! Data flows one way: scene text → directives (the `pbrt-parser` crate) →
//! scene description ([`scene_description`], written by [`scene`]'s builder)
//! → built scene ([`scene`]'s build) → integrator → film → image.
//! See `docs/architecture.md`.

pub mod accel;
pub mod bxdfs;
pub mod cameras;
pub mod error;
pub mod film;
pub mod filters;
pub mod image;
pub mod integrators;
pub mod interaction;
pub mod lights;
pub mod materials;
pub mod math;
pub mod media;
pub mod memory;
pub mod pipeline;
pub mod render;
pub mod samplers;
pub mod scene;
pub mod scene_description;
pub mod shapes;
pub mod spectrum;
pub mod textures;
pub mod tools;

pub use error::{Error, Result};
