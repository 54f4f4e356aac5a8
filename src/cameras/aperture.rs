//! The shape of the realistic camera's aperture stop (pbrt-v4's
//! `aperture` parameter): a grey-level mask over the stop's bounding
//! square that weighs each ray crossing the stop, instead of the plain
//! circular opening.
//!
//! | `aperture` | meaning |
//! |---|---|
//! | (absent) | the circular stop of the lens file, no mask |
//! | `gaussian` | exp(−r²) − exp(−1), r the distance from the centre over the stop radius; 0 beyond r = 1 |
//! | `square` | the middle half of the square in each direction |
//! | `pentagon` | a regular pentagon (0.8 of the stop radius to its corners) |
//! | `star` | a five-pointed star |
//! | any other string | an image file (resolved against the scene's directory); several channels are averaged over R, G, B |
//!
//! The built-in shapes are drawn on 256 × 256 texels. Every mask is then
//! turned upside down (image rows run down, the stop's y up) and scaled so
//! that its mean is π/4, the fraction of the square a circle of the stop's
//! radius covers: a mask passes as much light as the circular opening.

use crate::error::{image_file_error, scene_error, Result};
use crate::image::Image;
use glam::Vec2;
use pbrt_parser::Location;
use std::f32::consts::PI;
use std::path::Path;

/// Texels across a built-in shape.
const BUILTIN_RESOLUTION: usize = 256;

#[derive(Clone, Debug, PartialEq)]
pub struct ApertureMask {
    width: usize,
    height: usize,
    /// Row-major, row 0 at the stop's −y edge.
    values: Vec<f32>,
}

impl ApertureMask {
    /// The mask named by the `aperture` parameter (see the module
    /// documentation); `base_directory` resolves image file names and
    /// `location` (the parameter) locates errors.
    pub fn create(name: &str, base_directory: &Path, location: &Location) -> Result<Self> {
        let n = BUILTIN_RESOLUTION;
        let (width, height, values) = match name {
            "gaussian" => (
                n,
                n,
                texel_centres(n)
                    .map(|p| ((-p.length_squared()).exp() - (-1.0f32).exp()).max(0.0))
                    .collect(),
            ),
            "square" => (
                n,
                n,
                (0..n * n)
                    .map(|i| {
                        let (x, y) = (i % n, i / n);
                        let inside = |c: usize| c >= n / 4 && c < 3 * n / 4;
                        if inside(x) && inside(y) {
                            1.0
                        } else {
                            0.0
                        }
                    })
                    .collect(),
            ),
            "pentagon" => {
                // Corners clockwise from the top, at 0.8 of the radius.
                let corners: Vec<Vec2> = (0..5)
                    .map(|i| {
                        let angle = PI / 2.0 - 2.0 * PI * i as f32 / 5.0;
                        0.8 * Vec2::new(angle.cos(), angle.sin())
                    })
                    .collect();
                (n, n, rasterize_polygon(&corners, n))
            }
            "star" => {
                // Ten corners alternating between the outer radius 1 and
                // the inner radius at which the star's edges line up.
                let inner = 72f32.to_radians().cos() / 36f32.to_radians().cos();
                let corners: Vec<Vec2> = (0..10)
                    .rev()
                    .map(|i| {
                        let r = if i % 2 == 1 { 1.0 } else { inner };
                        let angle = PI * i as f32 / 5.0;
                        r * Vec2::new(angle.cos(), angle.sin())
                    })
                    .collect();
                (n, n, rasterize_polygon(&corners, n))
            }
            file => {
                let path = pbrt_parser::resolve_path(base_directory, file);
                let image = Image::read(&path)
                    .map_err(|e| image_file_error("camera \"aperture\" image", e, location))?
                    .to_linear();
                let (width, height) = (image.width() as usize, image.height() as usize);
                let channels: Vec<usize> = if image.channel_count() == 1 {
                    vec![0]
                } else {
                    match ["R", "G", "B"].map(|c| image.channel_index(c)) {
                        [Some(r), Some(g), Some(b)] => vec![r, g, b],
                        _ => {
                            return scene_error(
                                format!(
                                    "camera \"aperture\" image \"{}\" has neither one channel nor R, G and B",
                                    path.display()
                                ),
                                location,
                            )
                        }
                    }
                };
                let values = (0..height)
                    .flat_map(|y| (0..width).map(move |x| (x, y)))
                    .map(|(x, y)| {
                        let pixel = image.pixel(x as u32, y as u32);
                        channels.iter().map(|&c| pixel[c]).sum::<f32>() / channels.len() as f32
                    })
                    .collect();
                (width, height, values)
            }
        };
        let mut mask = ApertureMask {
            width,
            height,
            values,
        };
        mask.flip_rows();
        let mean =
            mask.values.iter().map(|&v| v as f64).sum::<f64>() / mask.values.len().max(1) as f64;
        if !(mean > 0.0 && mean.is_finite()) {
            return scene_error(
                format!(
                    "camera \"aperture\" \"{name}\" lets no light through (its mean is {mean})"
                ),
                location,
            );
        }
        let scale = (PI as f64 / 4.0 / mean) as f32;
        for v in &mut mask.values {
            *v *= scale;
        }
        Ok(mask)
    }

    fn flip_rows(&mut self) {
        let w = self.width;
        for y in 0..self.height / 2 {
            let mirror = self.height - 1 - y;
            for x in 0..w {
                self.values.swap(y * w + x, mirror * w + x);
            }
        }
    }

    fn texel(&self, x: i64, y: i64) -> f32 {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return 0.0;
        }
        self.values[y as usize * self.width + x as usize]
    }

    /// Bilinear interpolation at `uv` ∈ [0, 1]² over the stop's bounding
    /// square (texel centres at (i + ½)/width); 0 outside.
    pub fn bilerp(&self, uv: Vec2) -> f32 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (xf, yf) = (x.floor(), y.floor());
        let (dx, dy) = (x - xf, y - yf);
        // `as` saturates (NaN to 0), so wild coordinates stay in range.
        let (xi, yi) = (xf as i64, yf as i64);
        (1.0 - dx) * (1.0 - dy) * self.texel(xi, yi)
            + dx * (1.0 - dy) * self.texel(xi + 1, yi)
            + (1.0 - dx) * dy * self.texel(xi, yi + 1)
            + dx * dy * self.texel(xi + 1, yi + 1)
    }
}

/// Texel centres of an n × n grid over [−1, 1]², row by row.
fn texel_centres(n: usize) -> impl Iterator<Item = Vec2> {
    (0..n * n).map(move |i| {
        let (x, y) = (i % n, i / n);
        Vec2::new(
            -1.0 + 2.0 * (x as f32 + 0.5) / n as f32,
            -1.0 + 2.0 * (y as f32 + 0.5) / n as f32,
        )
    })
}

/// 1 at texel centres inside the polygon (non-zero winding number), 0
/// elsewhere, on an n × n grid over [−1, 1]².
fn rasterize_polygon(corners: &[Vec2], n: usize) -> Vec<f32> {
    texel_centres(n)
        .map(|p| {
            let mut winding = 0;
            for (i, &a) in corners.iter().enumerate() {
                let b = corners[(i + 1) % corners.len()];
                // Which side of the edge a → b the point is on.
                let side = (p.x - a.x) * (b.y - a.y) - (p.y - a.y) * (b.x - a.x);
                if a.y <= p.y {
                    if b.y > p.y && side > 0.0 {
                        winding += 1;
                    }
                } else if b.y <= p.y && side < 0.0 {
                    winding -= 1;
                }
            }
            if winding == 0 {
                0.0
            } else {
                1.0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn builtin(name: &str) -> ApertureMask {
        ApertureMask::create(name, Path::new("."), &Location::nowhere()).unwrap()
    }

    /// Every built-in shape passes as much light as the circle (mean π/4),
    /// is open in the middle and closed at the corners of the square.
    #[test]
    fn built_in_shapes_are_normalised_to_the_circles_light() {
        for name in ["gaussian", "square", "pentagon", "star"] {
            let mask = builtin(name);
            let mean =
                mask.values.iter().map(|&v| v as f64).sum::<f64>() / mask.values.len() as f64;
            assert!(
                (mean - std::f64::consts::FRAC_PI_4).abs() < 1e-5,
                "{name}: {mean}"
            );
            assert!(mask.bilerp(Vec2::splat(0.5)) > 0.0, "{name}");
            assert_eq!(mask.bilerp(Vec2::new(0.01, 0.01)), 0.0, "{name}");
            assert_eq!(mask.bilerp(Vec2::new(1.5, 0.5)), 0.0, "{name}");
        }
        // The square is open out to a quarter of the way in from the edge.
        let square = builtin("square");
        assert!(square.bilerp(Vec2::new(0.3, 0.7)) > 0.0);
        assert_eq!(square.bilerp(Vec2::new(0.2, 0.5)), 0.0);
    }

    /// The pentagon's corner at the top of the drawing (+y) ends up at the
    /// stop's −y after the flip; its flat bottom edge at +y.
    #[test]
    fn the_pentagon_is_flipped_as_pbrt_v4_flips_its_image() {
        let pentagon = builtin("pentagon");
        // Near the corner at 0.75 of the radius: open on −y, closed on +y
        // (the flat side is at 0.8·cos 36° ≈ 0.65).
        assert!(pentagon.bilerp(Vec2::new(0.5, (1.0 - 0.75) / 2.0)) > 0.0);
        assert_eq!(pentagon.bilerp(Vec2::new(0.5, (1.0 + 0.75) / 2.0)), 0.0);
    }

    #[test]
    fn a_missing_aperture_image_is_a_located_cannot_read() {
        let e = ApertureMask::create(
            "no-such-aperture.png",
            Path::new("/nonexistent"),
            &Location::nowhere(),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("cannot read") && e.contains("no-such-aperture.png"),
            "{e}"
        );
    }
}
