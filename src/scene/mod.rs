//! From directives to a scene description (the builder) and from a scene
//! description to a built scene (`build`): the layer above the families,
//! which it creates. The description itself, its parameters and their
//! schema are the layer below them, in `crate::scene_description`.

pub mod alpha;
pub mod build;
pub mod builder;
pub mod deviations;
pub mod instancing;
pub mod placed_shapes;
pub mod primitive;

pub use builder::{describe, load, load_fragment, load_text, Loaded, SceneBuilder};
