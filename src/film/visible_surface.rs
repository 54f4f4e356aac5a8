//! What the `gbuffer` film records besides radiance: the surface a camera
//! ray sees first (pbrt-v4's `VisibleSurface`), and the space the film
//! writes its geometry in.

use crate::spectrum::SampledSpectrum;
use glam::{Mat3, Mat4, Vec2, Vec3};

/// What a camera ray sees first, in render space.
#[derive(Clone, Copy, Debug)]
pub struct VisibleSurface {
    pub p: Vec3,
    pub n: Vec3,
    pub ns: Vec3,
    pub uv: Vec2,
    /// ∂p/∂x and ∂p/∂y: how far the point moves per pixel.
    pub dpdx: Vec3,
    pub dpdy: Vec3,
    /// The BSDF's reflectance for the camera's direction, estimated.
    pub albedo: SampledSpectrum,
}

/// Where the g-buffer's geometry is written: the output space from render
/// space, for points and for normals (inverse transpose).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GBufferSpace {
    pub output_from_render: Mat4,
    pub normal_output_from_render: Mat3,
}
