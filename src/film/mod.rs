//! The film: pixel sums of filtered, sensor-converted radiance samples.

pub mod rgb;

pub use rgb::RgbFilm;
