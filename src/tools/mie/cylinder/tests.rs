//! Tests of the cylinder series against physics that does not go through
//! it: energy conservation, the optical theorem against the absorption of
//! the internal field, the small-particle limits, the extinction paradox,
//! and direct evaluation of the Bessel functions by quadrature.

use super::*;
use std::f64::consts::PI;

/// A cylinder whose size parameter at 500 nm is `x`.
fn cylinder_with_size_parameter(x: f64, m: Complex64) -> (Cylinder, f64) {
    let wavelength_nm = 500.0;
    let diameter_um = x * wavelength_nm / (PI * 1000.0);
    (
        Cylinder {
            diameter_um,
            eta: m.re,
            kappa: m.im,
        },
        wavelength_nm,
    )
}

fn efficiencies_at(
    x: f64,
    m: Complex64,
    theta_i_deg: f64,
) -> (Coefficients, PolarisedEfficiencies) {
    let (cylinder, wavelength_nm) = cylinder_with_size_parameter(x, m);
    let coefficients =
        coefficients(&cylinder, wavelength_nm, theta_i_deg.to_radians()).expect("valid test input");
    let efficiencies = coefficients.efficiencies();
    (coefficients, efficiencies)
}

/// Without absorption every bit of removed power is scattered: Q_sca (a
/// sum of squares) must equal Q_ext (the forward amplitude) in both
/// polarisations. At oblique incidence this also checks the cross-
/// polarised coefficients, which enter Q_sca only.
#[test]
fn energy_is_conserved_without_absorption() {
    for x in [0.3, 5.0, 47.1, 300.0, 830.0] {
        for theta_i_deg in [0.0, 30.0, 60.0, 80.0] {
            let (_, q) = efficiencies_at(x, Complex64::new(1.55, 0.0), theta_i_deg);
            for (case, e) in [("I", q.case_i), ("II", q.case_ii)] {
                assert!(
                    (e.q_sca - e.q_ext).abs() < 1e-10,
                    "x = {x}, θ_i = {theta_i_deg}°, case {case}: Q_sca {} Q_ext {}",
                    e.q_sca,
                    e.q_ext
                );
            }
        }
    }
}

/// Reciprocity: at oblique incidence the two cross-polarised sets agree up
/// to sign, a_{n,I} = −b_{n,II} (B&H §8.4).
#[test]
fn cross_polarised_coefficients_are_reciprocal() {
    let (c, _) = efficiencies_at(40.0, Complex64::new(1.55, 0.02), 35.0);
    for n in 0..c.order_count() {
        assert!(
            (c.a_case_i[n] + c.b_case_ii[n]).norm() < 1e-12,
            "n = {n}: {} {}",
            c.a_case_i[n],
            c.b_case_ii[n]
        );
    }
}

/// J_n(z), n = 0..=highest, for complex z by the trapezoid rule on
/// J_n(z) = (1/2π)∫_0^{2π} exp(i(z sin τ − nτ)) dτ (Bessel's integral,
/// A&S 9.1.21): the integrand is periodic and entire, so the rule converges
/// geometrically; its error is the aliased J_{N−n}(z), negligible once
/// N − n exceeds |z| by a few Airy widths.
fn bessel_j_by_quadrature(z: Complex64, highest: usize) -> Vec<Complex64> {
    let point_count = highest + (z.norm() + 40.0 * z.norm().cbrt()) as usize + 64;
    let unit_roots: Vec<Complex64> = (0..point_count)
        .map(|k| Complex64::from_polar(1.0, -2.0 * PI * k as f64 / point_count as f64))
        .collect();
    let mut sums = vec![Complex64::new(0.0, 0.0); highest + 1];
    for k in 0..point_count {
        let tau = 2.0 * PI * k as f64 / point_count as f64;
        let kernel = (Complex64::i() * z * tau.sin()).exp();
        for (n, sum) in sums.iter_mut().enumerate() {
            *sum += kernel * unit_roots[(n * k) % point_count];
        }
    }
    sums.iter().map(|s| s / point_count as f64).collect()
}

/// Nodes and weights of 16-point Gauss–Legendre on [−1, 1], by Newton's
/// method on P_16 from Chebyshev-like first guesses.
fn gauss_legendre_16() -> Vec<(f64, f64)> {
    let count = 16;
    (0..count)
        .map(|i| {
            let mut node = (PI * (i as f64 + 0.75) / (count as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, node);
                for k in 2..=count {
                    let p2 = ((2 * k - 1) as f64 * node * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                derivative = count as f64 * (node * p1 - p0) / (node * node - 1.0);
                let step = p1 / derivative;
                node -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (node, 2.0 / ((1.0 - node * node) * derivative * derivative))
        })
        .collect()
}

fn composite_gauss(
    f: impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    panels: usize,
    rule: &[(f64, f64)],
) -> f64 {
    let width = (b - a) / panels as f64;
    let mut total = 0.0;
    for p in 0..panels {
        let centre = a + (p as f64 + 0.5) * width;
        for &(node, weight) in rule {
            total += weight * f(centre + 0.5 * width * node);
        }
    }
    total * 0.5 * width
}

/// Y_n(x) from the integral representation (A&S 9.1.22)
///   Y_n(x) = (1/π)∫_0^π sin(x sin τ − nτ) dτ
///          − (1/π)∫_0^∞ (e^{nt} + (−1)^n e^{−nt}) e^{−x sinh t} dt,
/// by composite Gauss–Legendre; independent of any recurrence.
fn bessel_y_by_quadrature(x: f64, n: usize, rule: &[(f64, f64)]) -> f64 {
    let order = n as f64;
    let oscillatory = composite_gauss(
        |tau| (x * tau.sin() - order * tau).sin(),
        0.0,
        PI,
        ((x + order) / 2.0) as usize + 16,
        rule,
    );
    // The second integrand e^{nt − x sinh t} peaks at cosh t = n/x (or at
    // t = 0); integrate until it is e^{−45} below its peak.
    let exponent = |t: f64| order * t - x * t.sinh();
    let peak_t = if order > x { (order / x).acosh() } else { 0.0 };
    let peak = exponent(peak_t);
    let mut end = peak_t + 1e-3;
    while exponent(end) > peak - 45.0 {
        end *= 1.2;
    }
    let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
    let evanescent = composite_gauss(
        |t| exponent(t).exp() + sign * (-order * t - x * t.sinh()).exp(),
        0.0,
        end,
        400,
        rule,
    );
    (oscillatory - evanescent) / PI
}

/// The coefficients straight from B&H (8.30)–(8.31), with J_n(η) and
/// J_n'(η) themselves (no log-derivative) and every Bessel function from
/// quadrature, for the orders in `orders`; returns (a_I, b_I, a_II, b_II).
fn direct_coefficients(
    x: f64,
    m: Complex64,
    theta_i_rad: f64,
    orders: &[usize],
) -> Vec<[Complex64; 4]> {
    let highest = orders.iter().copied().max().unwrap_or(0) + 1;
    let cos_zeta = theta_i_rad.sin();
    let xi = x * theta_i_rad.cos();
    let eta = x * (m * m - cos_zeta * cos_zeta).sqrt();
    let j_eta = bessel_j_by_quadrature(eta, highest);
    let j_xi = bessel_j_by_quadrature(Complex64::new(xi, 0.0), highest);
    let rule = gauss_legendre_16();
    let i = Complex64::i();
    orders
        .iter()
        .map(|&n| {
            let order = n as f64;
            // J_n' = (J_{n−1} − J_{n+1})/2 with J_{−1} = −J_1 (A&S 9.1.27).
            let derivative = |values: &[Complex64]| {
                let previous = if n == 0 { -values[1] } else { values[n - 1] };
                0.5 * (previous - values[n + 1])
            };
            let je = j_eta[n];
            let je_d = derivative(&j_eta);
            let j = j_xi[n].re;
            let j_d = derivative(&j_xi).re;
            let y = bessel_y_by_quadrature(xi, n, &rule);
            let y_previous = if n == 0 {
                -bessel_y_by_quadrature(xi, 1, &rule)
            } else {
                bessel_y_by_quadrature(xi, n - 1, &rule)
            };
            let y_next = bessel_y_by_quadrature(xi, n + 1, &rule);
            let h = Complex64::new(j, y);
            let h_d = Complex64::new(j_d, 0.5 * (y_previous - y_next));
            let mismatch = xi * xi / (eta * eta) - 1.0;
            let d_n = order * cos_zeta * eta * je * h * mismatch;
            let c_n = order * cos_zeta * eta * je * j * mismatch;
            let b_n = xi * (m * m * xi * je_d * j - eta * je * j_d);
            let v_n = xi * (m * m * xi * je_d * h - eta * je * h_d);
            let w_n = i * xi * (eta * je * h_d - xi * je_d * h);
            let a_n = i * xi * (xi * je_d * j - eta * je * j_d);
            let denominator = w_n * v_n + i * d_n * d_n;
            [
                (c_n * v_n - b_n * d_n) / denominator,
                (w_n * b_n + i * d_n * c_n) / denominator,
                -(a_n * v_n - i * c_n * d_n) / denominator,
                -i * (c_n * w_n + a_n * d_n) / denominator,
            ]
        })
        .collect()
}

/// The recurrences (Miller for J, upward Y, downward D_n started at
/// |mx| + 16|mx|^{1/3} + 20) against the quadratures above, up to the
/// size parameter of D = 100 µm at 380 nm; and the orders just past n_max,
/// evaluated directly, are negligible (the truncation is safe).
#[test]
fn coefficients_match_direct_bessel_evaluation() {
    let m = Complex64::new(1.55, 0.0005);
    for (x, stride) in [(3.7, 1), (95.0, 3), (830.0, 29)] {
        for theta_i_deg in [0.0, 30.0] {
            let (c, _) = efficiencies_at(x, m, theta_i_deg);
            let n_max = c.order_count() - 1;
            let mut orders: Vec<usize> = (0..=n_max).step_by(stride).collect();
            orders.extend([n_max - 1, n_max]);
            let direct = direct_coefficients(x, m, theta_i_deg.to_radians(), &orders);
            for (&n, expected) in orders.iter().zip(&direct) {
                let computed = [c.a_case_i[n], c.b_case_i[n], c.a_case_ii[n], c.b_case_ii[n]];
                for (k, (got, want)) in computed.iter().zip(expected).enumerate() {
                    assert!(
                        (got - want).norm() < 1e-10,
                        "x = {x}, θ_i = {theta_i_deg}°, n = {n}, coefficient {k}: {got} against {want}"
                    );
                }
            }
            let beyond: Vec<usize> = (n_max + 1..=n_max + 10).collect();
            let tail: f64 = direct_coefficients(x, m, theta_i_deg.to_radians(), &beyond)
                .iter()
                .map(|set| set.iter().map(|c| c.norm()).sum::<f64>())
                .sum();
            assert!(
                4.0 / x * tail < 1e-8,
                "x = {x}: the orders past n_max would add up to {}",
                4.0 / x * tail
            );
        }
    }
}

/// With absorption, Q_ext − Q_sca must be the power the internal field
/// dissipates. That power is the inward Poynting flux through the
/// surface: per order, with the internal field d_n J_n(mkr) e^{inφ} and
/// d_n J_n(mx) = J_n(x) − b_n H_n(x) from continuity of the tangential
/// field, Q_abs,I = −π Σ_n |J_n(x) − b_n H_n(x)|² Im(m J_n'(mx)/J_n(mx)),
/// and for case II (the internal H_z, with E_φ ∝ ∂_r H_z/ε)
/// Q_abs,II = −π Σ_n |J_n(x) − a_n H_n(x)|² Im(J_n'(mx)/(m J_n(mx))),
/// the sums over all integers n. (Equivalently the volume integral of
/// Im(ε)|E|², by ∫_0^a J_n(αr)J_n(βr) r dr with β = α*.) J_n(mx) comes
/// from quadrature, not from the log-derivative recurrence.
#[test]
fn optical_theorem_matches_internal_absorption() {
    for (x, m) in [
        (2.0, Complex64::new(1.55, 0.01)),
        (40.0, Complex64::new(1.55, 0.01)),
        (150.0, Complex64::new(1.55, 0.002)),
        (12.0, Complex64::new(1.33, 0.5)),
    ] {
        let (c, q) = efficiencies_at(x, m, 0.0);
        let n_max = c.order_count() - 1;
        let j_inside = bessel_j_by_quadrature(m * x, n_max + 1);
        let j = bessel_j_sequence(x, n_max + 1);
        let y = bessel_y_sequence(x, &j, n_max);
        let mut absorbed_i = 0.0;
        let mut absorbed_ii = 0.0;
        for n in 0..=n_max {
            let previous = if n == 0 {
                -j_inside[1]
            } else {
                j_inside[n - 1]
            };
            let log_derivative = 0.5 * (previous - j_inside[n + 1]) / j_inside[n];
            let h = Complex64::new(j[n], y[n]);
            let multiplicity = if n == 0 { 1.0 } else { 2.0 };
            absorbed_i -=
                multiplicity * PI * (j[n] - c.b_case_i[n] * h).norm_sqr() * (m * log_derivative).im;
            absorbed_ii -= multiplicity
                * PI
                * (j[n] - c.a_case_ii[n] * h).norm_sqr()
                * (log_derivative / m).im;
        }
        assert!(
            (absorbed_i - q.case_i.q_abs).abs() < 1e-9 * q.case_i.q_abs.max(1e-3),
            "x = {x}, m = {m}, case I: internal {absorbed_i}, Q_ext − Q_sca {}",
            q.case_i.q_abs
        );
        assert!(
            (absorbed_ii - q.case_ii.q_abs).abs() < 1e-9 * q.case_ii.q_abs.max(1e-3),
            "x = {x}, m = {m}, case II: internal {absorbed_ii}, Q_ext − Q_sca {}",
            q.case_ii.q_abs
        );
    }
}

/// x ≪ 1: the internal field is the uniform electrostatic one (E_in = E_0
/// for E along the axis; E_in = 2E_0/(m² + 1) across it), so
///   Q_abs,I = (πx/2) Im(m²),  Q_abs,II = 2πx Im(m²)/|m² + 1|²,
/// and the induced line dipole radiates
///   Q_sca,I = (π²x³/8)|m² − 1|²,  Q_sca,II = (π²x³/4)|(m² − 1)/(m² + 1)|²
/// (B&H §8.5, the small-x limits), all with relative corrections O(x²).
#[test]
fn small_size_parameter_matches_rayleigh_limit() {
    let x = 0.01;
    for m in [
        Complex64::new(1.55, 0.1),
        Complex64::new(1.33, 0.0),
        Complex64::new(2.0, 1.0),
    ] {
        let (_, q) = efficiencies_at(x, m, 0.0);
        let m2 = m * m;
        let q_abs_i = PI * x / 2.0 * m2.im;
        let q_abs_ii = 2.0 * PI * x * m2.im / (m2 + 1.0).norm_sqr();
        let q_sca_i = PI * PI * x.powi(3) / 8.0 * (m2 - 1.0).norm_sqr();
        let q_sca_ii = PI * PI * x.powi(3) / 4.0 * ((m2 - 1.0) / (m2 + 1.0)).norm_sqr();
        let close = |got: f64, want: f64| (got - want).abs() <= 2e-3 * want.abs() + 1e-15;
        assert!(
            close(q.case_i.q_sca, q_sca_i),
            "m = {m}: Q_sca,I {} against {q_sca_i}",
            q.case_i.q_sca
        );
        assert!(
            close(q.case_ii.q_sca, q_sca_ii),
            "m = {m}: Q_sca,II {} against {q_sca_ii}",
            q.case_ii.q_sca
        );
        assert!(
            close(q.case_i.q_abs, q_abs_i),
            "m = {m}: Q_abs,I {} against {q_abs_i}",
            q.case_i.q_abs
        );
        assert!(
            close(q.case_ii.q_abs, q_abs_ii),
            "m = {m}: Q_abs,II {} against {q_abs_ii}",
            q.case_ii.q_abs
        );
    }
}

/// The extinction paradox: a cylinder much wider than the wavelength
/// removes twice the power its shadow intercepts (half by diffraction), so
/// Q_ext → 2, and at oblique incidence, where the shadow of a length L is
/// 2aL cos θ_i, Q_ext → 2 cos θ_i. A clear cylinder converges slowly: the
/// rays through its centre interfere with the diffracted wave, a ripple of
/// relative size ~(π/2)·(2/(πρ))^{1/2} with ρ = 2x(η − 1) (anomalous
/// diffraction; ~0.05 at x = 500, η = 1.55, measured 0.063), so the 1 % check is made with
/// enough absorption to damp those rays (e^{−4κx} ≤ e^{−10}), and the
/// clear cylinder gets the ripple's bound.
#[test]
fn extinction_approaches_twice_the_shadow_for_large_cylinders() {
    let x = 500.0;
    for theta_i_deg in [0.0_f64, 30.0] {
        let limit = 2.0 * theta_i_deg.to_radians().cos();
        for (m, tolerance) in [
            (Complex64::new(1.55, 0.005), 0.01),
            (Complex64::new(1.55, 0.05), 0.01),
            (Complex64::new(1.55, 0.0), 0.1),
        ] {
            let (_, q) = efficiencies_at(x, m, theta_i_deg);
            for e in [q.case_i, q.case_ii, q.unpolarised] {
                assert!(
                    (e.q_ext - limit).abs() < tolerance * limit,
                    "θ_i = {theta_i_deg}°, m = {m}: Q_ext {} against {limit}",
                    e.q_ext
                );
            }
        }
    }
}

#[test]
fn invalid_input_is_rejected() {
    let good = Cylinder {
        diameter_um: 10.0,
        eta: 1.55,
        kappa: 0.0,
    };
    assert!(matches!(
        Cylinder::new(-1.0, 1.55, 0.0),
        Err(MieError::Diameter(_))
    ));
    assert!(matches!(
        Cylinder::new(10.0, 0.0, 0.0),
        Err(MieError::Eta(_))
    ));
    assert!(matches!(
        Cylinder::new(10.0, 1.5, -0.1),
        Err(MieError::Kappa(_))
    ));
    assert!(matches!(
        Cylinder::new(f64::NAN, 1.5, 0.0),
        Err(MieError::Diameter(_))
    ));
    assert!(matches!(
        coefficients(&good, 0.0, 0.0),
        Err(MieError::Wavelength(_))
    ));
    assert!(matches!(
        coefficients(&good, 500.0, 90f64.to_radians()),
        Err(MieError::IncidenceAngle(_))
    ));
}
