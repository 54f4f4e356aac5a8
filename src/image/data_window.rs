//! Where a partial image's pixels lie in the full image.

/// A render of part of the film (`--pixelbounds`, `--cropwindow`) holds
/// only the rendered pixels; this records the full film resolution and the
/// position of the image's top-left pixel in it. OpenEXR stores it as the
/// data window inside the display window, as pbrt-v4 writes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DataWindow {
    /// Width and height of the whole image.
    pub full_resolution: (u32, u32),
    /// The partial image's top-left pixel in the whole image.
    pub origin: (i32, i32),
}

impl DataWindow {
    /// The window of a `width` × `height` image that is the whole image.
    pub fn whole(width: u32, height: u32) -> DataWindow {
        DataWindow {
            full_resolution: (width, height),
            origin: (0, 0),
        }
    }
}
