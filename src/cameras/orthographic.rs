//! The orthographic camera: parallel rays along the camera's +z, starting
//! on the screen window in the camera's z = 0 plane, so that objects keep
//! their size at any distance.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `screenwindow` | float[4] | from the aspect ratio | the region of the z = 0 plane the film sees, xmin xmax ymin ymax, in camera-space units |
//! | `frameaspectratio` | float | x/y resolution | aspect ratio of the default screen window ([−ratio, ratio] × [−1, 1] when wider than tall, else [−1, 1] × [−1/ratio, 1/ratio]) |
//! | `lensradius` | float | 0 | thin-lens aperture radius (0: every ray parallel) |
//! | `focaldistance` | float | 1e6 | distance of the plane in focus |
//! | `shutteropen`, `shutterclose` | float | 0, 1 | shutter interval |
//!
//! With a lens, as pbrt-v4: each ray starts at its point on the lens (a
//! disk of `lensradius` about the camera's origin, not about the ray's
//! screen point) and passes through the point on the plane of focus that
//! the parallel ray would reach.

use super::differentials::{MinimumDifferentials, RayDifferentials, RayWithNeighbours};
use super::{screen_window, shutter_interval, thin_lens, CameraRay, CameraSample, CameraTransform};
use crate::error::Result;
use crate::math::sampling::sample_uniform_disk_concentric;
use crate::math::Ray;
use crate::scene_description::Entity;
use glam::{IVec2, Vec2, Vec3};

pub struct OrthographicCamera {
    pub transform: CameraTransform,
    pub shutter_open: f32,
    pub shutter_close: f32,
    /// Screen-window corner at raster (0, 0), and the screen extent per
    /// raster pixel (y decreases downwards).
    screen_origin: Vec2,
    screen_per_pixel: Vec2,
    pub(super) lens_radius: f32,
    focal_distance: f32,
    pub min_differentials: MinimumDifferentials,
    /// Whether camera samples are jittered across the pixel (see
    /// [`super::PerspectiveCamera`]).
    pub(super) pixel_jitter: bool,
}

impl OrthographicCamera {
    pub fn create(
        entity: &Entity,
        transform: CameraTransform,
        full_resolution: IVec2,
    ) -> Result<Self> {
        let p = &entity.params;
        let loc = &entity.location.0;
        let (shutter_open, shutter_close) = shutter_interval(p)?;
        let (lens_radius, focal_distance) = thin_lens(p, loc)?;
        let window = screen_window(p, full_resolution, loc)?;
        p.report_unused(|| "camera \"orthographic\"".into())?;
        let res = full_resolution.as_vec2();
        let screen_origin = Vec2::new(window[0], window[3]);
        let screen_per_pixel = Vec2::new(
            (window[1] - window[0]) / res.x,
            -(window[3] - window[2]) / res.y,
        );
        // Neighbouring rays are the same ray moved by one pixel's screen
        // extent: no change of direction anywhere on the film.
        let min_differentials = MinimumDifferentials::find(res, |p_film| {
            let origin = (screen_origin + p_film * screen_per_pixel).extend(0.0);
            Some(RayWithNeighbours {
                ray: (origin, Vec3::Z),
                x: (origin + Vec3::new(screen_per_pixel.x, 0.0, 0.0), Vec3::Z),
                y: (origin + Vec3::new(0.0, screen_per_pixel.y, 0.0), Vec3::Z),
            })
        });
        Ok(OrthographicCamera {
            transform,
            shutter_open,
            shutter_close,
            screen_origin,
            screen_per_pixel,
            lens_radius,
            focal_distance,
            min_differentials,
            pixel_jitter: true,
        })
    }

    pub fn generate_ray(&self, sample: &CameraSample) -> Option<CameraRay> {
        let p_camera = (self.screen_origin + sample.p_film * self.screen_per_pixel).extend(0.0);
        let dx_camera = Vec3::new(self.screen_per_pixel.x, 0.0, 0.0);
        let dy_camera = Vec3::new(0.0, self.screen_per_pixel.y, 0.0);
        let (ray, rx, ry) = if self.lens_radius > 0.0 {
            let lens = self.lens_radius * sample_uniform_disk_concentric(sample.p_lens);
            let lens_point = lens.extend(0.0);
            // The parallel ray from `start` reaches the plane of focus at
            // start + focal_distance·z; the lens ray aims there.
            let through_lens = |start: Vec3| {
                let focus = start + self.focal_distance * Vec3::Z;
                (lens_point, focus - lens_point)
            };
            (
                through_lens(p_camera),
                through_lens(p_camera + dx_camera),
                through_lens(p_camera + dy_camera),
            )
        } else {
            (
                (p_camera, Vec3::Z),
                (p_camera + dx_camera, Vec3::Z),
                (p_camera + dy_camera, Vec3::Z),
            )
        };
        let time = crate::math::lerp(sample.time, self.shutter_open, self.shutter_close);
        let m = self.transform.render_from_camera_at(time);
        let to_render =
            |(o, d): (Vec3, Vec3)| (m.transform_point3(o), m.transform_vector3(d).normalize());
        let (origin, direction) = to_render(ray);
        let (rx, ry) = (to_render(rx), to_render(ry));
        Some(CameraRay {
            ray: Ray::new(origin, direction, time),
            weight: 1.0,
            differentials: Some(RayDifferentials {
                rx_origin: rx.0,
                rx_direction: rx.1,
                ry_origin: ry.0,
                ry_direction: ry.1,
            }),
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::cameras::{Camera, CameraSample};
    use crate::scene::load_text;
    use crate::spectrum::SampledWavelengths;
    use glam::{IVec2, Vec2, Vec3};
    use std::path::Path;

    fn camera(text: &str) -> Camera {
        let loaded = load_text(Path::new("c.pbrt"), text).unwrap();
        Camera::create(&loaded.scene.camera, IVec2::new(200, 100)).unwrap()
    }

    fn ray_at(c: &Camera, x: f32, y: f32) -> crate::cameras::CameraRay {
        let sample = CameraSample {
            p_film: Vec2::new(x, y),
            p_lens: Vec2::new(0.3, 0.8),
            ..Default::default()
        };
        c.generate_ray(&sample, &SampledWavelengths::sample_visible(0.5))
            .unwrap()
    }

    /// Looking down −z from (0, 0, 5) with screen window [−4, 4] × [−2, 2]
    /// on a 200 × 100 film: every ray points along −z, and starts on the
    /// window (the camera's z = 0 plane; render space has the camera at
    /// the origin), 0.04 units per pixel, x flipped as pbrt's camera space
    /// is left-handed.
    #[test]
    fn rays_are_parallel_and_start_on_the_screen_window() {
        let c = camera(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-4 4 -2 2]\nWorldBegin",
        );
        for (x, y) in [(0.0, 0.0), (100.0, 50.0), (200.0, 100.0), (37.5, 81.25)] {
            let r = ray_at(&c, x, y);
            assert!(
                (r.ray.direction - Vec3::NEG_Z).length() < 1e-6,
                "{:?}",
                r.ray
            );
            let expected = Vec3::new(-(-4.0 + 0.04 * x), 2.0 - 0.04 * y, 0.0);
            assert!(
                (r.ray.origin - expected).length() < 1e-5,
                "{:?} vs {expected}",
                r.ray.origin
            );
            // Differentials: the same direction, one pixel over.
            let d = r.differentials.unwrap();
            assert!((d.rx_origin - r.ray.origin - Vec3::new(-0.04, 0.0, 0.0)).length() < 1e-5);
            assert!((d.ry_origin - r.ray.origin - Vec3::new(0.0, -0.04, 0.0)).length() < 1e-5);
            assert_eq!(d.rx_direction, r.ray.direction);
        }
        assert!(!c.uses_lens());
        // A wall facing the camera, on its axis (where pbrt-v4's
        // approximation, which turns the point onto the axis first, is
        // exact): a pixel is 0.04 units at any distance.
        for distance in [1.0, 100.0] {
            let p = Vec3::new(0.0, 0.0, -distance);
            let (dpdx, dpdy) = c.approximate_dp_dxy(p, Vec3::Z, 1);
            assert!((dpdx.length() - 0.04).abs() < 1e-5, "{dpdx}");
            assert!((dpdy.length() - 0.04).abs() < 1e-5, "{dpdy}");
        }
    }

    /// The default window of a 2:1 film is [−2, 2] × [−1, 1].
    #[test]
    fn default_window_follows_the_aspect_ratio() {
        let c = camera("Camera \"orthographic\"\nWorldBegin");
        let corner = ray_at(&c, 0.0, 0.0);
        // Camera space at the origin looking down +z (no transform).
        assert!((corner.ray.origin - Vec3::new(-2.0, 1.0, 0.0)).length() < 1e-5);
        assert!((corner.ray.direction - Vec3::Z).length() < 1e-6);
    }

    /// With a lens, every ray through a screen point meets the plane of
    /// focus where the parallel ray does, from a point on the lens disk.
    #[test]
    fn thin_lens_rays_meet_on_the_plane_of_focus() {
        let c = camera(
            "Camera \"orthographic\" \"float lensradius\" 0.5 \"float focaldistance\" 3\nWorldBegin",
        );
        assert!(c.uses_lens());
        let r = ray_at(&c, 50.0, 25.0);
        let screen = Vec3::new(-2.0 + 0.02 * 50.0, 1.0 - 0.02 * 25.0, 0.0);
        assert!(r.ray.origin.z.abs() < 1e-6 && r.ray.origin.truncate().length() <= 0.5);
        let t = 3.0 / r.ray.direction.z;
        let focus = r.ray.origin + t * r.ray.direction;
        assert!(
            (focus - (screen + 3.0 * Vec3::Z)).length() < 1e-4,
            "{focus}"
        );
    }

    #[test]
    fn a_bad_screen_window_is_a_located_error() {
        let loaded = load_text(
            Path::new("c.pbrt"),
            "Camera \"orthographic\" \"float screenwindow\" [-1 1 0]\nWorldBegin",
        )
        .unwrap();
        let err = Camera::create(&loaded.scene.camera, IVec2::new(20, 10))
            .err()
            .unwrap()
            .to_string();
        assert!(
            err.contains("c.pbrt:1:") && err.contains("screenwindow"),
            "{err}"
        );
    }
}
