//! pbrt-v4's `curve` shape (alias `bcurve`): cubic Bézier segments drawn as
//! a ribbon of varying width that faces the ray (`flat`), the same with a
//! normal that turns across the width to look round (`cylinder`, for hair),
//! or a ribbon oriented by given normals (`ribbon`).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `P` | point3[] | — | control points |
//! | `basis` | string | "bezier" | `bezier` or `bspline` |
//! | `degree` | integer | 3 | 2 or 3 (quadratic segments are elevated to cubic) |
//! | `type` | string | "flat" | `flat`, `cylinder` or `ribbon` |
//! | `N` | normal[] | — | ribbon orientation, one per segment end (required for `ribbon`) |
//! | `width` | float | 1 | width at both ends |
//! | `width0`, `width1` | float | `width` | width at the start and end of the whole curve |
//! | `splitdepth` | integer | 3 | each segment is split into 2^splitdepth pieces for the BVH |
//!
//! **Intersection.** pbrt-v4 subdivides each piece recursively per ray (up
//! to 2¹⁰ times) until the piece is nearly straight, then intersects its
//! chord. Here each segment is split into its 2^splitdepth pieces at build
//! time, as pbrt does, and a piece is subdivided further per ray only if
//! its control polygon deviates from its chord by more than a tenth of the
//! width (rare in hair; common in random test curves): it records how many
//! halvings make it flat enough for one closest point. Splitting those
//! pieces at build time instead made the 120 MB random-curve file of
//! `../shared/refs/README.md` need 18 GB and 150 s. Per ray, the piece is
//! projected into a frame along the ray and the parameter of the curve
//! point closest to the ray is found by Newton's method on
//! ⟨c(w), c′(w)⟩ = 0 from the chord's estimate. The hit
//! then follows pbrt's definition exactly: inside if that point is within
//! half the width of the ray, t from its depth, v from the signed distance.

pub mod frame;
pub mod splines;

use crate::error::{scene_error, Result};
use crate::interaction::SurfaceInteraction;
use crate::math::{Bounds3, Ray, Transform};
use crate::scene_description::{self, ParamSet};
use glam::{DVec3, Vec2, Vec3, Vec4};
use pbrt_parser::{Location, Values};
use splines::{
    blossom_piece, cubic_bspline_to_bezier, elevate_quadratic_bezier, evaluate_bezier,
    quadratic_bspline_to_bezier, split_in_half,
};

/// How the curve surface is oriented.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveType {
    Flat,
    Cylinder,
    Ribbon,
}

/// One cubic Bézier segment of a curve, in render space.
#[derive(Clone, Debug)]
pub struct CurveSegment {
    pub cp: [Vec3; 4],
    /// Width at u = 0 and u = 1 of this segment.
    pub width: [f32; 2],
    pub kind: CurveType,
    /// Ribbon normals at u = 0 and 1 (unit), and the angle between them.
    pub normals: [Vec3; 2],
    pub(crate) normal_angle: f32,
    pub(crate) inv_sin_normal_angle: f32,
    /// Flip the normal (reverse orientation XOR a handedness-swapping
    /// transform).
    pub flip_normal: bool,
    /// View-independent direction across the strand at u = 0 and 1
    /// (see [`frame`]), set only for curves whose material needs it
    /// (`fibre_frame`).
    pub reference: [Vec3; 2],
    /// Whether hits carry a view-independent reference direction (an
    /// elliptical fibre's orientation; `ShapeStorage::set_fibre_frames`).
    /// pbrt's hair needs none, so its hits skip the interpolation.
    pub fibre_frame: bool,
    /// Whether a strand starts here: the first segment of a `Shape
    /// "curve"`, or of each strand of a `cyhair` shape. A strand's frame
    /// (`ShapeStorage::set_fibre_frames`) runs from its first segment to
    /// the next that starts a strand. (Fits in the struct's padding.)
    pub strand_start: bool,
}

/// A piece [u0, u1] of a segment: the BVH primitive.
///
/// One cache line holds all a ray needs to reject it (most of the pieces
/// a ray's traversal reaches): the segment, twice that size, is read only
/// for a ray that passes the piece's hull test.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub struct CurvePiece {
    /// The piece's own Bézier control points (blossomed), one coordinate
    /// per array (element k: point k), so that a ray projects all four at
    /// once ([`RayFrame::project_four`]).
    x: [f32; 4],
    y: [f32; 4],
    z: [f32; 4],
    pub u0: f32,
    pub u1: f32,
    /// Half the largest width over [u0, u1] (kept in step with the
    /// segment's widths by `ShapeStorage::scale_curve_widths`).
    pub half_width: f32,
    /// The segment's index (low bits) and the halvings still needed per
    /// ray before the piece is flat enough for one closest point (high
    /// bits; 0 for almost all hair).
    segment_and_depth: u32,
}

const _: () = assert!(std::mem::size_of::<CurvePiece>() == 64);

/// Bits of `CurvePiece::segment_and_depth` holding the segment index.
const SEGMENT_BITS: u32 = 28;

/// The most curve segments a scene may have (the index shares 32 bits
/// with the refinement depth).
pub const MAX_SEGMENTS: usize = (1 << SEGMENT_BITS) - 1;

/// `segment_and_depth` of [`CurvePiece::placeholder`]: segment index
/// [`MAX_SEGMENTS`], which no segment has (a scene has fewer).
const PLACEHOLDER: u32 = u32::MAX;

impl CurveSegment {
    pub fn width_at(&self, u: f32) -> f32 {
        self.width[0] + (self.width[1] - self.width[0]) * u
    }

    /// The reference across the fibre at parameter u of a hit: the ribbon
    /// normal for ribbons, else the frame set at build time
    /// ([`frame::set_frame`]), interpolated. Neither unit nor exactly ⟂
    /// the tangent: the material uses only its direction across the fibre
    /// (its components in the shading frame's plane ⟂ dpdu, normalised
    /// there), so normalising and orthogonalising here would be done twice.
    pub fn reference_at(&self, u: f32, ribbon_normal: Vec3) -> Vec3 {
        if self.kind == CurveType::Ribbon {
            ribbon_normal
        } else {
            self.reference[0].lerp(self.reference[1], u)
        }
    }

    /// The ribbon normal at u (spherical interpolation, as pbrt).
    fn ribbon_normal(&self, u: f32) -> Vec3 {
        if self.normal_angle == 0.0 {
            return self.normals[0];
        }
        let sin0 = ((1.0 - u) * self.normal_angle).sin() * self.inv_sin_normal_angle;
        let sin1 = (u * self.normal_angle).sin() * self.inv_sin_normal_angle;
        sin0 * self.normals[0] + sin1 * self.normals[1]
    }
}

impl CurvePiece {
    fn new(
        segment: u32,
        u0: f32,
        u1: f32,
        cp: [Vec3; 4],
        refine_depth: u32,
        width: [f32; 2],
    ) -> Self {
        debug_assert!((segment as usize) <= MAX_SEGMENTS && refine_depth < 16);
        CurvePiece {
            x: cp.map(|p| p.x),
            y: cp.map(|p| p.y),
            z: cp.map(|p| p.z),
            u0,
            u1,
            half_width: 0.5 * width[0].max(width[1]),
            segment_and_depth: segment | (refine_depth << SEGMENT_BITS),
        }
    }

    /// A piece that is no curve: it fills the slot of a primitive that is
    /// not tested as a curve where pieces are stored by primitive index
    /// (see `BuiltScene`), and [`CurvePiece::is_placeholder`] tells it.
    pub fn placeholder() -> Self {
        CurvePiece {
            x: [0.0; 4],
            y: [0.0; 4],
            z: [0.0; 4],
            u0: 0.0,
            u1: 0.0,
            half_width: 0.0,
            segment_and_depth: PLACEHOLDER,
        }
    }

    pub fn is_placeholder(&self) -> bool {
        self.segment_and_depth == PLACEHOLDER
    }

    /// The piece's Bézier control points.
    pub fn control_points(&self) -> [Vec3; 4] {
        std::array::from_fn(|k| Vec3::new(self.x[k], self.y[k], self.z[k]))
    }

    /// Index of the segment in the scene's curve segments.
    pub fn segment(&self) -> u32 {
        self.segment_and_depth & ((1 << SEGMENT_BITS) - 1)
    }

    /// The piece with its segment index moved by `offset` (its segment
    /// moved from one storage to another; the caller keeps the index
    /// below [`MAX_SEGMENTS`]).
    pub fn with_segment_shifted(mut self, offset: u32) -> Self {
        debug_assert!(self.segment() as usize + (offset as usize) < MAX_SEGMENTS);
        self.segment_and_depth += offset;
        self
    }

    /// Halvings still needed per ray before the piece is flat enough for
    /// one closest point.
    pub fn refine_depth(&self) -> u8 {
        (self.segment_and_depth >> SEGMENT_BITS) as u8
    }

    /// Re-reads the piece's width from its (rescaled) segment.
    pub fn update_width(&mut self, segment: &CurveSegment) {
        self.half_width = 0.5 * segment.width_at(self.u0).max(segment.width_at(self.u1));
    }

    /// Bounds: the control points' box grown by half the largest width.
    pub fn bounds(&self) -> Bounds3 {
        let b = Bounds3::from_points(self.control_points());
        Bounds3 {
            min: b.min - Vec3::splat(self.half_width),
            max: b.max + Vec3::splat(self.half_width),
        }
    }

    /// The hit of `ray` with this piece before `t_max` (u in the
    /// segment's parameter).
    pub fn intersect(&self, segment: &CurveSegment, ray: &Ray, t_max: f32) -> Option<CurveHit> {
        self.intersect_in(segment, &RayFrame::new(ray)?, t_max)
    }

    /// The same, with the ray's frame computed once for all pieces.
    ///
    /// Always inlined: most pieces a ray reaches fail the hull test, which
    /// is then compiled into each copy of the scene's ray queries (with
    /// AVX2 in the x86-64-v3 one) and the frame's broadcasts can be hoisted
    /// out of the traversal loop; the rest is one call.
    #[inline(always)]
    pub fn intersect_in(
        &self,
        segment: &CurveSegment,
        frame: &RayFrame,
        t_max: f32,
    ) -> Option<CurveHit> {
        // The control polygon's hull (which contains a Bézier curve) first:
        // most pieces a ray reaches are rejected without reading `segment`.
        // Four points at a time, each coordinate as the one-point projection
        // and `hull_may_hit` compute it (the same products and sums in the
        // same order), so the same pieces pass.
        let projected = frame.project_four([self.x, self.y, self.z]);
        if !hull_may_hit_four(projected, self.half_width, frame.length * t_max) {
            return None;
        }
        self.intersect_within_hull(segment, frame, t_max, projected)
    }

    /// [`Self::intersect_in`] past the hull test, from the control points
    /// in the ray's frame (by coordinate).
    #[inline(never)]
    fn intersect_within_hull(
        &self,
        segment: &CurveSegment,
        frame: &RayFrame,
        t_max: f32,
        [x, y, z]: [Vec4; 3],
    ) -> Option<CurveHit> {
        let (x, y, z) = (x.to_array(), y.to_array(), z.to_array());
        let c: [Vec3; 4] = std::array::from_fn(|k| Vec3::new(x[k], y[k], z[k]));
        if !band_may_hit(&c, self.half_width) {
            return None;
        }
        intersect_projected(
            segment,
            frame,
            t_max,
            &c,
            (self.u0, self.u1),
            self.refine_depth(),
        )
    }
}

/// Whether the curve with control points `c` in a ray's frame, grown
/// sideways by `half_width`, may meet the ray between depth 0 and `z_max`:
/// its box first, then the band across its chord.
#[inline]
fn may_hit(c: &[Vec3; 4], half_width: f32, z_max: f32) -> bool {
    hull_may_hit(c, half_width, z_max) && band_may_hit(c, half_width)
}

/// Whether control points `c` in a ray's frame, grown sideways by
/// `half_width`, reach the ray (x = y = 0) between depth 0 and `z_max`.
#[inline]
fn hull_may_hit(c: &[Vec3; 4], half_width: f32, z_max: f32) -> bool {
    let (mut lo, mut hi) = (c[0], c[0]);
    for p in &c[1..] {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    lo.x <= half_width
        && hi.x >= -half_width
        && lo.y <= half_width
        && hi.y >= -half_width
        && hi.z >= 0.0
        && lo.z <= z_max
}

/// [`hull_may_hit`] for control points given by coordinate (lane k: point
/// k). min(x) ≤ w exactly when some x ≤ w, and so on: no horizontal minima
/// or maxima, one mask per bound.
#[inline(always)]
fn hull_may_hit_four([x, y, z]: [Vec4; 3], half_width: f32, z_max: f32) -> bool {
    let half_width = Vec4::splat(half_width);
    x.cmple(half_width).any()
        && x.cmpge(-half_width).any()
        && y.cmple(half_width).any()
        && y.cmpge(-half_width).any()
        && z.cmpge(Vec4::ZERO).any()
        && z.cmple(Vec4::splat(z_max)).any()
}

/// Whether the ray (x = y = 0) comes within `half_width` of the band the
/// control points `c` span across their chord, seen along the ray. The
/// projected curve lies in its control points' hull, and the hull in that
/// band, so this rejects no hit; and for a piece lying across its box's
/// diagonal (most hair, seen from most rays) the band is much narrower than
/// the box. Each distance is scaled by the chord's length (no division);
/// the margin covers their rounding, so a grazing hit is not lost to it.
#[inline]
fn band_may_hit(c: &[Vec3; 4], half_width: f32) -> bool {
    let origin = c[0].truncate();
    let chord = c[3].truncate() - origin;
    let across = |p: Vec2| chord.perp_dot(p - origin);
    let (first, second) = (across(c[1].truncate()), across(c[2].truncate()));
    let ray = across(Vec2::ZERO);
    let size: f32 = c.iter().map(|p| p.x.abs() + p.y.abs()).sum();
    let chord_length = chord.length();
    let reach = chord_length * (half_width + 1e-5 * size);
    ray >= first.min(second).min(0.0) - reach && ray <= first.max(second).max(0.0) + reach
}

/// The hit of the ray with the sub-curve `c` (control points in the ray's
/// frame, their hull already known to meet the ray) spanning `[u0, u1]` of
/// its segment, after `refine_depth` more halvings (the closer of the two
/// halves' hits).
fn intersect_projected(
    segment: &CurveSegment,
    frame: &RayFrame,
    t_max: f32,
    c: &[Vec3; 4],
    (u0, u1): (f32, f32),
    refine_depth: u8,
) -> Option<CurveHit> {
    if refine_depth > 0 {
        // Each half is tried only if its own, tighter hull meets the ray.
        let half = |c: &[Vec3; 4], (a, b): (f32, f32), t_max: f32| {
            let half_width = 0.5 * segment.width_at(a).max(segment.width_at(b));
            if !may_hit(c, half_width, frame.length * t_max) {
                return None;
            }
            intersect_projected(segment, frame, t_max, c, (a, b), refine_depth - 1)
        };
        let (first, second) = split_in_half(c);
        let mid = 0.5 * (u0 + u1);
        let near = half(&first, (u0, mid), t_max);
        let far = half(&second, (mid, u1), near.map_or(t_max, |h| h.t));
        return far.or(near);
    }

    // Newton on g(w) = ⟨c_xy(w), c′_xy(w)⟩, from the chord's closest
    // point. Pieces are split flat enough at build time for one root.
    let chord = c[3].truncate() - c[0].truncate();
    let denom = chord.length_squared();
    if denom == 0.0 {
        return None;
    }
    let mut w = (-c[0].truncate()).dot(chord) / denom;
    // Only the curve's x and y (across the ray) enter g.
    let c_xy = c.map(|p| p.truncate());
    // The control polygon's second differences: the second derivative of
    // the cubic is 6 × their lerp.
    let second = [
        c_xy[2] - 2.0 * c_xy[1] + c_xy[0],
        c_xy[3] - 2.0 * c_xy[2] + c_xy[1],
    ];
    for _ in 0..4 {
        let wc = w.clamp(-0.5, 1.5);
        let (p, d1) = evaluate_bezier(&c_xy, wc);
        let d2 = 6.0 * (second[0] * (1.0 - wc) + second[1] * wc);
        let g = p.x * d1.x + p.y * d1.y;
        let dg = d1.x * d1.x + d1.y * d1.y + p.x * d2.x + p.y * d2.y;
        if dg <= 0.0 {
            break;
        }
        let step = g / dg;
        w = wc - step;
        if step.abs() < 1e-7 {
            break;
        }
    }
    // The closest point lies in a neighbouring piece.
    if !(0.0..=1.0).contains(&w) {
        return None;
    }
    let u = u0 + (u1 - u0) * w;
    let mut hit_width = segment.width_at(u);
    let mut n_hit = Vec3::ZERO;
    if segment.kind == CurveType::Ribbon {
        n_hit = segment.ribbon_normal(u);
        hit_width *= n_hit.dot(frame.dz).abs();
    }
    let (pc, dpcdw) = evaluate_bezier(c, w);
    let dist2 = pc.x * pc.x + pc.y * pc.y;
    if dist2 > hit_width * hit_width * 0.25 {
        return None;
    }
    if pc.z < 0.0 || pc.z > frame.length * t_max {
        return None;
    }
    let dist = dist2.sqrt();
    let edge = dpcdw.x * -pc.y + pc.x * dpcdw.y;
    let v = if edge > 0.0 {
        0.5 + dist / hit_width
    } else {
        0.5 - dist / hit_width
    };
    Some(CurveHit {
        t: pc.z / frame.length,
        u,
        v,
        hit_width,
        n_hit,
    })
}

/// A ray's frame: origin, two axes across it and its unit direction,
/// (ex, ey, dz) right-handed as pbrt's LookAt (the rotation about the ray
/// does not matter; the handedness fixes the sign of v).
#[derive(Clone, Copy, Debug)]
pub struct RayFrame {
    pub origin: Vec3,
    pub ex: Vec3,
    pub ey: Vec3,
    pub dz: Vec3,
    /// Length of the ray's direction vector (t is in its units).
    pub length: f32,
}

impl RayFrame {
    pub fn new(ray: &Ray) -> Option<Self> {
        let length = ray.direction.length();
        if length == 0.0 || !length.is_finite() {
            return None;
        }
        let dz = ray.direction / length;
        let (ex, ey) = crate::math::frame::coordinate_system(dz);
        Some(RayFrame {
            origin: ray.origin,
            ex,
            ey,
            dz,
            length,
        })
    }

    #[cfg(test)]
    fn project(&self, p: Vec3) -> Vec3 {
        let q = p - self.origin;
        Vec3::new(q.dot(self.ex), q.dot(self.ey), q.dot(self.dz))
    }

    /// Four points given by coordinate (element k: point k) in this frame,
    /// each lane computed as the tests' one-point `project` computes it.
    #[inline]
    fn project_four(&self, [x, y, z]: [[f32; 4]; 3]) -> [Vec4; 3] {
        let q = [
            Vec4::from_array(x) - Vec4::splat(self.origin.x),
            Vec4::from_array(y) - Vec4::splat(self.origin.y),
            Vec4::from_array(z) - Vec4::splat(self.origin.z),
        ];
        let dot = |axis: Vec3| {
            q[0] * Vec4::splat(axis.x) + q[1] * Vec4::splat(axis.y) + q[2] * Vec4::splat(axis.z)
        };
        [dot(self.ex), dot(self.ey), dot(self.dz)]
    }
}

/// Where a ray hit a curve piece.
#[derive(Clone, Copy, Debug)]
pub struct CurveHit {
    pub t: f32,
    /// Segment parameter along the curve.
    pub u: f32,
    /// Across the width, 0…1.
    pub v: f32,
    pub hit_width: f32,
    pub n_hit: Vec3,
}

impl CurveHit {
    /// The surface interaction pbrt-v4 builds for this hit.
    pub fn interaction(&self, segment: &CurveSegment, ray: &Ray) -> SurfaceInteraction {
        let (_, dpdu) = evaluate_bezier(&segment.cp, self.u);
        let dpdv = match segment.kind {
            CurveType::Ribbon => self.n_hit.cross(dpdu).normalize_or_zero() * self.hit_width,
            _ => {
                // Perpendicular to the tangent in the plane facing the ray.
                let d = ray.direction.normalize();
                let (ex, ey) = crate::math::frame::coordinate_system(d);
                let tangent_plane = Vec3::new(dpdu.dot(ex), dpdu.dot(ey), dpdu.dot(d));
                let mut dpdv_plane = Vec3::new(-tangent_plane.y, tangent_plane.x, 0.0)
                    .normalize_or_zero()
                    * self.hit_width;
                if segment.kind == CurveType::Cylinder {
                    // Turn across the width so the normal sweeps a half
                    // cylinder: θ from −90° to 90°, rotating by −θ about the
                    // tangent.
                    let theta = (-90.0 + 180.0 * self.v).to_radians();
                    if let Some(axis) = tangent_plane.try_normalize() {
                        dpdv_plane = glam::Quat::from_axis_angle(axis, -theta) * dpdv_plane;
                    }
                }
                ex * dpdv_plane.x + ey * dpdv_plane.y + d * dpdv_plane.z
            }
        };
        let mut n = dpdu.cross(dpdv).normalize_or_zero();
        if segment.flip_normal {
            n = -n;
        }
        let p = ray.at(self.t);
        let mut si = SurfaceInteraction {
            p,
            p_error: Vec3::splat(self.hit_width),
            t: self.t,
            time: ray.time,
            wo: -ray.direction.normalize(),
            n,
            uv: glam::Vec2::new(self.u, self.v),
            dpdu,
            dpdv,
            curve_h: -1.0 + 2.0 * self.v,
            fibre_reference: if segment.fibre_frame {
                segment.reference_at(self.u, self.n_hit)
            } else {
                Vec3::ZERO
            },
            ..Default::default()
        };
        si.shading = crate::interaction::Shading {
            n,
            dpdu,
            dpdv,
            dndu: Vec3::ZERO,
            dndv: Vec3::ZERO,
        };
        si
    }
}

/// The curve's segments (in render space) and their BVH pieces.
pub fn create_curves(
    shape: &scene_description::Shape,
    render_from_object: &Transform,
    curve_transform: &CurveTransform,
    reverse_orientation: bool,
    segments: &mut Vec<CurveSegment>,
    pieces: &mut Vec<CurvePiece>,
) -> Result<()> {
    let p = &shape.entity.params;
    let loc = &shape.entity.location.0;
    // The optional parameters a curve gives, found in one pass: most
    // curves give one or two, and a lookup of an absent one scans every
    // parameter. (Absent, a lookup would give the default and mark
    // nothing; present, it is made as before, in the same order, so
    // errors and used marks stay the same.)
    let [has_basis, has_degree, has_width, has_width0, has_width1, has_split_depth, has_normals] =
        p.has_each([
            "basis",
            "degree",
            "width",
            "width0",
            "width1",
            "splitdepth",
            "N",
        ]);
    // Borrowed, not copied: a hair file has hundreds of thousands of
    // curves, each with its own points.
    let coordinates = p.point3_coordinates("P")?;
    let basis = if has_basis {
        p.string_ref("basis", "bezier")?
    } else {
        "bezier"
    };
    let degree = if has_degree { p.int("degree", 3)? } else { 3 };
    let kind = curve_type(p.string_ref("type", "flat")?, loc)?;
    let width = if has_width {
        p.float("width", 1.0)?
    } else {
        1.0
    };
    let width0 = if has_width0 {
        p.float("width0", width)?
    } else {
        width
    } as f32;
    let width1 = if has_width1 {
        p.float("width1", width)?
    } else {
        width
    } as f32;
    let split_depth = if has_split_depth {
        p.int("splitdepth", 3)?
    } else {
        3
    }
    .clamp(0, 10) as u32;
    let normals = if has_normals {
        p.normals("N")?
    } else {
        Vec::new()
    };
    if degree != 2 && degree != 3 {
        return scene_error(
            format!("curve \"degree\" must be 2 or 3, not {degree}"),
            loc,
        );
    }
    let degree = degree as usize;
    let n = coordinates.len() / 3;
    let cps = |i: usize| DVec3::from_slice(&coordinates[3 * i..3 * i + 3]);
    let segments_count = match basis {
        "bezier" => {
            if n < degree + 1 || (n - 1) % degree != 0 {
                return scene_error(
                    format!(
                        "a degree-{degree} bezier curve needs {degree}k + 1 control points (k ≥ 1); {n} given"
                    ),
                    loc,
                );
            }
            (n - 1) / degree
        }
        "bspline" => {
            if n < degree + 1 {
                return scene_error(format!("a degree-{degree} bspline curve needs at least {} control points; {n} given", degree + 1), loc);
            }
            n - degree
        }
        other => {
            return scene_error(
                format!("curve basis \"{other}\" unknown (expected bezier or bspline)"),
                loc,
            )
        }
    };
    if kind == CurveType::Ribbon && normals.len() != segments_count + 1 {
        return scene_error(
            format!(
                "a ribbon curve needs one normal \"N\" per segment end: {} expected, {} given",
                segments_count + 1,
                normals.len()
            ),
            loc,
        );
    }
    if !(width0 >= 0.0 && width1 >= 0.0) {
        return scene_error("curve widths must be ≥ 0", loc);
    }
    let m = render_from_object;
    // Widths are in object space: scale them by the transform's size.
    let width_scale = curve_transform.width_scale;
    let flip_normal = reverse_orientation ^ curve_transform.swaps_handedness;
    let to_render = |q: DVec3| m.point(q).as_vec3();
    for seg in 0..segments_count {
        let bez: [DVec3; 4] = match (basis, degree) {
            ("bezier", 3) => [
                cps(3 * seg),
                cps(3 * seg + 1),
                cps(3 * seg + 2),
                cps(3 * seg + 3),
            ],
            ("bezier", _) => {
                elevate_quadratic_bezier([cps(2 * seg), cps(2 * seg + 1), cps(2 * seg + 2)])
            }
            (_, 3) => cubic_bspline_to_bezier([cps(seg), cps(seg + 1), cps(seg + 2), cps(seg + 3)]),
            _ => quadratic_bspline_to_bezier([cps(seg), cps(seg + 1), cps(seg + 2)]),
        };
        let cp = bez.map(to_render);
        let w = segment_widths(width0, width1, seg, segments_count).map(|w| w * width_scale);
        let (normals_render, angle) = if kind == CurveType::Ribbon {
            let nt = |v: DVec3| {
                m.inverse
                    .transpose()
                    .transform_vector3(v)
                    .as_vec3()
                    .normalize_or_zero()
            };
            let (n0, n1) = (nt(normals[seg]), nt(normals[seg + 1]));
            (
                [n0, n1],
                crate::math::safe_acos(n0.dot(n1).clamp(-1.0, 1.0)),
            )
        } else {
            ([Vec3::ZERO; 2], 0.0)
        };
        let segment = CurveSegment {
            cp,
            width: w,
            kind,
            normals: normals_render,
            normal_angle: angle,
            inv_sin_normal_angle: if angle > 0.0 { 1.0 / angle.sin() } else { 0.0 },
            flip_normal,
            reference: [Vec3::ZERO; 2],
            fibre_frame: false,
            strand_start: seg == 0,
        };
        push_segment(segment, split_depth, segments, pieces, loc)?;
    }
    Ok(())
}

/// How many segments and pieces [`create_curves`] makes of a curve with
/// parameters `params`, read without marking them used: what a run of
/// placements reserves for its curves (a hair file's runs otherwise grow
/// their arrays a doubling at a time). Exact for a well-formed curve with
/// no repeated or attribute parameters; (0, 0) where it would fail.
pub fn expected_counts(params: &ParamSet) -> (usize, usize) {
    let (mut points, mut basis, mut degree, mut split_depth) = (0, "bezier", 3, 3);
    let first_number = |values: &Values| match values {
        Values::Numbers(numbers) => numbers.first().map(|&x| x as i32),
        _ => None,
    };
    // One pass, each name matched once (`ParamSet::find` would scan the
    // parameters per name); a repeated name is rare, and only a hint.
    for param in params.iter() {
        match (param.name.as_str(), &param.values) {
            ("P", Values::Numbers(numbers)) => points = numbers.len() / 3,
            ("basis", Values::Strings(strings)) => {
                basis = strings.first().map_or("", |s| s.as_str())
            }
            ("degree", values) => degree = first_number(values).unwrap_or(0),
            ("splitdepth", values) => split_depth = first_number(values).unwrap_or(0),
            _ => {}
        }
    }
    let degree = match degree {
        2 => 2,
        3 => 3,
        _ => return (0, 0),
    };
    let segments = match basis {
        "bezier" if points > degree && (points - 1) % degree == 0 => (points - 1) / degree,
        "bspline" if points > degree => points - degree,
        _ => 0,
    };
    (segments, segments << split_depth.clamp(0, 10))
}

/// The object-space widths at the ends of segment `seg` of a curve of
/// `count` segments whose `width0` and `width1` are given: linear in the
/// segment index, as pbrt-v4's `Curve::Create` (which writes the lerp as
/// (1 − t)·w0 + t·w1; this form, rpbrt's from the start, can differ from
/// it in the last bit). The `cyhair` shape takes its widths from here too,
/// so a file written by `cyhair2pbrt` gives the same widths bit for bit.
pub(crate) fn segment_widths(width0: f32, width1: f32, seg: usize, count: usize) -> [f32; 2] {
    let t0 = seg as f32 / count as f32;
    let t1 = (seg + 1) as f32 / count as f32;
    [
        width0 + (width1 - width0) * t0,
        width0 + (width1 - width0) * t1,
    ]
}

/// A curve `type` by its pbrt name.
pub(crate) fn curve_type(name: &str, loc: &Location) -> Result<CurveType> {
    match name {
        "flat" => Ok(CurveType::Flat),
        "cylinder" => Ok(CurveType::Cylinder),
        "ribbon" => Ok(CurveType::Ribbon),
        other => scene_error(
            format!("curve type \"{other}\" unknown (expected flat, cylinder or ribbon)"),
            loc,
        ),
    }
}

/// What the curves under one render-from-object share: computed once per
/// transform by a run of placements (a hair file's hundreds of thousands
/// of curves mostly share one; two determinants and a cube root per curve
/// were a twentieth of making them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveTransform {
    /// [`width_scale`] of the transform.
    pub width_scale: f32,
    /// [`Transform::swaps_handedness`] of it.
    pub swaps_handedness: bool,
}

impl CurveTransform {
    pub fn of(render_from_object: &Transform) -> Self {
        CurveTransform {
            width_scale: width_scale(render_from_object),
            swaps_handedness: render_from_object.swaps_handedness(),
        }
    }
}

/// What object-space curve widths are multiplied by in render space: the
/// transform's size (the cube root of its determinant).
pub(crate) fn width_scale(render_from_object: &Transform) -> f32 {
    glam::DMat3::from_mat4(render_from_object.matrix)
        .determinant()
        .abs()
        .cbrt() as f32
}

impl CurveSegment {
    /// A `flat` or `cylinder` segment (no ribbon normals) in render space.
    pub(crate) fn unoriented(
        cp: [Vec3; 4],
        width: [f32; 2],
        kind: CurveType,
        flip_normal: bool,
        strand_start: bool,
    ) -> Self {
        debug_assert!(kind != CurveType::Ribbon);
        CurveSegment {
            cp,
            width,
            kind,
            normals: [Vec3::ZERO; 2],
            normal_angle: 0.0,
            inv_sin_normal_angle: 0.0,
            flip_normal,
            reference: [Vec3::ZERO; 2],
            fibre_frame: false,
            strand_start,
        }
    }
}

/// Appends `segment` and its 2^split_depth BVH pieces; an error at `loc`
/// past [`MAX_SEGMENTS`].
pub(crate) fn push_segment(
    segment: CurveSegment,
    split_depth: u32,
    segments: &mut Vec<CurveSegment>,
    pieces: &mut Vec<CurvePiece>,
    loc: &Location,
) -> Result<()> {
    if segments.len() >= MAX_SEGMENTS {
        return scene_error(
            format!("too many curve segments: a scene may have at most {MAX_SEGMENTS}"),
            loc,
        );
    }
    let segment_index = segments.len() as u32;
    split_into_pieces(&segment, segment_index, split_depth, pieces);
    segments.push(segment);
    Ok(())
}

/// Splits a segment into its 2^split_depth pieces (pbrt-v4's count). A
/// piece whose control polygon strays from its chord by more than a tenth
/// of the width gets the number of per-ray halvings that will make it flat
/// enough for Newton's method to see one closest point (each halving
/// divides a cubic's deviation by about 4), within pbrt's 2¹⁰ pieces per
/// segment.
fn split_into_pieces(
    segment: &CurveSegment,
    index: u32,
    split_depth: u32,
    pieces: &mut Vec<CurvePiece>,
) {
    let n = 1u32 << split_depth;
    for i in 0..n {
        let (u0, u1) = (i as f32 / n as f32, (i + 1) as f32 / n as f32);
        let cp = blossom_piece(&segment.cp, u0, u1);
        let w = segment.width_at(u0).min(segment.width_at(u1)).max(1e-12);
        let tolerance = 0.1 * w.max(1e-3 * (cp[3] - cp[0]).length());
        let excess = deviation(&cp) / tolerance;
        let refine_depth = if excess > 1.0 {
            halvings_for_excess(excess).min(MAX_DEPTH.saturating_sub(split_depth))
        } else {
            0
        };
        pieces.push(CurvePiece::new(
            index,
            u0,
            u1,
            cp,
            refine_depth,
            [segment.width_at(u0), segment.width_at(u1)],
        ));
    }
}

/// ⌈log₂(excess) / 2⌉ as `(0.5 * excess.log2()).ceil() as u32` computes
/// it, for `excess` > 1 (each halving divides a piece's deviation by about
/// 4), mostly from the float's exponent: for the random curves of a test
/// file, where most pieces need halvings, `log2f` and `ceilf` were a tenth
/// of making the curves. With excess = 2^e·(1 + f), log₂ excess lies in
/// [e, e + 1), so the answer is e/2 + 1 (integer division) unless e is even
/// and log₂ excess rounds to e itself: only for f near 0, where `log2f`
/// decides as before.
fn halvings_for_excess(excess: f32) -> u32 {
    let bits = excess.to_bits();
    let exponent = (bits >> 23) & 0xff;
    let fraction = bits & 0x7f_ffff;
    // f ≥ 2⁻¹⁰: log₂(1 + f) ≥ 0.0014, far above log2f's error at any
    // exponent (an ulp of 127 is 2⁻¹⁷); the biased exponent 255 is inf.
    let near_a_power_of_four = exponent % 2 == 1 && fraction < 1 << 13;
    if near_a_power_of_four || !(127..255).contains(&exponent) {
        return (0.5 * excess.log2()).ceil() as u32;
    }
    (exponent - 127) / 2 + 1
}

/// pbrt-v4's limit on the halvings of a segment.
const MAX_DEPTH: u32 = 10;

/// How far the inner control points stray from the chord.
fn deviation(cp: &[Vec3; 4]) -> f32 {
    let chord = cp[3] - cp[0];
    let len2 = chord.length_squared();
    let dist = |p: Vec3| {
        if len2 == 0.0 {
            return (p - cp[0]).length();
        }
        let t = ((p - cp[0]).dot(chord) / len2).clamp(0.0, 1.0);
        (p - (cp[0] + chord * t)).length()
    };
    dist(cp[1]).max(dist(cp[2]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// The counts a run reserves are those `create_curves` makes.
    #[test]
    fn expected_counts_are_the_counts_made() {
        let cases = [
            (r#""point3 P" [0 0 0 1 0 0 2 0 0 3 0 0]"#, (1, 8)),
            (
                r#""point3 P" [0 0 0 1 0 0 2 0 0 3 0 0 4 0 0 5 0 0 6 0 0] "integer splitdepth" 1"#,
                (2, 4),
            ),
            (
                r#""point3 P" [0 0 0 1 0 0 2 0 0 3 0 0 4 0 0] "string basis" "bspline""#,
                (2, 16),
            ),
            (
                r#""point3 P" [0 0 0 1 0 0 2 0 0 3 1 0 4 0 0] "integer degree" 2 "integer splitdepth" 0"#,
                (2, 2),
            ),
            (
                r#""point3 P" [0 0 0 1 0 0 2 0 0 3 0 0] "integer splitdepth" 12"#,
                (1, 1024),
            ),
        ];
        for (params, expected) in cases {
            let text = format!("WorldBegin\nShape \"curve\" {params}\n");
            let loaded = crate::scene::load_text(std::path::Path::new("c.pbrt"), &text).unwrap();
            let shape = &loaded.scene.shapes[0];
            assert_eq!(expected_counts(&shape.entity.params), expected, "{params}");
            let (mut segments, mut pieces) = (Vec::new(), Vec::new());
            let identity = Transform::IDENTITY;
            let facts = CurveTransform::of(&identity);
            create_curves(shape, &identity, &facts, false, &mut segments, &mut pieces).unwrap();
            assert_eq!((segments.len(), pieces.len()), expected, "{params}");
        }
        // What `create_curves` refuses reserves nothing.
        let text = "WorldBegin\nShape \"curve\" \"point3 P\" [0 0 0 1 0 0] \"integer degree\" 4\n";
        let loaded = crate::scene::load_text(std::path::Path::new("c.pbrt"), text).unwrap();
        assert_eq!(
            expected_counts(&loaded.scene.shapes[0].entity.params),
            (0, 0)
        );
    }

    /// The halvings from the exponent agree with pbrt's ⌈log₂(x) / 2⌉
    /// rounded as `log2f` rounds it, at and around every power of two and
    /// across the range, up to infinity.
    #[test]
    fn halvings_match_the_rounded_logarithm() {
        let reference = |x: f32| (0.5 * x.log2()).ceil() as u32;
        let mut checked = 0;
        let mut check = |x: f32| {
            if x > 1.0 {
                assert_eq!(halvings_for_excess(x), reference(x), "{x:e}");
                checked += 1;
            }
        };
        for e in 0..128 {
            let power = 2f32.powi(e).to_bits();
            for step in 0..20_000u32 {
                check(f32::from_bits(power + step));
                check(f32::from_bits(power - step));
            }
        }
        for bits in (1f32.to_bits()..f32::MAX.to_bits()).step_by(997) {
            check(f32::from_bits(bits));
        }
        check(f32::MAX);
        check(f32::INFINITY);
        assert!(checked > 5_000_000);
        assert_eq!(halvings_for_excess(f32::INFINITY), u32::MAX);
        assert_eq!(halvings_for_excess(4.0), 1);
        assert_eq!(halvings_for_excess(4.5), 2);
        assert_eq!(halvings_for_excess(16.0), 2);
    }

    /// The band test rejects no control polygon whose curve (densely
    /// sampled) comes within the half width of the ray, including grazing
    /// ones, and rejects most of what passes the box test yet misses.
    #[test]
    fn band_test_keeps_every_hit_and_rejects_most_box_passes() {
        let mut rng = super::super::test_support::TestRng::new(5);
        let mut rnd = || rng.uniform();
        let (mut near, mut box_passes, mut band_rejects) = (0, 0, 0);
        for case in 0..20000 {
            let scale = [1e-3, 1.0, 100.0][case % 3];
            let start = Vec3::new(rnd() - 0.5, rnd() - 0.5, 1.0) * scale;
            let c: [Vec3; 4] = std::array::from_fn(|k| {
                let along = Vec3::new(0.3, 0.2, 0.1) * k as f32;
                start + (along + (Vec3::new(rnd(), rnd(), rnd()) - 0.5) * 0.3) * scale
            });
            let half_width = 0.05 * scale * rnd();
            let closest = (0..=2000)
                .map(|i| evaluate_bezier(&c, i as f32 / 2000.0).0.truncate().length())
                .fold(f32::INFINITY, f32::min);
            let hull = hull_may_hit(&c, half_width, f32::INFINITY);
            let band = band_may_hit(&c, half_width);
            if closest <= half_width {
                near += 1;
                assert!(
                    hull && band,
                    "case {case}: {c:?} w {half_width} closest {closest}"
                );
            } else if hull {
                box_passes += 1;
                band_rejects += !band as usize;
            }
        }
        assert!(near > 300, "{near}");
        assert!(
            band_rejects * 2 > box_passes,
            "{band_rejects} of {box_passes} box passes rejected"
        );
    }

    /// A piece's four-lane projection and hull test give the one-point
    /// projection's coordinates and `hull_may_hit`'s answer bit for bit
    /// (random pieces, rays from near and far, depths cutting through the
    /// hulls): the same pieces pass, so images do not change. Summing a
    /// dot product in another order fails it.
    #[test]
    fn four_lane_hull_test_matches_the_one_point_test() {
        let mut rng = super::super::test_support::TestRng::new(11);
        let (mut passed, mut cases) = (0, 0);
        for case in 0..60_000 {
            let scale = [1e-3, 1.0, 100.0][case % 3];
            let cp: [Vec3; 4] = std::array::from_fn(|_| {
                Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                ) * scale
            });
            let half_width = 0.2 * scale * rng.uniform();
            let piece = CurvePiece::new(0, 0.0, 1.0, cp, 0, [2.0 * half_width; 2]);
            let origin = rng.direction() * scale * rng.range(0.5, 4.0);
            // Towards the piece, give or take, with a direction of any length.
            let target = cp[case % 4] + rng.direction() * half_width * 2.0;
            let direction = (target - origin) * rng.range(0.01, 100.0);
            let Some(frame) = RayFrame::new(&Ray::new(origin, direction, 0.0)) else {
                continue;
            };
            let one_point = piece.control_points().map(|p| frame.project(p));
            let lanes = frame.project_four([piece.x, piece.y, piece.z]);
            for k in 0..4 {
                let lane = Vec3::new(lanes[0][k], lanes[1][k], lanes[2][k]);
                assert_eq!(
                    lane.to_array().map(f32::to_bits),
                    one_point[k].to_array().map(f32::to_bits),
                    "case {case}, point {k}"
                );
            }
            let z_max = frame.length * rng.range(0.0, 1.5);
            let hit = hull_may_hit(&one_point, half_width, z_max);
            assert_eq!(
                hull_may_hit_four(lanes, half_width, z_max),
                hit,
                "case {case}"
            );
            passed += usize::from(hit);
            cases += 1;
        }
        assert!(
            passed > cases / 10 && passed < cases * 9 / 10,
            "{passed} of {cases} passed"
        );
    }

    fn segment(cp: [Vec3; 4], w: f32, kind: CurveType) -> (CurveSegment, Vec<CurvePiece>) {
        segment_split(cp, w, kind, 3)
    }

    fn segment_split(
        cp: [Vec3; 4],
        w: f32,
        kind: CurveType,
        split_depth: u32,
    ) -> (CurveSegment, Vec<CurvePiece>) {
        let s = CurveSegment {
            cp,
            width: [w, w],
            kind,
            normals: [Vec3::Z, Vec3::Z],
            normal_angle: 0.0,
            inv_sin_normal_angle: 0.0,
            flip_normal: false,
            reference: [Vec3::ZERO; 2],
            fibre_frame: false,
            strand_start: true,
        };
        let mut pieces = Vec::new();
        split_into_pieces(&s, 0, split_depth, &mut pieces);
        (s, pieces)
    }

    fn closest(pieces: &[CurvePiece], s: &CurveSegment, ray: &Ray) -> Option<CurveHit> {
        pieces
            .iter()
            .filter_map(|p| p.intersect(s, ray, f32::INFINITY))
            .min_by(|a, b| a.t.total_cmp(&b.t))
    }

    /// f64 brute force: the point of the curve closest to the ray in the
    /// ray's frame, by dense sampling then golden-section refinement.
    fn reference(s: &CurveSegment, ray: &Ray) -> Option<(f64, f64, f64)> {
        let o = ray.origin.as_dvec3();
        let d = ray.direction.as_dvec3();
        let len = d.length();
        let dz = d / len;
        let helper = if dz.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
        let ex = helper.cross(dz).normalize();
        let ey = dz.cross(ex);
        let cp = s.cp.map(|p| p.as_dvec3());
        let eval = |u: f64| {
            let a = |i: usize| cp[i];
            let v = 1.0 - u;
            a(0) * v * v * v + a(1) * 3.0 * v * v * u + a(2) * 3.0 * v * u * u + a(3) * u * u * u
        };
        let proj = |u: f64| {
            let q = eval(u) - o;
            (DVec2::new(q.dot(ex), q.dot(ey)), q.dot(dz))
        };
        // Every local minimum of the distance to the ray is a candidate hit
        // (a bent curve can cross the ray's view twice); the nearest in
        // depth within half the width wins, as in pbrt.
        let n = 20000;
        let dist = |i: usize| proj(i as f64 / n as f64).0.length();
        let mut best: Option<(f64, f64, f64)> = None;
        for i in 1..n {
            if !(dist(i) <= dist(i - 1) && dist(i) <= dist(i + 1)) {
                continue;
            }
            let (mut a, mut b) = ((i - 1) as f64 / n as f64, (i + 1) as f64 / n as f64);
            for _ in 0..100 {
                let m1 = a + (b - a) * 0.382;
                let m2 = a + (b - a) * 0.618;
                if proj(m1).0.length() < proj(m2).0.length() {
                    b = m2;
                } else {
                    a = m1;
                }
            }
            let u = 0.5 * (a + b);
            let (xy, z) = proj(u);
            let w = s.width[0] as f64 + (s.width[1] - s.width[0]) as f64 * u;
            // The closest point must be interior (not clamped at an end).
            if xy.length() > w / 2.0 || z < 0.0 || u <= 1e-6 || u >= 1.0 - 1e-6 {
                continue;
            }
            if best.is_none_or(|(t, _, _)| z / len < t) {
                best = Some((z / len, u, xy.length() / w));
            }
        }
        best
    }

    /// f64: distance of the curve point at `u` from the ray, and its ray
    /// parameter.
    fn reference_at(s: &CurveSegment, ray: &Ray, u: f64) -> (f64, f64) {
        let o = ray.origin.as_dvec3();
        let d = ray.direction.as_dvec3();
        let cp = s.cp.map(|p| p.as_dvec3());
        let v = 1.0 - u;
        let p = cp[0] * v * v * v
            + cp[1] * 3.0 * v * v * u
            + cp[2] * 3.0 * v * u * u
            + cp[3] * u * u * u;
        let q = p - o;
        let t = q.dot(d) / d.length_squared();
        ((q - d * t).length(), t)
    }

    /// Random rays at random curves (control points spread `spread` across
    /// a length of 3): (hits compared, worst relative t error, worst v
    /// error, pieces refined per ray).
    fn compare_with_reference(
        split_depth: u32,
        spread: f32,
        strict_u: bool,
    ) -> (usize, f64, f64, usize) {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let (mut compared, mut worst_t, mut worst_v, mut refined) = (0, 0.0f64, 0.0f64, 0);
        for _ in 0..if strict_u { 400 } else { 120 } {
            let cp = [0, 1, 2, 3].map(|i| {
                Vec3::new(
                    i as f32,
                    (rnd() * 2.0 - 1.0) * spread,
                    (rnd() * 2.0 - 1.0) * spread,
                )
            });
            let w = 0.05 + 0.2 * rnd();
            let (s, pieces) = segment_split(cp, w, CurveType::Flat, split_depth);
            refined += pieces.iter().filter(|p| p.refine_depth() > 0).count();
            for _ in 0..50 {
                let target = evaluate_bezier(&cp, 0.05 + 0.9 * rnd()).0
                    + Vec3::new(0.0, rnd() - 0.5, rnd() - 0.5) * w;
                let origin =
                    target + Vec3::new(rnd() - 0.5, rnd() - 0.5, 3.0 + rnd()).normalize() * 5.0;
                let ray = Ray::new(origin, (target - origin) * (0.5 + rnd()), 0.0);
                let ours = closest(&pieces, &s, &ray);
                let reference = reference(&s, &ray);
                match (ours, reference) {
                    (Some(h), Some((t, u, dist_over_w))) => {
                        compared += 1;
                        if strict_u {
                            worst_t = worst_t.max((h.t as f64 - t).abs() / t);
                            // v = 0.5 ± dist/w: compare the distance part.
                            worst_v = worst_v.max(((h.v as f64 - 0.5).abs() - dist_over_w).abs());
                        }
                        if strict_u {
                            assert!((h.u as f64 - u).abs() < 1e-3, "u {} vs {u}", h.u);
                        } else {
                            // A bent curve may pass within half the width
                            // over a stretch; any point of it is a hit (pbrt's
                            // leaves take the nearest leaf), so check ours is
                            // on the curve, in the tube, and no farther than
                            // the nearest closest-point hit.
                            let (d, z) = reference_at(&s, &ray, h.u as f64);
                            assert!(
                                d <= s.width_at(h.u) as f64 * 0.5 + 1e-5,
                                "off the tube: {d}"
                            );
                            assert!((z - h.t as f64).abs() <= 1e-4 * z, "{z} vs {}", h.t);
                            assert!(h.t as f64 <= t * (1.0 + 1e-4), "{} beyond {t}", h.t);
                        }
                    }
                    (None, None) => {}
                    // Grazing the edge of the width: both are right within
                    // precision.
                    (a, b) => {
                        let near_edge = b.is_none_or(|(_, _, d)| d > 0.499)
                            && a.is_none_or(|h| (h.v - 0.5).abs() > 0.499);
                        assert!(near_edge, "ours {a:?} vs reference {b:?}");
                    }
                }
            }
        }
        (compared, worst_t, worst_v, refined)
    }

    #[test]
    fn hits_agree_with_an_f64_brute_force_reference() {
        let (compared, worst_t, worst_v, _) = compare_with_reference(3, 1.0, true);
        eprintln!("curve hits compared: {compared}; worst relative t error {worst_t:.2e}, worst v error {worst_v:.2e}");
        assert!(compared > 5000);
        assert!(worst_t < 1e-4, "{worst_t}");
        assert!(worst_v < 2e-3, "{worst_v}");
    }

    /// Curves too bent for build-time splitting alone (split depth 0, control
    /// points far off the chord) are refined per ray, and their hits are
    /// points of the curve within the width, no farther than the nearest
    /// closest-point hit.
    #[test]
    fn very_curved_pieces_refined_per_ray_agree_with_the_reference() {
        let (compared, _, _, refined) = compare_with_reference(0, 6.0, false);
        eprintln!("refined pieces {refined}; hits checked: {compared}");
        assert!(refined > 100, "{refined}");
        assert!(compared > 1000, "{compared}");
    }

    #[test]
    fn straight_curves_zero_widths_and_tiny_segments_are_finite() {
        let straight = [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(3.0, 0.0, 0.0),
        ];
        let tiny = [
            Vec3::ZERO,
            Vec3::splat(1e-7),
            Vec3::splat(2e-7),
            Vec3::splat(3e-7),
        ];
        let repeated = [
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
        ];
        for (cp, w) in [
            (straight, 0.1),
            (straight, 0.0),
            (tiny, 0.01),
            (repeated, 0.1),
        ] {
            for kind in [CurveType::Flat, CurveType::Cylinder] {
                let (s, pieces) = segment(cp, w, kind);
                for i in 0..50 {
                    let x = i as f32 / 49.0 * 3.0;
                    let ray = Ray::new(Vec3::new(x, 0.01, 5.0), Vec3::new(0.0, 0.0, -1.0), 0.0);
                    if let Some(h) = closest(&pieces, &s, &ray) {
                        let si = h.interaction(&s, &ray);
                        assert!(
                            si.p.is_finite() && si.n.is_finite() && si.curve_h.is_finite(),
                            "{si:?}"
                        );
                        assert!(h.t.is_finite() && (0.0..=1.0).contains(&h.v));
                    }
                }
            }
        }
    }

    #[test]
    fn no_self_intersection_from_offset_origins() {
        let cp = [
            Vec3::ZERO,
            Vec3::new(1.0, 0.5, 0.0),
            Vec3::new(2.0, -0.5, 0.2),
            Vec3::new(3.0, 0.0, 0.0),
        ];
        let (s, pieces) = segment(cp, 0.1, CurveType::Cylinder);
        let mut hits = 0;
        for i in 0..200 {
            let u = 0.02 + 0.96 * i as f32 / 199.0;
            let target = evaluate_bezier(&cp, u).0;
            let ray = Ray::new(
                target + Vec3::new(0.1, 0.2, 4.0),
                Vec3::new(-0.1, -0.2, -4.0),
                0.0,
            );
            let Some(h) = closest(&pieces, &s, &ray) else {
                continue;
            };
            hits += 1;
            let si = h.interaction(&s, &ray);
            // Leave the surface to the side of the normal and away from it.
            for d in [si.n, si.wo, (si.n + Vec3::new(0.3, 0.1, 0.0)).normalize()] {
                if d.dot(si.n) <= 0.0 {
                    continue;
                }
                let out = si.spawn_ray(d);
                assert!(
                    closest(&pieces, &s, &out).is_none_or(|h2| h2.t > 1e-2),
                    "re-hit at u {u}"
                );
            }
        }
        assert!(hits > 150);
    }

    #[test]
    fn cylinder_normal_turns_across_the_width() {
        let cp = [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(3.0, 0.0, 0.0),
        ];
        let (s, pieces) = segment(cp, 0.2, CurveType::Cylinder);
        let ray_at = |y: f32| Ray::new(Vec3::new(1.5, y, 5.0), Vec3::new(0.0, 0.0, -1.0), 0.0);
        let centre = closest(&pieces, &s, &ray_at(0.0))
            .unwrap()
            .interaction(&s, &ray_at(0.0));
        assert!(centre.n.z.abs() > 0.99, "{:?}", centre.n);
        let edge = closest(&pieces, &s, &ray_at(0.099)).unwrap();
        let si = edge.interaction(&s, &ray_at(0.099));
        assert!(si.n.z.abs() < 0.1, "normal at the edge {:?}", si.n);
        assert!((si.curve_h.abs() - 0.99).abs() < 0.01, "h {}", si.curve_h);
    }
}
