//! Images: reading and writing files (EXR, PFM, PNG; TGA and JPEG for
//! reading), colour encodings, and MIP maps for image textures, all
//! following pbrt-v4's behaviour.
//!
//! An [`Image`] holds `f32` samples, interleaved, row-major, top row first,
//! together with how they are encoded ([`ColorEncoding`]) and the precision
//! the file stored them at ([`PixelFormat`]). Files are user input: every
//! failure is an [`ImageError`] naming the file and what is wrong. Writes are
//! atomic (temporary file, then rename) and refuse NaN and infinite values.

mod atomic_write;
pub mod color_encoding;
mod data_window;
mod ewa_weights;
mod exr_file;
mod file_io;
mod image_buffer;
pub mod mipmap;
mod pfm_file;
pub mod pixel_format;
mod png_tga_jpeg_file;
mod pyramid;
mod resample;
mod rgb;
pub mod wrap_mode;

pub use color_encoding::ColorEncoding;
pub use data_window::DataWindow;
pub use image_buffer::{Image, NonFiniteSample};
pub use mipmap::{FilterFunction, MIPMap};
pub use pixel_format::PixelFormat;
pub use wrap_mode::WrapMode;

use std::path::PathBuf;

/// Everything that can go wrong reading, writing or building images.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The operating system refused (missing file, permissions, disk full).
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file's extension names no format rpbrt reads or writes.
    #[error("{}: unsupported image file extension (supported: {supported})", path.display())]
    UnsupportedExtension {
        path: PathBuf,
        supported: &'static str,
    },
    /// The file's contents are not a valid image of its format.
    #[error("{}: {message}", path.display())]
    Malformed { path: PathBuf, message: String },
    /// The image cannot be written in the requested format.
    #[error("{}: cannot write image: {message}", path.display())]
    Unwritable { path: PathBuf, message: String },
    /// Writing would store a NaN or infinite value.
    #[error(
        "{}: refusing to write non-finite value {} at pixel ({}, {}) channel {}",
        path.display(), sample.value, sample.x, sample.y, sample.channel
    )]
    NonFinite {
        path: PathBuf,
        sample: NonFiniteSample,
    },
    /// An image built in memory is inconsistent (size, channels, data).
    #[error("invalid image: {0}")]
    Invalid(String),
    /// An image with these channels cannot be used as a texture.
    #[error("an image texture needs R, G and B channels or a single channel; this one has {0:?}")]
    TextureChannels(Vec<String>),
}
