//! Integer-order cylinder functions for the Lorenz–Mie cylinder series:
//! J_n(x) and Y_n(x) of a real argument for n = 0..=N, and the logarithmic
//! derivative D_n(z) = J_n'(z)/J_n(z) of a complex argument.
//!
//! Each is computed by the recurrence that is stable in its direction
//! (Bohren & Huffman 1983, §8.3 and App. C; Abramowitz & Stegun 9.1.27):
//! J_n by Miller's downward recurrence, Y_n upward from Y_0 and Y_1 (which
//! come from Neumann series over the same J's), D_n downward. Size
//! parameters up to ~10^3 are in range; nothing here overflows there
//! because only ratios of J_n(z) of complex argument are ever formed.

use num_complex::Complex64;

/// Euler–Mascheroni constant (for the Neumann series of Y_0 and Y_1).
const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;

/// Values above this are rescaled during Miller's recurrence (which grows
/// towards low orders) so that nothing overflows, their squares (summed
/// for the normalisation) included.
const MILLER_RESCALE_THRESHOLD: f64 = 1e100;

/// The order at which the downward recurrences start for an argument of
/// modulus `modulus` when orders up to `highest_order` are wanted.
///
/// Below the turning point n ≈ |z| the recurrence is oscillatory and
/// errors in the starting value are not damped, so the start has to lie
/// well inside the evanescent region n > |z|, whose width grows as
/// |z|^{1/3} (the Airy scale). Issue 30 measured that |z| + 15 is not
/// enough at |z| ≈ 300 (coefficient errors of 1e-2) while
/// |z| + 16|z|^{1/3} + 20 agrees with direct evaluation to ~1e-12 up to
/// |z| ≈ 1300.
pub fn downward_start_order(modulus: f64, highest_order: usize) -> usize {
    let airy_margin = modulus + 16.0 * modulus.cbrt() + 20.0;
    (airy_margin.ceil() as usize).max(highest_order + 20)
}

/// J_n(x) for n = 0..=highest_order and real x > 0, by Miller's downward
/// recurrence J_{n−1} = (2n/x)J_n − J_{n+1} (A&S 9.1.27) from an arbitrary
/// small start far above the turning point, normalised by
/// J_0² + 2ΣJ_n² = 1 (A&S 9.1.76; all terms positive, so no cancellation),
/// with the sign fixed by J_0 + 2ΣJ_{2k} = 1 (A&S 9.1.46).
///
/// Returns `highest_order + 1` values plus the orders above (up to the
/// start), which the Neumann series for Y_0 and Y_1 need: the vector's
/// length is the start order + 1.
pub fn bessel_j_sequence(x: f64, highest_order: usize) -> Vec<f64> {
    let start = downward_start_order(x, highest_order);
    // Round up to even so the sign sum J_0 + 2ΣJ_{2k} sees whole pairs.
    let start = start + (start & 1);
    let mut values = vec![0.0_f64; start + 2];
    values[start] = 1e-30;
    for order in (1..=start).rev() {
        let lower = (2.0 * order as f64 / x) * values[order] - values[order + 1];
        values[order - 1] = lower;
        if lower.abs() > MILLER_RESCALE_THRESHOLD {
            // Rescale everything computed so far; the normalisation
            // below only needs the values up to a common factor.
            for value in &mut values[order - 1..] {
                *value /= MILLER_RESCALE_THRESHOLD;
            }
        }
    }
    values.truncate(start + 1);
    // Bring the largest value to 1 first: the start value is arbitrary, and
    // squares of values far from 1 would underflow or overflow.
    let largest = values
        .iter()
        .fold(0.0_f64, |largest, v| largest.max(v.abs()));
    for value in &mut values {
        *value /= largest;
    }
    let sum_of_squares: f64 =
        values[0] * values[0] + 2.0 * values[1..].iter().map(|v| v * v).sum::<f64>();
    let even_sum: f64 = values[0] + 2.0 * values[2..].iter().step_by(2).sum::<f64>();
    let scale = even_sum.signum() / sum_of_squares.sqrt();
    for value in &mut values {
        *value *= scale;
    }
    values
}

/// Y_n(x) for n = 0..=highest_order and real x > 0, given the J sequence
/// of [`bessel_j_sequence`] (which must extend past `highest_order`).
///
/// Y_0 from its Neumann series (A&S 9.1.88)
///   Y_0 = (2/π)[ln(x/2) + γ]J_0 − (4/π) Σ_{k≥1} (−1)^k J_{2k}/k,
/// Y_1 = −Y_0' from the derivative of the same series (with
/// J_0' = −J_1 and J_{2k}' = (J_{2k−1} − J_{2k+1})/2):
///   Y_1 = −(2/π)J_0/x + (2/π)[ln(x/2) + γ]J_1 + (2/π) Σ (−1)^k (J_{2k−1} − J_{2k+1})/k,
/// then upward Y_{n+1} = (2n/x)Y_n − Y_{n−1}, stable because Y_n is the
/// dominant solution.
pub fn bessel_y_sequence(x: f64, bessel_j: &[f64], highest_order: usize) -> Vec<f64> {
    let log_term = (x / 2.0).ln() + EULER_GAMMA;
    let two_over_pi = 2.0 / std::f64::consts::PI;
    let mut series_y0 = 0.0;
    let mut series_y1 = 0.0;
    let mut k = 1;
    while 2 * k + 1 < bessel_j.len() {
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        series_y0 += sign * bessel_j[2 * k] / k as f64;
        series_y1 += sign * (bessel_j[2 * k - 1] - bessel_j[2 * k + 1]) / k as f64;
        k += 1;
    }
    let y0 = two_over_pi * log_term * bessel_j[0] - 2.0 * two_over_pi * series_y0;
    let y1 = -two_over_pi * bessel_j[0] / x
        + two_over_pi * log_term * bessel_j[1]
        + two_over_pi * series_y1;
    let mut values = Vec::with_capacity(highest_order + 1);
    values.push(y0);
    if highest_order >= 1 {
        values.push(y1);
    }
    for order in 1..highest_order {
        let next = (2.0 * order as f64 / x) * values[order] - values[order - 1];
        values.push(next);
    }
    values
}

/// D_n(z) = J_n'(z)/J_n(z) for n = 0..=highest_order, by the downward
/// recurrence D_{n−1} = (n−1)/z − 1/(D_n + n/z) (from J_{n−1} = J_n' +
/// (n/z)J_n and J_{n−1}' = ((n−1)/z)J_{n−1} − J_n; Bohren & Huffman
/// §8.3), started at D = 0 at [`downward_start_order`].
pub fn log_derivative_sequence(z: Complex64, highest_order: usize) -> Vec<Complex64> {
    let start = downward_start_order(z.norm(), highest_order);
    let mut values = vec![Complex64::new(0.0, 0.0); start + 1];
    for order in (1..=start).rev() {
        let order_over_z = order as f64 / z;
        values[order - 1] = (order as f64 - 1.0) / z - 1.0 / (values[order] + order_over_z);
    }
    values.truncate(highest_order + 1);
    values
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tabulated values (Abramowitz & Stegun, Table 9.1, and the DLMF's
    /// 10-digit tables), independent of any recurrence.
    #[test]
    fn low_orders_match_tables() {
        let cases = [
            // x, J_0, J_1, Y_0, Y_1
            (
                1.0,
                0.765_197_686_557_966_6,
                0.440_050_585_744_933_5,
                0.088_256_964_215_676_96,
                -0.781_212_821_300_288_7,
            ),
            (
                10.0,
                -0.245_935_764_451_348_3,
                0.043_472_746_168_861_44,
                0.055_671_167_283_599_39,
                0.249_015_424_206_953_9,
            ),
        ];
        for (x, j0, j1, y0, y1) in cases {
            let j = bessel_j_sequence(x, 5);
            let y = bessel_y_sequence(x, &j, 5);
            assert!((j[0] - j0).abs() < 1e-14, "J_0({x}) = {}", j[0]);
            assert!((j[1] - j1).abs() < 1e-14, "J_1({x}) = {}", j[1]);
            assert!((y[0] - y0).abs() < 1e-13, "Y_0({x}) = {}", y[0]);
            assert!((y[1] - y1).abs() < 1e-13, "Y_1({x}) = {}", y[1]);
        }
    }

    /// The Wronskian J_{n+1}Y_n − J_nY_{n+1} = 2/(πx) (A&S 9.1.16) ties
    /// the two sequences together at every order, including the orders
    /// beyond the turning point where Y is large and J small.
    #[test]
    fn wronskian_holds_at_every_order() {
        for x in [0.05, 3.0, 120.0, 850.0] {
            let highest = (x + 4.0 * f64::cbrt(x) + 2.0) as usize;
            let j = bessel_j_sequence(x, highest + 1);
            let y = bessel_y_sequence(x, &j, highest + 1);
            let expected = 2.0 / (std::f64::consts::PI * x);
            for n in 0..=highest {
                let wronskian = j[n + 1] * y[n] - j[n] * y[n + 1];
                assert!(
                    (wronskian - expected).abs() < 1e-10 * expected,
                    "x = {x}, n = {n}: {wronskian} against {expected}"
                );
            }
        }
    }

    /// For real z the log-derivative must equal J_n'/J_n from the J
    /// sequence, with J_n' = J_{n−1} − (n/z)J_n (away from zeros of J_n).
    #[test]
    fn log_derivative_matches_real_sequence() {
        let x = 37.3;
        let j = bessel_j_sequence(x, 60);
        let d = log_derivative_sequence(Complex64::new(x, 0.0), 60);
        for n in 1..=60 {
            let derivative = j[n - 1] - n as f64 / x * j[n];
            if j[n].abs() > 1e-3 {
                let expected = derivative / j[n];
                assert!(
                    (d[n].re - expected).abs() < 1e-10 * expected.abs().max(1.0),
                    "n = {n}"
                );
                assert!(d[n].im.abs() < 1e-12);
            }
        }
    }
}
