//! Camera space, render space and world space.

use crate::math::Transform;
use crate::scene_description::AnimatedTransform;
use glam::{DVec3, Mat4};

/// pbrt-v4's CameraTransform for the "cameraworld" render space: render
/// space is world space translated so the camera sits at the origin.
#[derive(Clone, Copy, Debug)]
pub struct CameraTransform {
    pub render_from_camera: Mat4,
    pub camera_from_render: Mat4,
    /// World → render, in f64 (applied to every shape's transform).
    pub render_from_world: Transform,
}

impl CameraTransform {
    pub fn new(camera_from_world: &AnimatedTransform) -> Self {
        // Motion blur of the camera: render space uses the start transform
        // (animated cameras are refused elsewhere until supported).
        let world_from_camera = camera_from_world.start.inverse();
        let position = world_from_camera.point(DVec3::ZERO);
        let render_from_world = Transform::translate(-position);
        let render_from_camera = render_from_world.then(&world_from_camera);
        CameraTransform {
            render_from_camera: render_from_camera.to_mat4(),
            camera_from_render: render_from_camera.inverse_mat4(),
            render_from_world,
        }
    }
}
