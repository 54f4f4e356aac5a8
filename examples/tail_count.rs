//! `tail_count SPP IMAGE OTHER...`: how heavy IMAGE's tail of bright
//! samples is, against the mean of the OTHER images as the reference
//! (`rpbrt::tools::imgdiff::bright_samples`), and IMAGE's MRSE against it.
fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 4 {
        eprintln!("usage: tail_count SPP IMAGE OTHER...");
        std::process::exit(2);
    }
    let spp: u32 = args[1].parse().expect("SPP");
    let image = rpbrt::image::Image::read(&args[2]).expect("IMAGE");
    let x = image.rgb_data();
    let mut reference = vec![0f32; x.len()];
    for file in &args[3..] {
        let other = rpbrt::image::Image::read(file).expect("OTHER");
        for (r, o) in reference.iter_mut().zip(other.rgb_data()) {
            *r += o / (args.len() - 3) as f32;
        }
    }
    let mut line = format!("MRSE {:.6} ", rpbrt::tools::imgdiff::mrse(&x, &reference));
    for s in [25.0, 50.0, 100.0, 200.0] {
        let count = rpbrt::tools::imgdiff::bright_samples(&x, &reference, spp, s);
        line += &format!(" S>{s}: {count}");
    }
    println!("{line}");
}
