//! From directives to a scene description: the graphics state, named
//! things, instancing, and typed parameter lookups.

pub mod alpha;
pub mod build;
pub mod builder;
pub mod description;
pub mod deviations;
pub mod instancing;
pub mod params;
pub mod placed_shapes;
pub mod schema;
pub mod spectrum_param;

pub use builder::{describe, load, load_fragment, load_text, Loaded, SceneBuilder};
pub use description::SceneDescription;
pub use params::ParamSet;
