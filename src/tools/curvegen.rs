//! Generated curve scenes for parser and build benchmarks: the form of the
//! 120 MB file `../shared/refs/README.md` measured pbrt-v4 on.

use std::fmt::Write;

/// A small deterministic generator (xorshift64*), so benchmark files are
/// the same on every machine.
struct Rng(u64);

impl Rng {
    fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

/// The scene header: 16 × 16 pixels, 1 spp, one hair material.
pub fn header() -> String {
    "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
     Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16 \"string filename\" \"curves.exr\"\n\
     Sampler \"zsobol\" \"integer pixelsamples\" 1\nWorldBegin\n\
     LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\nMaterial \"hair\"\n"
        .to_string()
}

/// `lines` cylinder curves with random control points (6 decimals) and
/// widths, one `Shape` per line, after [`header`].
pub fn curve_scene(lines: usize, seed: u64) -> String {
    let mut rng = Rng(seed.max(1));
    let mut out = header();
    out.reserve(lines * 200);
    for _ in 0..lines {
        out.push_str("Shape \"curve\" \"string type\" [ \"cylinder\" ] \"point3 P\" [");
        for _ in 0..12 {
            let _ = write!(out, " {:.6}", rng.range(-4.0, 4.0));
        }
        let _ = writeln!(out, " ] \"float width\" [ {:.6} ]", rng.range(0.005, 0.02));
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn generated_scenes_describe() {
        let text = super::curve_scene(100, 7);
        let loaded = crate::scene::load_text(std::path::Path::new("gen.pbrt"), &text).unwrap();
        assert_eq!(loaded.scene.shape_counts()["curve"], 100);
        assert!(
            text.len() / 100 > 180 && text.len() / 100 < 220,
            "{}",
            text.len() / 100
        );
    }
}
