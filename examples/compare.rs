//! `compare IMAGE REFERENCE`: MRSE and 16×16 block bias (../shared/refs/README.md).
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(a), Some(b)) = (args.get(1), args.get(2)) else {
        eprintln!("usage: compare IMAGE REFERENCE");
        std::process::exit(2);
    };
    let image = rpbrt::image::Image::read(a).unwrap_or_else(|e| panic!("{e}"));
    let reference = rpbrt::image::Image::read(b).unwrap_or_else(|e| panic!("{e}"));
    let (x, r) = (image.rgb_data(), reference.rgb_data());
    let (w, h) = (reference.width() as usize, reference.height() as usize);
    let mean = |v: &[f32]| v.iter().map(|&x| x as f64).sum::<f64>() / v.len() as f64;
    println!(
        "MRSE {:.5}  block bias {:.4}  mean {:.4} vs {:.4}",
        rpbrt::tools::imgdiff::mrse(&x, &r),
        rpbrt::tools::imgdiff::block_bias(&x, &r, w, h, 3, 16),
        mean(&x),
        mean(&r)
    );
}
