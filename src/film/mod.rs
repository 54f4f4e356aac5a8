//! The film: pixel sums of filtered, sensor-converted radiance samples.

pub mod rgb;
pub mod splat;

pub use rgb::RgbFilm;
