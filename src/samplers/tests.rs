//! Tests over all sampler types: value range, determinism, seeds,
//! stratification, convergence, and `create`'s parameter handling.

use super::*;
use crate::scene::load_text;
use std::path::Path;

fn sampler_entity(text: &str) -> Entity {
    let scene = format!("{text}\nWorldBegin\n");
    match load_text(Path::new("test.pbrt"), &scene) {
        Ok(loaded) => loaded.scene.sampler,
        Err(e) => panic!("{e}"),
    }
}

fn make(text: &str, seed: i32, resolution: IVec2) -> Sampler {
    Sampler::create(&sampler_entity(text), seed, resolution, None)
        .unwrap_or_else(|e| panic!("{text}: {e}"))
}

/// Every sampler type and randomization, as scene text.
const ALL: &[&str] = &[
    "Sampler \"independent\"",
    "Sampler \"stratified\"",
    "Sampler \"stratified\" \"bool jitter\" false",
    "Sampler \"halton\"",
    "Sampler \"halton\" \"string randomization\" \"owen\"",
    "Sampler \"halton\" \"string randomization\" \"none\"",
    "Sampler \"sobol\"",
    "Sampler \"sobol\" \"string randomization\" \"owen\"",
    "Sampler \"sobol\" \"string randomization\" \"permutedigits\"",
    "Sampler \"sobol\" \"string randomization\" \"none\"",
    "Sampler \"paddedsobol\"",
    "Sampler \"paddedsobol\" \"string randomization\" \"owen\"",
    "Sampler \"paddedsobol\" \"string randomization\" \"permutedigits\"",
    "Sampler \"paddedsobol\" \"string randomization\" \"none\"",
    "Sampler \"zsobol\"",
    "Sampler \"zsobol\" \"string randomization\" \"owen\"",
    "Sampler \"zsobol\" \"string randomization\" \"permutedigits\"",
    "Sampler \"zsobol\" \"string randomization\" \"none\"",
    "Sampler \"pmj02bn\"",
];

const RESOLUTION: IVec2 = IVec2::new(40, 30);

/// A camera path's worth of values: wavelength, film, time, lens, then a
/// few bounces' worth.
fn path_values(sampler: &mut Sampler, pixel: IVec2, index: u32) -> Vec<f32> {
    sampler.start_pixel_sample(pixel, index, 0);
    let mut values = vec![sampler.get_1d()];
    values.extend(sampler.get_pixel_2d().to_array());
    values.push(sampler.get_1d());
    for _ in 0..10 {
        values.extend(sampler.get_2d().to_array());
        values.push(sampler.get_1d());
    }
    values
}

#[test]
fn values_lie_in_the_unit_interval() {
    for text in ALL {
        let mut sampler = make(text, 0, RESOLUTION);
        for pixel in [IVec2::new(0, 0), IVec2::new(39, 29), IVec2::new(17, 3)] {
            for index in 0..sampler.samples_per_pixel() {
                for v in path_values(&mut sampler, pixel, index) {
                    assert!((0.0..1.0).contains(&v), "{text}: {v}");
                }
            }
        }
    }
}

#[test]
fn values_are_deterministic_and_order_independent() {
    for text in ALL {
        let mut a = make(text, 5, RESOLUTION);
        let mut b = a.clone();
        let forward: Vec<Vec<f32>> = (0..8)
            .map(|i| path_values(&mut a, IVec2::new(3, 4), i))
            .collect();
        // Another clone, interleaved with other pixels, in reverse order.
        let mut backward = Vec::new();
        for i in (0..8).rev() {
            path_values(&mut b, IVec2::new(9, 1), i);
            backward.push(path_values(&mut b, IVec2::new(3, 4), i));
        }
        backward.reverse();
        assert_eq!(forward, backward, "{text}");
        // Starting at a later dimension continues the same stream (from
        // dimension 2, where every sampler's free dimensions have begun).
        let mut c = make(text, 5, RESOLUTION);
        c.start_pixel_sample(IVec2::new(3, 4), 2, 2);
        for _ in 0..6 {
            c.get_1d();
        }
        let next = c.get_1d();
        c.start_pixel_sample(IVec2::new(3, 4), 2, 8);
        assert_eq!(c.get_1d(), next, "{text}");
    }
}

#[test]
fn different_seeds_give_different_values() {
    for text in ALL {
        // Unrandomized sequences have no seed; pbrt-v4 seeds Halton's Owen
        // scrambling by dimension only.
        if text.contains("\"none\"")
            || text.contains("jitter\" false")
            || text.contains("halton\" \"string randomization\" \"owen")
        {
            continue;
        }
        let mut a = make(text, 0, RESOLUTION);
        let mut b = make(text, 1, RESOLUTION);
        let va = path_values(&mut a, IVec2::new(2, 2), 1);
        let vb = path_values(&mut b, IVec2::new(2, 2), 1);
        // The film position of halton and sobol is never scrambled; the rest
        // must change.
        let differing = va.iter().zip(&vb).filter(|(x, y)| x != y).count();
        assert!(
            differing >= va.len() - 2,
            "{text}: {differing} of {}",
            va.len()
        );
        // The "seed" parameter overrides the option.
        let with_param = format!("{text} \"integer seed\" 1");
        let mut c = make(&with_param, 0, RESOLUTION);
        assert_eq!(path_values(&mut c, IVec2::new(2, 2), 1), vb, "{text}");
    }
}

/// The cell of the `cells × cells` grid each of a pixel's points falls in.
fn cells_hit(points: &[Vec2], cells: usize) -> Vec<usize> {
    let mut counts = vec![0; cells * cells];
    for p in points {
        counts[(p.x * cells as f32) as usize + cells * (p.y * cells as f32) as usize] += 1;
    }
    counts
}

#[test]
fn film_positions_of_sixteen_samples_are_one_per_four_by_four_cell() {
    for text in [
        "Sampler \"sobol\"",
        "Sampler \"zsobol\"",
        "Sampler \"zsobol\" \"string randomization\" \"owen\"",
        "Sampler \"zsobol\" \"string randomization\" \"permutedigits\"",
        "Sampler \"zsobol\" \"string randomization\" \"none\"",
        "Sampler \"paddedsobol\"",
        "Sampler \"stratified\"",
        "Sampler \"pmj02bn\"",
    ] {
        let mut sampler = make(text, 7, RESOLUTION);
        assert_eq!(sampler.samples_per_pixel(), 16);
        for pixel in [IVec2::new(0, 0), IVec2::new(21, 13), IVec2::new(39, 29)] {
            let points: Vec<Vec2> = (0..16)
                .map(|i| {
                    sampler.start_pixel_sample(pixel, i, 0);
                    sampler.get_1d();
                    sampler.get_pixel_2d()
                })
                .collect();
            assert_eq!(cells_hit(&points, 4), vec![1; 16], "{text} {pixel}");
        }
    }
}

/// Halton's film dimensions are bases 2 and 3: 16 samples are stratified in
/// 16 strips along x, and 6 samples fall one per 2 × 3 cell.
#[test]
fn halton_film_positions_are_stratified_in_bases_two_and_three() {
    for randomization in ["permutedigits", "owen", "none"] {
        let text = format!("Sampler \"halton\" \"string randomization\" \"{randomization}\"");
        let mut sampler = make(&text, 7, RESOLUTION);
        for pixel in [IVec2::new(0, 0), IVec2::new(21, 13), IVec2::new(39, 29)] {
            let mut strips = [0; 16];
            for i in 0..16 {
                sampler.start_pixel_sample(pixel, i, 0);
                strips[(sampler.get_pixel_2d().x * 16.0) as usize] += 1;
            }
            assert_eq!(strips, [1; 16]);
        }
        let mut six = make(&format!("{text} \"integer pixelsamples\" 6"), 7, RESOLUTION);
        let mut cells = [0; 6];
        for i in 0..6 {
            six.start_pixel_sample(IVec2::new(5, 8), i, 0);
            let p = six.get_pixel_2d();
            cells[(p.x * 2.0) as usize + 2 * (p.y * 3.0) as usize] += 1;
        }
        assert_eq!(cells, [1; 6]);
    }
}

/// The first 2D dimension after the film position (the lens) of the
/// per-pixel Sobol' samplers is a scrambled (0, 4, 2)-net as well.
#[test]
fn lens_positions_of_sixteen_samples_are_one_per_four_by_four_cell() {
    for text in ["Sampler \"zsobol\"", "Sampler \"paddedsobol\""] {
        let mut sampler = make(text, 3, RESOLUTION);
        let points: Vec<Vec2> = (0..16)
            .map(|i| {
                sampler.start_pixel_sample(IVec2::new(11, 12), i, 0);
                sampler.get_1d();
                sampler.get_pixel_2d();
                sampler.get_1d();
                sampler.get_2d()
            })
            .collect();
        assert_eq!(cells_hit(&points, 4), vec![1; 16], "{text}");
    }
}

/// RMS error of the 64-sample estimate of ∫x² = 1/3 from the first 1D
/// value of each pixel sample, over a 16 × 16 image.
fn rms_error_of_x_squared(text: &str) -> f64 {
    let resolution = IVec2::new(16, 16);
    let mut sampler = make(text, 0, resolution);
    assert_eq!(sampler.samples_per_pixel(), 64, "{text}");
    let mut squared_errors = 0.0;
    for y in 0..16 {
        for x in 0..16 {
            let mut sum = 0.0f64;
            for i in 0..64 {
                sampler.start_pixel_sample(IVec2::new(x, y), i, 0);
                let u = f64::from(sampler.get_1d());
                sum += u * u;
            }
            squared_errors += (sum / 64.0 - 1.0 / 3.0).powi(2);
        }
    }
    (squared_errors / 256.0).sqrt()
}

#[test]
fn low_discrepancy_estimates_converge_faster_than_independent_ones() {
    let independent = rms_error_of_x_squared("Sampler \"independent\" \"integer pixelsamples\" 64");
    // Expected about sqrt((1/5 - 1/9) / 64) ≈ 0.037.
    assert!(
        (0.02..0.06).contains(&independent),
        "independent {independent}"
    );
    for text in [
        "Sampler \"halton\" \"integer pixelsamples\" 64",
        "Sampler \"halton\" \"integer pixelsamples\" 64 \"string randomization\" \"owen\"",
        "Sampler \"sobol\" \"integer pixelsamples\" 64",
        "Sampler \"sobol\" \"integer pixelsamples\" 64 \"string randomization\" \"owen\"",
        "Sampler \"zsobol\" \"integer pixelsamples\" 64",
        "Sampler \"zsobol\" \"integer pixelsamples\" 64 \"string randomization\" \"permutedigits\"",
        "Sampler \"paddedsobol\" \"integer pixelsamples\" 64",
        "Sampler \"pmj02bn\" \"integer pixelsamples\" 64",
        "Sampler \"stratified\" \"integer xsamples\" 8 \"integer ysamples\" 8",
    ] {
        let rms = rms_error_of_x_squared(text);
        println!("{text}: RMS {rms}, independent {independent}");
        assert!(
            rms < independent / 4.0,
            "{text}: {rms} vs independent {independent}"
        );
    }
}

#[test]
fn reserved_film_dimensions_do_not_shift_later_ones() {
    for text in ["Sampler \"halton\"", "Sampler \"sobol\""] {
        let mut sampler = make(text, 0, RESOLUTION);
        sampler.start_pixel_sample(IVec2::new(1, 1), 3, 0);
        let a = sampler.get_1d();
        let b = sampler.get_1d();
        sampler.start_pixel_sample(IVec2::new(1, 1), 3, 0);
        assert_eq!(sampler.get_1d(), a);
        sampler.get_pixel_2d();
        assert_eq!(sampler.get_1d(), b, "{text}");
    }
    let mut zsobol = make("Sampler \"zsobol\"", 0, RESOLUTION);
    zsobol.start_pixel_sample(IVec2::new(1, 1), 3, 0);
    let film = zsobol.get_pixel_2d();
    zsobol.start_pixel_sample(IVec2::new(1, 1), 3, 0);
    assert_eq!(zsobol.get_2d(), film);
}

#[test]
fn samples_per_pixel_and_overrides() {
    let spp = |text: &str, spp_override: Option<u32>| {
        Sampler::create(&sampler_entity(text), 0, RESOLUTION, spp_override)
            .unwrap()
            .samples_per_pixel()
    };
    assert_eq!(spp("Sampler \"independent\"", None), 4);
    assert_eq!(spp("Sampler \"halton\"", None), 16);
    assert_eq!(
        spp("Sampler \"stratified\" \"integer xsamples\" 3", None),
        12
    );
    assert_eq!(spp("Sampler \"stratified\"", Some(12)), 12);
    assert_eq!(nearly_square_factors(12), (4, 3));
    assert_eq!(nearly_square_factors(7), (7, 1));
    assert_eq!(
        spp("Sampler \"zsobol\" \"integer pixelsamples\" 24", None),
        16
    );
    assert_eq!(
        spp("Sampler \"sobol\" \"integer pixelsamples\" 24", None),
        24
    );
    assert_eq!(spp("Sampler \"paddedsobol\"", Some(5)), 5);
}

#[test]
fn bad_sampler_descriptions_are_scene_errors() {
    let error = |text: &str| {
        let entity = sampler_entity(text);
        match Sampler::create(&entity, 0, RESOLUTION, None) {
            Ok(_) => panic!("{text} was accepted"),
            Err(e) => e.to_string(),
        }
    };
    assert!(error("Sampler \"pmj02bn\" \"integer pixelsamples\" 0").contains("at least 1"));
    assert!(
        error("Sampler \"halton\" \"string randomization\" \"fastowen\"").contains("not supported")
    );
    assert!(
        error("Sampler \"zsobol\" \"string randomization\" \"shuffle\"")
            .contains("unknown randomization")
    );
    assert!(error("Sampler \"zsobol\" \"integer pixelsamples\" 0").contains("at least 1"));
    assert!(error("Sampler \"stratified\" \"integer xsamples\" -2").contains("at least 1"));
    let entity = sampler_entity("Sampler \"sobol\"");
    assert!(Sampler::create(&entity, 0, IVec2::new(0, 10), None).is_err());
    assert!(Sampler::create(&entity, 0, RESOLUTION, Some(0)).is_err());
}

/// Dimensions far past the tables wrap as pbrt-v4's do instead of failing.
#[test]
fn long_paths_keep_producing_values() {
    for text in ALL {
        let mut sampler = make(text, 0, RESOLUTION);
        sampler.start_pixel_sample(IVec2::new(4, 4), 0, 0);
        for _ in 0..1100 {
            assert!((0.0..1.0).contains(&sampler.get_1d()));
            let p = sampler.get_2d();
            assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
        }
    }
}

/// Skipping a value leaves every later value as it would be had it been
/// taken, for every sampler, including at the wrap of the dimension tables.
#[test]
fn skipping_keeps_later_dimensions() {
    for text in ALL {
        let mut taken = make(text, 3, RESOLUTION);
        let mut skipped = make(text, 3, RESOLUTION);
        for (pixel, index) in [(IVec2::new(5, 7), 0), (IVec2::new(39, 29), 13)] {
            taken.start_pixel_sample(pixel, index, 0);
            skipped.start_pixel_sample(pixel, index, 0);
            for round in 0..700 {
                let (a, b) = if round % 3 == 0 {
                    taken.get_1d();
                    skipped.skip(1);
                    (taken.get_2d(), skipped.get_2d())
                } else {
                    taken.get_2d();
                    skipped.skip(2);
                    (Vec2::splat(taken.get_1d()), Vec2::splat(skipped.get_1d()))
                };
                assert_eq!(a, b, "{text}: round {round}");
            }
        }
    }
}
