//! The pinhole / thin-lens perspective camera.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `fov` | float | 90 | field of view in degrees, across the shorter image axis |
//! | `lensradius` | float | 0 | thin-lens aperture radius (0: pinhole) |
//! | `focaldistance` | float | 1e6 | distance to the plane in focus |
//! | `frameaspectratio` | float | x/y resolution | aspect ratio of the screen window |
//! | `screenwindow` | float[4] | from the aspect ratio | screen window xmin xmax ymin ymax |
//! | `shutteropen`, `shutterclose` | float | 0, 1 | shutter interval |

use super::differentials::{MinimumDifferentials, RayDifferentials, RayWithNeighbours};
use super::{screen_window, shutter_interval, thin_lens, CameraRay, CameraSample, CameraTransform};
use crate::error::{scene_error, Result};
use crate::math::sampling::sample_uniform_disk_concentric;
use crate::math::Ray;
use crate::scene_description::Entity;
use glam::{IVec2, Vec2, Vec3};

pub struct PerspectiveCamera {
    pub transform: CameraTransform,
    pub shutter_open: f32,
    pub shutter_close: f32,
    /// Screen-window corner at raster (0, 0), and the screen extent per
    /// raster pixel (y decreases downwards).
    pub(super) screen_origin: Vec2,
    pub(super) screen_per_pixel: Vec2,
    /// tan(fov / 2).
    pub(super) tan_half_fov: f32,
    pub(super) lens_radius: f32,
    pub(super) focal_distance: f32,
    /// Area of the image on the z = 1 plane of camera space (for the
    /// camera's importance, [`super::importance`]).
    pub(super) image_plane_area: f32,
    pub min_differentials: MinimumDifferentials,
    /// Whether camera samples are jittered across the pixel (false under
    /// `Option "disablepixeljitter" true`): a ray's footprint is then a
    /// whole pixel at any sample count.
    pub(super) pixel_jitter: bool,
}

impl PerspectiveCamera {
    pub fn create(
        entity: &Entity,
        transform: CameraTransform,
        full_resolution: IVec2,
    ) -> Result<Self> {
        let p = &entity.params;
        let loc = &entity.location.0;
        let (shutter_open, shutter_close) = shutter_interval(p)?;
        let (lens_radius, focal_distance) = thin_lens(p, loc)?;
        let fov = p.float("fov", 90.0)? as f32;
        if !(fov > 0.0 && fov < 180.0) {
            return scene_error(
                format!("\"fov\" must be between 0 and 180 degrees, not {fov}"),
                loc,
            );
        }
        let window = screen_window(p, full_resolution, loc)?;
        p.report_unused(|| "camera \"perspective\"".into())?;
        let res = full_resolution.as_vec2();
        let screen_origin = Vec2::new(window[0], window[3]);
        let screen_per_pixel = Vec2::new(
            (window[1] - window[0]) / res.x,
            -(window[3] - window[2]) / res.y,
        );
        let tan_half_fov = (fov.to_radians() / 2.0).tan();
        // Rays through the lens centre (pbrt-v4 samples the lens at its
        // centre here, where thin-lens rays are pinhole ones).
        let min_differentials = MinimumDifferentials::find(res, |p_film| {
            let screen = screen_origin + p_film * screen_per_pixel;
            let p = Vec3::new(screen.x * tan_half_fov, screen.y * tan_half_fov, 1.0);
            let dx = Vec3::new(screen_per_pixel.x * tan_half_fov, 0.0, 0.0);
            let dy = Vec3::new(0.0, screen_per_pixel.y * tan_half_fov, 0.0);
            Some(RayWithNeighbours {
                ray: (Vec3::ZERO, p.normalize()),
                x: (Vec3::ZERO, (p + dx).normalize()),
                y: (Vec3::ZERO, (p + dy).normalize()),
            })
        });
        Ok(PerspectiveCamera {
            transform,
            shutter_open,
            shutter_close,
            screen_origin,
            screen_per_pixel,
            tan_half_fov,
            lens_radius,
            focal_distance,
            image_plane_area: ((window[1] - window[0]) * (window[3] - window[2])).abs()
                * tan_half_fov
                * tan_half_fov,
            min_differentials,
            pixel_jitter: true,
        })
    }

    pub fn generate_ray(&self, sample: &CameraSample) -> Option<CameraRay> {
        let screen = self.screen_origin + sample.p_film * self.screen_per_pixel;
        let p_camera = Vec3::new(
            screen.x * self.tan_half_fov,
            screen.y * self.tan_half_fov,
            1.0,
        );
        // One pixel over in x and y, on the same z = 1 plane.
        let dx_camera = Vec3::new(self.screen_per_pixel.x * self.tan_half_fov, 0.0, 0.0);
        let dy_camera = Vec3::new(0.0, self.screen_per_pixel.y * self.tan_half_fov, 0.0);
        // Directions are normalised once, after the transform to render
        // space: normalize(M d) is the same for d and d / |d|.
        let mut origin = Vec3::ZERO;
        let mut direction = p_camera;
        let mut rx = (origin, p_camera + dx_camera);
        let mut ry = (origin, p_camera + dy_camera);
        if self.lens_radius > 0.0 {
            let lens = self.lens_radius * sample_uniform_disk_concentric(sample.p_lens);
            origin = Vec3::new(lens.x, lens.y, 0.0);
            // Each ray passes through its own point on the plane of focus.
            let through_lens = |d: Vec3| {
                let focus = d * (self.focal_distance / d.z);
                (origin, focus - origin)
            };
            direction = through_lens(direction).1;
            rx = through_lens(rx.1);
            ry = through_lens(ry.1);
        }
        let time = crate::math::lerp(sample.time, self.shutter_open, self.shutter_close);
        let m = self.transform.render_from_camera_at(time);
        let to_render =
            |(o, d): (Vec3, Vec3)| (m.transform_point3(o), m.transform_vector3(d).normalize());
        let (origin, direction) = to_render((origin, direction));
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
    use super::*;
    use crate::cameras::Camera;
    use crate::scene::load_text;
    use std::path::Path;

    fn camera(text: &str) -> Camera {
        let loaded = load_text(Path::new("c.pbrt"), text).unwrap();
        Camera::create(&loaded.scene.camera, IVec2::new(200, 100)).unwrap()
    }

    #[test]
    fn center_ray_looks_at_the_target_and_fov_spans_the_short_axis() {
        let c = camera(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 90\nWorldBegin",
        );
        let sample = |x: f32, y: f32| CameraSample {
            p_film: Vec2::new(x, y),
            ..Default::default()
        };
        let center = c
            .generate_ray(
                &sample(100.0, 50.0),
                &crate::spectrum::SampledWavelengths::sample_visible(0.5),
            )
            .unwrap();
        assert!(
            (center.ray.direction - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-5,
            "{:?}",
            center.ray
        );
        // Render space: the camera is at the origin.
        assert!(center.ray.origin.length() < 1e-5);
        // fov 90 across the short (vertical) axis: the top edge is at 45°.
        let top = c
            .generate_ray(
                &sample(100.0, 0.0),
                &crate::spectrum::SampledWavelengths::sample_visible(0.5),
            )
            .unwrap();
        assert!(
            (top.ray.direction.y - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-5,
            "{:?}",
            top.ray.direction
        );
        // Raster x grows to the right of the image: pbrt's camera space is
        // left-handed, so looking down −z with +y up, right is −x in world.
        let right = c
            .generate_ray(
                &sample(200.0, 50.0),
                &crate::spectrum::SampledWavelengths::sample_visible(0.5),
            )
            .unwrap();
        assert!(right.ray.direction.x < 0.0, "{:?}", right.ray.direction);
    }

    #[test]
    fn approximate_differentials_use_the_smallest_ones_on_the_film() {
        // 200×100, fov 90 across y: the screen spans x ∈ [−2, 2], y ∈ [−1, 1],
        // 0.02 per pixel. Direction differentials are smallest at the
        // corners, direction (2, 1, 1).
        let c = camera(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 90\nWorldBegin",
        );
        let corner = Vec3::new(2.0, 1.0, 1.0);
        let step = |d: Vec3| ((corner + d).normalize() - corner.normalize()).length();
        let (ex, ey) = (step(Vec3::X * 0.02), step(Vec3::Y * 0.02));
        // A wall facing the camera 10 units away; 4 spp halves the offsets.
        let p = Vec3::new(0.0, 0.0, -10.0);
        for (spp, scale) in [(1, 1.0), (4, 0.5)] {
            let (dpdx, dpdy) = c.approximate_dp_dxy(p, Vec3::Z, spp);
            assert!(dpdx.z.abs() < 1e-4 && dpdy.z.abs() < 1e-4, "{dpdx} {dpdy}");
            let (lx, ly) = (dpdx.length(), dpdy.length());
            assert!(
                (lx / (10.0 * ex * scale) - 1.0).abs() < 0.01,
                "{lx} vs {}",
                10.0 * ex
            );
            assert!(
                (ly / (10.0 * ey * scale) - 1.0).abs() < 0.01,
                "{ly} vs {}",
                10.0 * ey
            );
        }
    }

    #[test]
    fn camera_ray_differentials_reach_one_pixel_over_at_the_first_hit() {
        // 0.02 screen units per pixel at unit distance: 0.2 at distance 10
        // in the middle of the image, narrowed to 1/√spp of it.
        let c = camera(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 90\nWorldBegin",
        );
        let sample = CameraSample {
            p_film: Vec2::new(100.0, 50.0),
            ..Default::default()
        };
        let lambda = crate::spectrum::SampledWavelengths::sample_visible(0.5);
        let ray = c.generate_ray(&sample, &lambda).unwrap();
        let p = ray.ray.origin + ray.ray.direction * 10.0;
        for (spp, scale) in [(1, 1.0), (16, 0.25), (1024, 0.125)] {
            let (dpdx, dpdy) = c.first_hit_dp_dxy(&ray, p, Vec3::Z, spp);
            assert!((dpdx.length() - 0.2 * scale).abs() < 1e-3 * scale, "{dpdx}");
            assert!((dpdy.length() - 0.2 * scale).abs() < 1e-3 * scale, "{dpdy}");
            assert!(dpdx.dot(dpdy).abs() < 1e-6 && dpdx.z.abs() < 1e-6);
        }
    }

    /// Without pixel jitter (pbrt-v4's `disablepixeljitter`) a camera
    /// ray's footprint is a whole pixel at any sample count, both from its
    /// differentials and from the camera's approximation.
    #[test]
    fn without_pixel_jitter_differentials_span_a_whole_pixel() {
        let c = camera(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 90\nWorldBegin",
        )
        .with_pixel_jitter(false);
        let sample = CameraSample {
            p_film: Vec2::new(100.0, 50.0),
            ..Default::default()
        };
        let lambda = crate::spectrum::SampledWavelengths::sample_visible(0.5);
        let ray = c.generate_ray(&sample, &lambda).unwrap();
        let p = ray.ray.origin + ray.ray.direction * 10.0;
        let (whole_x, _) = c.first_hit_dp_dxy(&ray, p, Vec3::Z, 1);
        let (approximate_x, _) = c.approximate_dp_dxy(p, Vec3::Z, 1);
        for spp in [16, 1024] {
            let (dpdx, dpdy) = c.first_hit_dp_dxy(&ray, p, Vec3::Z, spp);
            assert!((dpdx.length() - 0.2).abs() < 2e-4, "{dpdx}");
            assert!((dpdy.length() - 0.2).abs() < 2e-4, "{dpdy}");
            assert_eq!(dpdx, whole_x);
            assert_eq!(c.approximate_dp_dxy(p, Vec3::Z, spp).0, approximate_x);
        }
    }
}
