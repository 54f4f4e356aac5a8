//! Floating-point helpers pbrt-v4's shape code relies on: products with a
//! single rounding error (via fused multiply-add), and a clamp that never
//! panics (bounds computed from scene input may be NaN or out of order).

use glam::Vec3;

/// `a·b − c·d` with one rounding error (Kahan's algorithm with FMA).
pub fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let difference = a.mul_add(b, -cd);
    let error = (-c).mul_add(d, cd);
    difference + error
}

/// `a·b + c·d` with one rounding error.
pub fn sum_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let sum = a.mul_add(b, cd);
    let error = c.mul_add(d, -cd);
    sum + error
}

/// Componentwise `a·b − c·d` for vectors scaled by scalars.
pub fn difference_of_products_vector(a: f32, b: Vec3, c: f32, d: Vec3) -> Vec3 {
    Vec3::new(
        difference_of_products(a, b.x, c, d.x),
        difference_of_products(a, b.y, c, d.y),
        difference_of_products(a, b.z, c, d.z),
    )
}

/// `value` limited to [low, high] as pbrt's `Clamp` does: no checks, so
/// NaN or inverted bounds give a value instead of a panic.
pub fn clamp(value: f32, low: f32, high: f32) -> f32 {
    if value < low {
        low
    } else if value > high {
        high
    } else {
        value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compensated_products_are_accurate() {
        // 1.000001² − 1.000002 loses everything in naive f32 arithmetic.
        let a = 1.000_001f32;
        let exact = a as f64 * a as f64 - 1.000_002f32 as f64;
        let got = difference_of_products(a, a, 1.000_002, 1.0) as f64;
        assert!((got - exact).abs() <= 1e-12, "{got} vs {exact}");
    }

    #[test]
    fn clamp_tolerates_bad_bounds() {
        assert_eq!(clamp(2.0, -1.0, 1.0), 1.0);
        assert_eq!(clamp(0.5, 1.0, -1.0), 1.0);
        assert_eq!(clamp(0.5, f32::NAN, f32::NAN), 0.5);
    }
}
