//! Integrators: radiance along camera rays.

mod diffraction_connection;
pub mod path;
pub mod ray_counts;
pub mod volpath;

pub use path::path_li;
pub use ray_counts::RayCounts;
pub use volpath::volpath_li;
