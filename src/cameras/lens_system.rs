//! A lens system of spherical glass interfaces and an aperture stop, as
//! pbrt-v4's realistic camera traces it: the lens file, ray tracing
//! through the elements in either direction, the thick-lens approximation
//! that places the film at the requested focus, and the exit pupil's
//! bounds over the film.
//!
//! # Lens files
//!
//! Whitespace-separated numbers, four per interface, front (scene side)
//! to rear (film side); `#` starts a comment that runs to the end of its
//! line. All lengths are in millimetres:
//!
//! | column | meaning |
//! |---|---|
//! | 1 | curvature radius; positive: the centre is on the film side (convex towards the scene); 0: the aperture stop (flat) |
//! | 2 | thickness: distance along the axis to the next interface (for the last one, to the film; replaced by the focus computation) |
//! | 3 | index of refraction of the medium behind the interface (towards the film); 0 or 1: air |
//! | 4 | aperture diameter of the interface |
//!
//! # Coordinates
//!
//! Camera space has the film at z = 0 and the scene towards +z. The lens
//! elements are traced in "lens space", the same with z negated (the scene
//! towards −z), where each interface's z is minus the sum of the
//! thicknesses from it to the film. Internally every length is in metres.

use super::aperture::ApertureMask;
use crate::bxdfs::geometry::refract;
use crate::error::{scene_error, unreadable_file, Result};
use crate::math::lerp;
use crate::samplers::radical_inverse;
use crate::shapes::numeric::difference_of_products;
use glam::{Vec2, Vec3};
use pbrt_parser::{Location, SourceFile};
use std::path::Path;
use std::sync::Arc;

/// One interface of the lens system, lengths in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensElement {
    /// Signed radius of the spherical surface; 0 for the aperture stop.
    pub curvature_radius: f32,
    /// Axial distance to the next interface (the film, for the last).
    pub thickness: f32,
    /// Index of refraction behind the interface (film side); 0 is air.
    pub eta: f32,
    pub aperture_radius: f32,
}

impl LensElement {
    pub fn is_stop(&self) -> bool {
        self.curvature_radius == 0.0
    }
}

/// Where the thick-lens approximation puts the cardinal points, as lens
/// space z (the film at 0, the scene towards −z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThickLens {
    /// Principal plane and focal point on the film side (found with rays
    /// entering from the scene parallel to the axis).
    pub film_principal_z: f32,
    pub film_focal_z: f32,
    /// Principal plane and focal point on the scene side.
    pub scene_principal_z: f32,
    pub scene_focal_z: f32,
}

impl ThickLens {
    /// The effective focal length: from the film-side principal plane to
    /// the film-side focal point.
    pub fn focal_length(&self) -> f32 {
        self.film_focal_z - self.film_principal_z
    }
}

/// An axis-aligned rectangle on the plane of the rear element, where rays
/// from a band of film positions can pass through the whole system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PupilBounds {
    pub min: Vec2,
    pub max: Vec2,
}

impl PupilBounds {
    /// Nothing yet: min above max, so every point lies outside.
    fn empty() -> Self {
        PupilBounds {
            min: Vec2::splat(f32::MAX),
            max: Vec2::splat(f32::MIN),
        }
    }

    pub fn is_degenerate(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y
    }

    fn contains(&self, p: Vec2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    fn with_point(self, p: Vec2) -> Self {
        PupilBounds {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    pub fn area(&self) -> f32 {
        let d = self.max - self.min;
        d.x * d.y
    }

    /// The point at fractions `u` of the way across.
    pub fn lerp(&self, u: Vec2) -> Vec2 {
        Vec2::new(
            lerp(u.x, self.min.x, self.max.x),
            lerp(u.y, self.min.y, self.max.y),
        )
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct LensSystem {
    /// Front (scene side) to rear (film side).
    pub elements: Vec<LensElement>,
}

/// The numbers of a lens file with the byte offset of each, or a located
/// error at the first word that is not a finite number.
fn parse_numbers(text: &str, file: &Arc<SourceFile>) -> Result<Vec<(f32, usize)>> {
    let mut numbers = Vec::new();
    let mut line_start = 0;
    for line in text.split_inclusive('\n') {
        let content = line.split('#').next().unwrap_or("");
        let mut search_from = 0;
        for word in content.split_whitespace() {
            // Offsets for the error location: where this word starts.
            let offset = line_start + search_from + content[search_from..].find(word).unwrap_or(0);
            search_from = offset - line_start + word.len();
            match word.parse::<f32>() {
                Ok(value) if value.is_finite() => numbers.push((value, offset)),
                _ => {
                    return scene_error(
                        format!("lens file: \"{word}\" is not a finite number"),
                        &Location::new(file.clone(), offset),
                    )
                }
            }
        }
        line_start += line.len();
    }
    Ok(numbers)
}

/// The interfaces described by a lens file's text (see the module
/// documentation), lengths converted to metres. `name` is the file's path,
/// for error locations inside it.
pub fn parse_lens_file(text: &str, name: &Path) -> Result<Vec<LensElement>> {
    let file = SourceFile::in_memory(name, Arc::from(text.as_bytes()));
    let numbers = parse_numbers(text, &file)?;
    if numbers.is_empty() {
        return scene_error("lens file: no lens elements in it", &Location::new(file, 0));
    }
    if numbers.len() % 4 != 0 {
        let (_, offset) = numbers[numbers.len() - numbers.len() % 4];
        return scene_error(
            format!(
                "lens file: {} numbers, not a multiple of four (curvature radius, thickness, index of refraction, aperture diameter per element); this element is incomplete",
                numbers.len()
            ),
            &Location::new(file, offset),
        );
    }
    let mut elements = Vec::with_capacity(numbers.len() / 4);
    for row in numbers.chunks_exact(4) {
        let [radius, thickness, eta, diameter] = [row[0].0, row[1].0, row[2].0, row[3].0];
        let at = |i: usize| Location::new(file.clone(), row[i].1);
        if thickness < 0.0 {
            return scene_error(
                format!("lens file: thickness {thickness} must not be negative"),
                &at(1),
            );
        }
        if eta < 0.0 {
            return scene_error(
                format!("lens file: index of refraction {eta} must not be negative"),
                &at(2),
            );
        }
        if diameter <= 0.0 {
            return scene_error(
                format!("lens file: aperture diameter {diameter} must be positive"),
                &at(3),
            );
        }
        elements.push(LensElement {
            curvature_radius: radius / 1000.0,
            thickness: thickness / 1000.0,
            eta,
            aperture_radius: diameter / 2000.0,
        });
    }
    Ok(elements)
}

/// Reads and parses the lens file at `path`; a file that cannot be read is
/// reported at `location` (where the scene names it).
pub fn read_lens_file(path: &Path, location: &Location) -> Result<Vec<LensElement>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| unreadable_file("camera \"realistic\" lens file", path, &e, location))?;
    parse_lens_file(&text, path)
}

/// The index of refraction of a medium as the lens file gives it: 0 is air.
fn index_of(eta: f32) -> f32 {
    if eta == 0.0 {
        1.0
    } else {
        eta
    }
}

/// Both roots of a·t² + b·t + c, smaller first, as pbrt-v4 computes them in
/// single precision; `None` without real roots.
fn quadratic(a: f32, b: f32, c: f32) -> Option<(f32, f32)> {
    if a == 0.0 {
        if b == 0.0 {
            return None;
        }
        return Some((-c / b, -c / b));
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

/// Where a lens-space ray meets the sphere of `radius` centred on the axis
/// at `z_center`: the parameter t and the unit normal facing back along
/// the ray. Of the two crossings, the one on the element's actual surface
/// (the cap facing the ray's side) is taken.
pub fn intersect_spherical_element(
    radius: f32,
    z_center: f32,
    origin: Vec3,
    direction: Vec3,
) -> Option<(f32, Vec3)> {
    let o = origin - Vec3::new(0.0, 0.0, z_center);
    let a = direction.x * direction.x + direction.y * direction.y + direction.z * direction.z;
    let b = 2.0 * (direction.x * o.x + direction.y * o.y + direction.z * o.z);
    let c = o.x * o.x + o.y * o.y + o.z * o.z - radius * radius;
    let (t0, t1) = quadratic(a, b, c)?;
    // A convex-towards-the-ray surface is the nearer crossing.
    let use_closer = (direction.z > 0.0) ^ (radius < 0.0);
    let t = if use_closer { t0.min(t1) } else { t0.max(t1) };
    if t < 0.0 {
        return None;
    }
    let n = (o + t * direction).normalize();
    let n = if n.dot(-direction) < 0.0 { -n } else { n };
    Some((t, n))
}

/// Camera space ↔ lens space: z negated.
fn flip_z(v: Vec3) -> Vec3 {
    Vec3::new(v.x, v.y, -v.z)
}

impl LensSystem {
    pub fn new(elements: Vec<LensElement>) -> Self {
        LensSystem { elements }
    }

    /// Distance from the film to the rear element.
    pub fn rear_z(&self) -> f32 {
        self.elements.last().map_or(0.0, |e| e.thickness)
    }

    /// Distance from the film to the front element.
    pub fn front_z(&self) -> f32 {
        self.elements.iter().map(|e| e.thickness).sum()
    }

    pub fn rear_element_radius(&self) -> f32 {
        self.elements.last().map_or(0.0, |e| e.aperture_radius)
    }

    /// Traces a camera-space ray leaving the film through the elements,
    /// rear to front. Returns the ray leaving the front element (camera
    /// space, direction not normalised) and its weight: 1, or the
    /// aperture mask's value where it crosses the stop; `None` when an
    /// element or the stop blocks it or it is totally internally reflected.
    pub fn trace_from_film(
        &self,
        origin: Vec3,
        direction: Vec3,
        mask: Option<&ApertureMask>,
    ) -> Option<(Vec3, Vec3, f32)> {
        let (mut o, mut d) = (flip_z(origin), flip_z(direction));
        let mut element_z = 0.0;
        let mut weight = 1.0;
        for (i, element) in self.elements.iter().enumerate().rev() {
            element_z -= element.thickness;
            let (t, n) = if element.is_stop() {
                let t = (element_z - o.z) / d.z;
                // NaN (a ray parallel to the stop) fails here too.
                if t.is_nan() || t < 0.0 {
                    return None;
                }
                (t, Vec3::ZERO)
            } else {
                let z_center = element_z + element.curvature_radius;
                intersect_spherical_element(element.curvature_radius, z_center, o, d)?
            };
            let hit = o + t * d;
            match (element.is_stop(), mask) {
                (true, Some(mask)) => {
                    let uv = (Vec2::new(hit.x, hit.y) / element.aperture_radius + Vec2::ONE) / 2.0;
                    weight = mask.bilerp(uv);
                    if weight == 0.0 {
                        return None;
                    }
                }
                _ => {
                    if hit.x * hit.x + hit.y * hit.y
                        > element.aperture_radius * element.aperture_radius
                    {
                        return None;
                    }
                }
            }
            o = hit;
            if !element.is_stop() {
                // From the glass behind this interface into whatever is in
                // front of it (the previous element's medium, or air).
                let eta_incident = index_of(element.eta);
                let eta_transmitted = if i > 0 {
                    index_of(self.elements[i - 1].eta)
                } else {
                    1.0
                };
                let (w, _) = refract((-d).normalize(), n, eta_transmitted / eta_incident)?;
                d = w;
            }
        }
        Some((flip_z(o), flip_z(d), weight))
    }

    /// Traces a camera-space ray entering from the scene through the
    /// elements, front to rear (the mask is not consulted: this only serves
    /// the thick-lens approximation). Returns the ray leaving the rear
    /// element, camera space.
    pub fn trace_from_scene(&self, origin: Vec3, direction: Vec3) -> Option<(Vec3, Vec3)> {
        let (mut o, mut d) = (flip_z(origin), flip_z(direction));
        let mut element_z = -self.front_z();
        for (i, element) in self.elements.iter().enumerate() {
            let (t, n) = if element.is_stop() {
                let t = (element_z - o.z) / d.z;
                if t.is_nan() || t < 0.0 {
                    return None;
                }
                (t, Vec3::ZERO)
            } else {
                let z_center = element_z + element.curvature_radius;
                intersect_spherical_element(element.curvature_radius, z_center, o, d)?
            };
            let hit = o + t * d;
            if hit.x * hit.x + hit.y * hit.y > element.aperture_radius * element.aperture_radius {
                return None;
            }
            o = hit;
            if !element.is_stop() {
                let eta_incident = if i > 0 {
                    index_of(self.elements[i - 1].eta)
                } else {
                    1.0
                };
                let eta_transmitted = index_of(element.eta);
                let (w, _) = refract((-d).normalize(), n, eta_transmitted / eta_incident)?;
                d = w;
            }
            element_z += element.thickness;
        }
        Some((flip_z(o), flip_z(d)))
    }

    /// Principal plane and focal point (lens-space z) from a ray parallel
    /// to the axis (`incoming`) and what the system makes of it
    /// (`outgoing`), both camera space: the focal point is where the
    /// outgoing ray crosses the axis, the principal plane where it reaches
    /// the incoming ray's height.
    fn cardinal_points(incoming: (Vec3, Vec3), outgoing: (Vec3, Vec3)) -> (f32, f32) {
        let (o, d) = outgoing;
        let t_focal = -o.x / d.x;
        let focal_z = -(o.z + t_focal * d.z);
        let t_principal = (incoming.0.x - o.x) / d.x;
        let principal_z = -(o.z + t_principal * d.z);
        (principal_z, focal_z)
    }

    /// The thick-lens approximation, from rays parallel to the axis at a
    /// small height (a thousandth of the film diagonal) traced both ways;
    /// `None` when either is blocked (the one from the film also by a
    /// closed point of the aperture `mask`, as in pbrt-v4).
    pub fn thick_lens(&self, film_diagonal: f32, mask: Option<&ApertureMask>) -> Option<ThickLens> {
        let x = 0.001 * film_diagonal;
        let from_scene = (
            Vec3::new(x, 0.0, self.front_z() + 1.0),
            Vec3::new(0.0, 0.0, -1.0),
        );
        let to_film = self.trace_from_scene(from_scene.0, from_scene.1)?;
        let (film_principal_z, film_focal_z) = Self::cardinal_points(from_scene, to_film);
        let from_film = (
            Vec3::new(x, 0.0, self.rear_z() - 1.0),
            Vec3::new(0.0, 0.0, 1.0),
        );
        let (o, d, _) = self.trace_from_film(from_film.0, from_film.1, mask)?;
        let (scene_principal_z, scene_focal_z) = Self::cardinal_points(from_film, (o, d));
        Some(ThickLens {
            film_principal_z,
            film_focal_z,
            scene_principal_z,
            scene_focal_z,
        })
    }

    /// The rear element's distance from the film that focuses the thick
    /// lens on a plane `focus_distance` in front of the film: the lens is
    /// moved by δ solving the Gaussian lens equation for the conjugate
    /// distances. `None` when no such position exists (the plane is closer
    /// than the lens can focus).
    pub fn focused_rear_distance(&self, thick: &ThickLens, focus_distance: f32) -> Option<f32> {
        let f = thick.focal_length();
        let z = -focus_distance;
        let (p_film, p_scene) = (thick.film_principal_z, thick.scene_principal_z);
        let c = (p_scene - z - p_film) * (p_scene - z - 4.0 * f - p_film);
        if c.is_nan() || c <= 0.0 {
            return None;
        }
        let delta = (p_scene - z + p_film - c.sqrt()) / 2.0;
        Some(self.rear_z() + delta)
    }

    /// Bounds on the rear element's plane of where rays from film points
    /// (x, 0) with x in [x0, x1] get through the system: the points
    /// `pupil_samples` (fractions of a square 1.5 times the rear element's
    /// radius each way, see [`exit_pupil_samples`]), each paired with a
    /// film point along the segment, grown by twice the points' spacing.
    /// Degenerate when none gets through.
    pub fn bound_exit_pupil(
        &self,
        x0: f32,
        x1: f32,
        mask: Option<&ApertureMask>,
        pupil_samples: &[Vec2],
    ) -> PupilBounds {
        let count = pupil_samples.len().max(1) as f32;
        let rear = 1.5 * self.rear_element_radius();
        let rear_z = self.rear_z();
        let mut bounds = PupilBounds::empty();
        for (i, u) in pupil_samples.iter().enumerate() {
            let film = Vec3::new(lerp((i as f32 + 0.5) / count, x0, x1), 0.0, 0.0);
            let p = Vec2::new(lerp(u.x, -rear, rear), lerp(u.y, -rear, rear));
            // Points already inside need no trace: they cannot grow it.
            if !bounds.contains(p)
                && self
                    .trace_from_film(film, Vec3::new(p.x, p.y, rear_z) - film, mask)
                    .is_some()
            {
                bounds = bounds.with_point(p);
            }
        }
        if bounds.is_degenerate() {
            return bounds;
        }
        let spacing = 2.0 * (Vec2::splat(2.0 * rear)).length() / count.sqrt();
        PupilBounds {
            min: bounds.min - Vec2::splat(spacing),
            max: bounds.max + Vec2::splat(spacing),
        }
    }
}

/// The 2²⁰ points (Halton, bases 2 and 3) over the unit square that
/// [`LensSystem::bound_exit_pupil`] tries, as pbrt-v4 does; the same for
/// every band of the film, so computed once.
pub fn exit_pupil_samples() -> Vec<Vec2> {
    const SAMPLES: u64 = 1024 * 1024;
    (0..SAMPLES)
        .map(|i| Vec2::new(radical_inverse(0, i), radical_inverse(1, i)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A single biconvex lens (radii +R1, −R2, centre thickness d, index
    /// n) followed by air to the film, in lens-file millimetres, with an
    /// aperture stop of `stop` mm diameter 1 mm in front of it.
    pub(crate) fn single_lens_file(r1: f32, r2: f32, d: f32, n: f32, stop: f32) -> String {
        format!("# stop, then one biconvex lens\n0 1 1 {stop}\n{r1} {d} {n} 20\n{r2} 50 1 20\n")
    }

    fn single_lens(r1: f32, r2: f32, d: f32, n: f32) -> LensSystem {
        LensSystem::new(
            parse_lens_file(&single_lens_file(r1, r2, d, n, 10.0), Path::new("t.dat")).unwrap(),
        )
    }

    /// The lensmaker's equation for a thick lens in air:
    /// 1/f = (n − 1) (1/R1 − 1/R2 + (n − 1) d / (n R1 R2)).
    fn lensmaker_focal_length(r1: f32, r2: f32, d: f32, n: f32) -> f32 {
        1.0 / ((n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * d / (n * r1 * r2)))
    }

    #[test]
    fn thick_lens_focal_length_matches_the_lensmakers_equation() {
        for (r1, r2, d, n) in [
            (50.0, -50.0, 5.0, 1.5),
            (100.0, -40.0, 8.0, 1.7),
            (30.0, 200.0, 4.0, 1.6),
        ] {
            let lens = single_lens(r1, r2, d, n);
            let thick = lens.thick_lens(0.035, None).unwrap();
            let expected = lensmaker_focal_length(r1, r2, d, n) / 1000.0;
            let f = thick.focal_length();
            assert!(
                (f / expected - 1.0).abs() < 2e-3,
                "{r1} {r2} {d} {n}: {f} vs {expected}"
            );
        }
    }

    #[test]
    fn rays_from_the_focused_film_point_converge_on_the_focus_plane() {
        // Focus at 2 m: rays from the on-axis film point cross the axis
        // 2 m in front of the film in the paraxial limit (the thick-lens
        // approximation is paraxial); further out they cross short of it,
        // by an amount growing as the height squared (the singlet's
        // spherical aberration).
        let mut lens = single_lens(50.0, -50.0, 5.0, 1.5);
        let thick = lens.thick_lens(0.035, None).unwrap();
        let rear = lens.focused_rear_distance(&thick, 2.0).unwrap();
        lens.elements.last_mut().unwrap().thickness = rear;
        let rear_z = lens.rear_z();
        let crossing = |h: f32| {
            let (o, d, weight) = lens
                .trace_from_film(Vec3::ZERO, Vec3::new(h, 0.0, rear_z), None)
                .unwrap();
            assert_eq!(weight, 1.0);
            let t = -o.x / d.x;
            o.z + t * d.z
        };
        let paraxial = crossing(0.00005);
        assert!((paraxial - 2.0).abs() < 0.002, "{paraxial}");
        let (near, far) = (2.0 - crossing(0.0002), 2.0 - crossing(0.001));
        assert!(
            near > 0.0 && (far / near / 25.0 - 1.0).abs() < 0.1,
            "{near} {far}"
        );
    }

    #[test]
    fn the_stop_blocks_rays_outside_its_diameter() {
        // Stop of 4 mm diameter 1 mm in front of the lens: parallel rays
        // from the scene at 1.5 mm pass, at 2.5 mm do not.
        let lens = LensSystem::new(
            parse_lens_file(
                &single_lens_file(50.0, -50.0, 5.0, 1.5, 4.0),
                Path::new("t.dat"),
            )
            .unwrap(),
        );
        let z = lens.front_z() + 1.0;
        let down = Vec3::new(0.0, 0.0, -1.0);
        assert!(lens
            .trace_from_scene(Vec3::new(0.0015, 0.0, z), down)
            .is_some());
        assert!(lens
            .trace_from_scene(Vec3::new(0.0025, 0.0, z), down)
            .is_none());
        assert!(lens
            .trace_from_scene(Vec3::new(0.0, -0.0025, z), down)
            .is_none());
    }

    #[test]
    fn exit_pupil_bounds_contain_every_ray_that_gets_through() {
        let lens = single_lens(50.0, -50.0, 5.0, 1.5);
        let bounds = lens.bound_exit_pupil(0.0, 0.001, None, &exit_pupil_samples());
        assert!(!bounds.is_degenerate());
        let rear_z = lens.rear_z();
        let r = 1.5 * lens.rear_element_radius();
        let mut passed = 0;
        for i in 0..40 {
            for j in 0..40 {
                let p = Vec2::new(
                    -r + 2.0 * r * i as f32 / 39.0,
                    -r + 2.0 * r * j as f32 / 39.0,
                );
                let film = Vec3::new(0.0005, 0.0, 0.0);
                if lens
                    .trace_from_film(film, Vec3::new(p.x, p.y, rear_z) - film, None)
                    .is_some()
                {
                    passed += 1;
                    assert!(bounds.contains(p), "{p} outside {bounds:?}");
                }
            }
        }
        assert!(passed > 10);
    }

    #[test]
    fn lens_files_allow_comments_and_free_layout() {
        let text =
            "# radius thickness eta diameter\n\n 10.5\t2 1.5 8 # first\n-10.5 3\n1 8\n0 1 0 5\n";
        let elements = parse_lens_file(text, Path::new("t.dat")).unwrap();
        assert_eq!(elements.len(), 3);
        assert_eq!(
            elements[0],
            LensElement {
                curvature_radius: 0.0105,
                thickness: 0.002,
                eta: 1.5,
                aperture_radius: 0.004
            }
        );
        assert!(elements[2].is_stop());
        assert_eq!(elements[1].thickness, 0.003);
    }

    #[test]
    fn a_malformed_number_is_reported_at_its_line_in_the_lens_file() {
        let text = "# header\n10 2 1.5 8\n-10 3 1 8x\n";
        let e = parse_lens_file(text, Path::new("lenses/bad.dat"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("lenses/bad.dat:3:9") && e.contains("\"8x\""),
            "{e}"
        );
        let e = parse_lens_file("10 2 1.5 8\n-10 3 1\n", Path::new("short.dat"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("short.dat:2:1") && e.contains("multiple of four"),
            "{e}"
        );
        let e = parse_lens_file("# nothing\n", Path::new("empty.dat"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("empty.dat") && e.contains("no lens elements"),
            "{e}"
        );
        let e = parse_lens_file("10 2 1.5 0\n", Path::new("zero.dat"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("zero.dat:1:10") && e.contains("diameter"), "{e}");
    }
}
