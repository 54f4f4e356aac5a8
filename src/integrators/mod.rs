//! Integrators: radiance along camera rays.

mod diffraction_connection;
pub mod path;

pub use path::{path_li, RayCounts};
