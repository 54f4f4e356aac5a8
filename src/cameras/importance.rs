//! The camera as a sensor that light arrives at (pbrt-v4's `We`,
//! `PDF_We` and `SampleWi`), for integrators that trace paths from the
//! lights and join them to the camera: the importance W_e a ray leaving
//! the lens carries, the densities with which `generate_ray` makes it, and
//! a point on the lens chosen to see a given scene point. Perspective
//! cameras only (pinhole or thin lens).
//!
//! W_e is normalised so that, over the directions the image covers,
//! ∫ W_e cos θ dω = 1 / lens area: a unit of radiance arriving from the
//! whole image adds 1 to the film, as a camera ray's radiance does.

use super::{Camera, PerspectiveCamera};
use crate::math::sampling::sample_uniform_disk_concentric;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// A lens point sampled to see a scene point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraWiSample {
    /// Importance carried by the ray from the lens point to the scene
    /// point.
    pub we: f32,
    /// Unit direction from the scene point towards the lens point.
    pub wi: Vec3,
    /// Solid-angle density of `wi` at the scene point.
    pub pdf: f32,
    /// Where on the film the ray lands (raster coordinates).
    pub p_raster: Vec2,
    /// The lens point and the lens's normal (the view direction), in
    /// render space.
    pub p_lens: Vec3,
    pub n_lens: Vec3,
}

/// Raster bounds samples may land in: [min, max) per axis.
pub type SampleBounds = (Vec2, Vec2);

impl PerspectiveCamera {
    fn lens_area(&self) -> f32 {
        if self.lens_radius > 0.0 {
            PI * self.lens_radius * self.lens_radius
        } else {
            1.0
        }
    }

    /// The viewing direction (camera +z) in render space.
    fn forward(&self) -> Vec3 {
        self.transform
            .render_from_camera
            .transform_vector3(Vec3::Z)
            .normalize()
    }

    /// Importance of a ray leaving the lens at `origin` along unit `dir`
    /// (render space), with the raster point it belongs to; `None` where
    /// it comes from behind the lens or lands outside `bounds`.
    pub fn we(&self, origin: Vec3, dir: Vec3, bounds: SampleBounds) -> Option<(f32, Vec2)> {
        let cos = dir.dot(self.forward());
        if cos <= 0.0 {
            return None;
        }
        // The point the ray crosses on the plane in focus (z = 1 for a
        // pinhole), back in camera space and then on the film.
        let z = if self.lens_radius > 0.0 {
            self.focal_distance
        } else {
            1.0
        };
        let p_focus = origin + dir * (z / cos);
        let p_camera = self.transform.camera_from_render.transform_point3(p_focus);
        if p_camera.z <= 0.0 {
            return None;
        }
        let screen = Vec2::new(p_camera.x, p_camera.y) / (p_camera.z * self.tan_half_fov);
        let p_raster = (screen - self.screen_origin) / self.screen_per_pixel;
        let (lo, hi) = bounds;
        if !(p_raster.cmpge(lo).all() && p_raster.cmplt(hi).all()) {
            return None;
        }
        let cos2 = cos * cos;
        Some((
            1.0 / (self.image_plane_area * self.lens_area() * cos2 * cos2),
            p_raster,
        ))
    }

    /// The densities with which `generate_ray` makes a ray along unit
    /// `dir`: (per lens area, per solid angle); zero for a direction
    /// outside the image.
    pub fn pdf_we(&self, origin: Vec3, dir: Vec3, bounds: SampleBounds) -> (f32, f32) {
        if self.we(origin, dir, bounds).is_none() {
            return (0.0, 0.0);
        }
        let cos = dir.dot(self.forward());
        (
            1.0 / self.lens_area(),
            1.0 / (self.image_plane_area * cos * cos * cos),
        )
    }

    /// A point on the lens (from `u`) seen from the render-space point
    /// `p`, with the importance of the ray from it to `p`.
    pub fn sample_wi(&self, p: Vec3, u: Vec2, bounds: SampleBounds) -> Option<CameraWiSample> {
        let lens = self.lens_radius * sample_uniform_disk_concentric(u);
        let p_lens = self
            .transform
            .render_from_camera
            .transform_point3(Vec3::new(lens.x, lens.y, 0.0));
        let n_lens = self.forward();
        let to_lens = p_lens - p;
        let dist = to_lens.length();
        if dist == 0.0 {
            return None;
        }
        let wi = to_lens / dist;
        let cos = n_lens.dot(wi).abs();
        if cos == 0.0 {
            return None;
        }
        let (we, p_raster) = self.we(p_lens, -wi, bounds)?;
        Some(CameraWiSample {
            we,
            wi,
            pdf: dist * dist / (cos * self.lens_area()),
            p_raster,
            p_lens,
            n_lens,
        })
    }
}

impl Camera {
    /// The camera as [`PerspectiveCamera`], the one kind whose importance
    /// is known.
    pub fn as_perspective(&self) -> Option<&PerspectiveCamera> {
        match self {
            Camera::Perspective(c) => Some(c),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cameras::CameraSample;
    use crate::math::sampling::{sample_uniform_sphere, UNIFORM_SPHERE_PDF};
    use crate::scene::load_text;
    use crate::spectrum::SampledWavelengths;
    use glam::IVec2;
    use std::path::Path;

    const RES: IVec2 = IVec2::new(40, 30);

    fn camera(params: &str) -> Camera {
        let text =
            format!("LookAt 1 2 3  0 0 0  0 1 0\nCamera \"perspective\" {params}\nWorldBegin");
        let loaded = load_text(Path::new("c.pbrt"), &text).unwrap();
        Camera::create(&loaded.scene.camera, RES).unwrap()
    }

    fn bounds() -> SampleBounds {
        (Vec2::ZERO, RES.as_vec2())
    }

    /// Over the sphere of directions from the pinhole, ∫ W_e cos θ dω = 1
    /// and the direction density integrates to 1 (Monte Carlo, uniform
    /// directions on a stratified grid).
    #[test]
    fn pinhole_importance_and_density_integrate_to_one() {
        let c = camera("\"float fov\" 50");
        let c = c.as_perspective().unwrap();
        let origin = c.transform.render_from_camera.transform_point3(Vec3::ZERO);
        let n = 1000;
        let (mut importance, mut density) = (0.0f64, 0.0f64);
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let d = sample_uniform_sphere(u);
                if let Some((we, _)) = c.we(origin, d, bounds()) {
                    let cos = d.dot(c.forward());
                    importance += (we * cos / UNIFORM_SPHERE_PDF) as f64;
                    density += (c.pdf_we(origin, d, bounds()).1 / UNIFORM_SPHERE_PDF) as f64;
                }
            }
        }
        let (importance, density) = (importance / (n * n) as f64, density / (n * n) as f64);
        eprintln!("∫ We cos dω = {importance:.4}, ∫ pdf dω = {density:.4}");
        assert!((importance - 1.0).abs() < 0.01, "{importance}");
        assert!((density - 1.0).abs() < 0.01, "{density}");
    }

    /// A point seen through a thin lens: the camera ray through the raster
    /// point `sample_wi` reports, from the same lens point, goes to it.
    #[test]
    fn sample_wi_finds_the_raster_point_of_the_ray() {
        for params in [
            "\"float fov\" 40",
            "\"float fov\" 40 \"float lensradius\" 0.2 \"float focaldistance\" 3",
        ] {
            let cam = camera(params);
            let c = cam.as_perspective().unwrap();
            let lambda = SampledWavelengths::sample_visible(0.5);
            // In front of the camera, a little off its axis.
            let origin = c.transform.render_from_camera.transform_point3(Vec3::ZERO);
            let p = origin + 2.5 * c.forward() + Vec3::new(0.3, -0.2, 0.1);
            let u = Vec2::new(0.3, 0.8);
            let s = c.sample_wi(p, u, bounds()).unwrap();
            let ray = cam
                .generate_ray(
                    &CameraSample {
                        p_film: s.p_raster,
                        p_lens: u,
                        time: 0.5,
                        filter_weight: 1.0,
                    },
                    &lambda,
                )
                .unwrap()
                .ray;
            assert!((ray.origin - s.p_lens).length() < 1e-4, "{params}");
            let to_p = (p - ray.origin).normalize();
            assert!((ray.direction - to_p).length() < 1e-4, "{params}: {ray:?}");
            assert!((-s.wi - to_p).length() < 1e-4);
            // The importance is that of the ray, and the density is the
            // lens's area density turned into solid angle at p.
            let (we, _) = c.we(s.p_lens, -s.wi, bounds()).unwrap();
            assert_eq!(we, s.we);
            let area = if c.lens_radius > 0.0 { PI * 0.04 } else { 1.0 };
            let d2 = (p - s.p_lens).length_squared();
            let want = d2 / (s.wi.dot(s.n_lens).abs() * area);
            assert!((s.pdf / want - 1.0).abs() < 1e-4);
        }
    }

    /// Behind the camera and outside the image there is no importance.
    #[test]
    fn no_importance_outside_the_view() {
        let cam = camera("\"float fov\" 30");
        let c = cam.as_perspective().unwrap();
        let origin = c.transform.render_from_camera.transform_point3(Vec3::ZERO);
        assert!(c.we(origin, -c.forward(), bounds()).is_none());
        let sideways = c.forward().cross(Vec3::Y).normalize();
        assert!(c
            .we(origin, (c.forward() + sideways).normalize(), bounds())
            .is_none());
        assert!(c.we(origin, c.forward(), bounds()).is_some());
    }
}
