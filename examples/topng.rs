//! `topng IN OUT.png [SCALE]`: writes an image as sRGB PNG, scaled.
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let image = rpbrt::image::Image::read(&args[1]).unwrap_or_else(|e| panic!("{e}"));
    let scale: f32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let data: Vec<f32> = image.rgb_data().iter().map(|v| v * scale).collect();
    rpbrt::image::Image::from_rgb(image.width(), image.height(), data)
        .unwrap()
        .write(&args[2])
        .unwrap();
}
