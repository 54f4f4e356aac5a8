//! pbrt-v4's realistic camera: rays from a point on a physical film traced
//! through a lens system read from a file ([`super::lens_system`]).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `lensfile` | string | (required) | lens description file, resolved against the scene file's directory |
//! | `aperturediameter` | float | 1 | diameter of the aperture stop in mm (at most the lens file's stop diameter; larger is clamped) |
//! | `focusdistance` | float | 10 | distance from the film to the plane in focus, in scene units (metres) |
//! | `aperture` | string | (circular) | shape of the stop: `gaussian`, `square`, `pentagon`, `star` or an image file ([`super::aperture`]) |
//! | `shutteropen`, `shutterclose` | float | 0, 1 | shutter interval |
//!
//! The film's size is the film's `diagonal` (mm, default 35) with the
//! aspect ratio of its resolution; raster (0, 0) is at camera-space
//! (+x, −y) of the film, so the image, inverted by the lens, comes out
//! upright and unmirrored.
//!
//! At creation the lens is focused with a thick-lens approximation (the
//! distance from the rear element to the film is set so that the plane
//! `focusdistance` away is sharp), and the exit pupil is bounded in 64
//! bands of distance from the film centre. A ray starts at its film point
//! towards a point sampled uniformly in its band's pupil bounds (rotated
//! to the film point's direction from the centre); blocked rays give no
//! ray. The weight cos⁴θ / (pdf · d²), with θ the angle to the axis, pdf
//! the pupil sample's density and d the rear element's distance, makes
//! the radiance estimate one of the irradiance on the film (pbrt-v4's
//! convention; the image is brighter or darker with the f-number).
//!
//! Ray differentials are finite differences of rays 0.05 pixel over (or
//! back, where that ray is blocked), as pbrt-v4 forms them for cameras
//! without their own.

use super::aperture::ApertureMask;
use super::differentials::{MinimumDifferentials, RayDifferentials, RayWithNeighbours};
use super::lens_system::{exit_pupil_samples, read_lens_file, LensSystem, PupilBounds};
use super::{shutter_interval, CameraRay, CameraSample, CameraTransform};
use crate::error::{scene_error, Result};
use crate::math::Ray;
use crate::scene_description::Entity;
use glam::{IVec2, Vec2, Vec3};
use rayon::prelude::*;
use std::path::Path;

/// Bands of distance from the film centre with their own exit pupil bounds.
const PUPIL_BANDS: usize = 64;

/// How far over, in pixels, differentials take their neighbouring rays.
const DIFFERENCE_STEP: f32 = 0.05;

/// What a realistic camera needs from the film and the scene.
#[derive(Clone, Copy, Debug)]
pub struct FilmGeometry<'a> {
    pub full_resolution: IVec2,
    /// Film diagonal in metres.
    pub diagonal: f32,
    /// Where the scene's file names resolve.
    pub base_directory: &'a Path,
}

pub struct RealisticCamera {
    pub transform: CameraTransform,
    pub shutter_open: f32,
    pub shutter_close: f32,
    lens: LensSystem,
    mask: Option<ApertureMask>,
    resolution: Vec2,
    /// Film corner at raster (0, 0) and the opposite one, camera-space x, y
    /// before the x flip.
    physical_min: Vec2,
    physical_max: Vec2,
    film_diagonal: f32,
    /// Exit pupil bounds for film points at distances [i, i+1) / 64 of
    /// half the diagonal from the centre, along +x.
    pupil_bounds: Vec<PupilBounds>,
    pub min_differentials: MinimumDifferentials,
    pub(super) pixel_jitter: bool,
}

/// A camera-space ray (direction normalised) and its weight.
struct LensRay {
    origin: Vec3,
    direction: Vec3,
    weight: f32,
}

impl RealisticCamera {
    pub fn create(entity: &Entity, transform: CameraTransform, film: FilmGeometry) -> Result<Self> {
        let p = &entity.params;
        let loc = &entity.location.0;
        let (shutter_open, shutter_close) = shutter_interval(p)?;
        let lens_file = p.string_at("lensfile")?;
        let aperture_diameter = p.float("aperturediameter", 1.0)? as f32;
        let focus_distance = p.float("focusdistance", 10.0)? as f32;
        let aperture = p.string_at("aperture")?;
        p.report_unused(|| "camera \"realistic\"".into())?;
        let Some((lens_file, lens_location)) = lens_file else {
            return scene_error("camera \"realistic\" needs a \"lensfile\"", loc);
        };
        if !(aperture_diameter > 0.0 && aperture_diameter.is_finite()) {
            return scene_error(
                format!("\"aperturediameter\" must be positive, not {aperture_diameter}"),
                loc,
            );
        }
        if !(focus_distance > 0.0 && focus_distance.is_finite()) {
            return scene_error(
                format!("\"focusdistance\" must be positive, not {focus_distance}"),
                loc,
            );
        }
        if !(film.diagonal > 0.0 && film.diagonal.is_finite()) {
            return scene_error(
                format!(
                    "the film \"diagonal\" must be positive, not {} mm",
                    film.diagonal * 1000.0
                ),
                loc,
            );
        }
        let path = pbrt_parser::resolve_path(film.base_directory, &lens_file);
        let mut elements = read_lens_file(&path, &lens_location)?;
        // The stop opens to the requested diameter, at most to the one the
        // lens file gives it (pbrt-v4 warns and clamps).
        for element in elements.iter_mut().filter(|e| e.is_stop()) {
            element.aperture_radius = element.aperture_radius.min(aperture_diameter / 2000.0);
        }
        let mask = match aperture {
            Some((name, location)) if !name.is_empty() => {
                Some(ApertureMask::create(&name, film.base_directory, &location)?)
            }
            _ => None,
        };
        let mut lens = LensSystem::new(elements);
        let Some(thick) = lens.thick_lens(film.diagonal, mask.as_ref()) else {
            return scene_error(
                format!("camera \"realistic\": no ray parallel to the axis gets through the lens system of \"{}\" (is the aperture stop very small, or its shape closed at the centre?)", path.display()),
                loc,
            );
        };
        let Some(rear) = lens.focused_rear_distance(&thick, focus_distance) else {
            return scene_error(
                format!("camera \"realistic\": \"focusdistance\" {focus_distance} is too close for the lens of \"{}\" to focus (focal length {} mm)", path.display(), thick.focal_length() * 1000.0),
                loc,
            );
        };
        // A focus that would put the rear element on or behind the film
        // leaves no room for rays (and divides by its distance below).
        if rear.is_nan() || rear <= 0.0 {
            return scene_error(
                format!("camera \"realistic\": focusing the lens of \"{}\" at {focus_distance} would put its rear element {} mm behind the film", path.display(), -rear * 1000.0),
                loc,
            );
        }
        if let Some(last) = lens.elements.last_mut() {
            last.thickness = rear;
        }

        let resolution = full_resolution_vec(film.full_resolution);
        let aspect = resolution.y / resolution.x;
        let x = (film.diagonal * film.diagonal / (1.0 + aspect * aspect)).sqrt();
        let y = aspect * x;
        let half_diagonal = film.diagonal / 2.0;
        let pupil_samples = exit_pupil_samples();
        let pupil_bounds = (0..PUPIL_BANDS)
            .into_par_iter()
            .map(|i| {
                let r0 = i as f32 / PUPIL_BANDS as f32 * half_diagonal;
                let r1 = (i + 1) as f32 / PUPIL_BANDS as f32 * half_diagonal;
                lens.bound_exit_pupil(r0, r1, mask.as_ref(), &pupil_samples)
            })
            .collect();
        let mut camera = RealisticCamera {
            transform,
            shutter_open,
            shutter_close,
            lens,
            mask,
            resolution,
            physical_min: Vec2::new(-x / 2.0, -y / 2.0),
            physical_max: Vec2::new(x / 2.0, y / 2.0),
            film_diagonal: film.diagonal,
            pupil_bounds,
            min_differentials: MinimumDifferentials::find(Vec2::ONE, |_| None),
            pixel_jitter: true,
        };
        camera.min_differentials = MinimumDifferentials::find(resolution, |p_film| {
            camera.camera_space_with_neighbours(p_film, Vec2::splat(0.5))
        });
        Ok(camera)
    }

    /// The film point (camera space) of raster position `p_film`.
    fn film_point(&self, p_film: Vec2) -> Vec3 {
        let s = p_film / self.resolution;
        let p = Vec2::new(
            crate::math::lerp(s.x, self.physical_min.x, self.physical_max.x),
            crate::math::lerp(s.y, self.physical_min.y, self.physical_max.y),
        );
        Vec3::new(-p.x, p.y, 0.0)
    }

    /// A point on the rear element's plane for film point `film` from
    /// `u` ∈ [0,1)², with its density per unit area; `None` where no ray
    /// from there gets through.
    fn sample_exit_pupil(&self, film: Vec2, u: Vec2) -> Option<(Vec3, f32)> {
        let r = film.length();
        let band =
            ((r / (self.film_diagonal / 2.0) * PUPIL_BANDS as f32) as usize).min(PUPIL_BANDS - 1);
        let bounds = self.pupil_bounds[band];
        if bounds.is_degenerate() {
            return None;
        }
        let p = bounds.lerp(u);
        let pdf = 1.0 / bounds.area();
        // The bounds were found along +x: rotate them to the film point.
        let (sin, cos) = if r != 0.0 {
            (film.y / r, film.x / r)
        } else {
            (0.0, 1.0)
        };
        let pupil = Vec3::new(
            cos * p.x - sin * p.y,
            sin * p.x + cos * p.y,
            self.lens.rear_z(),
        );
        Some((pupil, pdf))
    }

    /// The camera-space ray for raster position `p_film` and lens sample
    /// `u`: origin, normalised direction and weight.
    fn camera_space_ray(&self, p_film: Vec2, u: Vec2) -> Option<LensRay> {
        let film = self.film_point(p_film);
        let (pupil, pdf) = self.sample_exit_pupil(Vec2::new(film.x, film.y), u)?;
        let to_pupil = pupil - film;
        let (origin, direction, mask_weight) =
            self.lens
                .trace_from_film(film, to_pupil, self.mask.as_ref())?;
        let cos_theta = to_pupil.normalize().z;
        let rear_z = self.lens.rear_z();
        let weight = mask_weight * cos_theta.powi(4) / (pdf * rear_z * rear_z);
        Some(LensRay {
            origin,
            direction: direction.normalize(),
            weight,
        })
    }

    /// The ray for `p_film` and its neighbours 1 pixel over in x and y by
    /// finite differences (camera space); `None` when the ray itself or a
    /// neighbour both ways is blocked.
    fn camera_space_with_neighbours(&self, p_film: Vec2, u: Vec2) -> Option<RayWithNeighbours> {
        let ray = self.camera_space_ray(p_film, u)?;
        let (x, y) = self.neighbours(&ray, p_film, u)?;
        Some(RayWithNeighbours {
            ray: (ray.origin, ray.direction),
            x,
            y,
        })
    }

    /// Neighbouring rays one pixel over in x and y, extrapolated from rays
    /// 0.05 pixel over (or back).
    #[allow(clippy::type_complexity)]
    fn neighbours(
        &self,
        ray: &LensRay,
        p_film: Vec2,
        u: Vec2,
    ) -> Option<((Vec3, Vec3), (Vec3, Vec3))> {
        let along = |axis: Vec2| {
            [DIFFERENCE_STEP, -DIFFERENCE_STEP]
                .into_iter()
                .find_map(|step| {
                    let shifted = self.camera_space_ray(p_film + axis * step, u)?;
                    Some((
                        ray.origin + (shifted.origin - ray.origin) / step,
                        ray.direction + (shifted.direction - ray.direction) / step,
                    ))
                })
        };
        Some((along(Vec2::X)?, along(Vec2::Y)?))
    }

    pub fn generate_ray(&self, sample: &CameraSample) -> Option<CameraRay> {
        let ray = self.camera_space_ray(sample.p_film, sample.p_lens)?;
        let time = crate::math::lerp(sample.time, self.shutter_open, self.shutter_close);
        let m = self.transform.render_from_camera_at(time);
        let differentials = self
            .neighbours(&ray, sample.p_film, sample.p_lens)
            .map(|(x, y)| RayDifferentials {
                rx_origin: m.transform_point3(x.0),
                rx_direction: m.transform_vector3(x.1),
                ry_origin: m.transform_point3(y.0),
                ry_direction: m.transform_vector3(y.1),
            });
        Some(CameraRay {
            ray: Ray::new(
                m.transform_point3(ray.origin),
                m.transform_vector3(ray.direction).normalize(),
                time,
            ),
            weight: ray.weight,
            differentials,
        })
    }
}

fn full_resolution_vec(resolution: IVec2) -> Vec2 {
    resolution.max(IVec2::ONE).as_vec2()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::cameras::Camera;
    use crate::scene::load_text;
    use crate::spectrum::SampledWavelengths;

    /// The double-Gauss 50 mm f/2 of US patent 2,673,491 (Tronnier), as
    /// "Modern Lens Design" lists it, scaled from 100 mm to 50 mm: radius,
    /// axial thickness, index, aperture diameter (mm).
    pub(crate) const DOUBLE_GAUSS_50MM: &str = "\
# D-Gauss F/2 22deg HFOV, scaled to 50 mm
# radius  thickness  index  diameter
29.475    3.76    1.67    25.2
84.83     0.12    1       25.2
19.275    4.025   1.67    23
40.77     3.275   1.699   23
12.75     5.705   1       18
0         4.5     0       17.1
-14.495   1.18    1.603   17
40.77     6.065   1.658   20
-20.385   0.19    1       20
437.065   3.22    1.717   20
-39.73    0       1       20
";

    /// A directory holding `dgauss.50mm.dat`, unique to `name`.
    pub(crate) fn lens_directory(name: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("rpbrt-realistic-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("dgauss.50mm.dat"), DOUBLE_GAUSS_50MM).unwrap();
        dir
    }

    fn camera_in(dir: &Path, camera_line: &str, resolution: IVec2) -> Result<Camera> {
        let text = format!("LookAt 0 0 5  0 0 0  0 1 0\n{camera_line}\nWorldBegin\n");
        let loaded = load_text(&dir.join("c.pbrt"), &text)?;
        Camera::create_for_film(
            &loaded.scene.camera,
            FilmGeometry {
                full_resolution: resolution,
                diagonal: 0.035,
                base_directory: dir,
            },
        )
    }

    fn realistic(c: &Camera) -> &RealisticCamera {
        match c {
            Camera::Realistic(r) => r,
            _ => panic!("not a realistic camera"),
        }
    }

    fn ray(c: &Camera, p_film: Vec2, p_lens: Vec2) -> Option<CameraRay> {
        let sample = CameraSample {
            p_film,
            p_lens,
            time: 0.5,
            filter_weight: 1.0,
        };
        c.generate_ray(&sample, &SampledWavelengths::sample_visible(0.5))
    }

    /// Lens samples on a 16 × 16 grid.
    fn lens_grid() -> impl Iterator<Item = Vec2> {
        (0..256).map(|i| Vec2::new((i % 16) as f32 + 0.5, (i / 16) as f32 + 0.5) / 16.0)
    }

    /// The double-Gauss focused at 3 m on a 60 × 40 film, its stop at
    /// `aperture_diameter` mm (8: about f/6; 17: wide open, about f/3),
    /// made once (each camera bounds its exit pupil with 2²⁶ rays).
    fn double_gauss(aperture_diameter: u32) -> &'static Camera {
        static CAMERAS: [std::sync::OnceLock<Camera>; 2] =
            [std::sync::OnceLock::new(), std::sync::OnceLock::new()];
        let index = usize::from(aperture_diameter != 8);
        CAMERAS[index].get_or_init(|| {
            let dir = lens_directory(&format!("shared-{aperture_diameter}"));
            let camera = camera_in(
                &dir,
                &format!("Camera \"realistic\" \"string lensfile\" \"dgauss.50mm.dat\" \"float aperturediameter\" {aperture_diameter} \"float focusdistance\" 3"),
                IVec2::new(60, 40),
            )
            .unwrap();
            std::fs::remove_dir_all(&dir).ok();
            camera
        })
    }

    #[test]
    fn the_double_gauss_focuses_at_50mm_and_its_centre_rays_meet_at_the_focus_distance() {
        let c = double_gauss(8);
        let thick = realistic(c).lens.thick_lens(0.035, None).unwrap();
        assert!(
            (thick.focal_length() - 0.050).abs() < 0.002,
            "{}",
            thick.focal_length()
        );
        // Rays from the film centre: the camera is at z = 5 looking down
        // −z, so the plane in focus is z = 2 (3 m from the film). Their
        // spread there (what spherical aberration leaves) is far smaller
        // than 1.5 m before it.
        let (mut at_focus, mut before, mut n) = (0.0f32, 0.0f32, 0);
        for u in lens_grid() {
            let Some(cr) = ray(c, Vec2::new(30.0, 20.0), u) else {
                continue;
            };
            assert!(cr.weight > 0.0 && cr.weight.is_finite());
            let o = cr.ray.origin + Vec3::new(0.0, 0.0, 5.0); // world space
            let d = cr.ray.direction;
            let hit = |z: f32| o + d * ((z - o.z) / d.z);
            at_focus = at_focus.max(hit(2.0).truncate().length());
            before = before.max(hit(3.5).truncate().length());
            n += 1;
        }
        assert!(n > 100, "{n} rays got through");
        assert!(
            at_focus < 0.25 * before && at_focus < 1e-3,
            "{at_focus} vs {before}"
        );
    }

    #[test]
    fn the_image_is_upright_and_the_corners_are_vignetted() {
        let mean = |c: &Camera, p: Vec2| {
            let (mut sum, mut direction) = (0.0, Vec3::ZERO);
            for u in lens_grid() {
                if let Some(cr) = ray(c, p, u) {
                    sum += cr.weight;
                    direction += cr.ray.direction;
                }
            }
            (sum / 256.0, direction.normalize_or_zero())
        };
        let wide = double_gauss(17);
        let (centre, centre_direction) = mean(wide, Vec2::new(30.0, 20.0));
        let (corner, _) = mean(wide, Vec2::new(1.0, 1.0));
        assert!(
            centre > 0.0 && corner < 0.8 * centre,
            "{corner} vs {centre}"
        );
        assert!(
            (centre_direction - Vec3::NEG_Z).length() < 1e-3,
            "{centre_direction}"
        );
        // Top of the image looks up, its right looks to world −x (pbrt's
        // left-handed camera space, as the perspective camera).
        let (_, top) = mean(wide, Vec2::new(30.0, 2.0));
        let (_, right) = mean(wide, Vec2::new(58.0, 20.0));
        assert!(top.y > 0.1 && top.x.abs() < 0.02, "{top}");
        assert!(right.x < -0.1 && right.y.abs() < 0.02, "{right}");
        // The light through the stop goes as its area, (8/17)² ≈ 0.22.
        let (small_centre, _) = mean(double_gauss(8), Vec2::new(30.0, 20.0));
        assert!(
            (small_centre / centre / (8.0f32 / 17.0).powi(2) - 1.0).abs() < 0.2,
            "{small_centre} vs {centre}"
        );
        assert!(wide.uses_lens());
    }

    #[test]
    fn differentials_reach_about_a_pixel_over() {
        let c = double_gauss(8);
        let cr = ray(c, Vec2::new(30.5, 20.5), Vec2::splat(0.5)).unwrap();
        // The plane in focus, 3 m from the film (render space: the camera
        // at the origin looking down −z).
        let p = cr.ray.origin + cr.ray.direction * (-(cr.ray.origin.z + 3.0) / cr.ray.direction.z);
        let (dpdx, dpdy) = c.first_hit_dp_dxy(&cr, p, Vec3::Z, 1);
        // The film is 35 mm across its diagonal: a pixel is
        // 0.035 / √(60² + 40²) m; at 3 m with f = 50 mm it spans ≈ 59×.
        let pixel = 0.035 / (60.0f32 * 60.0 + 40.0 * 40.0).sqrt() * (2.95 / 0.05);
        assert!(
            (dpdx.length() / pixel - 1.0).abs() < 0.1,
            "{dpdx} vs {pixel}"
        );
        assert!(
            (dpdy.length() / pixel - 1.0).abs() < 0.1,
            "{dpdy} vs {pixel}"
        );
    }

    #[test]
    fn lens_file_errors_are_located() {
        let dir = lens_directory("errors");
        let e = camera_in(
            &dir,
            "Camera \"realistic\" \"string lensfile\" \"missing.dat\"",
            IVec2::new(60, 40),
        )
        .err()
        .unwrap()
        .to_string();
        assert!(
            e.contains("c.pbrt:2:") && e.contains("cannot read") && e.contains("missing.dat"),
            "{e}"
        );
        let e = camera_in(&dir, "Camera \"realistic\"", IVec2::new(60, 40))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("c.pbrt:2:") && e.contains("lensfile"), "{e}");
        std::fs::write(dir.join("bad.dat"), "# ok\n10 2 1.5 8\n-10 2 1 eight\n").unwrap();
        let e = camera_in(
            &dir,
            "Camera \"realistic\" \"string lensfile\" \"bad.dat\"",
            IVec2::new(60, 40),
        )
        .err()
        .unwrap()
        .to_string();
        assert!(e.contains("bad.dat:3:9") && e.contains("eight"), "{e}");
        // Closer than the lens can focus.
        let e = camera_in(
            &dir,
            "Camera \"realistic\" \"string lensfile\" \"dgauss.50mm.dat\" \"float focusdistance\" 0.1",
            IVec2::new(60, 40),
        )
        .err()
        .unwrap()
        .to_string();
        assert!(e.contains("c.pbrt:2:") && e.contains("too close"), "{e}");
        let e = camera_in(
            &dir,
            "Camera \"realistic\" \"string lensfile\" \"dgauss.50mm.dat\" \"string aperture\" \"hexagon.png\"",
            IVec2::new(60, 40),
        )
        .err()
        .unwrap()
        .to_string();
        assert!(
            e.contains("c.pbrt:2:") && e.contains("cannot read") && e.contains("hexagon.png"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_shaped_aperture_weighs_rays_through_the_stop() {
        // The pentagon passes the circle's light (its mask is normalised
        // to it), up to what its corners cut off and sampling.
        let dir = lens_directory("shaped");
        let c = camera_in(
            &dir,
            "Camera \"realistic\" \"string lensfile\" \"dgauss.50mm.dat\" \"float aperturediameter\" 8 \"float focusdistance\" 3 \"string aperture\" \"pentagon\"",
            IVec2::new(60, 40),
        )
        .unwrap();
        std::fs::remove_dir_all(&dir).ok();
        let total = |c: &Camera| {
            lens_grid()
                .filter_map(|u| ray(c, Vec2::new(30.0, 20.0), u))
                .map(|cr| {
                    assert!(cr.weight.is_finite() && cr.weight > 0.0);
                    cr.weight
                })
                .sum::<f32>()
        };
        let (pentagon, circle) = (total(&c), total(double_gauss(8)));
        assert!(
            (pentagon / circle - 1.0).abs() < 0.2,
            "{pentagon} vs {circle}"
        );
    }
}
