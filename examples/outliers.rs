//! `outliers IMAGE REFERENCE [N]`: the N pixels contributing most to MRSE.
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let image = rpbrt::image::Image::read(&args[1]).unwrap();
    let reference = rpbrt::image::Image::read(&args[2]).unwrap();
    let n: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(10);
    let (x, r) = (image.rgb_data(), reference.rgb_data());
    let w = reference.width() as usize;
    let mut e: Vec<(f64, usize)> = (0..x.len() / 3)
        .map(|p| {
            let s: f64 = (0..3)
                .map(|c| {
                    let (a, b) = (x[3 * p + c] as f64, r[3 * p + c] as f64);
                    (a - b) * (a - b) / (b * b + 0.01)
                })
                .sum();
            (s, p)
        })
        .collect();
    let total: f64 = e.iter().map(|v| v.0).sum();
    e.sort_by(|a, b| b.0.total_cmp(&a.0));
    println!("total {total:.4}");
    for (s, p) in e.iter().take(n) {
        println!(
            "({}, {}): {:.4} ({:.1}%) value {:?} ref {:?}",
            p % w,
            p / w,
            s,
            100.0 * s / total,
            &x[3 * p..3 * p + 3],
            &r[3 * p..3 * p + 3]
        );
    }
}
