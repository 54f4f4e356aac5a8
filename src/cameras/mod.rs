//! Cameras: film positions to rays in render space.
//!
//! `perspective`, `orthographic`, `spherical` and `realistic` each have
//! their own file;
//! the parameters the projective ones share (shutter, thin lens, screen
//! window) are read here.
//!
//! Render space is pbrt-v4's default "cameraworld": world axes, origin at the
//! camera, which keeps coordinates small where the rays are.

pub mod aperture;
pub mod differentials;
pub mod importance;
pub mod lens_system;
pub mod orthographic;
pub mod perspective;
pub mod realistic;
pub mod spherical;
pub mod transform;

pub use orthographic::OrthographicCamera;
pub use perspective::PerspectiveCamera;
pub use realistic::{FilmGeometry, RealisticCamera};
pub use spherical::SphericalCamera;
pub use transform::CameraTransform;

use crate::error::{scene_error, Result};
use crate::math::Ray;
use crate::scene_description;
use crate::scene_description::ParamSet;
use crate::spectrum::SampledWavelengths;
use glam::{IVec2, Vec2, Vec3};
use pbrt_parser::Location;

/// Where on the film and lens, and when, a camera ray starts.
#[derive(Clone, Copy, Debug, Default)]
pub struct CameraSample {
    /// Position on the film in raster coordinates (pixels, y down).
    pub p_film: Vec2,
    /// Position on the lens, in [0,1)².
    pub p_lens: Vec2,
    /// Time in [0,1), mapped to the shutter interval.
    pub time: f32,
    /// The pixel filter's weight for this sample.
    pub filter_weight: f32,
}

/// A camera ray and its weight.
#[derive(Clone, Copy, Debug)]
pub struct CameraRay {
    pub ray: Ray,
    pub weight: f32,
    /// Rays one pixel over in x and y, for texture filtering at the first hit.
    pub differentials: Option<differentials::RayDifferentials>,
}

pub enum Camera {
    Perspective(PerspectiveCamera),
    Orthographic(OrthographicCamera),
    Spherical(SphericalCamera),
    Realistic(RealisticCamera),
}

/// `shutteropen`, `shutterclose` (default 0, 1; swapped if reversed, as
/// pbrt-v4 does after a warning).
pub(crate) fn shutter_interval(params: &ParamSet) -> Result<(f32, f32)> {
    let open = params.float("shutteropen", 0.0)? as f32;
    let close = params.float("shutterclose", 1.0)? as f32;
    Ok(if close < open {
        (close, open)
    } else {
        (open, close)
    })
}

/// `lensradius` (default 0: a pinhole) and `focaldistance` (default 10⁶).
/// A lens needs a positive, finite distance to focus at.
pub(crate) fn thin_lens(params: &ParamSet, location: &Location) -> Result<(f32, f32)> {
    let lens_radius = params.float("lensradius", 0.0)? as f32;
    let focal_distance = params.float("focaldistance", 1e6)? as f32;
    if !lens_radius.is_finite() {
        return scene_error(
            format!("\"lensradius\" must be finite, not {lens_radius}"),
            location,
        );
    }
    if lens_radius > 0.0 && !(focal_distance > 0.0 && focal_distance.is_finite()) {
        return scene_error(
            format!("\"focaldistance\" must be positive with a lens, not {focal_distance}"),
            location,
        );
    }
    Ok((lens_radius, focal_distance))
}

/// The screen window, xmin xmax ymin ymax: `screenwindow` if given, else
/// [−a, a] × [−1, 1] for a frame aspect ratio a > 1 (`frameaspectratio`,
/// default the film's), [−1, 1] × [−1/a, 1/a] otherwise.
pub(crate) fn screen_window(
    params: &ParamSet,
    full_resolution: IVec2,
    location: &Location,
) -> Result<[f32; 4]> {
    let frame = params.float(
        "frameaspectratio",
        full_resolution.x as f64 / full_resolution.y as f64,
    )? as f32;
    let mut window = if frame > 1.0 {
        [-frame, frame, -1.0, 1.0]
    } else {
        [-1.0, 1.0, -1.0 / frame, 1.0 / frame]
    };
    let sw = params.floats("screenwindow")?;
    match sw.len() {
        0 => {}
        4 => window = [sw[0] as f32, sw[1] as f32, sw[2] as f32, sw[3] as f32],
        n => {
            return scene_error(
                format!("\"screenwindow\" needs 4 values, not {n}"),
                location,
            )
        }
    }
    if window.iter().any(|v| !v.is_finite()) || window[0] == window[1] || window[2] == window[3] {
        return scene_error(
            format!("the screen window {window:?} is empty or not finite"),
            location,
        );
    }
    Ok(window)
}

/// How much of a pixel a camera ray's footprint spans: max(1/8, 1/√spp),
/// as pbrt-v4 scales its differentials; a whole pixel when the samples are
/// not jittered (pbrt-v4's `disablepixeljitter`: every sample of a pixel
/// is its centre).
fn differential_scale(samples_per_pixel: u32, pixel_jitter: bool) -> f32 {
    if !pixel_jitter {
        return 1.0;
    }
    (1.0 / (samples_per_pixel.max(1) as f32).sqrt()).max(0.125)
}

impl Camera {
    /// Creates the scene's camera for a film of `full_resolution` with
    /// pbrt-v4's default 35 mm diagonal, file names resolving against the
    /// camera's own scene file's directory.
    pub fn create(camera: &scene_description::Camera, full_resolution: IVec2) -> Result<Camera> {
        let directory = camera.entity.location.0.file.directory().to_path_buf();
        Camera::create_for_film(
            camera,
            FilmGeometry {
                full_resolution,
                diagonal: 0.035,
                base_directory: &directory,
            },
        )
    }

    /// Creates the scene's camera for `film`.
    pub fn create_for_film(
        camera: &scene_description::Camera,
        film: FilmGeometry,
    ) -> Result<Camera> {
        let full_resolution = film.full_resolution;
        let entity = &camera.entity;
        let transform = CameraTransform::new(&camera.camera_from_world);
        match entity.kind.as_str() {
            "perspective" => Ok(Camera::Perspective(PerspectiveCamera::create(
                entity,
                transform,
                full_resolution,
            )?)),
            "orthographic" => Ok(Camera::Orthographic(OrthographicCamera::create(
                entity,
                transform,
                full_resolution,
            )?)),
            "spherical" => Ok(Camera::Spherical(SphericalCamera::create(
                entity,
                transform,
                full_resolution,
            )?)),
            "realistic" => Ok(Camera::Realistic(RealisticCamera::create(
                entity, transform, film,
            )?)),
            other => scene_error(
                format!("camera \"{other}\" is not supported yet (supported: perspective, orthographic, spherical, realistic)"),
                &entity.location.0,
            ),
        }
    }

    /// The camera for renders whose samples are (or, with `false`, are
    /// not) jittered across each pixel, which sets how far apart texture
    /// lookups take their neighbours.
    pub fn with_pixel_jitter(mut self, jitter: bool) -> Camera {
        match &mut self {
            Camera::Perspective(c) => c.pixel_jitter = jitter,
            Camera::Orthographic(c) => c.pixel_jitter = jitter,
            Camera::Spherical(c) => c.pixel_jitter = jitter,
            Camera::Realistic(c) => c.pixel_jitter = jitter,
        }
        self
    }

    fn pixel_jitter(&self) -> bool {
        match self {
            Camera::Perspective(c) => c.pixel_jitter,
            Camera::Orthographic(c) => c.pixel_jitter,
            Camera::Spherical(c) => c.pixel_jitter,
            Camera::Realistic(c) => c.pixel_jitter,
        }
    }

    pub fn generate_ray(
        &self,
        sample: &CameraSample,
        _lambda: &SampledWavelengths,
    ) -> Option<CameraRay> {
        match self {
            Camera::Perspective(c) => c.generate_ray(sample),
            Camera::Orthographic(c) => c.generate_ray(sample),
            Camera::Spherical(c) => c.generate_ray(sample),
            Camera::Realistic(c) => c.generate_ray(sample),
        }
    }

    /// Whether rays depend on `CameraSample::p_lens` (a lens of non-zero
    /// radius); without one the sampler need not compute it.
    pub fn uses_lens(&self) -> bool {
        match self {
            Camera::Perspective(c) => c.lens_radius > 0.0,
            Camera::Orthographic(c) => c.lens_radius > 0.0,
            Camera::Spherical(_) => false,
            Camera::Realistic(_) => true,
        }
    }

    /// Approximate (∂p/∂x, ∂p/∂y) at a render-space point with normal `n`
    /// for a render of `samples_per_pixel` (see [`differentials`]).
    pub fn approximate_dp_dxy(&self, p: Vec3, n: Vec3, samples_per_pixel: u32) -> (Vec3, Vec3) {
        let scale = differential_scale(samples_per_pixel, self.pixel_jitter());
        let (minimum, transform) = match self {
            Camera::Perspective(c) => (&c.min_differentials, &c.transform),
            Camera::Orthographic(c) => (&c.min_differentials, &c.transform),
            Camera::Spherical(c) => (&c.min_differentials, &c.transform),
            Camera::Realistic(c) => (&c.min_differentials, &c.transform),
        };
        minimum.approximate_dp_dxy(transform, p, n, scale)
    }

    /// (∂p/∂x, ∂p/∂y) at the first hit `p` (normal `n`) of a camera ray,
    /// from its differentials when it has them (pbrt-v4's
    /// `ComputeDifferentials`), else approximated.
    pub fn first_hit_dp_dxy(
        &self,
        camera_ray: &CameraRay,
        p: Vec3,
        n: Vec3,
        samples_per_pixel: u32,
    ) -> (Vec3, Vec3) {
        let ray = &camera_ray.ray;
        camera_ray
            .differentials
            .and_then(|d| {
                d.scaled(
                    ray.origin,
                    ray.direction,
                    differential_scale(samples_per_pixel, self.pixel_jitter()),
                )
                .dp_dxy(p, n)
            })
            .unwrap_or_else(|| self.approximate_dp_dxy(p, n, samples_per_pixel))
    }

    pub fn transform(&self) -> &CameraTransform {
        match self {
            Camera::Perspective(c) => &c.transform,
            Camera::Orthographic(c) => &c.transform,
            Camera::Spherical(c) => &c.transform,
            Camera::Realistic(c) => &c.transform,
        }
    }

    /// The shutter interval, [open, close].
    pub fn shutter(&self) -> (f32, f32) {
        match self {
            Camera::Perspective(c) => (c.shutter_open, c.shutter_close),
            Camera::Orthographic(c) => (c.shutter_open, c.shutter_close),
            Camera::Spherical(c) => (c.shutter_open, c.shutter_close),
            Camera::Realistic(c) => (c.shutter_open, c.shutter_close),
        }
    }
}
