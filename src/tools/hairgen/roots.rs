//! Where strands grow: roots with their surface normals on a sphere, a
//! head-like cap or a triangle mesh, uniform by area, and the growth
//! direction from the normal (lean, spread). Random numbers come from
//! pbrt-v4's PCG32, one stream per strand, so a strand depends only on the
//! seed and its index.
//!
//! | surface  | roots                                                                 |
//! |----------|-----------------------------------------------------------------------|
//! | sphere   | uniform over the sphere of `--radius` about `--center`; normal outward |
//! | cap      | uniform over the part of that sphere within `--cap-angle` degrees of its top (the pole opposite `--down`): a scalp |
//! | mesh     | a triangle chosen with probability ∝ its area, a uniform point in it; normal: the vertex normals interpolated when the mesh has them, else the face's (counter-clockwise front, or as `ReverseOrientation` and the transform say) |
//!
//! | direction option | meaning                                                     |
//! |------------------|-------------------------------------------------------------|
//! | `--lean V`, `--lean-amount a` | tilt from the normal towards V projected onto the tangent plane, by a·90° (0: along the normal, 1: flat on the surface) |
//! | `--spread deg`   | then a uniform random tilt within a cone of that half-angle |

use super::strand::perpendicular;
use crate::math::pcg32::Pcg32;
use glam::DVec3;
use std::f64::consts::{FRAC_PI_2, TAU};

/// A deterministic random stream.
pub struct Random(Pcg32);

impl Random {
    /// The stream of strand (or guide) `index` for `seed`; `kind` keeps
    /// strands and guides apart.
    pub fn new(seed: u64, kind: u64, index: u64) -> Self {
        let mut rng = Pcg32::default();
        rng.set_sequence_with_seed(
            crate::math::hash::mix_bits(index.wrapping_mul(2).wrapping_add(kind)),
            seed,
        );
        Random(rng)
    }

    /// Uniform in [0, 1), 53 bits.
    pub fn uniform(&mut self) -> f64 {
        let high = u64::from(self.0.uniform_u32());
        let low = u64::from(self.0.uniform_u32());
        (((high << 32) | low) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// A root and the surface's unit normal there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Root {
    pub point: DVec3,
    pub normal: DVec3,
}

/// A triangle with its (optional) vertex normals and its front normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub p: [DVec3; 3],
    /// Vertex normals (not normalised), when the mesh has them.
    pub n: Option<[DVec3; 3]>,
    /// Unit face normal on the front side.
    pub face_normal: DVec3,
}

impl Triangle {
    /// A triangle whose front is counter-clockwise, flipped when `flip`;
    /// with vertex normals, the front is their side. `None` when degenerate.
    pub fn new(p: [DVec3; 3], n: Option<[DVec3; 3]>, flip: bool) -> Option<Self> {
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let mut face_normal = cross.try_normalize()?;
        if flip {
            face_normal = -face_normal;
        }
        if let Some(n) = n {
            if face_normal.dot(n[0] + n[1] + n[2]) < 0.0 {
                face_normal = -face_normal;
            }
        }
        Some(Triangle { p, n, face_normal })
    }

    pub fn area(&self) -> f64 {
        0.5 * (self.p[1] - self.p[0])
            .cross(self.p[2] - self.p[0])
            .length()
    }
}

/// Triangles and the cumulative distribution of their areas.
#[derive(Clone, Debug)]
pub struct TriangleSet {
    pub triangles: Vec<Triangle>,
    cdf: Vec<f64>,
    pub area: f64,
}

impl TriangleSet {
    /// `None` when there is no triangle of positive area.
    pub fn new(triangles: Vec<Triangle>) -> Option<Self> {
        let mut cdf = Vec::with_capacity(triangles.len());
        let mut total = 0.0;
        for t in &triangles {
            total += t.area();
            cdf.push(total);
        }
        (total > 0.0 && total.is_finite()).then_some(TriangleSet {
            triangles,
            cdf,
            area: total,
        })
    }

    /// The triangle holding fraction `u` of the area.
    fn pick(&self, u: f64) -> &Triangle {
        let target = u * self.area;
        let index = self.cdf.partition_point(|&c| c <= target);
        &self.triangles[index.min(self.triangles.len() - 1)]
    }
}

/// A surface strands grow on.
#[derive(Clone, Debug)]
pub enum Surface {
    Sphere {
        center: DVec3,
        radius: f64,
    },
    /// The part of the sphere within the angle whose cosine is `cos_max` of
    /// `up`.
    Cap {
        center: DVec3,
        radius: f64,
        up: DVec3,
        cos_max: f64,
    },
    Mesh(TriangleSet),
}

impl Surface {
    /// The corners of a box around the surface.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        match self {
            Surface::Sphere { center, radius } | Surface::Cap { center, radius, .. } => (
                *center - DVec3::splat(*radius),
                *center + DVec3::splat(*radius),
            ),
            Surface::Mesh(set) => set.triangles.iter().flat_map(|t| t.p).fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(p), hi.max(p)),
            ),
        }
    }

    /// A root uniform by area.
    pub fn sample(&self, random: &mut Random) -> Root {
        match self {
            Surface::Sphere { center, radius } => {
                let z = 1.0 - 2.0 * random.uniform();
                let normal = around(DVec3::Z, z, random.uniform());
                Root {
                    point: *center + normal * *radius,
                    normal,
                }
            }
            Surface::Cap {
                center,
                radius,
                up,
                cos_max,
            } => {
                let cos_theta = 1.0 - random.uniform() * (1.0 - cos_max);
                let normal = around(*up, cos_theta, random.uniform());
                Root {
                    point: *center + normal * *radius,
                    normal,
                }
            }
            Surface::Mesh(set) => {
                let t = set.pick(random.uniform());
                let (u1, u2) = (random.uniform(), random.uniform());
                let root = u1.sqrt();
                let b = [1.0 - root, u2 * root, root * (1.0 - u2)];
                let point = t.p[0] * b[0] + t.p[1] * b[1] + t.p[2] * b[2];
                let interpolated =
                    t.n.and_then(|n| (n[0] * b[0] + n[1] * b[1] + n[2] * b[2]).try_normalize());
                Root {
                    point,
                    normal: interpolated.unwrap_or(t.face_normal),
                }
            }
        }
    }
}

/// The unit vector at cosine `cos_theta` from the unit `axis`, at azimuth
/// 2π·`u`.
fn around(axis: DVec3, cos_theta: f64, u: f64) -> DVec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let x = perpendicular(axis);
    let y = axis.cross(x);
    let (s, c) = (TAU * u).sin_cos();
    (x * (c * sin_theta) + y * (s * sin_theta) + axis * cos_theta).normalize()
}

/// How a strand's growth direction leaves the normal.
#[derive(Clone, Copy, Debug)]
pub struct Lean {
    /// The comb direction (any length; projected onto the tangent plane).
    pub towards: DVec3,
    /// In [0, 1]: the tilt is `amount`·90°.
    pub amount: f64,
    /// Half-angle of the random cone, radians.
    pub spread: f64,
}

impl Lean {
    /// The growth direction at a root with unit `normal`.
    pub fn direction(&self, normal: DVec3, random: &mut Random) -> DVec3 {
        let mut d = normal;
        if self.amount > 0.0 {
            if let Some(t) = (self.towards - normal * self.towards.dot(normal)).try_normalize() {
                let (s, c) = (self.amount * FRAC_PI_2).sin_cos();
                d = (normal * c + t * s).normalize();
            }
        }
        let (u1, u2) = (random.uniform(), random.uniform());
        if self.spread > 0.0 {
            let cos_theta = 1.0 - u1 * (1.0 - self.spread.cos());
            d = around(d, cos_theta, u2);
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cap_roots_stay_within_the_angle() {
        let cap = Surface::Cap {
            center: DVec3::ZERO,
            radius: 2.0,
            up: DVec3::Y,
            cos_max: 0.5,
        };
        for i in 0..2000 {
            let r = cap.sample(&mut Random::new(3, 0, i));
            assert!((r.point.length() - 2.0).abs() < 1e-9);
            assert!(r.normal.y >= 0.5 - 1e-12, "{:?}", r);
        }
    }

    #[test]
    fn mesh_roots_follow_the_area() {
        // Areas 3 : 1 on either side of x = 0.
        let a = Triangle::new(
            [
                DVec3::new(-3.0, 0.0, 0.0),
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(-3.0, 0.0, -2.0),
            ],
            None,
            false,
        )
        .unwrap();
        let b = Triangle::new(
            [
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(0.0, 0.0, -2.0),
            ],
            None,
            false,
        )
        .unwrap();
        assert!(a.face_normal.dot(DVec3::Y) > 0.999);
        let set = TriangleSet::new(vec![a, b]).unwrap();
        assert!((set.area - 4.0).abs() < 1e-12);
        let surface = Surface::Mesh(set);
        let n = 40_000;
        let left = (0..n)
            .filter(|&i| surface.sample(&mut Random::new(1, 0, i)).point.x < 0.0)
            .count();
        let fraction = left as f64 / n as f64;
        let sigma = (0.75 * 0.25 / n as f64).sqrt();
        assert!((fraction - 0.75).abs() < 5.0 * sigma, "{fraction}");
    }

    #[test]
    fn lean_tilts_towards_the_comb_direction() {
        let lean = Lean {
            towards: DVec3::new(1.0, 5.0, 0.0),
            amount: 0.5,
            spread: 0.0,
        };
        let d = lean.direction(DVec3::Y, &mut Random::new(0, 0, 0));
        let expected = DVec3::new(1.0, 1.0, 0.0).normalize();
        assert!((d - expected).length() < 1e-12, "{d}");
    }

    #[test]
    fn streams_differ_by_seed_and_index() {
        let a = Random::new(1, 0, 5).uniform();
        assert_eq!(a, Random::new(1, 0, 5).uniform());
        assert_ne!(a, Random::new(2, 0, 5).uniform());
        assert_ne!(a, Random::new(1, 0, 6).uniform());
        assert_ne!(a, Random::new(1, 1, 5).uniform());
    }
}
