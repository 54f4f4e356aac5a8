//! A bilinear patch of a [`BilinearPatchMesh`] (pbrt-v4's `bilinearmesh`,
//! and the quads of a `plymesh`): p(u,v) = lerp(u, lerp(v, p00, p01),
//! lerp(v, p10, p11)).
//!
//! | parameter     | type      | default                  | meaning                      |
//! |---------------|-----------|--------------------------|------------------------------|
//! | `P`           | point3[]  | required                 | vertex positions             |
//! | `indices`     | integer[] | `0 1 2 3` if exactly 4 `P` | p00 p10 p01 p11 per patch  |
//! | `N`           | normal[]  | none                     | per-vertex shading normals   |
//! | `uv`          | point2[]  | the patch's own (u,v)    | per-vertex texture (s,t)     |
//! | `faceIndices` | integer[] | none                     | per-patch face index (Ptex)  |
//!
//! Ray tests follow pbrt-v4 (after Reshetov 2019): a quadratic in u for the
//! distance from the ray to the patch's u iso-lines, then v and t from 3×3
//! determinants. The geometric normal is ∂p/∂u × ∂p/∂v, negated under
//! `ReverseOrientation` XOR a handedness-swapping transform; with normals
//! `N` the shading frame is the true one rotated onto the interpolated
//! normal (and the geometric normal turned to its side).
//!
//! Sampling: rectangles by solid angle (spherical rectangle sampling, with
//! the bilinear cos θ warp at surface receivers) unless they subtend less
//! than 10⁻⁴ sr; other patches by approximately uniform area (a bilinear
//! warp by the corner area densities). pbrt-v4's `emissionfilename`
//! image-driven sampling is not supported. `pdf_from` evaluates the area
//! density at the hit's parametric (u,v) directly (pbrt-v4 recovers it by
//! inverting the interpolated texture coordinates).

use super::mesh::BilinearPatchMesh;
use super::numeric::difference_of_products;
use super::spherical::{
    invert_spherical_rectangle_sample, sample_spherical_rectangle, spherical_quad_area,
};
use super::surface::{
    face_forward, set_shading_geometry, surface_interaction, weingarten_normal_derivatives,
    SurfacePoint,
};
use super::warps::{bilinear_pdf, sample_bilinear};
use super::{
    area_sample_to_solid_angle, ShapeIntersection, ShapeSample, ShapeSampleContext, ShapeStorage,
};
use crate::interaction::SurfaceInteraction;
use crate::math::ray::gamma;
use crate::math::{Bounds3, Ray};
use glam::{Vec2, Vec3};

/// Rectangles subtending less than this solid angle (sr) are sampled by
/// area.
const MIN_SPHERICAL_SAMPLE_AREA: f32 = 1e-4;

/// Patch `index` of mesh `mesh` of a [`ShapeStorage`] (the `bilinearmesh`
/// parameters and conventions: see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BilinearPatch {
    pub mesh: u32,
    pub index: u32,
}

/// Parametric (u,v) and ray parameter of a ray–patch hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BilinearHit {
    pub uv: Vec2,
    pub t: f32,
}

fn lerp3(t: f32, a: Vec3, b: Vec3) -> Vec3 {
    (1.0 - t) * a + t * b
}

fn lerp2(t: f32, a: Vec2, b: Vec2) -> Vec2 {
    (1.0 - t) * a + t * b
}

/// Roots of a·x² + b·x + c = 0, smaller first (pbrt's `Quadratic`).
fn solve_quadratic(a: f32, b: f32, c: f32) -> Option<(f32, f32)> {
    if a == 0.0 {
        if b == 0.0 {
            return None;
        }
        let root = -c / b;
        return Some((root, root));
    }
    let discriminant = difference_of_products(b, b, 4.0 * a, c);
    if discriminant < 0.0 {
        return None;
    }
    let root = discriminant.sqrt();
    let q = -0.5 * (b + root.copysign(b));
    let (t0, t1) = (q / a, c / q);
    Some(if t0 > t1 { (t1, t0) } else { (t0, t1) })
}

/// The determinant of the 3×3 matrix with columns `a`, `b`, `c`, with
/// compensated products.
fn determinant3(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    // Rows are (a.x b.x c.x), (a.y b.y c.y), (a.z b.z c.z).
    let minor12 = difference_of_products(b.y, c.z, c.y, b.z);
    let minor02 = difference_of_products(a.y, c.z, c.y, a.z);
    let minor01 = difference_of_products(a.y, b.z, b.y, a.z);
    c.x.mul_add(minor01, difference_of_products(a.x, minor12, b.x, minor02))
}

/// v and t of the hit on the u iso-line at `u`, if in range.
fn iso_line_hit(ray: &Ray, u: f32, p00: Vec3, p10: Vec3, p01: Vec3, p11: Vec3) -> (f32, f32, f32) {
    let uo = lerp3(u, p00, p10);
    let ud = lerp3(u, p01, p11) - uo;
    let delta_o = uo - ray.origin;
    let perpendicular = ray.direction.cross(ud);
    let perpendicular2 = perpendicular.length_squared();
    let v = determinant3(delta_o, ray.direction, perpendicular);
    let t = determinant3(delta_o, ud, perpendicular);
    (v, t, perpendicular2)
}

/// The closest hit with 0 < t < t_max of the patch p00 p10 p01 p11.
pub fn intersect_bilinear_patch(
    ray: &Ray,
    t_max: f32,
    p00: Vec3,
    p10: Vec3,
    p01: Vec3,
    p11: Vec3,
) -> Option<BilinearHit> {
    let a = (p10 - p00).cross(p01 - p11).dot(ray.direction);
    let c = (p00 - ray.origin).cross(ray.direction).dot(p01 - p00);
    let b = (p10 - ray.origin).cross(ray.direction).dot(p11 - p10) - (a + c);
    let (u1, u2) = solve_quadratic(a, b, c)?;

    let mut t = t_max;
    let mut uv = Vec2::ZERO;
    if (0.0..=1.0).contains(&u1) {
        let (v1, t1, p2) = iso_line_hit(ray, u1, p00, p10, p01, p11);
        if t1 > 0.0 && 0.0 <= v1 && v1 <= p2 {
            uv = Vec2::new(u1, v1 / p2);
            t = t1 / p2;
        }
    }
    if (0.0..=1.0).contains(&u2) && u2 != u1 {
        let (v2, t2, p2) = iso_line_hit(ray, u2, p00, p10, p01, p11);
        let t2 = t2 / p2;
        if 0.0 <= v2 && v2 <= p2 && t > t2 && t2 > 0.0 {
            t = t2;
            uv = Vec2::new(u2, v2 / p2);
        }
    }
    if t >= t_max {
        return None;
    }
    Some(BilinearHit { uv, t })
}

/// `x` rotated by the rotation taking unit vector `from` to unit vector
/// `to` (pbrt's RotateFromTo: two reflections).
fn rotate_from_to(from: Vec3, to: Vec3, x: Vec3) -> Vec3 {
    let reflection = if from.x.abs() < 0.72 && to.x.abs() < 0.72 {
        Vec3::X
    } else if from.y.abs() < 0.72 && to.y.abs() < 0.72 {
        Vec3::Y
    } else {
        Vec3::Z
    };
    let u = reflection - from;
    let v = reflection - to;
    let (uu, vv, uv) = (u.dot(u), v.dot(v), u.dot(v));
    x - (2.0 / uu) * u.dot(x) * u - (2.0 / vv) * v.dot(x) * v
        + (4.0 * uv / (uu * vv)) * u.dot(x) * v
}

impl BilinearPatch {
    pub fn new(mesh: u32, index: u32) -> Self {
        BilinearPatch { mesh, index }
    }

    /// The mesh this patch belongs to.
    pub fn mesh_of<'a>(&self, storage: &'a ShapeStorage) -> &'a BilinearPatchMesh {
        &storage.bilinear_meshes[self.mesh as usize]
    }

    /// p00, p10, p01, p11.
    fn positions(&self, mesh: &BilinearPatchMesh) -> [Vec3; 4] {
        mesh.patch(self.index).map(|v| mesh.positions[v])
    }

    /// A planar patch whose corners are equidistant from its centre.
    pub fn is_rectangle(&self, mesh: &BilinearPatchMesh) -> bool {
        let [p00, p10, p01, p11] = self.positions(mesh);
        if p00 == p01 || p01 == p11 || p11 == p10 || p10 == p00 {
            return false;
        }
        let n = (p10 - p00).cross(p01 - p00).normalize_or_zero();
        if (p11 - p00).normalize_or_zero().dot(n).abs() > 1e-5 {
            return false;
        }
        let center = (p00 + p01 + p10 + p11) / 4.0;
        let d2 = [p00, p01, p10, p11].map(|p| p.distance_squared(center));
        d2[1..].iter().all(|d| (d - d2[0]).abs() / d2[0] <= 1e-4)
    }

    pub fn bounds(&self, mesh: &BilinearPatchMesh) -> Bounds3 {
        Bounds3::from_points(self.positions(mesh))
    }

    /// Exact for rectangles; otherwise the area of a 3×3 grid of
    /// quadrilaterals on the patch (as pbrt-v4 computes it).
    pub fn area(&self, mesh: &BilinearPatchMesh) -> f32 {
        let [p00, p10, p01, p11] = self.positions(mesh);
        if self.is_rectangle(mesh) {
            return p00.distance(p01) * p00.distance(p10);
        }
        const N: usize = 3;
        let point = |i: usize, j: usize| {
            let (u, v) = (i as f32 / N as f32, j as f32 / N as f32);
            lerp3(u, lerp3(v, p00, p01), lerp3(v, p10, p11))
        };
        let mut area = 0.0;
        for i in 0..N {
            for j in 0..N {
                let diagonal1 = point(i + 1, j + 1) - point(i, j);
                let diagonal2 = point(i + 1, j) - point(i, j + 1);
                area += 0.5 * diagonal1.cross(diagonal2).length();
            }
        }
        area
    }

    pub fn face_index(&self, mesh: &BilinearPatchMesh) -> i32 {
        mesh.face_indices
            .get(self.index as usize)
            .copied()
            .unwrap_or(0)
    }

    fn basic_intersect(
        &self,
        mesh: &BilinearPatchMesh,
        ray: &Ray,
        t_max: f32,
    ) -> Option<BilinearHit> {
        let [p00, p10, p01, p11] = self.positions(mesh);
        intersect_bilinear_patch(ray, t_max, p00, p10, p01, p11)
    }

    pub fn intersect_p(&self, mesh: &BilinearPatchMesh, ray: &Ray, t_max: f32) -> bool {
        self.basic_intersect(mesh, ray, t_max).is_some()
    }

    pub fn intersect(
        &self,
        mesh: &BilinearPatchMesh,
        ray: &Ray,
        t_max: f32,
    ) -> Option<ShapeIntersection> {
        let hit = self.basic_intersect(mesh, ray, t_max)?;
        let mut interaction = self.interaction(mesh, hit.uv, ray.time, -ray.direction);
        interaction.t = hit.t;
        Some(ShapeIntersection {
            interaction,
            t_hit: hit.t,
        })
    }

    /// The surface interaction at parametric `uv` (pbrt-v4's
    /// `BilinearPatch::InteractionFromIntersection`).
    pub fn interaction(
        &self,
        mesh: &BilinearPatchMesh,
        uv: Vec2,
        time: f32,
        wo: Vec3,
    ) -> SurfaceInteraction {
        let vertices = mesh.patch(self.index);
        let [p00, p10, p01, p11] = self.positions(mesh);
        let p = lerp3(uv.x, lerp3(uv.y, p00, p01), lerp3(uv.y, p10, p11));
        let mut dpdu = lerp3(uv.y, p10, p11) - lerp3(uv.y, p00, p01);
        let mut dpdv = lerp3(uv.x, p01, p11) - lerp3(uv.x, p00, p10);

        // Texture coordinates (s,t) and the derivatives with respect to them.
        let mut st = uv;
        let (mut duds, mut dudt, mut dvds, mut dvdt) = (1.0, 0.0, 0.0, 1.0);
        if !mesh.uvs.is_empty() {
            let [uv00, uv10, uv01, uv11] = vertices.map(|v| mesh.uvs[v]);
            st = lerp2(uv.x, lerp2(uv.y, uv00, uv01), lerp2(uv.y, uv10, uv11));
            let dst_du = lerp2(uv.y, uv10, uv11) - lerp2(uv.y, uv00, uv01);
            let dst_dv = lerp2(uv.x, uv01, uv11) - lerp2(uv.x, uv00, uv10);
            let inverse = |x: f32| if x.abs() < 1e-8 { 0.0 } else { 1.0 / x };
            duds = inverse(dst_du.x);
            dvds = inverse(dst_dv.x);
            dudt = inverse(dst_du.y);
            dvdt = inverse(dst_dv.y);
            let dpds = dpdu * duds + dpdv * dvds;
            let mut dpdt = dpdu * dudt + dpdv * dvdt;
            if dpds.cross(dpdt) != Vec3::ZERO {
                if dpdu.cross(dpdv).dot(dpds.cross(dpdt)) < 0.0 {
                    dpdt = -dpdt;
                }
                dpdu = dpds;
                dpdv = dpdt;
            }
        }

        let d2p_duv = (p00 - p01) + (p11 - p10);
        let (dndu, dndv) =
            weingarten_normal_derivatives(dpdu, dpdv, Vec3::ZERO, d2p_duv, Vec3::ZERO);
        let dnds = dndu * duds + dndv * dvds;
        let dndt = dndu * dudt + dndv * dvdt;

        let p_error = gamma(6) * (p00.abs() + p01.abs() + p10.abs() + p11.abs());
        let flip = mesh.reverse_orientation ^ mesh.transform_swaps_handedness;
        let mut interaction = surface_interaction(
            &SurfacePoint {
                p,
                p_error,
                uv: st,
                dpdu,
                dpdv,
                dndu: dnds,
                dndv: dndt,
            },
            wo,
            time,
            flip,
        );

        if !mesh.normals.is_empty() {
            let [n00, n10, n01, n11] = vertices.map(|v| mesh.normals[v]);
            let ns = lerp3(uv.x, lerp3(uv.y, n00, n01), lerp3(uv.y, n10, n11));
            if let Some(ns) = ns.try_normalize() {
                let dndu = lerp3(uv.y, n10, n11) - lerp3(uv.y, n00, n01);
                let dndv = lerp3(uv.x, n01, n11) - lerp3(uv.x, n00, n10);
                let dnds = dndu * duds + dndv * dvds;
                let dndt = dndu * dudt + dndv * dvdt;
                let n = interaction.n.normalize_or_zero();
                let shading_dpdu = rotate_from_to(n, ns, dpdu);
                let shading_dpdv = rotate_from_to(n, ns, dpdv);
                set_shading_geometry(
                    &mut interaction,
                    ns,
                    shading_dpdu,
                    shading_dpdv,
                    dnds,
                    dndt,
                    true,
                );
            }
        }
        interaction
    }

    /// The geometric normal `n` (of a sample) oriented as at a hit.
    fn oriented_normal(&self, mesh: &BilinearPatchMesh, n: Vec3, uv: Vec2) -> Vec3 {
        if !mesh.normals.is_empty() {
            let [n00, n10, n01, n11] = mesh.patch(self.index).map(|v| mesh.normals[v]);
            face_forward(n, lerp3(uv.x, lerp3(uv.y, n00, n01), lerp3(uv.y, n10, n11)))
        } else if mesh.reverse_orientation ^ mesh.transform_swaps_handedness {
            -n
        } else {
            n
        }
    }

    fn texture_coordinates(&self, mesh: &BilinearPatchMesh, uv: Vec2) -> Vec2 {
        if mesh.uvs.is_empty() {
            return uv;
        }
        let [uv00, uv10, uv01, uv11] = mesh.patch(self.index).map(|v| mesh.uvs[v]);
        lerp2(uv.x, lerp2(uv.y, uv00, uv01), lerp2(uv.y, uv10, uv11))
    }

    /// The area densities at the corners (for approximately uniform area
    /// sampling of non-rectangular patches).
    fn corner_area_weights(&self, mesh: &BilinearPatchMesh) -> [f32; 4] {
        let [p00, p10, p01, p11] = self.positions(mesh);
        [
            (p10 - p00).cross(p01 - p00).length(),
            (p10 - p00).cross(p11 - p10).length(),
            (p01 - p00).cross(p11 - p01).length(),
            (p11 - p10).cross(p11 - p01).length(),
        ]
    }

    /// ∂p/∂u × ∂p/∂v at parametric `uv`.
    fn jacobian(&self, mesh: &BilinearPatchMesh, uv: Vec2) -> (Vec3, Vec3, Vec3) {
        let [p00, p10, p01, p11] = self.positions(mesh);
        let pu0 = lerp3(uv.y, p00, p01);
        let pu1 = lerp3(uv.y, p10, p11);
        let dpdu = pu1 - pu0;
        let dpdv = lerp3(uv.x, p01, p11) - lerp3(uv.x, p00, p10);
        (lerp3(uv.x, pu0, pu1), dpdu, dpdv)
    }

    /// A point distributed (approximately, for non-rectangles) uniformly by
    /// area; the density is the exact one of the warp used.
    pub fn sample_area(&self, mesh: &BilinearPatchMesh, u: Vec2) -> Option<ShapeSample> {
        let (uv, pdf) = if self.is_rectangle(mesh) {
            (u, 1.0)
        } else {
            let w = self.corner_area_weights(mesh);
            let uv = sample_bilinear([u.x, u.y], w);
            (Vec2::from(uv), bilinear_pdf(uv, w))
        };
        let (p, dpdu, dpdv) = self.jacobian(mesh, uv);
        if dpdu.length_squared() == 0.0 || dpdv.length_squared() == 0.0 {
            return None;
        }
        let [p00, p10, p01, p11] = self.positions(mesh);
        let cross = dpdu.cross(dpdv);
        Some(ShapeSample {
            p,
            p_error: gamma(6) * (p00.abs() + p01.abs() + p10.abs() + p11.abs()),
            n: self.oriented_normal(mesh, cross.normalize_or_zero(), uv),
            uv: self.texture_coordinates(mesh, uv),
            pdf: pdf / cross.length(),
        })
    }

    /// The area density of [`BilinearPatch::sample_area`] at parametric `uv`.
    fn area_pdf(&self, mesh: &BilinearPatchMesh, uv: Vec2) -> f32 {
        let pdf = if self.is_rectangle(mesh) {
            1.0
        } else {
            bilinear_pdf([uv.x, uv.y], self.corner_area_weights(mesh))
        };
        let (_, dpdu, dpdv) = self.jacobian(mesh, uv);
        pdf / dpdu.cross(dpdv).length()
    }

    /// Unit vectors from `p` to p00, p10, p01, p11.
    fn corner_directions(&self, mesh: &BilinearPatchMesh, p: Vec3) -> [Vec3; 4] {
        self.positions(mesh)
            .map(|corner| (corner - p).normalize_or_zero())
    }

    /// Whether `ctx` sees the patch as a rectangle large enough for
    /// spherical rectangle sampling.
    fn samples_by_solid_angle(
        &self,
        mesh: &BilinearPatchMesh,
        ctx: &ShapeSampleContext,
    ) -> Option<f32> {
        if !self.is_rectangle(mesh) {
            return None;
        }
        let [v00, v10, v01, v11] = self.corner_directions(mesh, ctx.p);
        let solid_angle = spherical_quad_area(v00, v10, v11, v01);
        (solid_angle > MIN_SPHERICAL_SAMPLE_AREA).then_some(solid_angle)
    }

    fn warp_weights(&self, mesh: &BilinearPatchMesh, ctx: &ShapeSampleContext) -> [f32; 4] {
        self.corner_directions(mesh, ctx.p)
            .map(|v| v.dot(ctx.ns).abs().max(0.01))
    }

    pub fn sample_from(
        &self,
        mesh: &BilinearPatchMesh,
        ctx: &ShapeSampleContext,
        u: Vec2,
    ) -> Option<ShapeSample> {
        if self.samples_by_solid_angle(mesh, ctx).is_none() {
            return area_sample_to_solid_angle(self.sample_area(mesh, u)?, ctx);
        }
        let mut pdf = 1.0;
        let mut u = u;
        if ctx.ns != Vec3::ZERO {
            let w = self.warp_weights(mesh, ctx);
            let warped = sample_bilinear([u.x, u.y], w);
            pdf *= bilinear_pdf(warped, w);
            u = Vec2::from(warped);
        }
        let [p00, p10, p01, _] = self.positions(mesh);
        let (eu, ev) = (p10 - p00, p01 - p00);
        let (p, rectangle_pdf) = sample_spherical_rectangle(ctx.p, p00, eu, ev, u);
        pdf *= rectangle_pdf;
        if pdf == 0.0 {
            return None;
        }
        let uv = Vec2::new(
            (p - p00).dot(eu) / p10.distance_squared(p00),
            (p - p00).dot(ev) / p01.distance_squared(p00),
        );
        Some(ShapeSample {
            p,
            p_error: Vec3::ZERO,
            n: self.oriented_normal(mesh, eu.cross(ev).normalize_or_zero(), uv),
            uv: self.texture_coordinates(mesh, uv),
            pdf,
        })
    }

    pub fn pdf_from(&self, mesh: &BilinearPatchMesh, ctx: &ShapeSampleContext, wi: Vec3) -> f32 {
        let Some(hit) = self.basic_intersect(mesh, &ctx.spawn_ray(wi), f32::INFINITY) else {
            return 0.0;
        };
        let interaction = self.interaction(mesh, hit.uv, ctx.time, -wi);
        let Some(solid_angle) = self.samples_by_solid_angle(mesh, ctx) else {
            let pdf = self.area_pdf(mesh, hit.uv) * ctx.p.distance_squared(interaction.p)
                / interaction.n.dot(-wi).abs();
            return if pdf.is_infinite() { 0.0 } else { pdf };
        };
        let pdf = 1.0 / solid_angle;
        if ctx.ns == Vec3::ZERO {
            return pdf;
        }
        let [p00, p10, p01, _] = self.positions(mesh);
        let u = invert_spherical_rectangle_sample(ctx.p, p00, p10 - p00, p01 - p00, interaction.p);
        bilinear_pdf([u.x, u.y], self.warp_weights(mesh, ctx)) * pdf
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Transform;
    use crate::shapes::mesh::MeshData;
    use crate::shapes::test_support::{check_solid_angle_sampling, mean_and_error, TestRng};
    use crate::shapes::Shape;
    use glam::DVec3;

    fn patch_mesh(
        p: [Vec3; 4],
        transform: &Transform,
        reverse: bool,
        uvs: Vec<Vec2>,
        normals: Vec<Vec3>,
    ) -> BilinearPatchMesh {
        BilinearPatchMesh::new(
            transform,
            reverse,
            MeshData {
                vertex_indices: vec![0, 1, 2, 3],
                positions: p.to_vec(),
                uvs,
                normals,
                ..MeshData::default()
            },
        )
    }

    fn storage_with(mesh: BilinearPatchMesh) -> ShapeStorage {
        ShapeStorage {
            bilinear_meshes: vec![mesh],
            ..Default::default()
        }
    }

    const SQUARE: [Vec3; 4] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(2.0, 1.0, 0.0),
    ];

    /// A saddle: the corners alternate in height.
    const SADDLE: [Vec3; 4] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.5),
        Vec3::new(0.0, 1.0, 0.5),
        Vec3::new(1.0, 1.0, 0.0),
    ];

    #[test]
    fn hits_on_a_rectangle_match_the_analytic_answers() {
        let mesh = patch_mesh(
            SQUARE,
            &Transform::translate(DVec3::new(0.0, 0.0, 1.0)),
            false,
            vec![],
            vec![],
        );
        let patch = BilinearPatch::new(0, 0);
        assert!(patch.is_rectangle(&mesh));
        assert_eq!(patch.area(&mesh), 2.0);
        let ray = Ray::new(Vec3::new(0.5, 0.25, 4.0), -Vec3::Z, 0.0);
        let hit = patch.intersect(&mesh, &ray, f32::INFINITY).unwrap();
        assert!((hit.t_hit - 3.0).abs() < 1e-6);
        let si = hit.interaction;
        assert!((si.p - Vec3::new(0.5, 0.25, 1.0)).length() < 1e-6);
        assert!((si.uv - Vec2::new(0.25, 0.25)).length() < 1e-6);
        assert!((si.n - Vec3::Z).length() < 1e-6);
        assert!((si.dpdu - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6);
        assert!((si.dpdv - Vec3::Y).length() < 1e-6);
        assert!(!patch.intersect_p(
            &mesh,
            &Ray::new(Vec3::new(2.5, 0.25, 4.0), -Vec3::Z, 0.0),
            f32::INFINITY
        ));
        assert!(!patch.intersect_p(&mesh, &ray, 2.9));
        // Reverse orientation.
        let reversed = patch_mesh(SQUARE, &Transform::IDENTITY, true, vec![], vec![]);
        let si = patch
            .intersect(&reversed, &ray, f32::INFINITY)
            .unwrap()
            .interaction;
        assert!((si.n + Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn hits_on_a_saddle_lie_on_the_surface() {
        let mesh = patch_mesh(SADDLE, &Transform::IDENTITY, false, vec![], vec![]);
        let patch = BilinearPatch::new(0, 0);
        assert!(!patch.is_rectangle(&mesh));
        let mut rng = TestRng::new(41);
        for _ in 0..2000 {
            let uv = rng.uniform2();
            let target = lerp3(
                uv.x,
                lerp3(uv.y, SADDLE[0], SADDLE[2]),
                lerp3(uv.y, SADDLE[1], SADDLE[3]),
            );
            let origin = target + rng.direction_around(Vec3::Z) * rng.range(0.5, 5.0);
            let hit = patch.intersect(
                &mesh,
                &Ray::new(origin, target - origin, 0.0),
                f32::INFINITY,
            );
            let Some(hit) = hit else {
                panic!("missed the saddle at {uv}");
            };
            // The first hit may be elsewhere on the curved patch, but it lies
            // on the patch at its (u,v).
            let si = hit.interaction;
            let expected = lerp3(
                si.uv.x,
                lerp3(si.uv.y, SADDLE[0], SADDLE[2]),
                lerp3(si.uv.y, SADDLE[1], SADDLE[3]),
            );
            assert!((si.p - expected).length() < 1e-4);
            assert!((origin + hit.t_hit * (target - origin) - si.p).length() < 1e-4);
            if hit.t_hit > 0.9999 {
                assert!((si.uv - uv).length() < 1e-3, "{} vs {uv}", si.uv);
            }
            assert!(si.n.dot(si.dpdu).abs() < 1e-4 && si.n.dot(si.dpdv).abs() < 1e-4);
        }
    }

    #[test]
    fn texture_coordinates_and_shading_normals() {
        let uvs = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(4.0, 0.0),
            Vec2::new(0.0, 2.0),
            Vec2::new(4.0, 2.0),
        ];
        let tilt = Vec3::new(0.3, 0.0, 1.0).normalize();
        let mesh = patch_mesh(SQUARE, &Transform::IDENTITY, false, uvs, vec![tilt; 4]);
        let patch = BilinearPatch::new(0, 0);
        let si = patch
            .intersect(
                &mesh,
                &Ray::new(Vec3::new(1.0, 0.5, 1.0), -Vec3::Z, 0.0),
                f32::INFINITY,
            )
            .unwrap()
            .interaction;
        assert!((si.uv - Vec2::new(2.0, 1.0)).length() < 1e-5);
        // dp/ds and dp/dt: s spans 2 units of x over 4 of s.
        assert!((si.dpdu - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-5);
        assert!((si.dpdv - Vec3::new(0.0, 0.5, 0.0)).length() < 1e-5);
        assert!((si.shading.n - tilt).length() < 1e-5);
        assert!(si.shading.dpdu.dot(tilt).abs() < 1e-5 && si.shading.dpdv.dot(tilt).abs() < 1e-5);
        // Normals pointing down turn the geometric normal down.
        let down = patch_mesh(
            SQUARE,
            &Transform::IDENTITY,
            false,
            vec![],
            vec![-Vec3::Z; 4],
        );
        let si = patch
            .intersect(
                &down,
                &Ray::new(Vec3::new(1.0, 0.5, 1.0), -Vec3::Z, 0.0),
                f32::INFINITY,
            )
            .unwrap()
            .interaction;
        assert!((si.n + Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn spawned_rays_never_rehit_a_flat_patch() {
        let mut rng = TestRng::new(43);
        for case in 0..10_000 {
            let scale = if case % 2 == 0 { 1.0 } else { 1e4 };
            let center = rng.direction() * scale;
            let size = if scale == 1.0 {
                rng.range(0.01, 5.0)
            } else {
                rng.range(1.0, 100.0)
            };
            let (e1, e2) = (size * rng.direction(), size * rng.direction());
            let p = [center, center + e1, center + e2, center + e1 + e2];
            let mesh = patch_mesh(p, &Transform::IDENTITY, false, vec![], vec![]);
            let patch = BilinearPatch::new(0, 0);
            let uv = rng.uniform2();
            let target = center + uv.x * e1 + uv.y * e2;
            let origin = target + rng.direction() * size * rng.range(0.1, 10.0);
            let Some(hit) = patch.intersect(
                &mesh,
                &Ray::new(origin, target - origin, 0.0),
                f32::INFINITY,
            ) else {
                continue;
            };
            let si = hit.interaction;
            for _ in 0..2 {
                let w = rng.direction();
                assert!(
                    !patch.intersect_p(&mesh, &si.spawn_ray(w), f32::INFINITY),
                    "case {case}: re-hit"
                );
            }
        }
    }

    #[test]
    fn area_sampling_of_a_saddle_has_the_density_it_claims() {
        let mesh = patch_mesh(SADDLE, &Transform::IDENTITY, false, vec![], vec![]);
        let patch = BilinearPatch::new(0, 0);
        let mut rng = TestRng::new(47);
        // E[1/pdf] over area samples is the area; E[z/pdf] is ∫ z dA.
        let mut inverse = Vec::new();
        let mut z = Vec::new();
        for _ in 0..40_000 {
            let s = patch.sample_area(&mesh, rng.uniform2()).unwrap();
            inverse.push(1.0 / s.pdf as f64);
            z.push(s.p.z as f64 / s.pdf as f64);
        }
        // Reference by a fine midpoint rule on (u,v).
        let n = 400;
        let (mut area, mut z_integral) = (0.0f64, 0.0f64);
        for i in 0..n {
            for j in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (p, dpdu, dpdv) = patch.jacobian(&mesh, uv);
                let da = dpdu.cross(dpdv).length() as f64 / (n * n) as f64;
                area += da;
                z_integral += p.z as f64 * da;
            }
        }
        let (mean, error) = mean_and_error(&inverse);
        assert!(
            (mean - area).abs() < 4.0 * error + 1e-4,
            "{mean} ± {error} vs {area}"
        );
        let (mean_z, error_z) = mean_and_error(&z);
        assert!(
            (mean_z - z_integral).abs() < 4.0 * error_z + 1e-4,
            "{mean_z} vs {z_integral}"
        );
        // pbrt's 3×3 area estimate is close to the true area.
        assert!((patch.area(&mesh) as f64 - area).abs() < 0.01 * area);
    }

    #[test]
    fn solid_angle_sampling_of_rectangles_and_saddles() {
        let rectangle = [
            Vec3::new(-1.0, -0.5, 2.0),
            Vec3::new(1.0, -0.5, 2.0),
            Vec3::new(-1.0, 0.5, 2.5),
            Vec3::new(1.0, 0.5, 2.5),
        ];
        let storage = storage_with(patch_mesh(
            rectangle,
            &Transform::IDENTITY,
            false,
            vec![],
            vec![],
        ));
        let shape = Shape::BilinearPatch(BilinearPatch::new(0, 0));
        let origin = Vec3::new(0.2, 0.1, 0.0);
        let [v00, v10, v01, v11] = rectangle.map(|p| (p - origin).normalize());
        let expected = spherical_quad_area(v00, v10, v11, v01);
        // Cross-check with two spherical triangles.
        let two_triangles = crate::shapes::spherical::spherical_triangle_area(v00, v10, v11)
            + crate::shapes::spherical::spherical_triangle_area(v00, v11, v01);
        assert!((expected - two_triangles).abs() < 1e-4 * expected);
        let tilted = Vec3::new(0.0, 0.6, 0.8);
        let surface = ShapeSampleContext {
            p: origin,
            p_error: Vec3::ZERO,
            n: tilted,
            ns: tilted,
            time: 0.0,
        };
        check_solid_angle_sampling(&shape, &storage, &surface, expected, 51);
        check_solid_angle_sampling(
            &shape,
            &storage,
            &ShapeSampleContext::in_medium(origin, 0.0),
            expected,
            52,
        );

        // A saddle is sampled by area; from far above it is seen once.
        let saddle = storage_with(patch_mesh(
            SADDLE,
            &Transform::IDENTITY,
            false,
            vec![],
            vec![],
        ));
        let above = ShapeSampleContext::in_medium(Vec3::new(0.5, 0.5, 3.0), 0.0);
        // Solid angle ∫ |cos θ| / d² dA by a fine midpoint rule (a height
        // field seen from above: every direction hits it at most once).
        let saddle_patch = BilinearPatch::new(0, 0);
        let n = 400;
        let mut saddle_solid_angle = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (p, dpdu, dpdv) = saddle_patch.jacobian(&saddle.bilinear_meshes[0], uv);
                let d = p - above.p;
                let cross = dpdu.cross(dpdv);
                saddle_solid_angle +=
                    (cross.dot(d).abs() / d.length().powi(3)) as f64 / (n * n) as f64;
            }
        }
        check_solid_angle_sampling(&shape, &saddle, &above, saddle_solid_angle as f32, 54);
    }
}
