//! The image readers used for textures and environment maps
//! (`rpbrt::image::Image::read_from_bytes`, the code `Image::read` runs on
//! a file). The first byte picks the format (EXR, PFM, PNG, TGA, JPEG) and
//! the rest is the file; each either gives an image or an error, never a
//! panic, a hang or an unbounded allocation. An image read is converted to
//! linear (what textures do first).
#![no_main]

use libfuzzer_sys::fuzz_target;
use rpbrt::image::Image;

const NAMES: [&str; 5] = ["f.exr", "f.pfm", "f.png", "f.tga", "f.jpg"];

fuzz_target!(|data: &[u8]| {
    let Some((&which, bytes)) = data.split_first() else {
        return;
    };
    let name = NAMES[which as usize % NAMES.len()];
    match Image::read_from_bytes(bytes, name) {
        Ok(image) => {
            let _ = image.to_linear();
        }
        Err(e) => {
            let _ = e.to_string();
        }
    }
});
