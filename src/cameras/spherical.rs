//! The spherical (environment) camera: every direction about the camera's
//! position, one image covering the whole sphere.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `mapping` | string | `equalarea` | `equalarea`: Clarberg's equal-area octahedral square (as pbrt-v4's image infinite lights read); `equirectangular`: latitude–longitude |
//! | `shutteropen`, `shutterclose` | float | 0, 1 | shutter interval |
//! | `lensradius`, `focaldistance`, `frameaspectratio`, `screenwindow` | | | accepted and ignored, as pbrt-v4 |
//!
//! Film position (x, y) is first taken to (u, v) = (x / width, y / height).
//! `equirectangular` gives the direction with polar angle θ = πv and
//! azimuth φ = 2πu about the camera's +y (up) axis, φ = 0 along +x: the top
//! row looks up, the bottom row down, the middle row round the horizon.
//! `equalarea` maps (u, v) through the octahedral square (see
//! [`crate::math::equal_area`]) with its pole along +y; each pixel then
//! covers the same solid angle, 4π / (width·height).
//!
//! Ray differentials are finite differences of neighbouring rays, as
//! pbrt-v4 forms them for cameras without their own.

use super::differentials::{MinimumDifferentials, RayDifferentials, RayWithNeighbours};
use super::{screen_window, shutter_interval, thin_lens, CameraRay, CameraSample, CameraTransform};
use crate::error::{scene_error, Result};
use crate::math::equal_area::{equal_area_square_to_sphere, wrap_equal_area_square_point};
use crate::math::Ray;
use crate::scene_description::Entity;
use glam::{IVec2, Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SphericalMapping {
    EqualArea,
    Equirectangular,
}

pub struct SphericalCamera {
    pub transform: CameraTransform,
    pub shutter_open: f32,
    pub shutter_close: f32,
    pub mapping: SphericalMapping,
    resolution: Vec2,
    pub min_differentials: MinimumDifferentials,
    /// Whether camera samples are jittered across the pixel (see
    /// [`super::PerspectiveCamera`]).
    pub(super) pixel_jitter: bool,
}

/// How far over, in pixels, the neighbouring rays of a ray's differentials
/// are taken; the difference is then divided by it (pbrt-v4's 0.05).
const DIFFERENCE_STEP: f32 = 0.05;

impl SphericalCamera {
    pub fn create(
        entity: &Entity,
        transform: CameraTransform,
        full_resolution: IVec2,
    ) -> Result<Self> {
        let p = &entity.params;
        let loc = &entity.location.0;
        let (shutter_open, shutter_close) = shutter_interval(p)?;
        // Read (so they are not reported as unused) but meaningless here.
        thin_lens(p, loc)?;
        screen_window(p, full_resolution, loc)?;
        let mapping = match p.string("mapping", "equalarea")?.as_str() {
            "equalarea" => SphericalMapping::EqualArea,
            "equirectangular" => SphericalMapping::Equirectangular,
            other => {
                return scene_error(
                    format!("spherical camera \"mapping\" \"{other}\" unknown (expected \"equalarea\" or \"equirectangular\")"),
                    loc,
                )
            }
        };
        p.report_unused(|| "camera \"spherical\"".into())?;
        let resolution = full_resolution.as_vec2();
        let min_differentials = MinimumDifferentials::find(resolution, |p_film| {
            let d = direction(mapping, resolution, p_film);
            let neighbour = |offset: Vec2| {
                let shifted = direction(mapping, resolution, p_film + offset * DIFFERENCE_STEP);
                (Vec3::ZERO, d + (shifted - d) / DIFFERENCE_STEP)
            };
            Some(RayWithNeighbours {
                ray: (Vec3::ZERO, d),
                x: neighbour(Vec2::X),
                y: neighbour(Vec2::Y),
            })
        });
        Ok(SphericalCamera {
            transform,
            shutter_open,
            shutter_close,
            mapping,
            resolution,
            min_differentials,
            pixel_jitter: true,
        })
    }

    pub fn generate_ray(&self, sample: &CameraSample) -> Option<CameraRay> {
        let time = crate::math::lerp(sample.time, self.shutter_open, self.shutter_close);
        let m = self.transform.render_from_camera_at(time);
        let render_direction = |p_film: Vec2| {
            m.transform_vector3(direction(self.mapping, self.resolution, p_film))
                .normalize()
        };
        let d = render_direction(sample.p_film);
        let neighbour = |offset: Vec2| {
            let shifted = render_direction(sample.p_film + offset * DIFFERENCE_STEP);
            d + (shifted - d) / DIFFERENCE_STEP
        };
        let origin = m.transform_point3(Vec3::ZERO);
        Some(CameraRay {
            ray: Ray::new(origin, d, time),
            weight: 1.0,
            differentials: Some(RayDifferentials {
                rx_origin: origin,
                rx_direction: neighbour(Vec2::X),
                ry_origin: origin,
                ry_direction: neighbour(Vec2::Y),
            }),
        })
    }
}

/// The camera-space direction of film position `p_film` (raster units).
pub fn direction(mapping: SphericalMapping, resolution: Vec2, p_film: Vec2) -> Vec3 {
    let uv = p_film / resolution;
    // Both mappings put their pole on z; camera space has y up.
    let d = match mapping {
        SphericalMapping::Equirectangular => {
            let (theta, phi) = (PI * uv.y, 2.0 * PI * uv.x);
            Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        }
        SphericalMapping::EqualArea => {
            // Film positions just past the edge (the filter's reach) fold
            // back across it, as the octahedral square is glued; anything
            // further (not a film position) is clamped into the square.
            let wrapped = wrap_equal_area_square_point(uv).clamp(Vec2::ZERO, Vec2::ONE);
            let wrapped = if wrapped.is_nan() {
                Vec2::splat(0.5)
            } else {
                wrapped
            };
            equal_area_square_to_sphere(wrapped)
        }
    };
    Vec3::new(d.x, d.z, d.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cameras::Camera;
    use crate::scene::load_text;
    use crate::spectrum::SampledWavelengths;
    use std::path::Path;

    fn camera(text: &str, resolution: IVec2) -> Camera {
        let loaded = load_text(Path::new("c.pbrt"), text).unwrap();
        Camera::create(&loaded.scene.camera, resolution).unwrap()
    }

    fn ray_direction(c: &Camera, x: f32, y: f32) -> Vec3 {
        let sample = CameraSample {
            p_film: Vec2::new(x, y),
            ..Default::default()
        };
        c.generate_ray(&sample, &SampledWavelengths::sample_visible(0.5))
            .unwrap()
            .ray
            .direction
    }

    /// Equirectangular on a 400 × 200 film, camera at the origin with no
    /// transform: top row up (+y), bottom row down, the middle row round
    /// the horizon with φ = 2πx/width from +x towards +z.
    #[test]
    fn equirectangular_directions_are_latitude_and_longitude() {
        let c = camera(
            "Camera \"spherical\" \"string mapping\" \"equirectangular\"\nWorldBegin",
            IVec2::new(400, 200),
        );
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
        assert!(close(ray_direction(&c, 123.0, 0.0), Vec3::Y));
        assert!(close(ray_direction(&c, 17.0, 200.0), Vec3::NEG_Y));
        assert!(close(ray_direction(&c, 0.0, 100.0), Vec3::X));
        assert!(close(ray_direction(&c, 100.0, 100.0), Vec3::Z));
        assert!(close(ray_direction(&c, 200.0, 100.0), Vec3::NEG_X));
        assert!(close(ray_direction(&c, 300.0, 100.0), Vec3::NEG_Z));
        // 45° above the horizon, a quarter turn round.
        let d = ray_direction(&c, 100.0, 50.0);
        assert!(close(d, Vec3::new(0.0, 1.0, 1.0).normalize()), "{d}");
    }

    /// Equal-area: over the film, directions cover the sphere evenly. The
    /// solid angle of each of a grid of film cells, estimated from the
    /// cross product of its edge directions, is 4π / cells; the mean
    /// direction is zero and the default mapping is this one.
    #[test]
    fn equal_area_pixels_subtend_equal_solid_angles() {
        let c = camera("Camera \"spherical\"\nWorldBegin", IVec2::new(64, 64));
        let cells = 32;
        let step = 64.0 / cells as f32;
        let expected = 4.0 * PI / (cells * cells) as f32;
        let mut total = 0.0;
        let mut mean = Vec3::ZERO;
        for i in 0..cells {
            for j in 0..cells {
                let (x, y) = (i as f32 * step, j as f32 * step);
                // Subdivide the cell so the spherical quadrilaterals are
                // nearly flat, and sum their areas.
                let n = 8;
                let h = step / n as f32;
                let mut solid_angle = 0.0;
                for a in 0..n {
                    for b in 0..n {
                        let (x0, y0) = (x + a as f32 * h, y + b as f32 * h);
                        let p00 = ray_direction(&c, x0, y0);
                        let p10 = ray_direction(&c, x0 + h, y0);
                        let p01 = ray_direction(&c, x0, y0 + h);
                        let p11 = ray_direction(&c, x0 + h, y0 + h);
                        solid_angle += 0.5 * (p10 - p00).cross(p01 - p00).length()
                            + 0.5 * (p10 - p11).cross(p01 - p11).length();
                        mean += p00;
                    }
                }
                // Cells are equal to within the flat-triangle estimate,
                // except where a cell's fold (the square's diagonals, where
                // the octahedron's edges are) bends it.
                total += solid_angle;
                let ratio = solid_angle / expected;
                assert!((0.85..1.02).contains(&ratio), "cell {i},{j}: {ratio}");
            }
        }
        assert!((total / (4.0 * PI) - 1.0).abs() < 0.02, "{total}");
        assert!(
            mean.length() / ((cells * cells * 64) as f32) < 0.02,
            "{mean}"
        );
        // The centre of the square looks up (+y, the pole), the corners down.
        assert!((ray_direction(&c, 32.0, 32.0) - Vec3::Y).length() < 1e-5);
        assert!((ray_direction(&c, 0.0, 0.0) - Vec3::NEG_Y).length() < 1e-5);
        assert!(!c.uses_lens());
    }

    #[test]
    fn an_unknown_mapping_is_a_located_error() {
        let loaded = load_text(
            Path::new("c.pbrt"),
            "Camera \"spherical\" \"string mapping\" \"cubemap\"\nWorldBegin",
        )
        .unwrap();
        let err = Camera::create(&loaded.scene.camera, IVec2::new(20, 10))
            .err()
            .unwrap()
            .to_string();
        assert!(
            err.contains("c.pbrt:1:") && err.contains("cubemap"),
            "{err}"
        );
    }
}
