//! A triangle of a [`TriangleMesh`] (pbrt-v4's `trianglemesh`, and the
//! triangles of a `plymesh`).
//!
//! | parameter     | type      | default               | meaning                        |
//! |---------------|-----------|-----------------------|--------------------------------|
//! | `P`           | point3[]  | required              | vertex positions               |
//! | `indices`     | integer[] | `0 1 2` if exactly 3 `P` | 3 vertex indices per triangle |
//! | `N`           | normal[]  | none                  | per-vertex shading normals     |
//! | `S`           | vector3[] | none                  | per-vertex shading tangents    |
//! | `uv`          | point2[]  | (0,0) (1,0) (1,1)     | per-vertex (u,v)               |
//! | `faceIndices` | integer[] | none                  | per-triangle face index (Ptex) |
//!
//! Ray tests use the watertight algorithm of Woop, Benthin and Wald (2013)
//! as pbrt-v4 does (with its double-precision retry on edges and its
//! conservative bound on t), so rays through shared edges and vertices
//! never slip between triangles.
//!
//! Orientation: the geometric normal is (p0 − p2) × (p1 − p2), negated under
//! `ReverseOrientation` XOR a handedness-swapping transform; when the mesh
//! has normals `N`, the geometric normal is instead turned to the side of
//! the interpolated shading normal (pbrt's "orientation is authoritative").
//!
//! Sampling from a point uses pbrt-v4's spherical triangle sampling, warped
//! bilinearly towards cos θ at the receiver when it has a surface normal;
//! triangles subtending very small (< 2·10⁻⁴ sr) or very large (> 6.22 sr)
//! solid angles are sampled by area instead. `pdf_from` returns 0 for
//! directions that miss the triangle (pbrt-v4 returns the spherical
//! density regardless; its callers only ask about directions that hit).

use super::mesh::TriangleMesh;
use super::numeric::{difference_of_products, difference_of_products_vector};
use super::spherical::{
    invert_spherical_triangle_sample, sample_spherical_triangle, spherical_triangle_area,
};
use super::surface::{face_forward, set_shading_geometry, surface_interaction, SurfacePoint};
use super::warps::{bilinear_pdf, sample_bilinear};
use super::{
    area_sample_to_solid_angle, solid_angle_pdf_of_hit, ShapeIntersection, ShapeSample,
    ShapeSampleContext, ShapeStorage,
};
use crate::interaction::SurfaceInteraction;
use crate::math::frame::coordinate_system;
use crate::math::ray::gamma;
use crate::math::sampling::sample_uniform_triangle;
use crate::math::{Bounds3, Ray};
use glam::{Vec2, Vec3};

/// Below this solid angle (sr) triangles are sampled by area.
const MIN_SPHERICAL_SAMPLE_AREA: f32 = 2e-4;
/// Above this solid angle (sr) triangles are sampled by area.
const MAX_SPHERICAL_SAMPLE_AREA: f32 = 6.22;

/// Triangle `index` of mesh `mesh` of a [`ShapeStorage`] (the
/// `trianglemesh` parameters and conventions: see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Triangle {
    pub mesh: u32,
    pub index: u32,
}

/// Barycentrics and ray parameter of a ray–triangle hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub b0: f32,
    pub b1: f32,
    pub b2: f32,
    pub t: f32,
}

/// pbrt's MaxComponentIndex (ties go to the later axis).
fn max_component_index(v: Vec3) -> usize {
    if v.x > v.y {
        if v.x > v.z {
            0
        } else {
            2
        }
    } else if v.y > v.z {
        1
    } else {
        2
    }
}

fn permute(v: Vec3, x: usize, y: usize, z: usize) -> Vec3 {
    Vec3::new(v[x], v[y], v[z])
}

/// The watertight ray–triangle test: in a frame where the ray runs along
/// +z from the origin, the 2D edge functions of the projected vertices
/// decide the hit (recomputed in f64 when one is exactly 0), and t must be
/// provably positive given its error bound.
pub fn intersect_triangle(
    ray: &Ray,
    t_max: f32,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
) -> Option<TriangleHit> {
    if (p2 - p0).cross(p1 - p0).length_squared() == 0.0 {
        return None;
    }
    let kz = max_component_index(ray.direction.abs());
    let kx = (kz + 1) % 3;
    let ky = (kx + 1) % 3;
    let d = permute(ray.direction, kx, ky, kz);
    let mut p0t = permute(p0 - ray.origin, kx, ky, kz);
    let mut p1t = permute(p1 - ray.origin, kx, ky, kz);
    let mut p2t = permute(p2 - ray.origin, kx, ky, kz);

    // Shear so the ray points along +z (z scaling deferred).
    let shear_x = -d.x / d.z;
    let shear_y = -d.y / d.z;
    let shear_z = 1.0 / d.z;
    for p in [&mut p0t, &mut p1t, &mut p2t] {
        p.x += shear_x * p.z;
        p.y += shear_y * p.z;
    }

    let mut e0 = difference_of_products(p1t.x, p2t.y, p1t.y, p2t.x);
    let mut e1 = difference_of_products(p2t.x, p0t.y, p2t.y, p0t.x);
    let mut e2 = difference_of_products(p0t.x, p1t.y, p0t.y, p1t.x);
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        let (x0, y0) = (p0t.x as f64, p0t.y as f64);
        let (x1, y1) = (p1t.x as f64, p1t.y as f64);
        let (x2, y2) = (p2t.x as f64, p2t.y as f64);
        e0 = (y2 * x1 - x2 * y1) as f32;
        e1 = (y0 * x2 - x0 * y2) as f32;
        e2 = (y1 * x0 - x1 * y0) as f32;
    }
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }

    p0t.z *= shear_z;
    p1t.z *= shear_z;
    p2t.z *= shear_z;
    let t_scaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
        return None;
    }
    let inverse_det = 1.0 / det;
    let t = t_scaled * inverse_det;

    // Reject hits whose t is not conservatively greater than zero.
    let max_zt = p0t.z.abs().max(p1t.z.abs()).max(p2t.z.abs());
    let delta_z = gamma(3) * max_zt;
    let max_xt = p0t.x.abs().max(p1t.x.abs()).max(p2t.x.abs());
    let max_yt = p0t.y.abs().max(p1t.y.abs()).max(p2t.y.abs());
    let delta_x = gamma(5) * (max_xt + max_zt);
    let delta_y = gamma(5) * (max_yt + max_zt);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = e0.abs().max(e1.abs()).max(e2.abs());
    let delta_t =
        3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inverse_det.abs();
    if t <= delta_t {
        return None;
    }
    Some(TriangleHit {
        b0: e0 * inverse_det,
        b1: e1 * inverse_det,
        b2: e2 * inverse_det,
        t,
    })
}

impl Triangle {
    pub fn new(mesh: u32, index: u32) -> Self {
        Triangle { mesh, index }
    }

    /// The mesh this triangle belongs to.
    pub fn mesh_of<'a>(&self, storage: &'a ShapeStorage) -> &'a TriangleMesh {
        &storage.triangle_meshes[self.mesh as usize]
    }

    fn positions(&self, mesh: &TriangleMesh) -> [Vec3; 3] {
        mesh.triangle(self.index).map(|v| mesh.positions[v])
    }

    fn uvs(&self, mesh: &TriangleMesh) -> [Vec2; 3] {
        if mesh.uvs.is_empty() {
            [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::ONE]
        } else {
            mesh.triangle(self.index).map(|v| mesh.uvs[v])
        }
    }

    pub fn bounds(&self, mesh: &TriangleMesh) -> Bounds3 {
        Bounds3::from_points(self.positions(mesh))
    }

    pub fn area(&self, mesh: &TriangleMesh) -> f32 {
        let [p0, p1, p2] = self.positions(mesh);
        0.5 * (p1 - p0).cross(p2 - p0).length()
    }

    pub fn face_index(&self, mesh: &TriangleMesh) -> i32 {
        mesh.face_indices
            .get(self.index as usize)
            .copied()
            .unwrap_or(0)
    }

    /// Solid angle subtended at `p`.
    pub fn solid_angle(&self, mesh: &TriangleMesh, p: Vec3) -> f32 {
        let [p0, p1, p2] = self.positions(mesh);
        spherical_triangle_area(
            (p0 - p).normalize_or_zero(),
            (p1 - p).normalize_or_zero(),
            (p2 - p).normalize_or_zero(),
        )
    }

    pub fn intersect_p(&self, mesh: &TriangleMesh, ray: &Ray, t_max: f32) -> bool {
        let [p0, p1, p2] = self.positions(mesh);
        intersect_triangle(ray, t_max, p0, p1, p2).is_some()
    }

    pub fn intersect(
        &self,
        mesh: &TriangleMesh,
        ray: &Ray,
        t_max: f32,
    ) -> Option<ShapeIntersection> {
        let [p0, p1, p2] = self.positions(mesh);
        let hit = intersect_triangle(ray, t_max, p0, p1, p2)?;
        let mut interaction = self.interaction(mesh, &hit, ray.time, -ray.direction);
        interaction.t = hit.t;
        Some(ShapeIntersection {
            interaction,
            t_hit: hit.t,
        })
    }

    /// The surface interaction at barycentrics `hit` (pbrt-v4's
    /// `Triangle::InteractionFromIntersection`).
    pub fn interaction(
        &self,
        mesh: &TriangleMesh,
        hit: &TriangleHit,
        time: f32,
        wo: Vec3,
    ) -> SurfaceInteraction {
        let vertices = mesh.triangle(self.index);
        let [p0, p1, p2] = self.positions(mesh);
        let uv = self.uvs(mesh);
        let (b0, b1, b2) = (hit.b0, hit.b1, hit.b2);

        // ∂p/∂u and ∂p/∂v from the (u,v) parametrisation, or any frame
        // around the normal when it is degenerate.
        let duv02 = uv[0] - uv[2];
        let duv12 = uv[1] - uv[2];
        let dp02 = p0 - p2;
        let dp12 = p1 - p2;
        let determinant = difference_of_products(duv02.x, duv12.y, duv02.y, duv12.x);
        let degenerate_uv = determinant.abs() < 1e-9;
        let (mut dpdu, mut dpdv) = (Vec3::ZERO, Vec3::ZERO);
        if !degenerate_uv {
            let inverse = 1.0 / determinant;
            dpdu = difference_of_products_vector(duv12.y, dp02, duv02.y, dp12) * inverse;
            dpdv = difference_of_products_vector(duv02.x, dp12, duv12.x, dp02) * inverse;
        }
        if degenerate_uv || dpdu.cross(dpdv).length_squared() == 0.0 {
            let mut ng = (p2 - p0).cross(p1 - p0);
            if ng.length_squared() == 0.0 {
                ng = (p2 - p0).as_dvec3().cross((p1 - p0).as_dvec3()).as_vec3();
            }
            (dpdu, dpdv) = coordinate_system(ng.try_normalize().unwrap_or(Vec3::Z));
        }

        let p = b0 * p0 + b1 * p1 + b2 * p2;
        let uv_hit = b0 * uv[0] + b1 * uv[1] + b2 * uv[2];
        let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());
        let flip = mesh.reverse_orientation ^ mesh.transform_swaps_handedness;
        let mut interaction = surface_interaction(
            &SurfacePoint {
                p,
                p_error,
                uv: uv_hit,
                dpdu,
                dpdv,
                dndu: Vec3::ZERO,
                dndv: Vec3::ZERO,
            },
            wo,
            time,
            flip,
        );
        // The true geometric normal, whatever the (u,v) parametrisation.
        let mut n = dp02.cross(dp12).normalize_or_zero();
        if flip {
            n = -n;
        }
        interaction.n = n;
        interaction.shading.n = n;

        if !mesh.normals.is_empty() || !mesh.tangents.is_empty() {
            let interpolate = |values: &[Vec3]| {
                b0 * values[vertices[0]] + b1 * values[vertices[1]] + b2 * values[vertices[2]]
            };
            let ns = if mesh.normals.is_empty() {
                n
            } else {
                interpolate(&mesh.normals).try_normalize().unwrap_or(n)
            };
            let mut ss = if mesh.tangents.is_empty() {
                interaction.dpdu
            } else {
                let s = interpolate(&mesh.tangents);
                if s.length_squared() == 0.0 {
                    interaction.dpdu
                } else {
                    s
                }
            };
            let mut ts = ns.cross(ss);
            if ts.length_squared() > 0.0 {
                ss = ts.cross(ns);
            } else {
                (ss, ts) = coordinate_system(ns);
            }
            let (dndu, dndv) = if mesh.normals.is_empty() {
                (Vec3::ZERO, Vec3::ZERO)
            } else {
                let [n0, n1, n2] = vertices.map(|v| mesh.normals[v]);
                let dn1 = n0 - n2;
                let dn2 = n1 - n2;
                if degenerate_uv {
                    // Derivatives in the same arbitrary frame as dpdu/dpdv.
                    let dn = (n2 - n0).cross(n1 - n0);
                    if dn.length_squared() == 0.0 {
                        (Vec3::ZERO, Vec3::ZERO)
                    } else {
                        coordinate_system(dn)
                    }
                } else {
                    let inverse = 1.0 / determinant;
                    (
                        difference_of_products_vector(duv12.y, dn1, duv02.y, dn2) * inverse,
                        difference_of_products_vector(duv02.x, dn2, duv12.x, dn1) * inverse,
                    )
                }
            };
            set_shading_geometry(&mut interaction, ns, ss, ts, dndu, dndv, true);
        }
        interaction
    }

    /// The geometric normal at barycentrics `b`, oriented as at a hit.
    fn oriented_normal(&self, mesh: &TriangleMesh, b: [f32; 3]) -> Vec3 {
        let [p0, p1, p2] = self.positions(mesh);
        let n = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        if !mesh.normals.is_empty() {
            let [n0, n1, n2] = mesh.triangle(self.index).map(|v| mesh.normals[v]);
            face_forward(n, b[0] * n0 + b[1] * n1 + (1.0 - b[0] - b[1]) * n2)
        } else if mesh.reverse_orientation ^ mesh.transform_swaps_handedness {
            -n
        } else {
            n
        }
    }

    /// The sample at barycentrics `b` with density `pdf`.
    fn sample_at(&self, mesh: &TriangleMesh, b: [f32; 3], pdf: f32) -> ShapeSample {
        let [p0, p1, p2] = self.positions(mesh);
        let uv = self.uvs(mesh);
        let b2 = 1.0 - b[0] - b[1];
        ShapeSample {
            p: b[0] * p0 + b[1] * p1 + b[2] * p2,
            p_error: gamma(6) * ((b[0] * p0).abs() + (b[1] * p1).abs() + (b2 * p2).abs()),
            n: self.oriented_normal(mesh, b),
            uv: b[0] * uv[0] + b[1] * uv[1] + b[2] * uv[2],
            pdf,
        }
    }

    /// A point uniformly distributed by area, density 1/area.
    pub fn sample_area(&self, mesh: &TriangleMesh, u: Vec2) -> Option<ShapeSample> {
        let b = sample_uniform_triangle(u);
        Some(self.sample_at(mesh, b, 1.0 / self.area(mesh)))
    }

    /// The cos θ weights of the bilinear warp at the corners of the
    /// spherical-triangle sample domain: (0,0) and (1,0) map to p1, (0,1)
    /// to p0, (1,1) to p2.
    fn warp_weights(&self, mesh: &TriangleMesh, ctx: &ShapeSampleContext) -> [f32; 4] {
        let [p0, p1, p2] = self.positions(mesh);
        let cosine = |p: Vec3| ctx.ns.dot((p - ctx.p).normalize_or_zero()).abs().max(0.01);
        let (w0, w1, w2) = (cosine(p0), cosine(p1), cosine(p2));
        [w1, w1, w0, w2]
    }

    pub fn sample_from(
        &self,
        mesh: &TriangleMesh,
        ctx: &ShapeSampleContext,
        u: Vec2,
    ) -> Option<ShapeSample> {
        let solid_angle = self.solid_angle(mesh, ctx.p);
        if !(MIN_SPHERICAL_SAMPLE_AREA..=MAX_SPHERICAL_SAMPLE_AREA).contains(&solid_angle) {
            return area_sample_to_solid_angle(self.sample_area(mesh, u)?, ctx);
        }
        let mut pdf = 1.0;
        let mut u = [u.x, u.y];
        if ctx.ns != Vec3::ZERO {
            let w = self.warp_weights(mesh, ctx);
            u = sample_bilinear(u, w);
            pdf = bilinear_pdf(u, w);
        }
        let (b, triangle_pdf) =
            sample_spherical_triangle(self.positions(mesh), ctx.p, Vec2::from(u));
        if triangle_pdf == 0.0 {
            return None;
        }
        Some(self.sample_at(mesh, b, pdf * triangle_pdf))
    }

    pub fn pdf_from(&self, mesh: &TriangleMesh, ctx: &ShapeSampleContext, wi: Vec3) -> f32 {
        let solid_angle = self.solid_angle(mesh, ctx.p);
        let ray = ctx.spawn_ray(wi);
        if !(MIN_SPHERICAL_SAMPLE_AREA..=MAX_SPHERICAL_SAMPLE_AREA).contains(&solid_angle) {
            let hit = self.intersect(mesh, &ray, f32::INFINITY);
            return solid_angle_pdf_of_hit(hit.as_ref(), |_| 1.0 / self.area(mesh), ctx, wi);
        }
        if !self.intersect_p(mesh, &ray, f32::INFINITY) {
            return 0.0;
        }
        let mut pdf = 1.0 / solid_angle;
        if ctx.ns != Vec3::ZERO {
            let u = invert_spherical_triangle_sample(self.positions(mesh), ctx.p, wi);
            pdf *= bilinear_pdf([u.x, u.y], self.warp_weights(mesh, ctx));
        }
        pdf
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Transform;
    use crate::shapes::mesh::MeshData;
    use crate::shapes::test_support::{
        check_sample_densities, check_solid_angle_sampling, TestRng,
    };
    use crate::shapes::Shape;
    use glam::DVec3;

    fn storage_with(mesh: TriangleMesh) -> ShapeStorage {
        ShapeStorage {
            triangle_meshes: vec![mesh],
            ..Default::default()
        }
    }

    fn single(p: [Vec3; 3], transform: &Transform, reverse: bool) -> TriangleMesh {
        TriangleMesh::new(
            transform,
            reverse,
            MeshData {
                vertex_indices: vec![0, 1, 2],
                positions: p.to_vec(),
                ..MeshData::default()
            },
        )
    }

    const UNIT: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

    #[test]
    fn hits_match_the_analytic_answers() {
        let mesh = single(
            UNIT,
            &Transform::translate(DVec3::new(0.0, 0.0, 2.0)),
            false,
        );
        let t = Triangle::new(0, 0);
        let ray = Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z, 0.0);
        let hit = t.intersect(&mesh, &ray, f32::INFINITY).unwrap();
        assert!((hit.t_hit - 3.0).abs() < 1e-6);
        let si = hit.interaction;
        assert!((si.p - Vec3::new(0.25, 0.25, 2.0)).length() < 1e-6);
        assert_eq!(si.n, Vec3::Z);
        // Default (u,v): b0·(0,0) + b1·(1,0) + b2·(1,1) with b = (½, ¼, ¼).
        assert_eq!(si.uv, Vec2::new(0.5, 0.25));
        assert_eq!(si.dpdu, Vec3::X);
        assert_eq!(si.dpdv, Vec3::new(-1.0, 1.0, 0.0));
        assert!(t.intersect(&mesh, &ray, 2.9).is_none());
        assert!(!t.intersect_p(
            &mesh,
            &Ray::new(Vec3::new(0.6, 0.6, 5.0), -Vec3::Z, 0.0),
            f32::INFINITY
        ));
        // Both sides are hit.
        let below = t.intersect(
            &mesh,
            &Ray::new(Vec3::new(0.1, 0.2, -1.0), Vec3::Z, 0.0),
            f32::INFINITY,
        );
        assert!((below.unwrap().t_hit - 3.0).abs() < 1e-6);
    }

    #[test]
    fn uvs_and_normals_are_interpolated() {
        let mesh = TriangleMesh::new(
            &Transform::IDENTITY,
            false,
            MeshData {
                vertex_indices: vec![0, 1, 2],
                positions: UNIT.to_vec(),
                uvs: vec![
                    Vec2::new(0.0, 0.0),
                    Vec2::new(2.0, 0.0),
                    Vec2::new(0.0, 4.0),
                ],
                normals: vec![-Vec3::Z, Vec3::new(0.0, 1.0, -1.0), -Vec3::Z],
                ..MeshData::default()
            },
        );
        let ray = Ray::new(Vec3::new(0.5, 0.25, 1.0), -Vec3::Z, 0.0);
        let si = Triangle::new(0, 0)
            .intersect(&mesh, &ray, f32::INFINITY)
            .unwrap()
            .interaction;
        assert_eq!(si.uv, Vec2::new(1.0, 1.0));
        assert_eq!(si.dpdu, Vec3::new(0.5, 0.0, 0.0));
        assert_eq!(si.dpdv, Vec3::new(0.0, 0.25, 0.0));
        // The normals point down: the geometric normal follows them.
        assert_eq!(si.n, -Vec3::Z);
        let expected_ns =
            (0.25 * -Vec3::Z + 0.5 * Vec3::new(0.0, 1.0, -1.0) + 0.25 * -Vec3::Z).normalize();
        assert!((si.shading.n - expected_ns).length() < 1e-6);
        assert!(si.shading.dpdu.dot(si.shading.n).abs() < 1e-6);
        assert!(si.shading.dndu != Vec3::ZERO || si.shading.dndv != Vec3::ZERO);
    }

    #[test]
    fn orientation_flips_with_reverse_orientation_xor_handedness() {
        let ray = Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.0);
        let mirror = Transform::scale(DVec3::new(1.0, 1.0, -1.0)).unwrap();
        let normal = |t: &Transform, reverse| {
            let mesh = single(UNIT, t, reverse);
            let si = Triangle::new(0, 0)
                .intersect(&mesh, &ray, f32::INFINITY)
                .unwrap()
                .interaction;
            let sample = Triangle::new(0, 0)
                .sample_area(&mesh, Vec2::splat(0.3))
                .unwrap();
            assert_eq!(si.n, sample.n);
            si.n.z
        };
        assert_eq!(normal(&Transform::IDENTITY, false), 1.0);
        assert_eq!(normal(&Transform::IDENTITY, true), -1.0);
        // Mirroring z keeps the triangle in place but swaps handedness.
        assert_eq!(normal(&mirror, false), -1.0);
        assert_eq!(normal(&mirror, true), 1.0);
    }

    #[test]
    fn degenerate_triangles_are_never_hit() {
        let mesh = single(
            [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X],
            &Transform::IDENTITY,
            false,
        );
        let ray = Ray::new(Vec3::new(0.5, 0.0, 1.0), -Vec3::Z, 0.0);
        assert!(!Triangle::new(0, 0).intersect_p(&mesh, &ray, f32::INFINITY));
        // Degenerate (u,v) still gives a usable frame.
        let mesh = TriangleMesh::new(
            &Transform::IDENTITY,
            false,
            MeshData {
                vertex_indices: vec![0, 1, 2],
                positions: UNIT.to_vec(),
                uvs: vec![Vec2::ZERO; 3],
                ..MeshData::default()
            },
        );
        let si = Triangle::new(0, 0)
            .intersect(
                &mesh,
                &Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.0),
                f32::INFINITY,
            )
            .unwrap()
            .interaction;
        assert!(si.dpdu.cross(si.dpdv).normalize().dot(Vec3::Z).abs() > 0.999);
    }

    /// A mesh of `n`×`n` quads, each split in two, on a bumpy surface.
    fn grid_mesh(n: usize, scale: f32, offset: Vec3, rng: &mut TestRng) -> TriangleMesh {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let z = 0.2 * rng.range(-1.0, 1.0);
                positions.push(
                    offset
                        + scale * Vec3::new(i as f32 / n as f32, j as f32 / n as f32, z / n as f32),
                );
            }
        }
        let mut indices = Vec::new();
        for j in 0..n as u32 {
            for i in 0..n as u32 {
                let v00 = j * (n as u32 + 1) + i;
                let (v10, v01, v11) = (v00 + 1, v00 + n as u32 + 1, v00 + n as u32 + 2);
                if (i + j) % 2 == 0 {
                    indices.extend([v00, v10, v11, v00, v11, v01]);
                } else {
                    indices.extend([v00, v10, v01, v10, v11, v01]);
                }
            }
        }
        TriangleMesh::new(
            &Transform::IDENTITY,
            false,
            MeshData {
                vertex_indices: indices,
                positions,
                ..MeshData::default()
            },
        )
    }

    #[test]
    fn rays_through_shared_edges_and_vertices_never_slip_through() {
        let mut rng = TestRng::new(21);
        for (scale, offset) in [(1.0, Vec3::ZERO), (3.0, Vec3::new(1e4, -2e4, 5e3))] {
            let mesh = grid_mesh(4, scale, offset, &mut rng);
            let triangles: Vec<Triangle> = (0..mesh.triangle_count() as u32)
                .map(|i| Triangle::new(0, i))
                .collect();
            let hits_any = |ray: &Ray| {
                triangles
                    .iter()
                    .any(|t| t.intersect_p(&mesh, ray, f32::INFINITY))
            };
            let mut tested = 0;
            for _ in 0..20_000 {
                // A point on an interior edge or at an interior vertex.
                let t = triangles[(rng.next_u32() as usize) % triangles.len()];
                let [a, b, _] = t.positions(&mesh);
                let v = mesh.triangle(t.index);
                let interior = |p: Vec3| {
                    let local = (p - offset) / scale;
                    local.x > 1e-3 && local.x < 0.999 && local.y > 1e-3 && local.y < 0.999
                };
                let along = if rng.uniform() < 0.2 {
                    0.0
                } else {
                    rng.uniform()
                };
                let target = a + along * (b - a);
                if !interior(target) || v[0] == v[1] {
                    continue;
                }
                // Steeper than any face of the grid, so the ray crosses the
                // surface at the target rather than grazing a ridge.
                let mut direction = rng.direction_around(Vec3::Z);
                while direction.z < 0.7 {
                    direction = rng.direction_around(Vec3::Z);
                }
                let origin = target + direction * scale * rng.range(0.5, 20.0);
                let ray = Ray::new(origin, target - origin, 0.0);
                assert!(hits_any(&ray), "ray {origin} → {target} slipped through");
                tested += 1;
            }
            assert!(tested > 10_000);
        }
    }

    #[test]
    fn rays_exactly_through_vertices_and_edges_hit() {
        // A flat grid with exactly representable vertices: rays aimed
        // exactly at vertices and edge midpoints make edge functions exactly
        // zero, which a non-watertight test would treat as a miss.
        let n = 8;
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.push(Vec3::new(i as f32 / n as f32, j as f32 / n as f32, 0.0));
            }
        }
        let mut indices = Vec::new();
        for j in 0..n as u32 {
            for i in 0..n as u32 {
                let v00 = j * (n as u32 + 1) + i;
                let (v10, v01, v11) = (v00 + 1, v00 + n as u32 + 1, v00 + n as u32 + 2);
                indices.extend([v00, v10, v11, v00, v11, v01]);
            }
        }
        let mesh = TriangleMesh::new(
            &Transform::IDENTITY,
            false,
            MeshData {
                vertex_indices: indices,
                positions,
                ..MeshData::default()
            },
        );
        let triangles: Vec<Triangle> = (0..mesh.triangle_count() as u32)
            .map(|i| Triangle::new(0, i))
            .collect();
        let directions = [
            -Vec3::Z,
            Vec3::Z,
            Vec3::new(0.125, 0.0625, -1.0),
            Vec3::new(-0.25, 0.5, -1.0),
            Vec3::new(1.0, 1.0, -1.0),
        ];
        let mut tested = 0;
        for j in 1..2 * n {
            for i in 1..2 * n {
                // Vertices (both even), edge midpoints and diagonal midpoints.
                let target = Vec3::new(i as f32 / (2 * n) as f32, j as f32 / (2 * n) as f32, 0.0);
                for d in directions {
                    let ray = Ray::new(target - 4.0 * d, d, 0.0);
                    let hits = triangles
                        .iter()
                        .filter(|t| t.intersect_p(&mesh, &ray, f32::INFINITY))
                        .count();
                    assert!(hits >= 1, "ray along {d} at {target} slipped through");
                    tested += 1;
                }
            }
        }
        assert_eq!(tested, 15 * 15 * directions.len());
    }

    #[test]
    fn spawned_rays_never_rehit_the_triangle() {
        let mut rng = TestRng::new(23);
        for case in 0..10_000 {
            let scale = if case % 2 == 0 { 1.0 } else { 1e4 };
            let center = rng.direction() * scale;
            let size = if scale == 1.0 {
                rng.range(0.01, 5.0)
            } else {
                rng.range(1.0, 100.0)
            };
            let p = [0, 1, 2].map(|_| center + size * rng.direction());
            let mesh = single(p, &Transform::IDENTITY, false);
            let t = Triangle::new(0, 0);
            let b = sample_uniform_triangle(rng.uniform2());
            let target = b[0] * p[0] + b[1] * p[1] + b[2] * p[2];
            let origin = target + rng.direction() * size * rng.range(0.1, 10.0);
            let Some(hit) = t.intersect(
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
                    !t.intersect_p(&mesh, &si.spawn_ray(w), f32::INFINITY),
                    "case {case}: re-hit"
                );
            }
        }
    }

    #[test]
    fn area_samples_are_uniform() {
        let mesh = single(
            [
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(3.0, 1.0, 0.0),
                Vec3::new(0.0, 2.0, 1.0),
            ],
            &Transform::IDENTITY,
            false,
        );
        let t = Triangle::new(0, 0);
        let mut rng = TestRng::new(29);
        let n = 30_000;
        let mut mean = Vec3::ZERO;
        for _ in 0..n {
            let s = t.sample_area(&mesh, rng.uniform2()).unwrap();
            assert!((s.pdf * t.area(&mesh) - 1.0).abs() < 1e-5);
            mean += s.p / n as f32;
        }
        let centroid = (mesh.positions[0] + mesh.positions[1] + mesh.positions[2]) / 3.0;
        assert!((mean - centroid).length() < 0.02, "{mean} vs {centroid}");
    }

    #[test]
    fn solid_angle_sampling_matches_the_spherical_triangle() {
        let p = [
            Vec3::new(-1.0, -0.5, 2.0),
            Vec3::new(1.5, -0.2, 2.5),
            Vec3::new(0.2, 1.0, 1.5),
        ];
        let storage = storage_with(single(p, &Transform::IDENTITY, false));
        let shape = Shape::Triangle(Triangle::new(0, 0));
        let origin = Vec3::new(0.1, 0.0, -0.3);
        let expected = Triangle::new(0, 0).solid_angle(&storage.triangle_meshes[0], origin);
        let analytic = spherical_triangle_area(
            (p[0] - origin).normalize(),
            (p[1] - origin).normalize(),
            (p[2] - origin).normalize(),
        );
        assert_eq!(expected, analytic);
        // From a surface point (cos θ warp) and from a point in a medium.
        let tilted = Vec3::new(0.6, 0.0, 0.8);
        let surface = ShapeSampleContext {
            p: origin,
            p_error: Vec3::ZERO,
            n: tilted,
            ns: tilted,
            time: 0.0,
        };
        check_solid_angle_sampling(&shape, &storage, &surface, expected, 31);
        check_solid_angle_sampling(
            &shape,
            &storage,
            &ShapeSampleContext::in_medium(origin, 0.0),
            expected,
            32,
        );
        // Tiny (area sampling below 2e-4 sr) and huge (above 6.22 sr) triangles.
        let far = ShapeSampleContext {
            p: Vec3::new(0.0, 0.0, -200.0),
            ..surface
        };
        let far_expected = Triangle::new(0, 0).solid_angle(&storage.triangle_meshes[0], far.p);
        assert!(far_expected < MIN_SPHERICAL_SAMPLE_AREA);
        check_solid_angle_sampling(&shape, &storage, &far, far_expected, 33);
        let big = storage_with(single(
            [
                Vec3::new(-100.0, -100.0, 0.0),
                Vec3::new(200.0, -100.0, 0.0),
                Vec3::new(-100.0, 200.0, 0.0),
            ],
            &Transform::IDENTITY,
            false,
        ));
        let close = ShapeSampleContext {
            p: Vec3::new(0.0, 0.0, 0.05),
            p_error: Vec3::ZERO,
            n: Vec3::Z,
            ns: Vec3::Z,
            time: 0.0,
        };
        let close_expected = Triangle::new(0, 0).solid_angle(&big.triangle_meshes[0], close.p);
        assert!(close_expected > MAX_SPHERICAL_SAMPLE_AREA);
        // (Area sampling from so close has too heavy a tail for E[1/pdf] to
        // converge: check the densities only.)
        check_sample_densities(&shape, &big, &close, 40_000, &mut TestRng::new(34), |_| 1.0);
    }
}
