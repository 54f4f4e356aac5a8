//! Writes a generated curve scene: `gen_curves LINES OUT.pbrt`.
//! 606208 lines give the ~120 MB file of `../shared/refs/README.md`.

fn main() -> std::io::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let lines: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(606_208);
    let out = args.get(2).map_or("curves.pbrt", String::as_str);
    std::fs::write(out, rpbrt::tools::curvegen::curve_scene(lines, 1))?;
    eprintln!("wrote {out}: {lines} curves");
    Ok(())
}
