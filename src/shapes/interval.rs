//! Interval arithmetic with outward rounding, for the quadrics' ray
//! intersection tests (pbrt-v4 solves the sphere and cylinder quadratics on
//! intervals, so that a root is only accepted as "in front of the ray" when
//! its whole error interval is).
//!
//! Every operation rounds its lower bound one ulp down and its upper bound
//! one ulp up, so the true result of the exact operation on any values in
//! the operands is always inside the result.

use crate::math::ray::{next_float_down, next_float_up};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A closed interval `[low, high]` of f32 values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    pub low: f32,
    pub high: f32,
}

impl Interval {
    /// The interval holding exactly `value`.
    pub fn exact(value: f32) -> Self {
        Interval {
            low: value,
            high: value,
        }
    }

    /// `value ± error` (rounded outwards; exact when `error` is 0).
    pub fn from_value_and_error(value: f32, error: f32) -> Self {
        if error == 0.0 {
            return Self::exact(value);
        }
        Interval {
            low: next_float_down(value - error),
            high: next_float_up(value + error),
        }
    }

    /// The centre of the interval: the value pbrt uses when an interval is
    /// read as a plain number.
    pub fn midpoint(self) -> f32 {
        0.5 * (self.low + self.high)
    }

    pub fn contains(self, value: f32) -> bool {
        self.low <= value && value <= self.high
    }

    /// `factor × self`.
    pub fn scaled(self, factor: f32) -> Self {
        if factor > 0.0 {
            Interval {
                low: next_float_down(factor * self.low),
                high: next_float_up(factor * self.high),
            }
        } else {
            Interval {
                low: next_float_down(factor * self.high),
                high: next_float_up(factor * self.low),
            }
        }
    }

    /// `self²` (tighter than `self × self`: never negative).
    pub fn squared(self) -> Self {
        let mut small = self.low.abs();
        let mut large = self.high.abs();
        if small > large {
            std::mem::swap(&mut small, &mut large);
        }
        if self.contains(0.0) {
            return Interval {
                low: 0.0,
                high: next_float_up(large * large),
            };
        }
        Interval {
            low: next_float_down(small * small),
            high: next_float_up(large * large),
        }
    }

    /// Square root (negative parts clamp to 0).
    pub fn sqrt(self) -> Self {
        Interval {
            low: next_float_down(self.low.sqrt()).max(0.0),
            high: next_float_up(self.high.sqrt()),
        }
    }
}

impl Add for Interval {
    type Output = Interval;
    fn add(self, other: Interval) -> Interval {
        Interval {
            low: next_float_down(self.low + other.low),
            high: next_float_up(self.high + other.high),
        }
    }
}

impl Sub for Interval {
    type Output = Interval;
    fn sub(self, other: Interval) -> Interval {
        Interval {
            low: next_float_down(self.low - other.high),
            high: next_float_up(self.high - other.low),
        }
    }
}

impl Neg for Interval {
    type Output = Interval;
    fn neg(self) -> Interval {
        Interval {
            low: -self.high,
            high: -self.low,
        }
    }
}

impl Mul for Interval {
    type Output = Interval;
    fn mul(self, other: Interval) -> Interval {
        let products = [
            self.low * other.low,
            self.high * other.low,
            self.low * other.high,
            self.high * other.high,
        ];
        let low = products.iter().copied().fold(f32::INFINITY, f32::min);
        let high = products.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        Interval {
            low: next_float_down(low),
            high: next_float_up(high),
        }
    }
}

impl Div for Interval {
    type Output = Interval;
    fn div(self, other: Interval) -> Interval {
        if other.contains(0.0) {
            // Division by an interval holding zero: anything is possible.
            return Interval {
                low: f32::NEG_INFINITY,
                high: f32::INFINITY,
            };
        }
        let quotients = [
            self.low / other.low,
            self.high / other.low,
            self.low / other.high,
            self.high / other.high,
        ];
        let low = quotients.iter().copied().fold(f32::INFINITY, f32::min);
        let high = quotients.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        Interval {
            low: next_float_down(low),
            high: next_float_up(high),
        }
    }
}

/// The roots of the quadric a t² + b t + c = 0 in interval arithmetic, with
/// the discriminant in pbrt-v4's cancellation-free form 4a (r + ℓ)(r − ℓ)
/// (ℓ: distance from the axis or centre to the ray's closest point): the
/// first root in (0, t_max) and the far root, or `None`.
pub(crate) fn solve_quadric(
    a: Interval,
    b: Interval,
    c: Interval,
    radius: Interval,
    length: Interval,
    t_max: f32,
) -> Option<(Interval, Interval)> {
    let discriminant = a.scaled(4.0) * (radius + length) * (radius - length);
    if discriminant.low < 0.0 {
        return None;
    }
    let root = discriminant.sqrt();
    let q = if b.midpoint() < 0.0 {
        (b - root).scaled(-0.5)
    } else {
        (b + root).scaled(-0.5)
    };
    let mut t0 = q / a;
    let mut t1 = c / q;
    if t0.low > t1.low {
        std::mem::swap(&mut t0, &mut t1);
    }
    if t0.high > t_max || t1.low <= 0.0 {
        return None;
    }
    let mut t_hit = t0;
    if t_hit.low <= 0.0 {
        t_hit = t1;
        if t_hit.high > t_max {
            return None;
        }
    }
    Some((t_hit, t1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn operations_contain_the_exact_result() {
        let a = Interval::from_value_and_error(1.0 / 3.0, 1e-7);
        let b = Interval::from_value_and_error(-2.5, 1e-6);
        let (x, y) = (1.0f64 / 3.0, -2.5f64);
        let inside = |i: Interval, v: f64| i.low as f64 <= v && v <= i.high as f64;
        assert!(inside(a + b, x + y));
        assert!(inside(a - b, x - y));
        assert!(inside(a * b, x * y));
        assert!(inside(a / b, x / y));
        assert!(inside(b.squared(), y * y));
        assert!(inside(a.sqrt(), x.sqrt()));
        assert!(inside(a.scaled(-3.0), -3.0 * x));
        assert!(inside(-b, -y));
    }

    #[test]
    fn squares_are_never_negative_and_division_by_zero_is_unbounded() {
        let around_zero = Interval::from_value_and_error(0.0, 1.0);
        assert_eq!(around_zero.squared().low, 0.0);
        assert!((around_zero * around_zero).low < 0.0);
        let q = Interval::exact(1.0) / around_zero;
        assert!(q.low.is_infinite() && q.high.is_infinite());
    }
}
