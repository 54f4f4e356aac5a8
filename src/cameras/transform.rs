//! Camera space, render space and world space.

use crate::math::{MotionTransform, Transform};
use crate::scene_description::AnimatedTransform;
use glam::{DVec3, Mat4};

/// pbrt-v4's CameraTransform for the "cameraworld" render space: render
/// space is world space translated so the camera sits at the origin (at
/// the middle of its transform times, for a moving camera).
#[derive(Clone, Debug)]
pub struct CameraTransform {
    /// render-from-camera: the camera's whole transform when it stands
    /// still; for a moving camera, where it is at the middle time.
    pub render_from_camera: Mat4,
    pub camera_from_render: Mat4,
    /// World → render, in f64 (applied to every shape's transform).
    pub render_from_world: Transform,
    /// render-from-camera over the shutter interval, for a moving camera
    /// (motion blur).
    motion: Option<Box<MotionTransform>>,
}

impl CameraTransform {
    pub fn new(camera_from_world: &AnimatedTransform) -> Self {
        let start_time = camera_from_world.start_time as f32;
        let end_time = camera_from_world.end_time as f32;
        let world_from_camera = MotionTransform::new(
            camera_from_world.start.inverse(),
            start_time,
            camera_from_world
                .end
                .unwrap_or(camera_from_world.start)
                .inverse(),
            end_time,
        );
        let middle = world_from_camera.at(0.5 * (start_time + end_time));
        let position = middle.point(DVec3::ZERO);
        let render_from_world = Transform::translate(-position);
        let render_from_camera = render_from_world.then(&middle);
        let motion = world_from_camera.is_animated().then(|| {
            Box::new(MotionTransform::new(
                render_from_world.then(world_from_camera.start()),
                start_time,
                render_from_world.then(world_from_camera.end()),
                end_time,
            ))
        });
        CameraTransform {
            render_from_camera: render_from_camera.to_mat4(),
            camera_from_render: render_from_camera.inverse_mat4(),
            render_from_world,
            motion,
        }
    }

    /// Whether the camera moves during the shutter interval.
    pub fn is_moving(&self) -> bool {
        self.motion.is_some()
    }

    /// render-from-camera at `time`.
    #[inline]
    pub fn render_from_camera_at(&self, time: f32) -> Mat4 {
        match &self.motion {
            None => self.render_from_camera,
            Some(motion) => motion.at(time).to_mat4(),
        }
    }
}
