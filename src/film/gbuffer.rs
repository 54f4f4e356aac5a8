//! pbrt-v4's `gbuffer` film: the `rgb` film's image plus, per pixel, what
//! the camera sees first — position, depth slopes, normals, (u, v),
//! albedo — and the variance of the samples: the inputs of a denoiser.
//!
//! Channels, as pbrt-v4 writes them: `R G B`, `Albedo.R/G/B`, `P.X/Y/Z`,
//! `dzdx`, `dzdy`, `N.X/Y/Z`, `Ns.X/Y/Z`, `u`, `v`, `Variance.R/G/B`,
//! `RelativeVariance.R/G/B`. Geometry is the filter-weighted mean over
//! the samples that saw a surface; albedo the weighted mean over all
//! samples; variances are of the sensor RGB of the samples that saw a
//! surface (Welford's running sums, unweighted).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `coordinatesystem` | string | "camera" | space of P, N, Ns, dz: "camera" or "world" |
//!
//! and every parameter of the `rgb` film; the file name must end in `.exr`.

use super::rgb::{Pixel, RgbFilm};
use super::visible_surface::VisibleSurface;
use super::FilmPixel;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{DVec2, DVec3, Vec3};

/// Welford's running mean and variance (pbrt-v4's `VarianceEstimator`).
#[derive(Clone, Copy, Debug, Default)]
struct RunningVariance {
    count: f64,
    mean: f64,
    sum_squares: f64,
}

impl RunningVariance {
    fn add(&mut self, x: f64) {
        self.count += 1.0;
        let delta = x - self.mean;
        self.mean += delta / self.count;
        self.sum_squares += delta * (x - self.mean);
    }

    fn variance(&self) -> f64 {
        if self.count > 1.0 {
            self.sum_squares / (self.count - 1.0)
        } else {
            0.0
        }
    }

    fn relative_variance(&self) -> f64 {
        if self.count < 1.0 || self.mean == 0.0 {
            0.0
        } else {
            self.variance() / self.mean
        }
    }
}

/// A g-buffer pixel's sums.
#[derive(Clone, Copy, Debug, Default)]
pub struct GBufferPixel {
    pub rgb: Pixel,
    surface_weight: f64,
    p: DVec3,
    dzdx: f64,
    dzdy: f64,
    n: DVec3,
    ns: DVec3,
    uv: DVec2,
    albedo: [f64; 3],
    variance: [RunningVariance; 3],
}

/// The g-buffer's channel names, in the order [`GBufferPixel::values`]
/// gives them.
pub const CHANNELS: [&str; 25] = [
    "R",
    "G",
    "B",
    "Albedo.R",
    "Albedo.G",
    "Albedo.B",
    "P.X",
    "P.Y",
    "P.Z",
    "dzdx",
    "dzdy",
    "N.X",
    "N.Y",
    "N.Z",
    "Ns.X",
    "Ns.Y",
    "Ns.Z",
    "u",
    "v",
    "Variance.R",
    "Variance.G",
    "Variance.B",
    "RelativeVariance.R",
    "RelativeVariance.G",
    "RelativeVariance.B",
];

impl GBufferPixel {
    /// The channels after R, G, B (see [`CHANNELS`]).
    pub fn values(&self) -> [f32; 22] {
        let over = |v: f64, w: f64| if w != 0.0 { v / w } else { 0.0 };
        let unit = |v: DVec3| v.try_normalize().unwrap_or(DVec3::ZERO);
        let w = self.rgb.weight_sum;
        let s = self.surface_weight;
        let (n, ns) = (unit(self.n), unit(self.ns));
        let values = [
            over(self.albedo[0], w),
            over(self.albedo[1], w),
            over(self.albedo[2], w),
            over(self.p.x, s),
            over(self.p.y, s),
            over(self.p.z, s),
            over(self.dzdx, s).abs(),
            over(self.dzdy, s).abs(),
            n.x,
            n.y,
            n.z,
            ns.x,
            ns.y,
            ns.z,
            over(self.uv.x, s),
            over(self.uv.y, s),
            self.variance[0].variance(),
            self.variance[1].variance(),
            self.variance[2].variance(),
            self.variance[0].relative_variance(),
            self.variance[1].relative_variance(),
            self.variance[2].relative_variance(),
        ];
        values.map(|v| v as f32)
    }
}

impl FilmPixel for GBufferPixel {
    const USES_VISIBLE_SURFACE: bool = true;

    fn add_sample(
        &mut self,
        film: &RgbFilm,
        l: SampledSpectrum,
        lambda: &SampledWavelengths,
        weight: f32,
        visible: Option<&VisibleSurface>,
    ) {
        let rgb = film.sensor_rgb(l, lambda);
        let w = weight as f64;
        if let (Some(v), Some(space)) = (visible, film.gbuffer) {
            self.surface_weight += w;
            for c in 0..3 {
                self.variance[c].add(rgb[c] as f64);
            }
            let m = space.output_from_render;
            let normal = |n: Vec3| (space.normal_output_from_render * n).as_dvec3();
            self.p += w * m.transform_point3(v.p).as_dvec3();
            self.n += w * normal(v.n);
            self.ns += w * normal(v.ns);
            self.dzdx += w * m.transform_vector3(v.dpdx).z as f64;
            self.dzdy += w * m.transform_vector3(v.dpdy).z as f64;
            self.uv += w * v.uv.as_dvec2();
            // The albedo lit by the colour space's white, in its RGB.
            let albedo = film.albedo_rgb(v.albedo, lambda);
            for c in 0..3 {
                self.albedo[c] += w * albedo[c] as f64;
            }
        }
        for c in 0..3 {
            self.rgb.rgb_sum[c] += w * rgb[c] as f64;
        }
        self.rgb.weight_sum += w;
    }

    fn rgb(&self) -> &Pixel {
        &self.rgb
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_variance_matches_the_sample_variance() {
        let xs = [1.0, 4.0, 2.0, 8.0, 5.0];
        let mut v = RunningVariance::default();
        xs.iter().for_each(|&x| v.add(x));
        let mean = xs.iter().sum::<f64>() / 5.0;
        let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / 4.0;
        assert!((v.variance() - var).abs() < 1e-12);
        assert!((v.relative_variance() - var / mean).abs() < 1e-12);
        assert_eq!(RunningVariance::default().variance(), 0.0);
    }
}
