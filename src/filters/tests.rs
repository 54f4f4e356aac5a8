//! Tests over all filter types: defaults, integrals, and sampling weights.

use super::*;
use crate::scene::load_text;
use std::path::Path;

fn filter_entity(text: &str) -> Entity {
    let scene = format!("{text}\nWorldBegin\n");
    match load_text(Path::new("test.pbrt"), &scene) {
        Ok(loaded) => loaded.scene.filter,
        Err(e) => panic!("{e}"),
    }
}

fn make(text: &str) -> Filter {
    Filter::create(&filter_entity(text)).unwrap_or_else(|e| panic!("{text}: {e}"))
}

const ALL: &[&str] = &[
    "PixelFilter \"box\"",
    "PixelFilter \"box\" \"float xradius\" 1 \"float yradius\" 0.75",
    "PixelFilter \"triangle\"",
    "PixelFilter \"triangle\" \"float xradius\" 1.25",
    "PixelFilter \"gaussian\"",
    "PixelFilter \"gaussian\" \"float sigma\" 0.3 \"float yradius\" 1",
    "PixelFilter \"mitchell\"",
    "PixelFilter \"mitchell\" \"float B\" 0 \"float C\" 0.5",
    "PixelFilter \"sinc\"",
    "PixelFilter \"sinc\" \"float tau\" 2 \"float xradius\" 2",
];

/// ∫ f·g over the support by the midpoint rule on an n × n grid.
fn integrate(filter: &Filter, g: impl Fn(Vec2) -> f64, n: usize) -> f64 {
    let r = filter.radius();
    let cell = Vec2::new(2.0 * r.x / n as f32, 2.0 * r.y / n as f32);
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let p = -r + Vec2::new((i as f32 + 0.5) * cell.x, (j as f32 + 0.5) * cell.y);
            sum += f64::from(filter.evaluate(p)) * g(p);
        }
    }
    sum * f64::from(cell.x) * f64::from(cell.y)
}

#[test]
fn defaults_are_pbrts() {
    let radius = |text: &str| make(text).radius();
    assert_eq!(radius("PixelFilter \"box\""), Vec2::splat(0.5));
    assert_eq!(radius("PixelFilter \"gaussian\""), Vec2::splat(1.5));
    assert_eq!(radius("PixelFilter \"mitchell\""), Vec2::splat(2.0));
    assert_eq!(radius("PixelFilter \"sinc\""), Vec2::splat(4.0));
    assert_eq!(radius("PixelFilter \"triangle\""), Vec2::splat(2.0));
    match make("PixelFilter \"gaussian\"") {
        Filter::Gaussian(g) => assert_eq!(g.sigma(), 0.5),
        other => panic!("{other:?}"),
    }
    // The Mitchell defaults B = C = 1/3 give 8/9 at the centre (1D: 16/18).
    let mitchell = make("PixelFilter \"mitchell\"");
    assert!((mitchell.evaluate(Vec2::ZERO) - (8.0f32 / 9.0).powi(2)).abs() < 1e-6);
    // Lanczos sinc with tau 3 is 1 at the centre, 0 at integers.
    let sinc = make("PixelFilter \"sinc\"");
    assert_eq!(sinc.evaluate(Vec2::ZERO), 1.0);
    assert!(sinc.evaluate(Vec2::new(1.0, 0.0)).abs() < 1e-6);
    assert_eq!(make("PixelFilter \"triangle\"").evaluate(Vec2::ZERO), 4.0);
}

#[test]
fn integrals_match_numerical_integration() {
    for text in ALL {
        let filter = make(text);
        let numerical = integrate(&filter, |_| 1.0, 1000);
        let integral = f64::from(filter.integral());
        // pbrt-v4 estimates the sinc's integral with 4096 jittered samples,
        // which is off by about 1%; the others are exact.
        let tolerance = if matches!(filter, Filter::LanczosSinc(_)) {
            2e-2
        } else {
            2e-3
        };
        assert!(
            (integral - numerical).abs() < tolerance * numerical.abs(),
            "{text}: {integral} vs {numerical}"
        );
    }
}

/// A smooth, asymmetric test function.
fn g(p: Vec2) -> f64 {
    let (x, y) = (f64::from(p.x), f64::from(p.y));
    (0.4 * x - 0.3 * y).exp() + 0.5 * x * y * y + (1.7 * y).cos()
}

/// Over a 256 × 256 grid of stratified u: E[w], and E[w·g] / E[w] (what the
/// film's weighted average converges to).
fn sampled_moments(filter: &Filter) -> (f64, f64) {
    let n = 256;
    let (mut weights, mut weighted) = (0.0, 0.0);
    for j in 0..n {
        for i in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let s = filter.sample(u);
            let r = filter.radius();
            assert!(s.p.x.abs() <= r.x && s.p.y.abs() <= r.y, "{s:?}");
            weights += f64::from(s.weight);
            weighted += f64::from(s.weight) * g(s.p);
        }
    }
    let count = (n * n) as f64;
    (weights / count, weighted / weights)
}

#[test]
fn sample_weights_reproduce_the_filtered_average() {
    for text in ALL {
        let filter = make(text);
        let expected = integrate(&filter, g, 1000) / integrate(&filter, |_| 1.0, 1000);
        let (mean_weight, average) = sampled_moments(&filter);
        assert!(
            (average - expected).abs() < 5e-3 * expected.abs(),
            "{text}: {average} vs {expected}"
        );
        // Exact samplers weigh 1; tabulated ones weigh ∫f on average.
        let expected_weight = match filter {
            Filter::Box(_) | Filter::Triangle(_) => 1.0,
            _ => f64::from(filter.integral()),
        };
        assert!(
            (mean_weight - expected_weight).abs() < 1e-2 * expected_weight,
            "{text}: mean weight {mean_weight} vs {expected_weight}"
        );
    }
}

#[test]
fn negative_lobes_give_negative_weights() {
    let mitchell = make("PixelFilter \"mitchell\" \"float B\" 0 \"float C\" 1");
    let mut negative = 0;
    for j in 0..64 {
        for i in 0..64 {
            let s = mitchell.sample(Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0));
            if s.weight < 0.0 {
                negative += 1;
                assert!(mitchell.evaluate(s.p) <= 1e-3, "{s:?}");
            }
        }
    }
    assert!(negative > 0);
}

#[test]
fn bad_filter_descriptions_are_scene_errors() {
    let error = |text: &str| match Filter::create(&filter_entity(text)) {
        Ok(f) => panic!("{text} gave {f:?}"),
        Err(e) => e.to_string(),
    };
    assert!(error("PixelFilter \"box\" \"float xradius\" 0").contains("must be positive"));
    assert!(error("PixelFilter \"gaussian\" \"float sigma\" -1").contains("must be positive"));
    assert!(error("PixelFilter \"sinc\" \"float tau\" 0").contains("must be positive"));
    assert!(
        error("PixelFilter \"mitchell\" \"float xradius\" 1000 \"float yradius\" 1000")
            .contains("too large")
    );
}
