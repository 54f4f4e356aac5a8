//! Clarberg's equal-area octahedral mapping between the unit square and the
//! unit sphere, as pbrt-v4 uses it to store environment maps (`infinite`
//! lights with an image are square images in this parameterisation).
//!
//! The square [0, 1]² is centred on +z; its four corners all map to −z; the
//! edge midpoints (1, ½), (½, 1), (0, ½), (½, 0) map to +x, +y, −x, −y. Every
//! region of the square covers a part of the sphere 4π times its area, so
//! uniform texels are uniform solid angles and sampling needs no Jacobian
//! beyond the constant 1/(4π).
//!
//! In signed coordinates (u, v) ∈ [−1, 1]², the square's inner diamond
//! |u| + |v| ≤ 1 is the upper hemisphere and the four outer triangles fold
//! over onto the lower one. With r = 1 − |1 − |u| − |v||, the polar angle
//! satisfies 1 − |z| = r² and the azimuth within a quadrant is
//! φ = (π/4)·((|v| − |u|)/r + 1).

use glam::{IVec2, Vec2, Vec3};
use std::f32::consts::FRAC_PI_2;

/// A point of [0, 1]² → the unit direction it stands for.
pub fn equal_area_square_to_sphere(p: Vec2) -> Vec3 {
    debug_assert!(
        (0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y),
        "equal-area square point {p} outside [0,1]²"
    );
    let u = 2.0 * p.x - 1.0;
    let v = 2.0 * p.y - 1.0;
    let abs_u = u.abs();
    let abs_v = v.abs();

    // Signed distance from the diamond's edge: positive inside (upper
    // hemisphere), negative in the folded corners (lower hemisphere).
    let signed_distance = 1.0 - (abs_u + abs_v);
    let r = 1.0 - signed_distance.abs();

    // Azimuth in units of π/2 within the first quadrant; r = 0 is a pole,
    // where any azimuth will do.
    let azimuth_quarters = if r == 0.0 {
        1.0
    } else {
        (abs_v - abs_u) / r + 1.0
    };
    let azimuth = azimuth_quarters * (FRAC_PI_2 / 2.0);

    let z = (1.0 - r * r).copysign(signed_distance);
    // sinθ = sqrt(1 − z²) with 1 − |z| = r², written to keep precision.
    let sin_theta = r * (2.0 - r * r).max(0.0).sqrt();
    let cos_phi = azimuth.cos().copysign(u);
    let sin_phi = azimuth.sin().copysign(v);
    Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, z)
}

/// A unit direction → its point of [0, 1]² (inverse of
/// [`equal_area_square_to_sphere`]). pbrt-v4 evaluates the arctangent with a
/// polynomial; this uses the exact one (they agree to about 1e-6).
pub fn equal_area_sphere_to_square(d: Vec3) -> Vec2 {
    debug_assert!(
        (d.length_squared() - 1.0).abs() < 1e-3,
        "equal-area mapping of a non-unit direction {d}"
    );
    let x = d.x.abs();
    let y = d.y.abs();
    let z = d.z.abs();

    let r = (1.0 - z).max(0.0).sqrt();

    // Azimuth within the first octant, as a fraction of π/2, measured from
    // the larger of x and y so the arctangent argument stays in [0, 1].
    let larger = x.max(y);
    let ratio = if larger == 0.0 {
        0.0
    } else {
        x.min(y) / larger
    };
    let mut azimuth_fraction = ratio.atan() / FRAC_PI_2;
    if x < y {
        azimuth_fraction = 1.0 - azimuth_fraction;
    }

    let mut v = azimuth_fraction * r;
    let mut u = r - v;
    if d.z < 0.0 {
        // Lower hemisphere: reflect into the outer triangle of this quadrant.
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    u = u.copysign(d.x);
    v = v.copysign(d.y);
    Vec2::new(0.5 * (u + 1.0), 0.5 * (v + 1.0))
}

/// Brings a point just outside [0, 1]² back inside the way the octahedral
/// parameterisation is glued: crossing a side of the square continues on the
/// same side, mirrored about that side's midpoint (the sphere folds there).
/// Valid within one square-width of the edges.
pub fn wrap_equal_area_square_point(mut uv: Vec2) -> Vec2 {
    if uv.x < 0.0 {
        uv = Vec2::new(-uv.x, 1.0 - uv.y);
    } else if uv.x > 1.0 {
        uv = Vec2::new(2.0 - uv.x, 1.0 - uv.y);
    }
    if uv.y < 0.0 {
        uv = Vec2::new(1.0 - uv.x, -uv.y);
    } else if uv.y > 1.0 {
        uv = Vec2::new(1.0 - uv.x, 2.0 - uv.y);
    }
    uv
}

/// The texel that pixel `p` (possibly outside the image) stands for in an
/// equal-area image of `resolution`: the pixel-grid form of
/// [`wrap_equal_area_square_point`]. This is how pbrt-v4 looks up texels
/// past the edge of an environment map when filtering, and its rule is kept
/// exactly: past the right and bottom sides pixel centres map to pixel
/// centres, but past the left and top sides pixel −k maps to k rather than
/// k − 1 (mirrored about the centre of pixel 0, not about the edge), one
/// texel from the exact glueing. Valid within one image-width of the edges;
/// the result is always clamped into the image so it can index it.
pub fn wrap_equal_area_square(p: IVec2, resolution: IVec2) -> IVec2 {
    let resolution = resolution.max(IVec2::ONE);
    let (width, height) = (resolution.x, resolution.y);
    // Beyond one image-width the rule means nothing; pinning the input to
    // that band keeps the arithmetic below from overflowing.
    let mut p = IVec2::new(
        p.x.clamp(-width, width.saturating_mul(2) - 1),
        p.y.clamp(-height, height.saturating_mul(2) - 1),
    );
    if p.x < 0 {
        p = IVec2::new(-p.x, height - 1 - p.y);
    } else if p.x >= width {
        p = IVec2::new(2 * width - 1 - p.x, height - 1 - p.y);
    }
    if p.y < 0 {
        p = IVec2::new(width - 1 - p.x, -p.y);
    } else if p.y >= height {
        p = IVec2::new(width - 1 - p.x, 2 * height - 1 - p.y);
    }
    // A single row or column mirrors onto itself; pbrt-v4 pins it to 0.
    if width == 1 {
        p.x = 0;
    }
    if height == 1 {
        p.y = 0;
    }
    p.clamp(IVec2::ZERO, resolution - IVec2::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    /// A small deterministic generator (SplitMix64) for test samples.
    struct TestRandom(u64);

    impl TestRandom {
        fn next_f32(&mut self) -> f32 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 40) as f32 / (1u64 << 24) as f32
        }

        fn direction(&mut self) -> Vec3 {
            let z = 1.0 - 2.0 * self.next_f32();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * PI * self.next_f32();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        }
    }

    #[test]
    fn axis_conventions_match_pbrt() {
        let cases = [
            (Vec2::new(0.5, 0.5), Vec3::Z),
            (Vec2::new(1.0, 0.5), Vec3::X),
            (Vec2::new(0.5, 1.0), Vec3::Y),
            (Vec2::new(0.0, 0.5), -Vec3::X),
            (Vec2::new(0.5, 0.0), -Vec3::Y),
            (Vec2::new(0.0, 0.0), -Vec3::Z),
            (Vec2::new(1.0, 1.0), -Vec3::Z),
        ];
        for (square, direction) in cases {
            let mapped = equal_area_square_to_sphere(square);
            assert!((mapped - direction).length() < 1e-6, "{square} → {mapped}");
        }
        // The first quadrant of the square is the +x/+y quadrant of the sphere.
        let d = equal_area_square_to_sphere(Vec2::new(0.7, 0.6));
        assert!(d.x > 0.0 && d.y > 0.0 && d.z > 0.0);
    }

    #[test]
    fn sphere_to_square_to_sphere_round_trips() {
        let mut random = TestRandom(7);
        let mut worst = 0.0f32;
        for _ in 0..100_000 {
            let d = random.direction();
            let p = equal_area_sphere_to_square(d);
            assert!((0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y));
            let back = equal_area_square_to_sphere(p);
            worst = worst.max((back - d).length());
        }
        assert!(worst < 1e-5, "worst round-trip error {worst}");
        // The poles and the equator's axis points too.
        for d in [Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y] {
            let back = equal_area_square_to_sphere(equal_area_sphere_to_square(d));
            assert!((back - d).length() < 1e-6, "{d} → {back}");
        }
    }

    #[test]
    fn square_to_sphere_gives_unit_vectors_and_inverts() {
        let mut random = TestRandom(11);
        for _ in 0..20_000 {
            let p = Vec2::new(random.next_f32(), random.next_f32());
            let d = equal_area_square_to_sphere(p);
            assert!((d.length() - 1.0).abs() < 1e-5);
            let back = equal_area_sphere_to_square(d);
            assert!((back - p).length() < 1e-4, "{p} → {d} → {back}");
        }
    }

    /// The local area scale |∂d/∂u × ∂d/∂v| must be 4π everywhere (the
    /// square has area 1, the sphere 4π).
    #[test]
    fn jacobian_is_constant() {
        let step = 1e-3f32;
        let cells = 97; // odd, so no sample sits on the folds at u or v = ½
        for i in 0..cells {
            for j in 0..cells {
                let p = Vec2::new(
                    (i as f32 + 0.5) / cells as f32 * 0.98 + 0.01,
                    (j as f32 + 0.5) / cells as f32 * 0.98 + 0.01,
                );
                // Stay off the diamond edge |u|+|v| = 1, where the map folds.
                let (u, v) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
                if ((u.abs() + v.abs()) - 1.0).abs() < 4.0 * step {
                    continue;
                }
                if u.abs() < 4.0 * step || v.abs() < 4.0 * step {
                    continue;
                }
                let du = (equal_area_square_to_sphere(p + Vec2::new(step, 0.0))
                    - equal_area_square_to_sphere(p - Vec2::new(step, 0.0)))
                    / (2.0 * step);
                let dv = (equal_area_square_to_sphere(p + Vec2::new(0.0, step))
                    - equal_area_square_to_sphere(p - Vec2::new(0.0, step)))
                    / (2.0 * step);
                let scale = du.cross(dv).length();
                assert!((scale / (4.0 * PI) - 1.0).abs() < 0.01, "at {p}: {scale}");
            }
        }
    }

    /// Uniform points of the square must land uniformly on the sphere:
    /// z uniform in [−1, 1] and azimuth uniform in [0, 2π) (Archimedes).
    #[test]
    fn uniform_square_samples_are_uniform_on_the_sphere() {
        const SAMPLES: usize = 200_000;
        const BINS: usize = 20;
        let mut random = TestRandom(3);
        let mut z_histogram = [0usize; BINS];
        let mut azimuth_histogram = [0usize; BINS];
        for _ in 0..SAMPLES {
            let d = equal_area_square_to_sphere(Vec2::new(random.next_f32(), random.next_f32()));
            let z_bin = (((d.z + 1.0) * 0.5 * BINS as f32) as usize).min(BINS - 1);
            z_histogram[z_bin] += 1;
            let azimuth = d.y.atan2(d.x).rem_euclid(2.0 * PI);
            let azimuth_bin = ((azimuth / (2.0 * PI) * BINS as f32) as usize).min(BINS - 1);
            azimuth_histogram[azimuth_bin] += 1;
        }
        let expected = (SAMPLES / BINS) as f64;
        let chi_square = |histogram: &[usize; BINS]| -> f64 {
            histogram
                .iter()
                .map(|&n| (n as f64 - expected).powi(2) / expected)
                .sum()
        };
        // 19 degrees of freedom: the 99.9th percentile is 43.8.
        let z_statistic = chi_square(&z_histogram);
        let azimuth_statistic = chi_square(&azimuth_histogram);
        assert!(
            z_statistic < 43.8,
            "z histogram {z_histogram:?}, χ² = {z_statistic}"
        );
        assert!(
            azimuth_statistic < 43.8,
            "azimuth histogram {azimuth_histogram:?}, χ² = {azimuth_statistic}"
        );
    }

    /// Crossing a side of the square must land on the sphere next to where
    /// the point was: the two sides of each glued edge map to one great arc.
    #[test]
    fn wrap_glues_edges_consistently_with_the_mapping() {
        for i in 0..=64 {
            let t = i as f32 / 64.0;
            for (edge, glued) in [
                (Vec2::new(0.0, t), Vec2::new(0.0, 1.0 - t)),
                (Vec2::new(1.0, t), Vec2::new(1.0, 1.0 - t)),
                (Vec2::new(t, 0.0), Vec2::new(1.0 - t, 0.0)),
                (Vec2::new(t, 1.0), Vec2::new(1.0 - t, 1.0)),
            ] {
                let a = equal_area_square_to_sphere(edge);
                let b = equal_area_square_to_sphere(glued);
                assert!((a - b).length() < 1e-5, "{edge} and {glued}: {a} vs {b}");
            }
        }
        // A point slightly outside maps (after wrapping) close to its
        // nearest edge point, as continuity across the seam requires.
        let epsilon = 1e-3;
        for i in 1..64 {
            let t = i as f32 / 64.0;
            for (outside, edge) in [
                (Vec2::new(-epsilon, t), Vec2::new(0.0, t)),
                (Vec2::new(1.0 + epsilon, t), Vec2::new(1.0, t)),
                (Vec2::new(t, -epsilon), Vec2::new(t, 0.0)),
                (Vec2::new(t, 1.0 + epsilon), Vec2::new(t, 1.0)),
            ] {
                let wrapped = wrap_equal_area_square_point(outside);
                assert!((0.0..=1.0).contains(&wrapped.x) && (0.0..=1.0).contains(&wrapped.y));
                let distance = (equal_area_square_to_sphere(wrapped)
                    - equal_area_square_to_sphere(edge))
                .length();
                assert!(distance < 0.02, "{outside} → {wrapped}: {distance}");
            }
        }
    }

    /// The pixel wrap agrees with the continuous wrap at pixel centres past
    /// the high sides; past the low sides it lands one texel further in, as
    /// pbrt-v4's rule does (see [`wrap_equal_area_square`]).
    #[test]
    fn pixel_wrap_matches_continuous_wrap() {
        for resolution in [IVec2::new(8, 8), IVec2::new(5, 7)] {
            let size = resolution.as_vec2();
            for y in -1..=resolution.y {
                for x in -1..=resolution.x {
                    let p = IVec2::new(x, y);
                    let wrapped = wrap_equal_area_square(p, resolution);
                    assert!(wrapped.cmpge(IVec2::ZERO).all() && wrapped.cmplt(resolution).all());
                    let x_inside = (0..resolution.x).contains(&x);
                    let y_inside = (0..resolution.y).contains(&y);
                    if x_inside && y_inside {
                        assert_eq!(wrapped, p);
                        continue;
                    }
                    if !x_inside && !y_inside {
                        continue; // corners: only required to stay inside
                    }
                    let centre = (p.as_vec2() + Vec2::splat(0.5)) / size;
                    let exact = (wrap_equal_area_square_point(centre) * size)
                        .floor()
                        .as_ivec2();
                    let expected = match (x, y) {
                        (-1, _) => exact + IVec2::X,
                        (_, -1) => exact + IVec2::Y,
                        _ => exact,
                    };
                    assert_eq!(wrapped, expected, "{p} at {resolution}");
                }
            }
        }
        assert_eq!(
            wrap_equal_area_square(IVec2::new(-1, 3), IVec2::new(1, 4)),
            IVec2::new(0, 0)
        );
    }
}
