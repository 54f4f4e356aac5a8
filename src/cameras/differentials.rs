//! How a surface point seen by the camera moves from one pixel to the
//! next, without tracing ray differentials (pbrt-v4's
//! `CameraBase::FindMinimumDifferentials` and `Approximate_dp_dxy`).
//!
//! At creation the camera's ray differentials are sampled along the image
//! diagonal and the smallest kept (in camera space, the direction ones in
//! each ray's own frame). At a hit, rays offset by those from a ray straight
//! at the point are intersected with the hit's tangent plane; the offsets
//! of those intersections, scaled by max(1/8, 1/√spp), are ∂p/∂x, ∂p/∂y.
//! Texture filtering uses them at every hit but the first, where the camera
//! ray's own differentials ([`RayDifferentials`]) give ∂p/∂x, ∂p/∂y
//! (pbrt-v4 also carries differentials through specular bounces; rpbrt
//! approximates there).

use super::CameraTransform;
use crate::math::Frame;
use glam::{Mat3, Vec2, Vec3};

/// The rays one pixel over in x and y from a camera ray, in render space
/// (pbrt-v4's `RayDifferential` offsets).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayDifferentials {
    pub rx_origin: Vec3,
    pub rx_direction: Vec3,
    pub ry_origin: Vec3,
    pub ry_direction: Vec3,
}

impl RayDifferentials {
    /// The offsets scaled by `scale` about the main ray (`origin`,
    /// `direction`): pbrt-v4 narrows camera-ray footprints to
    /// max(1/8, 1/√spp) of a pixel.
    pub fn scaled(&self, origin: Vec3, direction: Vec3, scale: f32) -> Self {
        RayDifferentials {
            rx_origin: origin + (self.rx_origin - origin) * scale,
            rx_direction: direction + (self.rx_direction - direction) * scale,
            ry_origin: origin + (self.ry_origin - origin) * scale,
            ry_direction: direction + (self.ry_direction - direction) * scale,
        }
    }

    /// (∂p/∂x, ∂p/∂y) at `p` on the plane through it with normal `n`: where
    /// the offset rays meet that plane, relative to `p`; `None` when one
    /// runs parallel to it.
    pub fn dp_dxy(&self, p: Vec3, n: Vec3) -> Option<(Vec3, Vec3)> {
        let (nx, ny) = (n.dot(self.rx_direction), n.dot(self.ry_direction));
        if nx == 0.0 || ny == 0.0 {
            return None;
        }
        let d = -n.dot(p);
        let tx = (-n.dot(self.rx_origin) - d) / nx;
        let ty = (-n.dot(self.ry_origin) - d) / ny;
        Some((
            self.rx_origin + tx * self.rx_direction - p,
            self.ry_origin + ty * self.ry_direction - p,
        ))
    }
}

/// A camera ray and its neighbours one pixel over in x and y, in camera
/// space: (origin, direction) each.
pub struct RayWithNeighbours {
    pub ray: (Vec3, Vec3),
    pub x: (Vec3, Vec3),
    pub y: (Vec3, Vec3),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MinimumDifferentials {
    position_x: Vec3,
    position_y: Vec3,
    direction_x: Vec3,
    direction_y: Vec3,
}

impl MinimumDifferentials {
    /// Samples `generate` (film position in raster units → camera-space
    /// rays) at 512 points on the diagonal of a film of `resolution`.
    pub fn find(resolution: Vec2, generate: impl Fn(Vec2) -> Option<RayWithNeighbours>) -> Self {
        let mut m = MinimumDifferentials {
            position_x: Vec3::INFINITY,
            position_y: Vec3::INFINITY,
            direction_x: Vec3::INFINITY,
            direction_y: Vec3::INFINITY,
        };
        let n = 512;
        let keep_shorter = |kept: &mut Vec3, v: Vec3| {
            if v.length() < kept.length() {
                *kept = v;
            }
        };
        for i in 0..n {
            let p_film = resolution * (i as f32 / (n - 1) as f32);
            let Some(r) = generate(p_film) else {
                continue;
            };
            keep_shorter(&mut m.position_x, r.x.0 - r.ray.0);
            keep_shorter(&mut m.position_y, r.y.0 - r.ray.0);
            let d = r.ray.1.normalize();
            let frame = Frame::from_z(d);
            let df = frame.to_local(d);
            let dxf = frame.to_local(r.x.1.normalize()).normalize();
            let dyf = frame.to_local(r.y.1.normalize()).normalize();
            keep_shorter(&mut m.direction_x, dxf - df);
            keep_shorter(&mut m.direction_y, dyf - df);
        }
        m
    }

    /// (∂p/∂x, ∂p/∂y) at render-space point `p` with normal `n`, scaled by
    /// `scale` (max(1/8, 1/√spp)).
    pub fn approximate_dp_dxy(
        &self,
        transform: &CameraTransform,
        p: Vec3,
        n: Vec3,
        scale: f32,
    ) -> (Vec3, Vec3) {
        let p_camera = transform.camera_from_render.transform_point3(p);
        // Normals transform by the inverse transpose.
        let n_camera = Mat3::from_mat4(transform.render_from_camera).transpose() * n;
        let down_z_from_camera = rotate_from_to(p_camera.normalize(), Vec3::Z);
        let p_down_z = down_z_from_camera * p_camera;
        let n_down_z = down_z_from_camera * n_camera;
        let d = n_down_z.z * p_down_z.z;
        let on_plane = |origin: Vec3, direction: Vec3| {
            let t = -(n_down_z.dot(origin) - d) / n_down_z.dot(direction);
            origin + t * direction
        };
        let px = on_plane(self.position_x, Vec3::Z + self.direction_x);
        let py = on_plane(self.position_y, Vec3::Z + self.direction_y);
        let camera_from_down_z = down_z_from_camera.transpose();
        let to_render = |v: Vec3| {
            scale
                * transform
                    .render_from_camera
                    .transform_vector3(camera_from_down_z * v)
        };
        (to_render(px - p_down_z), to_render(py - p_down_z))
    }
}

/// The rotation taking unit vector `from` to unit vector `to`, as pbrt-v4
/// builds it (two reflections through an axis chosen away from both, so
/// the result matches pbrt-v4's frame, not just any such rotation).
fn rotate_from_to(from: Vec3, to: Vec3) -> Mat3 {
    let refl = if from.x.abs() < 0.72 && to.x.abs() < 0.72 {
        Vec3::X
    } else if from.y.abs() < 0.72 && to.y.abs() < 0.72 {
        Vec3::Y
    } else {
        Vec3::Z
    };
    let u = refl - from;
    let v = refl - to;
    let (uu, vv, uv) = (u.dot(u), v.dot(v), u.dot(v));
    // Row i, column j: δij − 2/(u·u) ui uj − 2/(v·v) vi vj + 4 (u·v)/((u·u)(v·v)) vi uj.
    let element = |i: usize, j: usize| {
        let delta = if i == j { 1.0 } else { 0.0 };
        delta - 2.0 / uu * u[i] * u[j] - 2.0 / vv * v[i] * v[j] + 4.0 * uv / (uu * vv) * v[i] * u[j]
    };
    // glam matrices are built from columns.
    Mat3::from_cols(
        Vec3::new(element(0, 0), element(1, 0), element(2, 0)),
        Vec3::new(element(0, 1), element(1, 1), element(2, 1)),
        Vec3::new(element(0, 2), element(1, 2), element(2, 2)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_takes_from_to_to() {
        for from in [
            Vec3::new(0.3, -0.4, 0.8).normalize(),
            Vec3::X,
            Vec3::new(-0.9, 0.1, 0.1).normalize(),
        ] {
            let r = rotate_from_to(from, Vec3::Z);
            assert!((r * from - Vec3::Z).length() < 1e-5, "{from}");
            assert!((r.determinant() - 1.0).abs() < 1e-5);
        }
    }
}
