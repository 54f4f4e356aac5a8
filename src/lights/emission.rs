//! Sampling the light a light emits (pbrt-v4's `SampleLe` and `PDF_Le`):
//! a point on the light and a direction leaving it, with their densities,
//! for integrators that trace paths from the lights. Point and diffuse
//! area lights; [`Light::samples_emission`] tells which.

use super::{DiffuseAreaLight, Light, PointLight};
use crate::math::frame::Frame;
use crate::math::sampling::{
    cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_sphere, UNIFORM_SPHERE_PDF,
};
use crate::shapes::ShapeStorage;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// A ray leaving a light.
#[derive(Clone, Copy, Debug)]
pub struct LightLeSample {
    /// Radiance (area lights) or intensity (point lights) along `dir`.
    pub l: SampledSpectrum,
    /// The point on the light, its error bound and its normal (zero for
    /// a point light).
    pub p: Vec3,
    pub p_error: Vec3,
    pub n: Vec3,
    /// The surface coordinates of `p` (zero for a point light).
    pub uv: Vec2,
    /// Unit direction leaving the light.
    pub dir: Vec3,
    /// Density of `p` per area (1 for a point light's one point).
    pub pdf_pos: f32,
    /// Density of `dir` per solid angle.
    pub pdf_dir: f32,
}

impl Light {
    /// Whether [`Light::sample_le`] can sample this light.
    pub fn samples_emission(&self) -> bool {
        matches!(self, Light::Point(_) | Light::DiffuseArea(_))
    }

    /// A ray leaving the light: its point from `u_pos`, its direction from
    /// `u_dir`. `None` where nothing is emitted, or for a light that
    /// [`Light::samples_emission`] refuses.
    pub fn sample_le(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        lambda: &SampledWavelengths,
        shapes: &ShapeStorage,
    ) -> Option<LightLeSample> {
        match self {
            Light::Point(l) => Some(l.sample_le(u_dir, lambda)),
            Light::DiffuseArea(l) => l.sample_le(u_pos, u_dir, lambda, shapes),
            _ => None,
        }
    }

    /// The densities (per area, per solid angle) with which
    /// [`Light::sample_le`] makes a ray leaving the point with normal `n`
    /// along unit `dir`.
    pub fn pdf_le(&self, n: Vec3, dir: Vec3) -> (f32, f32) {
        match self {
            Light::Point(_) => (0.0, UNIFORM_SPHERE_PDF),
            Light::DiffuseArea(l) => l.pdf_le(n, dir),
            _ => (0.0, 0.0),
        }
    }
}

impl PointLight {
    /// A direction uniform over the sphere.
    fn sample_le(&self, u: Vec2, lambda: &SampledWavelengths) -> LightLeSample {
        LightLeSample {
            l: self.intensity.sample(lambda) * self.scale,
            p: self.position,
            p_error: Vec3::ZERO,
            n: Vec3::ZERO,
            uv: Vec2::ZERO,
            dir: sample_uniform_sphere(u),
            pdf_pos: 1.0,
            pdf_dir: UNIFORM_SPHERE_PDF,
        }
    }
}

impl DiffuseAreaLight {
    /// A point uniform over the shape's area and a cosine-weighted
    /// direction about its normal (either side, evenly, when two-sided).
    fn sample_le(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        lambda: &SampledWavelengths,
        shapes: &ShapeStorage,
    ) -> Option<LightLeSample> {
        let ss = self.shape.sample_area(shapes, u_pos)?;
        let (local, pdf_dir) = if self.two_sided {
            // The first number picks the side and is stretched back to
            // [0, 1) for the direction.
            let below = u_dir.x >= 0.5;
            let x = if below { u_dir.x - 0.5 } else { u_dir.x };
            let u = Vec2::new((2.0 * x).min(1.0 - f32::EPSILON / 2.0), u_dir.y);
            let mut w = sample_cosine_hemisphere(u);
            if below {
                w.z = -w.z;
            }
            (w, cosine_hemisphere_pdf(w.z.abs()) / 2.0)
        } else {
            let w = sample_cosine_hemisphere(u_dir);
            (w, cosine_hemisphere_pdf(w.z))
        };
        if pdf_dir == 0.0 || ss.pdf == 0.0 {
            return None;
        }
        let dir = Frame::from_z(ss.n).from_local(local);
        Some(LightLeSample {
            l: self.l(ss.p, ss.n, ss.uv, dir, lambda),
            p: ss.p,
            p_error: ss.p_error,
            n: ss.n,
            uv: ss.uv,
            dir,
            pdf_pos: ss.pdf,
            pdf_dir,
        })
    }

    fn pdf_le(&self, n: Vec3, dir: Vec3) -> (f32, f32) {
        let cos = n.dot(dir);
        let pdf_dir = if self.two_sided {
            cosine_hemisphere_pdf(cos.abs()) / 2.0
        } else {
            cosine_hemisphere_pdf(cos.max(0.0))
        };
        (1.0 / self.area, pdf_dir)
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::build::{build, RenderOverrides};
    use crate::scene::load_text;
    use crate::spectrum::SampledWavelengths;
    use glam::Vec2;
    use std::path::Path;

    /// Emitted power by Monte Carlo over `sample_le`'s rays,
    /// E[L |cos θ| / (pdf_pos pdf_dir)] (no cosine for a point light),
    /// against the light's own Φ; and `pdf_le` agrees with the densities
    /// each sample reports.
    #[test]
    fn sampled_emission_adds_up_to_the_power() {
        for light in [
            "LightSource \"point\" \"rgb I\" [2 1 0.5] \"point3 from\" [0 1 0]",
            "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 2 3]\n\
             Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n\
             \"point3 P\" [0 0 0  2 0 0  2 1 0  0 1 0]\nAttributeEnd",
            "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool twosided\" true\n\
             Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd",
        ] {
            let text = format!("Camera \"perspective\"\nWorldBegin\n{light}\n");
            let loaded = load_text(Path::new("l.pbrt"), &text).unwrap();
            let scene = build(loaded.scene, &RenderOverrides::default()).unwrap();
            let l = &scene.lights[0];
            assert!(l.samples_emission());
            let lambda = SampledWavelengths::sample_visible(0.3);
            let n = 200;
            let mut sum = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let u_pos = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let u_dir = Vec2::new((j as f32 + 0.37) / n as f32, (i as f32 + 0.61) / n as f32);
                    let Some(s) = l.sample_le(u_pos, u_dir, &lambda, &scene.shapes) else {
                        continue;
                    };
                    let cos = if s.n == glam::Vec3::ZERO {
                        1.0
                    } else {
                        s.n.dot(s.dir).abs()
                    };
                    sum += (s.l[0] * cos / (s.pdf_pos * s.pdf_dir)) as f64;
                    let (pos, dir) = l.pdf_le(s.n, s.dir);
                    assert!((dir / s.pdf_dir - 1.0).abs() < 1e-4, "{light}");
                    if pos != 0.0 {
                        assert!((pos / s.pdf_pos - 1.0).abs() < 1e-3, "{light}");
                    }
                }
            }
            let estimate = sum / (n * n) as f64;
            let phi = l.phi(&lambda, &scene.shapes)[0] as f64;
            eprintln!("{light}: Φ {phi:.5}, sampled {estimate:.5}");
            assert!((estimate / phi - 1.0).abs() < 0.01, "{light}: {estimate} against {phi}");
        }
    }
}
