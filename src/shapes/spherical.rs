//! Spherical polygons seen from a point: their solid angles, and uniform
//! sampling of the directions they subtend (Arvo's spherical triangle
//! sampling, Ureña et al.'s spherical rectangle sampling) with the inverse
//! mappings, as pbrt-v4 uses them for triangle and rectangle lights.

use crate::math::{lerp, safe_asin, safe_sqrt, sqr, Frame};
use crate::shapes::numeric::{clamp, difference_of_products, sum_of_products};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The angle between two unit vectors, accurate for nearly (anti)parallel
/// vectors.
pub fn angle_between(v1: Vec3, v2: Vec3) -> f32 {
    if v1.dot(v2) < 0.0 {
        PI - 2.0 * safe_asin((v1 + v2).length() / 2.0)
    } else {
        2.0 * safe_asin((v2 - v1).length() / 2.0)
    }
}

/// `v` minus its component along the unit vector `w`.
pub fn gram_schmidt(v: Vec3, w: Vec3) -> Vec3 {
    v - v.dot(w) * w
}

/// The unit vector with polar angle θ (given by its sine and cosine) and
/// azimuth φ about +z.
pub fn spherical_direction(sin_theta: f32, cos_theta: f32, phi: f32) -> Vec3 {
    let sin_theta = sin_theta.clamp(-1.0, 1.0);
    Vec3::new(
        sin_theta * phi.cos(),
        sin_theta * phi.sin(),
        cos_theta.clamp(-1.0, 1.0),
    )
}

/// Solid angle of the spherical triangle with unit-vector vertices.
pub fn spherical_triangle_area(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    (2.0 * a
        .dot(b.cross(c))
        .atan2(1.0 + a.dot(b) + a.dot(c) + b.dot(c)))
    .abs()
}

/// Solid angle of the spherical quadrilateral with unit-vector vertices
/// `a b c d` in order around it (0 when two consecutive ones coincide).
pub fn spherical_quad_area(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> f32 {
    let edges = [a.cross(b), b.cross(c), c.cross(d), d.cross(a)];
    if edges.iter().any(|e| e.length_squared() == 0.0) {
        return 0.0;
    }
    let [axb, bxc, cxd, dxa] = edges.map(Vec3::normalize);
    let alpha = angle_between(dxa, -axb);
    let beta = angle_between(axb, -bxc);
    let gamma = angle_between(bxc, -cxd);
    let delta = angle_between(cxd, -dxa);
    (alpha + beta + gamma + delta - 2.0 * PI).abs()
}

/// The triangle's spherical triangle from `p`: unit vectors to its
/// vertices, the normalised great-circle plane of edge ab and its three
/// angles. `None` when an edge degenerates.
struct SphericalTriangle {
    a: Vec3,
    b: Vec3,
    c: Vec3,
    n_ab: Vec3,
    alpha: f32,
    beta: f32,
    gamma: f32,
}

impl SphericalTriangle {
    fn new(v: [Vec3; 3], p: Vec3) -> Option<Self> {
        let a = (v[0] - p).try_normalize()?;
        let b = (v[1] - p).try_normalize()?;
        let c = (v[2] - p).try_normalize()?;
        let n_ab = a.cross(b).try_normalize()?;
        let n_bc = b.cross(c).try_normalize()?;
        let n_ca = c.cross(a).try_normalize()?;
        Some(SphericalTriangle {
            a,
            b,
            c,
            n_ab,
            alpha: angle_between(n_ab, -n_ca),
            beta: angle_between(n_bc, -n_ab),
            gamma: angle_between(n_ca, -n_bc),
        })
    }
}

/// A direction from `p` uniformly distributed over the solid angle of the
/// triangle `v`, returned as the barycentrics of the point it hits, and the
/// density (1/solid angle; 0 for a degenerate spherical triangle).
pub fn sample_spherical_triangle(v: [Vec3; 3], p: Vec3, u: Vec2) -> ([f32; 3], f32) {
    let Some(t) = SphericalTriangle::new(v, p) else {
        return ([0.0; 3], 0.0);
    };
    let (a, b, c) = (t.a, t.b, t.c);
    let alpha = t.alpha;

    // Pick the sub-triangle area A' uniformly, which fixes the vertex c'
    // on the arc from a to c.
    let area_plus_pi = t.alpha + t.beta + t.gamma;
    let sub_area_plus_pi = lerp(u.x, PI, area_plus_pi);
    let area = area_plus_pi - PI;
    let pdf = if area <= 0.0 { 0.0 } else { 1.0 / area };

    let (cos_alpha, sin_alpha) = (alpha.cos(), alpha.sin());
    let sin_phi = sub_area_plus_pi.cos() * sin_alpha - sub_area_plus_pi.sin() * cos_alpha;
    let cos_phi = -sub_area_plus_pi.cos() * cos_alpha - sub_area_plus_pi.sin() * sin_alpha;
    let k1 = cos_phi - cos_alpha;
    let k2 = sin_phi + sin_alpha * a.dot(b);
    let cos_b_prime = (difference_of_products(k2, cos_phi, k1, sin_phi) * cos_alpha - k2)
        / (sum_of_products(k2, sin_phi, k1, cos_phi) * sin_alpha);
    if cos_b_prime.is_nan() {
        // The triangle covers (nearly) a whole hemisphere.
        return ([1.0 / 3.0; 3], 0.0);
    }
    let cos_b_prime = cos_b_prime.clamp(-1.0, 1.0);
    let sin_b_prime = safe_sqrt(1.0 - sqr(cos_b_prime));
    let c_prime = cos_b_prime * a + sin_b_prime * gram_schmidt(c, a).normalize_or_zero();

    // Then the direction along the arc from b to c'.
    let cos_theta = 1.0 - u.y * (1.0 - c_prime.dot(b));
    let sin_theta = safe_sqrt(1.0 - sqr(cos_theta));
    let w = cos_theta * b + sin_theta * gram_schmidt(c_prime, b).normalize_or_zero();

    // Barycentrics of the point the direction hits.
    let e1 = v[1] - v[0];
    let e2 = v[2] - v[0];
    let s1 = w.cross(e2);
    let divisor = s1.dot(e1);
    if divisor == 0.0 {
        return ([1.0 / 3.0; 3], pdf);
    }
    let inv_divisor = 1.0 / divisor;
    let s = p - v[0];
    let mut b1 = (s.dot(s1) * inv_divisor).clamp(0.0, 1.0);
    let mut b2 = (w.dot(s.cross(e1)) * inv_divisor).clamp(0.0, 1.0);
    if b1 + b2 > 1.0 {
        let sum = b1 + b2;
        b1 /= sum;
        b2 /= sum;
    }
    ([1.0 - b1 - b2, b1, b2], pdf)
}

/// The sample `u` for which [`sample_spherical_triangle`] gives the
/// direction `w` (Arvo's inversion).
pub fn invert_spherical_triangle_sample(v: [Vec3; 3], p: Vec3, w: Vec3) -> Vec2 {
    let Some(t) = SphericalTriangle::new(v, p) else {
        return Vec2::ZERO;
    };
    let (a, b, c) = (t.a, t.b, t.c);

    // c' is where the great circle through b and w meets the arc a–c.
    let mut c_prime = b.cross(w).cross(c.cross(a)).normalize_or_zero();
    if c_prime.dot(a + c) < 0.0 {
        c_prime = -c_prime;
    }

    let u0 = if a.dot(c_prime) > 0.999_998_5 {
        0.0
    } else {
        let n_cpb = c_prime.cross(b);
        let n_acp = a.cross(c_prime);
        let (Some(n_cpb), Some(n_acp)) = (n_cpb.try_normalize(), n_acp.try_normalize()) else {
            return Vec2::splat(0.5);
        };
        let sub_area_plus_pi =
            t.alpha + angle_between(t.n_ab, n_cpb) + angle_between(n_acp, -n_cpb);
        let area_plus_pi = t.alpha + t.beta + t.gamma;
        (sub_area_plus_pi - PI) / (area_plus_pi - PI)
    };
    let u1 = (1.0 - w.dot(b)) / (1.0 - c_prime.dot(b));
    Vec2::new(u0.clamp(0.0, 1.0), u1.clamp(0.0, 1.0))
}

/// The rectangle `corner + s·ex + t·ey` (s, t ∈ [0,1]; ex ⟂ ey) seen from
/// `p`: local frame and coordinates, edge-plane normals and angles.
struct SphericalRectangle {
    frame: Frame,
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    z0: f32,
    b0: f32,
    b1: f32,
    g2: f32,
    g3: f32,
    solid_angle: f32,
}

impl SphericalRectangle {
    fn new(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> Self {
        let ex_length = ex.length();
        let ey_length = ey.length();
        let x = ex / ex_length;
        let y = ey / ey_length;
        let mut frame = Frame {
            x,
            y,
            z: x.cross(y),
        };
        let d = frame.to_local(corner - p);
        let mut z0 = d.z;
        // Make z point away from the rectangle.
        if z0 > 0.0 {
            frame.z = -frame.z;
            z0 = -z0;
        }
        let (x0, y0) = (d.x, d.y);
        let (x1, y1) = (x0 + ex_length, y0 + ey_length);
        let v00 = Vec3::new(x0, y0, z0);
        let v01 = Vec3::new(x0, y1, z0);
        let v10 = Vec3::new(x1, y0, z0);
        let v11 = Vec3::new(x1, y1, z0);
        let n0 = v00.cross(v10).normalize_or_zero();
        let n1 = v10.cross(v11).normalize_or_zero();
        let n2 = v11.cross(v01).normalize_or_zero();
        let n3 = v01.cross(v00).normalize_or_zero();
        let g0 = angle_between(-n0, n1);
        let g1 = angle_between(-n1, n2);
        let g2 = angle_between(-n2, n3);
        let g3 = angle_between(-n3, n0);
        let solid_angle =
            (g0 as f64 + g1 as f64 + g2 as f64 + g3 as f64 - 2.0 * std::f64::consts::PI) as f32;
        SphericalRectangle {
            frame,
            x0,
            x1,
            y0,
            y1,
            z0,
            b0: n0.z,
            b1: n2.z,
            g2,
            g3,
            solid_angle,
        }
    }
}

/// A point of the rectangle `corner + s·ex + t·ey` whose direction from `p`
/// is uniformly distributed over the rectangle's solid angle, and the
/// density (1/solid angle; 0 when the rectangle is seen edge-on). Tiny
/// solid angles fall back to the (s, t) point directly, as pbrt does.
pub fn sample_spherical_rectangle(
    p: Vec3,
    corner: Vec3,
    ex: Vec3,
    ey: Vec3,
    u: Vec2,
) -> (Vec3, f32) {
    let r = SphericalRectangle::new(p, corner, ex, ey);
    if r.solid_angle <= 0.0 || r.solid_angle.is_nan() {
        return (corner + u.x * ex + u.y * ey, 0.0);
    }
    let pdf = (1.0 / r.solid_angle).max(0.0);
    if r.solid_angle < 1e-3 {
        return (corner + u.x * ex + u.y * ey, pdf);
    }

    // The x coordinate from the sub-rectangle area.
    let au = u.x * r.solid_angle - r.g2 - r.g3;
    let fu = (au.cos() * r.b0 - r.b1) / au.sin();
    let mut cu = (1.0 / (sqr(fu) + sqr(r.b0)).sqrt()).copysign(fu);
    cu = cu.clamp(-ONE_BELOW_ONE, ONE_BELOW_ONE);
    let xu = clamp(-(cu * r.z0) / safe_sqrt(1.0 - sqr(cu)), r.x0, r.x1);

    // The y coordinate along that column.
    let dd = (sqr(xu) + sqr(r.z0)).sqrt();
    let h0 = r.y0 / (sqr(dd) + sqr(r.y0)).sqrt();
    let h1 = r.y1 / (sqr(dd) + sqr(r.y1)).sqrt();
    let hv = h0 + u.y * (h1 - h0);
    let hv2 = sqr(hv);
    let yv = if hv2 < 1.0 - 1e-6 {
        hv * dd / (1.0 - hv2).sqrt()
    } else {
        r.y1
    };
    (p + r.frame.from_local(Vec3::new(xu, yv, r.z0)), pdf)
}

const ONE_BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

/// The sample `u` for which [`sample_spherical_rectangle`] gives the point
/// `p_rectangle`.
pub fn invert_spherical_rectangle_sample(
    p: Vec3,
    corner: Vec3,
    ex: Vec3,
    ey: Vec3,
    p_rectangle: Vec3,
) -> Vec2 {
    let r = SphericalRectangle::new(p, corner, ex, ey);
    if r.solid_angle < 1e-3 {
        let q = p_rectangle - corner;
        return Vec2::new(
            q.dot(ex) / ex.length_squared(),
            q.dot(ey) / ey.length_squared(),
        );
    }
    let local = r.frame.to_local(p_rectangle - p);
    let mut xu = clamp(local.x, r.x0, r.x1);
    if xu == 0.0 {
        xu = 1e-10;
    }
    let yv = local.y;
    let z0_sq = sqr(r.z0);

    let inverse_cu_sq = 1.0 + z0_sq / sqr(xu);
    let fu_sq = inverse_cu_sq - sqr(r.b0);
    let fu = fu_sq.sqrt().copysign(xu);
    let root = safe_sqrt(difference_of_products(r.b0, r.b0, r.b1, r.b1) + fu_sq);
    let mut au =
        (-(r.b1 * fu) - (r.b0 * root).copysign(fu * r.b0)).atan2(r.b0 * r.b1 - root * fu.abs());
    if au > 0.0 {
        au -= 2.0 * PI;
    }
    if fu == 0.0 {
        au = PI;
    }
    let u0 = (au + r.g2 + r.g3) / r.solid_angle;

    let dd_sq = sqr(xu) + z0_sq;
    let dd = dd_sq.sqrt();
    let h0 = r.y0 / (dd_sq + sqr(r.y0)).sqrt();
    let h1 = r.y1 / (dd_sq + sqr(r.y1)).sqrt();
    let yv_sq = sqr(yv);
    let spread = (h0 - h1).abs() * (yv_sq * (dd_sq + yv_sq)).sqrt() / (dd_sq + yv_sq);
    let base = difference_of_products(h0, h0, h0, h1);
    let candidates = [
        (base - spread) / sqr(h0 - h1),
        (base + spread) / sqr(h0 - h1),
    ];
    // Keep the root whose y reproduces the point's.
    let y_of = |u1: f32| {
        let hv = lerp(u1, h0, h1);
        hv * dd / (1.0 - sqr(hv)).sqrt()
    };
    let u1 = if (y_of(candidates[0]) - yv).abs() < (y_of(candidates[1]) - yv).abs() {
        candidates[0]
    } else {
        candidates[1]
    };
    Vec2::new(u0.clamp(0.0, 1.0), u1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> impl Iterator<Item = Vec2> {
        (0..n * n).map(move |k| {
            Vec2::new(
                ((k % n) as f32 + 0.5) / n as f32,
                ((k / n) as f32 + 0.5) / n as f32,
            )
        })
    }

    #[test]
    fn octant_triangle_has_solid_angle_pi_over_two() {
        let area = spherical_triangle_area(Vec3::X, Vec3::Y, Vec3::Z);
        assert!((area - PI / 2.0).abs() < 1e-6);
        let quad = spherical_quad_area(Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y);
        assert!((quad - 2.0 * PI).abs() < 1e-4, "{quad}");
    }

    #[test]
    fn spherical_triangle_samples_land_on_the_triangle_and_invert() {
        let v = [
            Vec3::new(-1.0, -0.5, 2.0),
            Vec3::new(1.5, -0.2, 2.5),
            Vec3::new(0.2, 1.0, 1.5),
        ];
        let p = Vec3::new(0.1, 0.0, -0.3);
        let expected = 1.0
            / spherical_triangle_area(
                (v[0] - p).normalize(),
                (v[1] - p).normalize(),
                (v[2] - p).normalize(),
            );
        for u in grid(40) {
            let (b, pdf) = sample_spherical_triangle(v, p, u);
            assert!((pdf - expected).abs() < 1e-3 * expected);
            assert!(b.iter().all(|&x| (-1e-5..=1.0 + 1e-5).contains(&x)));
            let hit = b[0] * v[0] + b[1] * v[1] + b[2] * v[2];
            let back = invert_spherical_triangle_sample(v, p, (hit - p).normalize());
            assert!((back - u).abs().max_element() < 2e-3, "{u} -> {back}");
        }
    }

    #[test]
    fn spherical_rectangle_samples_land_on_the_rectangle_and_invert() {
        let corner = Vec3::new(-1.0, -0.5, 3.0);
        let ex = Vec3::new(2.0, 0.0, 0.0);
        let ey = Vec3::new(0.0, 1.5, 0.5);
        let p = Vec3::new(0.3, 0.2, 0.0);
        for u in grid(30) {
            let (q, pdf) = sample_spherical_rectangle(p, corner, ex, ey, u);
            assert!(pdf > 0.0);
            let local = q - corner;
            let s = local.dot(ex) / ex.length_squared();
            let t = local.dot(ey) / ey.length_squared();
            assert!(
                (-1e-4..=1.0001).contains(&s) && (-1e-4..=1.0001).contains(&t),
                "{s} {t}"
            );
            let back = invert_spherical_rectangle_sample(p, corner, ex, ey, q);
            assert!((back - u).abs().max_element() < 2e-3, "{u} -> {back}");
        }
    }
}
