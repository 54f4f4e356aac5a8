//! The ray part of Benamira & Pattanaik's dual hair model (2021, §4): the
//! path of a ray through a fibre of elliptical cross-section, in the
//! azimuthal plane, with Bravais' index η' (Eq. 5) standing in for the 3D
//! refraction.
//!
//! Everything is vector geometry (entry point, normals, Snell, chords as
//! quadratic roots); the paper's closed-form angles (Eq. 9–20) are checked
//! against it in the tests below, which confirm the slips the printed
//! formulas have (signed angles in Eq. 9 and 18, Eq. 12 inverted, Eq. 18's
//! extra π, Eq. 7's narrow width, Eq. 24's exponent).
//!
//! Frame: the ellipse x²/a² + y²/b² = 1 with the major axis along x; an
//! azimuth φ is the angle of a direction in this plane from the major axis.
//! A ray *comes from* azimuth φ_in (it travels along −(cos φ_in, sin φ_in))
//! and meets the fibre at offset h ∈ [−1, 1] across the projected width,
//! with the sign convention of pbrt's circular fibre (h = sin γ for a
//! circle, the reflection leaving at φ_in − 2γ).
//!
//! Normalisation (paper §7.2): lengths are in units of the mean semi-axis
//! r̄ = (a + b)/2, so σ_a keeps pbrt's meaning (absorption per unit radius)
//! and a 30 × 20 µm ellipse absorbs like the 50 µm-thick circular fibre the
//! paper compares it with; a = b is pbrt's fibre exactly.

use super::fresnel::fr_dielectric;
use crate::math::{safe_sqrt, sqr};
use crate::spectrum::SampledSpectrum;
use glam::DVec2;

/// Explicit lobes R, TT, TRT (as pbrt's `P_MAX`).
pub const LOBES: usize = 3;

/// Exits traced one by one (R's reflection counts as exit 0); later exits
/// form a geometric tail with the mean chord and escape of the traced
/// residual exits.
const TRACED_EXITS: usize = 6;

/// Which equations the ray part follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// Physically consistent: h spans the exact projected width, energy
    /// stopped by total internal reflection continues to the next exit, and
    /// higher orders form pbrt's residual lobe.
    Exact,
    /// The paper as printed: h spans Eq. 7's width, A_p = 0 under total
    /// internal reflection (Eq. 22), no residual lobe (Eq. 37).
    Paper,
}

/// The Fresnel reflectance used at the fibre's inner interfaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InternalFresnel {
    /// Each interface reflects with the Fresnel term of its own side
    /// (hair → air at the internal angle, 1 under total internal
    /// reflection). For a circular fibre this equals pbrt's f0 at every
    /// interface.
    Pbrt,
    /// The paper's f_p = F(ρ, arccos(cos θ cos γ_{i,p})) (Eq. 22): the
    /// air → hair term at the internal angle; for a circular fibre Eq. 24's
    /// f1.
    Paper,
}

/// An elliptical cross-section, semi-axes in units of the mean semi-axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipse {
    pub a: f32,
    pub b: f32,
}

/// The 3D angles the 2D problem needs (Bravais' reduction).
#[derive(Clone, Copy, Debug)]
pub struct Optics {
    /// Index of refraction ρ.
    pub eta: f32,
    /// Bravais' index η'(θ, ρ) (Eq. 5).
    pub eta_p: f32,
    /// cos θ of the incident ray outside, and of the refracted ray inside.
    pub cos_theta: f32,
    pub cos_theta_t: f32,
}

impl Optics {
    /// For an incident ray with longitudinal sin θ. Near θ = ±π/2 Bravais'
    /// index grows without bound; it is capped where refraction is already
    /// along the normal to float precision.
    pub fn new(eta: f32, sin_theta: f32) -> Self {
        let cos_theta = safe_sqrt(1.0 - sqr(sin_theta));
        let cos_theta_t = safe_sqrt(1.0 - sqr(sin_theta / eta));
        let eta_p = (safe_sqrt(sqr(eta) - sqr(sin_theta)) / cos_theta.max(1e-7)).min(1e7);
        Optics {
            eta,
            eta_p,
            cos_theta,
            cos_theta_t,
        }
    }
}

/// One way out of the fibre: the azimuth it leaves at, the fraction of the
/// entering power that leaves there before absorption (Fresnel only), and
/// the path length inside up to there (in mean-radius units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Exit {
    pub phi: f32,
    pub escape: f32,
    pub length: f32,
}

/// The traced path for one (φ_in, h).
#[derive(Clone, Copy, Debug, Default)]
pub struct Trace {
    /// Exit 0 is the reflection R, exit p the p-th refraction out.
    pub exits: [Exit; TRACED_EXITS],
    /// Power still inside after the last traced exit, and its path length.
    pub remaining: f32,
    pub remaining_length: f32,
    /// Mean escape fraction and chord length over the exits after TRT,
    /// which continue as a geometric tail.
    pub tail_escape: f32,
    pub tail_chord: f32,
    /// Whether later orders are kept (the exact variant's residual lobe).
    pub residual: bool,
}

/// 2D reflection of d about the unit normal n.
fn reflect(d: DVec2, n: DVec2) -> DVec2 {
    d - 2.0 * d.dot(n) * n
}

fn sqrt0(x: f64) -> f64 {
    x.max(0.0).sqrt()
}

impl Ellipse {
    /// Semi-axes a ≥ b > 0 (any unit): normalised to (a + b)/2 = 1.
    pub fn new(a: f32, b: f32) -> Self {
        let r = 0.5 * (a + b);
        Ellipse { a: a / r, b: b / r }
    }

    pub const CIRCLE: Ellipse = Ellipse { a: 1.0, b: 1.0 };

    /// Half the exact width projected across a ray from azimuth φ (the
    /// support function): √(a² sin²φ + b² cos²φ).
    pub fn half_width(&self, phi: f32) -> f32 {
        let (s, c) = phi.sin_cos();
        (sqr(self.a * s) + sqr(self.b * c)).sqrt()
    }

    /// The paper's Eq. 7 (halved): b cos²φ + a sin²φ, a lower bound of the
    /// exact half width (up to 1.9 % narrow at a/b = 1.5).
    pub fn half_width_eq7(&self, phi: f32) -> f32 {
        let (s, c) = phi.sin_cos();
        self.b * c * c + self.a * s * s
    }

    /// Half the width h spans in a variant.
    pub fn half_width_for(&self, phi: f32, variant: Variant) -> f32 {
        match variant {
            Variant::Exact => self.half_width(phi),
            Variant::Paper => self.half_width_eq7(phi),
        }
    }

    /// M·v with M = diag(1/a², 1/b²), the ellipse's quadratic form.
    fn m(&self, v: DVec2) -> DVec2 {
        DVec2::new(v.x / (self.a as f64).powi(2), v.y / (self.b as f64).powi(2))
    }

    /// Outward unit normal at a boundary point (Eq. 8).
    pub fn normal(&self, p: DVec2) -> DVec2 {
        self.m(p).normalize_or(DVec2::X)
    }

    /// Where a ray from direction u at offset `offset` (in mean-radius
    /// units along w, u turned by −90°) first meets the ellipse: the larger
    /// root of the line c + t u against the quadratic form.
    pub fn entry(&self, u: DVec2, offset: f64) -> DVec2 {
        let w = DVec2::new(u.y, -u.x);
        let c = offset * w;
        let mu = self.m(u);
        let qa = u.dot(mu);
        let qb = c.dot(mu);
        let qc = c.dot(self.m(c)) - 1.0;
        let t = (-qb + sqrt0(qb * qb - qa * qc)) / qa;
        self.project(c + t * u)
    }

    /// Length of the chord from boundary point p along inward direction d:
    /// the non-zero root of (p + L d)ᵀ M (p + L d) = 1 (Eq. 13/17's vector
    /// form).
    pub fn chord(&self, p: DVec2, d: DVec2) -> f64 {
        (-2.0 * p.dot(self.m(d)) / d.dot(self.m(d))).max(0.0)
    }

    /// Back onto the boundary along the ray from the centre (removes the
    /// drift of many chords).
    fn project(&self, p: DVec2) -> DVec2 {
        let q = p.dot(self.m(p));
        if q > 0.0 {
            p / q.sqrt()
        } else {
            DVec2::new(self.a as f64, 0.0)
        }
    }

    /// Traces a ray from azimuth `phi_in` at offset h across the variant's
    /// width: reflection R, then chord by chord, refraction out or internal
    /// reflection at each exit with the chosen Fresnel. The geometry runs
    /// in f64: near grazing entry the exit is near the critical angle, where
    /// f32 rounding would move A_p by 0.1 %.
    pub fn trace(
        &self,
        phi_in: f32,
        h: f32,
        optics: &Optics,
        variant: Variant,
        fresnel: InternalFresnel,
    ) -> Trace {
        let (sin_phi, cos_phi) = (phi_in as f64).sin_cos();
        let u = DVec2::new(cos_phi, sin_phi);
        let h = h.clamp(-1.0, 1.0) as f64;
        let eta_p = optics.eta_p as f64;
        // The width in f64 too: an f32 width would put h = ±1 a rounding
        // error inside the tangent, far from grazing (cos γ ~ √ε).
        let (a, b) = (self.a as f64, self.b as f64);
        let half_width = match variant {
            Variant::Exact => (a * a * sin_phi * sin_phi + b * b * cos_phi * cos_phi).sqrt(),
            Variant::Paper => b * cos_phi * cos_phi + a * sin_phi * sin_phi,
        };
        let mut p = self.entry(u, h * half_width);
        let n = self.normal(p);
        let d = -u;
        let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
        let r = reflect(d, n);
        let f0 = fr_dielectric(optics.cos_theta * cos_i as f32, optics.eta);
        let mut trace = Trace {
            residual: variant == Variant::Exact,
            ..Trace::default()
        };
        trace.exits[0] = Exit {
            phi: r.y.atan2(r.x) as f32,
            escape: f0,
            length: 0.0,
        };
        // Refract in (Snell with η'): t = d/η' + (cos_i/η' − cos_t) n.
        let inv = 1.0 / eta_p;
        let cos_t = sqrt0(1.0 - inv * inv * (1.0 - cos_i * cos_i));
        let mut d = (d * inv + (cos_i * inv - cos_t) * n).normalize_or(-n);
        let mut inside = 1.0 - f0;
        let mut length = 0.0f64;
        let (mut tail_escape, mut tail_chord) = (0.0, 0.0);
        for (k, exit) in trace.exits.iter_mut().enumerate().skip(1) {
            let l = self.chord(p, d);
            length += l;
            p = self.project(p + l * d);
            let n = self.normal(p);
            let cos_int = d.dot(n).clamp(0.0, 1.0);
            let sin2_out = eta_p * eta_p * (1.0 - cos_int * cos_int);
            let tir = sin2_out >= 1.0;
            let cos_out = sqrt0(1.0 - sin2_out);
            let f = match fresnel {
                _ if tir && variant == Variant::Exact => 1.0,
                // Hair → air at the internal angle equals air → hair at
                // the external one (Fresnel is reciprocal); the external
                // form is the well-conditioned one near the critical angle.
                InternalFresnel::Pbrt if tir => 1.0,
                InternalFresnel::Pbrt => {
                    fr_dielectric(optics.cos_theta * cos_out as f32, optics.eta)
                }
                InternalFresnel::Paper => {
                    fr_dielectric(optics.cos_theta * cos_int as f32, optics.eta)
                }
            };
            let out = if tir {
                reflect(d, n)
            } else {
                eta_p * d + (cos_out - eta_p * cos_int) * n
            };
            *exit = Exit {
                phi: out.y.atan2(out.x) as f32,
                escape: if tir { 0.0 } else { inside * (1.0 - f) },
                length: length as f32,
            };
            if k >= LOBES {
                tail_escape += if tir { 0.0 } else { 1.0 - f };
                tail_chord += l as f32;
            }
            inside *= f;
            d = reflect(d, n);
        }
        let later = (TRACED_EXITS - LOBES) as f32;
        trace.tail_escape = tail_escape / later;
        trace.tail_chord = tail_chord / later;
        trace.remaining = inside;
        trace.remaining_length = length as f32;
        trace
    }
}

impl Trace {
    /// A_0…A_2 and the residual A_3 (all later exits) for absorption σ_a
    /// per unit mean radius: T = exp(−σ_a L / cos θ_t) per path (Eq. 22).
    pub fn attenuations(
        &self,
        sigma_a: SampledSpectrum,
        cos_theta_t: f32,
    ) -> [SampledSpectrum; LOBES + 1] {
        let k = sigma_a / cos_theta_t.max(1e-7);
        let transmit = |len: f32| (-(k * len)).exp();
        let mut a = [SampledSpectrum::ZERO; LOBES + 1];
        for (p, e) in self.exits.iter().enumerate().take(LOBES) {
            a[p] = transmit(e.length) * e.escape;
        }
        if !self.residual {
            return a;
        }
        for e in &self.exits[LOBES..] {
            if e.escape > 0.0 {
                a[LOBES] += transmit(e.length) * e.escape;
            }
        }
        // Tail: the power left inside escapes at the traced later exits'
        // mean rate ē per chord of mean length ℓ̄, absorbed on the way:
        // Σ_j (1 − ē)^{j−1} ē τ^j = ē τ / (1 − (1 − ē) τ), τ = e^{−k ℓ̄}
        // (pbrt's geometric residual when every chord is alike).
        if self.remaining > 0.0 {
            let tau = transmit(self.tail_chord);
            let e = self.tail_escape.max(1e-4);
            let tail = (tau * e).safe_div(SampledSpectrum::ONE - tau * (1.0 - e));
            a[LOBES] += transmit(self.remaining_length) * tail * self.remaining;
        }
        a
    }
}

/// One row (fixed φ_in) of the h-averaged azimuthal maps of the ray part:
/// for lobes R, TT, TRT, N_p(φ_out) = ½∫_{−1}^{1} A_p(h) L(φ_out − φ_p(h), s) dh
/// by the midpoint rule over `n_h` offsets (L pbrt's logistic trimmed to
/// [−π, π]), and the residual A_3/(2π) (its direction is uniform). So
/// ∫ N_p dφ_out is the h average of A_p. σ_a is grey here.
#[allow(clippy::too_many_arguments)]
pub fn h_averaged_row(
    ellipse: &Ellipse,
    phi_in: f32,
    optics: &Optics,
    sigma_a: f32,
    s: f32,
    variant: Variant,
    fresnel: InternalFresnel,
    n_h: usize,
    phi_out: &[f32],
) -> [Vec<f32>; LOBES + 1] {
    use super::hair::{trimmed_logistic, wrap_angle};
    use std::f32::consts::PI;
    let mut rows: [Vec<f32>; LOBES + 1] = std::array::from_fn(|_| vec![0.0; phi_out.len()]);
    let weight = 1.0 / n_h as f32; // ½ dh with dh = 2/n_h
    for i in 0..n_h {
        let h = -1.0 + (2.0 * i as f32 + 1.0) / n_h as f32;
        let trace = ellipse.trace(phi_in, h, optics, variant, fresnel);
        let a = trace.attenuations(SampledSpectrum::splat(sigma_a), optics.cos_theta_t);
        for p in 0..LOBES {
            if a[p][0] <= 0.0 {
                continue;
            }
            let center = trace.exits[p].phi;
            for (v, &phi) in rows[p].iter_mut().zip(phi_out) {
                let x = wrap_angle(phi - center);
                // The kernel is below 1e-16 of its peak past 40 s.
                if x.abs() < 40.0 * s {
                    *v += weight * a[p][0] * trimmed_logistic(x, s, -PI, PI);
                }
            }
        }
        for v in rows[LOBES].iter_mut() {
            *v += weight * a[LOBES][0] / (2.0 * PI);
        }
    }
    rows
}
