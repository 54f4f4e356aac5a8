//! An environment image seen only through a rectangular opening, the
//! *portal* (`infinite` with `portal`; pbrt-v4's
//! `PortalImageInfiniteLight`, after Bitterli et al. 2015, "Portal-masked
//! environment map sampling").
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `portal` | point3[4] | — | the opening's corners, in world space, in order around a rectangle |
//! | `filename` | string | — | square RGB image (EXR, PFM, PNG) in equal-area octahedral mapping |
//! | `L` | spectrum | — | without `filename`: a constant environment, made into a 1×1 sRGB image |
//! | `scale` | float | 1 | scale |
//! | `illuminance` | float | — | not supported yet with a portal |
//!
//! The light lights only the side the portal faces: directions leaving
//! the room through the opening. At construction the equal-area image is
//! resampled (bilinearly) into a *rectified* image of the portal's frame,
//! in which pixel (u, v) stands for the direction with angles
//! α = π(u − ½), β = π(v − ½) about the portal's normal: tan α and tan β
//! are the direction's slopes along the portal's edges. From any point,
//! the portal then covers an axis-aligned rectangle of that image (its
//! corners 0 and 2 give it), so sampling the image within that rectangle
//! ([`WindowedPiecewiseConstant2D`]) yields only directions through the
//! opening, which a plain image light wastes most samples on missing.
//!
//! Radiance reads the nearest texel of the rectified image, and is zero
//! for directions outside the portal as seen from the ray's origin.

use super::{LightLiSample, LightSampleContext, Radiance};
use crate::image::{Image, WrapMode};
use crate::math::equal_area::equal_area_sphere_to_square;
use crate::math::frame::Frame;
use crate::math::Ray;
use crate::samplers::{Domain2D, WindowedPiecewiseConstant2D};
use crate::spectrum::color_space::RgbColorSpace;
use crate::spectrum::{DenselySampled, RgbSigmoidPolynomial, SampledSpectrum, SampledWavelengths};
use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};
use std::sync::Arc;

/// Tolerance on the cosines between the portal's edges (pbrt-v4's): opposite
/// edges must be parallel and adjacent ones perpendicular to within it.
const EDGE_COSINE_TOLERANCE: f32 = 1e-3;

/// What makes four points unusable as a portal.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PortalShapeError {
    #[error("a portal needs 4 corners, but {0} are given")]
    CornerCount(usize),
    #[error("corners {0} and {1} of the portal coincide")]
    Degenerate(usize, usize),
    #[error("the portal is not a planar rectangle: opposite edges are not parallel, or adjacent edges not perpendicular (corners go in order around it)")]
    NotRectangle,
}

/// The portal's corners p0…p3, checked to go in order around a rectangle
/// (pbrt-v4 prints an error and goes on with a skewed frame; rpbrt stops).
pub fn portal_corners(corners: &[Vec3]) -> Result<[Vec3; 4], PortalShapeError> {
    let &[p0, p1, p2, p3] = corners else {
        return Err(PortalShapeError::CornerCount(corners.len()));
    };
    let edge = |a: usize, b: usize| {
        (corners[b] - corners[a])
            .try_normalize()
            .ok_or(PortalShapeError::Degenerate(a.min(b), a.max(b)))
    };
    let (p01, p12, p32, p03) = (edge(0, 1)?, edge(1, 2)?, edge(3, 2)?, edge(0, 3)?);
    let parallel = |a: Vec3, b: Vec3| (a.dot(b) - 1.0).abs() <= EDGE_COSINE_TOLERANCE;
    let perpendicular = |a: Vec3, b: Vec3| a.dot(b).abs() <= EDGE_COSINE_TOLERANCE;
    let rectangle = parallel(p01, p32)
        && parallel(p12, p03)
        && perpendicular(p01, p12)
        && perpendicular(p12, p32)
        && perpendicular(p32, p03)
        && perpendicular(p03, p01);
    if !rectangle {
        return Err(PortalShapeError::NotRectangle);
    }
    Ok([p0, p1, p2, p3])
}

pub struct PortalInfiniteLight {
    /// Corners in render space, in order around the rectangle.
    portal: [Vec3; 4],
    /// x along corner 0 → 3, y along 0 → 1, z = x × y the lit side's
    /// normal (pbrt-v4's `Frame::FromXY(p03, p01)`).
    frame: Frame,
    /// Rectified image, row-major, `resolution` × `resolution`: each
    /// texel's illuminant spectrum (scale and sigmoid polynomial of its
    /// RGB, clamped at 0), computed once.
    texels: Vec<(f32, RgbSigmoidPolynomial)>,
    /// The colour space's illuminant, which the texels' spectra modulate.
    illuminant: Arc<DenselySampled>,
    resolution: usize,
    scale: f32,
    distribution: WindowedPiecewiseConstant2D,
    scene_radius: f32,
}

impl PortalInfiniteLight {
    /// `equal_area`: linear RGB channels, square; `portal`: render-space
    /// corners checked by [`portal_corners`]; `render_from_light` orients the
    /// environment.
    pub fn new(
        render_from_light: Mat4,
        equal_area: &Image,
        color_space: &'static RgbColorSpace,
        scale: f32,
        portal: [Vec3; 4],
    ) -> Self {
        let x = (portal[3] - portal[0]).normalize();
        let y = (portal[1] - portal[0]).normalize();
        let frame = Frame {
            x,
            y,
            z: x.cross(y),
        };
        let resolution = equal_area.width().max(1) as usize;
        let light_from_render = render_from_light.inverse();
        // Each rectified texel takes the environment's bilinear value along
        // the direction its centre stands for.
        let mut rgb = Vec::with_capacity(resolution * resolution);
        for j in 0..resolution {
            for i in 0..resolution {
                let uv = Vec2::new(
                    (i as f32 + 0.5) / resolution as f32,
                    (j as f32 + 0.5) / resolution as f32,
                );
                let (w, _) = render_from_image(&frame, uv);
                let w_light = light_from_render.transform_vector3(w).normalize();
                let st = equal_area_sphere_to_square(w_light);
                rgb.push(Vec3::from_array(std::array::from_fn(|c| {
                    equal_area.bilerp_channel(st, c, WrapMode::OctahedralSphere)
                })));
            }
        }
        // Sampled in proportion to the texel's channel average times
        // dω/d(u, v), so that directions come out in proportion to radiance
        // per solid angle.
        let density: Vec<f32> = rgb
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let uv = Vec2::new(
                    ((k % resolution) as f32 + 0.5) / resolution as f32,
                    ((k / resolution) as f32 + 0.5) / resolution as f32,
                );
                (c.x + c.y + c.z) / 3.0 * render_from_image(&frame, uv).1
            })
            .collect();
        let distribution = WindowedPiecewiseConstant2D::new(&density, resolution, resolution);
        PortalInfiniteLight {
            portal,
            frame,
            texels: rgb
                .iter()
                .map(|&c| color_space.illuminant_coefficients(c))
                .collect(),
            illuminant: Arc::clone(color_space.illuminant_densely_sampled()),
            resolution,
            scale,
            distribution,
            scene_radius: 0.0,
        }
    }

    pub fn preprocess(&mut self, _center: Vec3, radius: f32) {
        self.scene_radius = radius;
    }

    /// The rectified image's (u, v) of unit render-space direction `w`, and
    /// dω/d(u, v) there; `None` for directions parallel to the
    /// portal or leaving on its unlit side.
    fn image_from_render(&self, w: Vec3) -> Option<(Vec2, f32)> {
        let local = self.frame.to_local(w);
        if local.z <= 0.0 {
            return None;
        }
        let alpha = local.x.atan2(local.z);
        let beta = local.y.atan2(local.z);
        let uv = Vec2::new(
            ((alpha + FRAC_PI_2) / PI).clamp(0.0, 1.0),
            ((beta + FRAC_PI_2) / PI).clamp(0.0, 1.0),
        );
        Some((uv, jacobian(local)))
    }

    /// The rectangle of the rectified image that the portal covers seen
    /// from `p`; `None` from behind the portal.
    fn image_bounds(&self, p: Vec3) -> Option<Domain2D> {
        let (a, _) = self.image_from_render((self.portal[0] - p).normalize())?;
        let (b, _) = self.image_from_render((self.portal[2] - p).normalize())?;
        Some(Domain2D::new(a.min(b), a.max(b)))
    }

    /// Radiance of the rectified texel nearest `uv`.
    fn image_le(&self, uv: Vec2, lambda: &SampledWavelengths) -> SampledSpectrum {
        let n = self.resolution;
        let x = ((uv.x * n as f32) as usize).min(n - 1);
        let y = ((uv.y * n as f32) as usize).min(n - 1);
        self.texel_le(y * n + x, lambda)
    }

    fn texel_le(&self, i: usize, lambda: &SampledWavelengths) -> SampledSpectrum {
        let (scale, polynomial) = &self.texels[i];
        SampledSpectrum::from_fn(|k| {
            let l = lambda.lambda[k];
            scale * polynomial.eval(l) * self.illuminant.eval(l)
        }) * self.scale
    }

    /// Radiance along a ray that escapes the scene: the image where the ray
    /// leaves through the portal as seen from its origin, zero elsewhere.
    pub fn le(&self, ray: &Ray, lambda: &SampledWavelengths) -> SampledSpectrum {
        let Some(direction) = ray.direction.try_normalize() else {
            return SampledSpectrum::ZERO;
        };
        let (Some((uv, _)), Some(bounds)) = (
            self.image_from_render(direction),
            self.image_bounds(ray.origin),
        ) else {
            return SampledSpectrum::ZERO;
        };
        let inside = uv.cmpge(bounds.min).all() && uv.cmple(bounds.max).all();
        if !inside {
            return SampledSpectrum::ZERO;
        }
        self.image_le(uv, lambda)
    }

    /// A direction through the portal from `ctx`, in proportion to the
    /// image's radiance there. pbrt-v4 samples the same way whether or not
    /// the BSDF is sampled too (no compensated distribution).
    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample<'_>> {
        let bounds = self.image_bounds(ctx.p)?;
        let (uv, map_pdf) = self.distribution.sample(u, bounds)?;
        let (wi, dw_duv) = render_from_image(&self.frame, uv);
        if dw_duv == 0.0 {
            return None;
        }
        Some(LightLiSample {
            l: Radiance::Value(self.image_le(uv, lambda)),
            wi,
            pdf: map_pdf / dw_duv,
            p_light: ctx.p + wi * (2.0 * self.scene_radius),
            p_light_error: Vec3::ZERO,
            n_light: Vec3::ZERO,
        })
    }

    /// Solid-angle density with which `sample_li` picks unit `wi` from
    /// `ctx`.
    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3) -> f32 {
        let Some((uv, dw_duv)) = self.image_from_render(wi) else {
            return 0.0;
        };
        let Some(bounds) = self.image_bounds(ctx.p) else {
            return 0.0;
        };
        if dw_duv == 0.0 {
            return 0.0;
        }
        self.distribution.pdf(uv, bounds) / dw_duv
    }

    /// Power, for the power light sampler: the portal's area × the mean over
    /// texels of radiance ÷ dω/d(u, v) (pbrt-v4's formula, kept so that
    /// light is weighed against others as pbrt-v4 weighs it).
    pub fn phi(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        let n = self.resolution;
        let mut sum = SampledSpectrum::ZERO;
        for i in 0..n * n {
            let uv = Vec2::new(
                ((i % n) as f32 + 0.5) / n as f32,
                ((i / n) as f32 + 0.5) / n as f32,
            );
            let (_, dw_duv) = render_from_image(&self.frame, uv);
            sum += self.texel_le(i, lambda) / dw_duv;
        }
        let area =
            (self.portal[1] - self.portal[0]).length() * (self.portal[3] - self.portal[0]).length();
        sum * (area / (n * n) as f32)
    }
}

/// The unit render-space direction of rectified-image point `uv`, and
/// dω/d(u, v) there.
fn render_from_image(frame: &Frame, uv: Vec2) -> (Vec3, f32) {
    let alpha = -FRAC_PI_2 + uv.x * PI;
    let beta = -FRAC_PI_2 + uv.y * PI;
    let local = Vec3::new(alpha.tan(), beta.tan(), 1.0).normalize();
    (frame.from_local(local), jacobian(local))
}

/// dω/d(u, v) for the portal-local unit direction `w` (z > 0): with
/// u = (atan(x/z) + π/2)/π and likewise v, a texel of area du dv covers
/// π² (1 − x²)(1 − y²)/z du dv of solid angle (pbrt-v4 names it `duv_dw`,
/// and divides densities in (u, v) by it as here).
fn jacobian(w: Vec3) -> f32 {
    PI * PI * (1.0 - w.x * w.x) * (1.0 - w.y * w.y) / w.z
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_description::ColorSpaceName;

    /// A 1 × 1 window in the plane y = 2 (the ceiling of a room below it),
    /// lit from above: corners in order around it, so that the frame's z
    /// (x along 0 → 3, y along 0 → 1) points up, +y.
    fn window() -> [Vec3; 4] {
        [
            Vec3::new(-0.5, 2.0, -0.5),
            Vec3::new(0.5, 2.0, -0.5),
            Vec3::new(0.5, 2.0, 0.5),
            Vec3::new(-0.5, 2.0, 0.5),
        ]
    }

    /// A 32 × 32 environment with smooth colours and a bright patch, so
    /// that sampling is far from uniform.
    fn environment() -> Image {
        let n = 32;
        let mut data = Vec::with_capacity(n * n * 3);
        for i in 0..n * n {
            let (x, y) = ((i % n) as f32 / n as f32, (i / n) as f32 / n as f32);
            let bright = if (x - 0.5).abs() < 0.1 && (y - 0.45).abs() < 0.12 {
                30.0
            } else {
                0.0
            };
            data.extend([0.2 + x + bright, 0.1 + y + bright, 0.3 + x * y + bright]);
        }
        Image::from_rgb(n as u32, n as u32, data).expect("an image")
    }

    fn light(image: &Image) -> PortalInfiniteLight {
        let space = crate::spectrum::color_space::get(ColorSpaceName::Srgb);
        let rotation = Mat4::from_rotation_y(0.4) * Mat4::from_rotation_x(-0.3);
        let corners = portal_corners(&window()).expect("a rectangle");
        let mut light = PortalInfiniteLight::new(rotation, image, space, 1.5, corners);
        light.preprocess(Vec3::ZERO, 10.0);
        light
    }

    fn context(p: Vec3) -> LightSampleContext {
        LightSampleContext {
            p,
            p_error: Vec3::ZERO,
            n: Vec3::Y,
            ns: Vec3::Y,
            time: 0.0,
        }
    }

    /// Corner counts other than 4, coinciding corners and skewed or
    /// out-of-order quadrilaterals are refused, each for its reason.
    #[test]
    fn only_rectangles_make_portals() {
        let w = window();
        assert_eq!(
            portal_corners(&w[..3]),
            Err(PortalShapeError::CornerCount(3))
        );
        assert_eq!(
            portal_corners(&[w[0], w[0], w[2], w[3]]),
            Err(PortalShapeError::Degenerate(0, 1))
        );
        let skewed = [w[0], w[1], w[2] + Vec3::X * 0.3, w[3] + Vec3::X * 0.3];
        assert_eq!(portal_corners(&skewed), Err(PortalShapeError::NotRectangle));
        let bent = [w[0], w[1], w[2] + Vec3::Y * 0.2, w[3]];
        assert_eq!(portal_corners(&bent), Err(PortalShapeError::NotRectangle));
        let crossed = [w[0], w[2], w[1], w[3]];
        assert_eq!(
            portal_corners(&crossed),
            Err(PortalShapeError::NotRectangle)
        );
        assert!(portal_corners(&w).is_ok());
    }

    /// `pdf_li` gives each sampled direction the density `sample_li`
    /// returned; the direction leaves through the portal, where `le` sees
    /// the radiance the sample carries.
    #[test]
    fn pdf_li_matches_sample_li() {
        let light = light(&environment());
        let lambda = SampledWavelengths::sample_visible(0.42);
        let p = Vec3::new(0.3, 0.4, -0.7);
        let ctx = context(p);
        let m = 48;
        for j in 0..m * m {
            let u = Vec2::new(
                ((j % m) as f32 + 0.5) / m as f32,
                ((j / m) as f32 + 0.5) / m as f32,
            );
            let s = light.sample_li(&ctx, u, &lambda).expect("a sample");
            let pdf = light.pdf_li(&ctx, s.wi);
            assert!(
                (pdf - s.pdf).abs() <= 2e-3 * s.pdf,
                "pdf {pdf} vs {}",
                s.pdf
            );
            // Through the opening: the ray from p along wi meets y = 2
            // within the window (round-off allowed at its edges).
            let t = (2.0 - p.y) / s.wi.y;
            let hit = p + s.wi * t;
            assert!(
                t > 0.0 && hit.x.abs() <= 0.501 && hit.z.abs() <= 0.501,
                "{hit}"
            );
            let ray = Ray::new(p, s.wi, 0.0);
            let seen = light.le(&ray, &lambda);
            let carried = s.l.value(&lambda);
            for k in 0..4 {
                assert!((seen.0[k] - carried.0[k]).abs() <= 1e-4 * carried.0[k].max(1.0));
            }
        }
        // Nothing is lit from above the portal, nor away from it.
        assert!(light
            .sample_li(
                &context(Vec3::new(0.0, 3.0, 0.0)),
                Vec2::splat(0.5),
                &lambda
            )
            .is_none());
        assert_eq!(light.pdf_li(&ctx, -Vec3::Y), 0.0);
    }

    /// Irradiance at a point in the room, by importance sampling the
    /// portal light, equals a brute-force integral over the window's area
    /// of Le cos θ cos θ' / r².
    #[test]
    fn sampled_irradiance_matches_brute_force_over_the_window() {
        let light = light(&environment());
        let lambda = SampledWavelengths::sample_visible(0.58);
        let p = Vec3::new(0.3, 0.4, -0.7);
        let n = Vec3::new(0.2, 1.0, 0.1).normalize();
        let ctx = context(p);
        let m = 256;
        let mut estimate = 0.0f64;
        for j in 0..m * m {
            let u = Vec2::new(
                ((j % m) as f32 + 0.5) / m as f32,
                ((j / m) as f32 + 0.5) / m as f32,
            );
            if let Some(s) = light.sample_li(&ctx, u, &lambda) {
                estimate += (s.l.value(&lambda).0[0] * s.wi.dot(n).max(0.0) / s.pdf) as f64;
            }
        }
        estimate /= (m * m) as f64;

        let k = 1200;
        let mut brute = 0.0f64;
        for j in 0..k * k {
            let x = -0.5 + ((j % k) as f32 + 0.5) / k as f32;
            let z = -0.5 + ((j / k) as f32 + 0.5) / k as f32;
            let d = Vec3::new(x, 2.0, z) - p;
            let r2 = d.length_squared();
            let wi = d / r2.sqrt();
            let le = light.le(&Ray::new(p, wi, 0.0), &lambda).0[0];
            brute += (le * wi.dot(n).max(0.0) * wi.y / r2) as f64;
        }
        brute /= (k * k) as f64;
        assert!(
            (estimate - brute).abs() < 5e-3 * brute,
            "sampled {estimate} vs brute force {brute}"
        );
    }

    /// A constant environment seen through the portal has the plain image
    /// light's radiance: the rectified image loses nothing.
    #[test]
    fn a_constant_environment_keeps_its_radiance() {
        let image = Image::from_rgb(1, 1, vec![0.7, 0.4, 0.2]).expect("an image");
        let portal = light(&image);
        let space = crate::spectrum::color_space::get(ColorSpaceName::Srgb);
        let plain =
            super::super::ImageInfiniteLight::new(Mat4::IDENTITY, &[0.7, 0.4, 0.2], 1, space, 1.5);
        let lambda = SampledWavelengths::sample_visible(0.3);
        let ray = Ray::new(Vec3::new(0.1, 0.5, 0.2), Vec3::new(0.1, 1.0, -0.2), 0.0);
        let (a, b) = (portal.le(&ray, &lambda), plain.le(ray.direction, &lambda));
        for k in 0..4 {
            assert!((a.0[k] - b.0[k]).abs() <= 1e-5 * b.0[k], "{a:?} vs {b:?}");
        }
        // Outside the opening there is nothing.
        let away = Ray::new(Vec3::new(0.1, 0.5, 0.2), Vec3::new(1.0, 0.3, 0.0), 0.0);
        assert!(portal.le(&away, &lambda).is_zero());
    }
}
