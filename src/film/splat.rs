//! The film's splat buffer (pbrt-v4's `AddSplat`): light that integrators
//! tracing from the lights deposit at whatever raster point their paths
//! reach the camera, spread over the pixels the filter covers, and added
//! to the final image divided by the samples per pixel and the filter's
//! integral.
//!
//! Sums are kept in 32.32 fixed point in atomic integers: integer
//! addition does not depend on order, so the image is the same at any
//! thread count (floating-point atomics would not be).

use crate::filters::Filter;
use glam::{IVec2, Vec2, Vec3};
use std::sync::atomic::{AtomicI64, Ordering};

/// One unit in the fixed-point sums.
const ONE: f64 = (1u64 << 32) as f64;
/// The largest value one splat adds to a channel (beyond it a channel's
/// sum could overflow).
const MAX_SPLAT: f32 = 1e6;

pub struct SplatBuffer {
    /// The pixels kept: [min, max) in x and y.
    bounds: (IVec2, IVec2),
    sums: Vec<[AtomicI64; 3]>,
}

impl SplatBuffer {
    /// An empty buffer over `bounds`.
    pub fn new(bounds: (IVec2, IVec2)) -> Self {
        let size = (bounds.1 - bounds.0).max(IVec2::ZERO);
        let sums = (0..size.x * size.y)
            .map(|_| [AtomicI64::new(0), AtomicI64::new(0), AtomicI64::new(0)])
            .collect();
        SplatBuffer { bounds, sums }
    }

    /// Adds sensor RGB `rgb` arriving at raster point `p`, weighted by the
    /// filter at each pixel centre within its reach. Non-finite or
    /// negative values are dropped.
    pub fn add(&self, p: Vec2, rgb: Vec3, filter: &Filter) {
        if !rgb.is_finite() || rgb.min_element() < 0.0 || !p.is_finite() {
            return;
        }
        let rgb = rgb.min(Vec3::splat(MAX_SPLAT));
        let radius = filter.radius();
        let centre = p + Vec2::splat(0.5);
        let lo = (centre - radius).floor().as_ivec2().max(self.bounds.0);
        let hi = ((centre + radius).floor().as_ivec2() + IVec2::ONE).min(self.bounds.1);
        let width = self.bounds.1.x - self.bounds.0.x;
        for y in lo.y..hi.y {
            for x in lo.x..hi.x {
                let offset = p - Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let w = filter.evaluate(offset);
                if w == 0.0 {
                    continue;
                }
                let i = ((y - self.bounds.0.y) * width + (x - self.bounds.0.x)) as usize;
                for (c, sum) in self.sums[i].iter().enumerate() {
                    let v = (w as f64 * rgb[c] as f64 * ONE).round() as i64;
                    sum.fetch_add(v, Ordering::Relaxed);
                }
            }
        }
    }

    /// The sum of the splats at the `index`-th pixel (row-major over the
    /// bounds).
    pub fn sum(&self, index: usize) -> Vec3 {
        let s = &self.sums[index];
        let get = |a: &AtomicI64| (a.load(Ordering::Relaxed) as f64 / ONE) as f32;
        Vec3::new(get(&s[0]), get(&s[1]), get(&s[2]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load_text;
    use std::path::Path;

    fn filter(text: &str) -> Filter {
        let loaded = load_text(Path::new("f.pbrt"), &format!("{text}\nWorldBegin")).unwrap();
        Filter::create(&loaded.scene.filter).unwrap()
    }

    /// Splats at points spread over the film add up to the filter's
    /// integral times what was splatted (far from the edges; the filter is
    /// summed at pixel centres, a Riemann sum of its integral: within 1%
    /// over these offsets), and give the same sums in any order.
    #[test]
    fn splats_spread_by_the_filter_and_add_in_any_order() {
        let f = filter("PixelFilter \"gaussian\" \"float xradius\" 1.5 \"float yradius\" 1.5");
        let forwards = SplatBuffer::new((IVec2::ZERO, IVec2::new(20, 20)));
        let backwards = SplatBuffer::new((IVec2::ZERO, IVec2::new(20, 20)));
        let points: Vec<Vec2> = (0..100)
            .map(|i| Vec2::new(6.0 + (i % 10) as f32 * 0.8, 6.0 + (i / 10) as f32 * 0.77))
            .collect();
        let rgb = Vec3::new(1.0, 0.5, 0.25);
        for p in &points {
            forwards.add(*p, rgb, &f);
        }
        for p in points.iter().rev() {
            backwards.add(*p, rgb * 1.0, &f);
        }
        let mut total = Vec3::ZERO;
        for i in 0..400 {
            assert_eq!(forwards.sum(i), backwards.sum(i));
            total += forwards.sum(i);
        }
        let want = rgb * (100.0 * f.integral());
        assert!(
            (total / want - Vec3::ONE).abs().max_element() < 0.01,
            "{total} {want}"
        );
        // Nothing non-finite or negative gets in.
        forwards.add(Vec2::splat(10.0), Vec3::new(f32::NAN, 1.0, 1.0), &f);
        forwards.add(Vec2::splat(10.0), Vec3::new(-1.0, 1.0, 1.0), &f);
        assert_eq!(forwards.sum(210), backwards.sum(210));
    }
}
