//! Integrators: radiance along camera rays.

pub mod path;

pub use path::{path_li, RayCounts};
