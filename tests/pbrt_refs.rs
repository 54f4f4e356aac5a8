//! Renders the scenes of `../shared/refs/` and compares them with
//! pbrt-v4's references as `../shared/refs/README.md` defines: at N spp,
//! MRSE(rpbrt) ≤ 1.25 × MRSE(pbrt) and block bias(rpbrt) ≤ max(2 × block
//! bias(pbrt), 0.01), pbrt's figures computed here from its own N-spp
//! render (hair-curl-300, whose MRSE is a matter of a few fireflies, at
//! pbrt-v4's 1024-spp render by its tail of bright samples instead: see its
//! test). At pbrt-v4's own seed the renders are compared with pbrt-v4's
//! sample for sample too (`same_seed_as_pbrt_v4`). Skipped, with a message,
//! when `../shared` is absent.

mod common;

use rpbrt::image::Image;
use rpbrt::scene::build::RenderOverrides;
use rpbrt::tools::imgdiff::{block_bias, bright_samples, mrse};
use std::path::Path;

struct Comparison {
    mrse: f64,
    block_bias: f64,
}

fn compare(image: &Image, reference: &Image) -> Comparison {
    let (w, h) = (reference.width() as usize, reference.height() as usize);
    let x = image.rgb_data();
    let r = reference.rgb_data();
    Comparison {
        mrse: mrse(&x, &r),
        block_bias: block_bias(&x, &r, w, h, 3, 16),
    }
}

/// The seed our renders are compared at, other than pbrt-v4's.
const OUR_SEED: i32 = 7;

/// The seed of pbrt-v4's N-spp renders in `../shared/refs/` (its reference
/// has seed 1).
const PBRT_SEED: i32 = 2;

/// Our render of `name` at `spp` (2 threads).
fn render(shared: &Path, name: &str, spp: u32, seed: i32) -> (Image, f64) {
    let out =
        std::env::temp_dir().join(format!("rpbrt-ref-{name}-{spp}-{}.exr", std::process::id()));
    let overrides = RenderOverrides {
        spp: Some(spp),
        seed: Some(seed),
        outfile: Some(out.clone()),
        ..Default::default()
    };
    let scene = shared.join("scenes/derived").join(format!("{name}.pbrt"));
    let report = rpbrt::pipeline::render_file(&scene, &overrides, 2, false).expect("render");
    let ours = Image::read(&out).expect("our render");
    std::fs::remove_file(&out).ok();
    assert_eq!(report.bad_samples, 0, "NaN/Inf samples");
    (ours, report.render.as_secs_f64())
}

/// The README's rule at `spp`, rendered with `seed`; returns our render and
/// pbrt-v4's.
fn check_scene(shared: &Path, name: &str, spp: u32, seed: i32) -> (Image, Image, Image) {
    let refs = shared.join("refs");
    let reference = Image::read(refs.join(format!("{name}-ref.exr"))).expect("reference image");
    let pbrt = Image::read(refs.join(format!("{name}-{spp}.exr"))).expect("pbrt render");
    let pbrt_cmp = compare(&pbrt, &reference);
    let (ours, seconds) = render(shared, name, spp, seed);
    let our_cmp = compare(&ours, &reference);
    eprintln!(
        "{name} @ {spp} spp, seed {seed}: rpbrt MRSE {:.5} block bias {:.4} ({seconds:.2} s render) | pbrt MRSE {:.5} block bias {:.4}",
        our_cmp.mrse,
        our_cmp.block_bias,
        pbrt_cmp.mrse,
        pbrt_cmp.block_bias
    );
    assert!(
        our_cmp.mrse <= 1.25 * pbrt_cmp.mrse,
        "{name}: MRSE {} > 1.25 × pbrt's {}",
        our_cmp.mrse,
        pbrt_cmp.mrse
    );
    let bound = (2.0 * pbrt_cmp.block_bias).max(0.01);
    assert!(
        our_cmp.block_bias <= bound,
        "{name}: block bias {} > {bound}",
        our_cmp.block_bias
    );
    (ours, pbrt, reference)
}

#[test]
fn cornell_box_matches_pbrt_v4() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    check_scene(&shared, "cornell-box-256", 64, OUR_SEED);
}

/// hair-curl-300, a single curly strand, is compared at pbrt-v4's largest
/// render of it, the 1024-spp reference, by its tail of bright samples
/// rather than by MRSE at 64 spp. Its MRSE is set by a few fireflies per
/// image (single samples of value ≈ 50–200 from next-event estimation of
/// the distant light through the TT lobe after a first bounce across the
/// curl), so at 64 spp it is a matter of luck: pbrt-v4's 16-, 64- and
/// 256-spp renders share one seed and so one sample sequence (each the
/// first samples of the next: the 16-spp image's largest firefly is in the
/// 64-spp image too), and its 64-spp draw, with no sample above 50, has
/// MRSE 0.00039, below every one of twelve rpbrt seeds (0.00058–0.0042);
/// rpbrt at pbrt-v4's seed renders that same draw, MRSE 0.00039
/// ([`same_seed_as_pbrt_v4`]).
/// At 1024 spp the tails agree: counted each against the other, rpbrt's
/// samples above 50 and pbrt-v4's differ by no more than Poisson noise
/// (seeds 21–24: 34, 30, 26, 40 against 30, 29, 32, 28), so does the MRSE
/// of the two renders against a common reference, and the block bias is
/// within bound. The test asserts the block bias and that rpbrt's count is
/// not above pbrt-v4's by more than three standard deviations (a tail
/// twice as heavy fails it).
#[test]
fn hair_curl_matches_pbrt_v4() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    let name = "hair-curl-300";
    let refs = shared.join("refs");
    let reference = Image::read(refs.join(format!("{name}-ref.exr"))).expect("reference image");
    let pbrt_256 = Image::read(refs.join(format!("{name}-256.exr"))).expect("pbrt render");
    let spp = 1024;
    let (ours, seconds) = render(&shared, name, spp, OUR_SEED);
    let (x, r) = (ours.rgb_data(), reference.rgb_data());
    let ours_bright = bright_samples(&x, &r, spp, 50.0);
    let pbrt_bright = bright_samples(&r, &x, spp, 50.0);
    let our_cmp = compare(&ours, &reference);
    let bound = (2.0 * compare(&pbrt_256, &reference).block_bias).max(0.01);
    eprintln!(
        "{name} @ {spp} spp ({seconds:.2} s render): samples above 50: rpbrt {ours_bright}, pbrt-v4 {pbrt_bright}; block bias {:.4} (bound {bound:.4}); MRSE against pbrt-v4's {:.6}",
        our_cmp.block_bias, our_cmp.mrse
    );
    assert!(
        our_cmp.block_bias <= bound,
        "{name}: block bias {} > {bound}",
        our_cmp.block_bias
    );
    let allowed = pbrt_bright as f64 + 3.0 * ((ours_bright + pbrt_bright) as f64).sqrt();
    assert!(
        ours_bright as f64 <= allowed,
        "{name}: {ours_bright} samples above 50 against pbrt-v4's {pbrt_bright}"
    );
}

#[test]
fn hair_eumel_matches_pbrt_v4() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    check_scene(&shared, "hair-eumel-2-256", 32, OUR_SEED);
}

#[test]
fn hair_blonde_matches_pbrt_v4() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    check_scene(&shared, "hair-blonde-3-bounces-256", 32, OUR_SEED);
}

/// At pbrt-v4's seed, rpbrt draws pbrt-v4's samples: the same sampler
/// (`sobol` or `halton`, same randomisation), the same dimensions asked in
/// the same order, the same estimator. So the README's rule holds at every
/// N for the hair scenes there, with the luck of pbrt-v4's draw on both
/// sides, and where the sampler is `sobol` (hair-curl-300, cornell-box-256)
/// the two images are the same but for float rounding: their MRSE against
/// each other is under a tenth of pbrt-v4's against its reference (measured
/// 0.015–0.058 and 0.0006 of it). The `halton` hair scenes agree less
/// closely (0.24 and 0.61 of the noise at 8 spp), as expected of paths that
/// bounce many times in dense hair once a hit point differs in its last
/// bits (our curve intersector is not pbrt-v4's subdivision): the
/// difference falls as 1/N like noise (hair-eumel-2-256: 0.035, 0.012,
/// 0.0037 at 8, 32, 128 spp), and so does its block bias.
#[test]
fn same_seed_as_pbrt_v4() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    let cases = [
        ("hair-curl-300", 16, true),
        ("hair-curl-300", 64, true),
        ("hair-curl-300", 256, true),
        ("cornell-box-256", 16, true),
        ("hair-eumel-2-256", 8, false),
        ("hair-blonde-3-bounces-256", 8, false),
    ];
    for (name, spp, same_samples) in cases {
        let (ours, pbrt, reference) = check_scene(&shared, name, spp, PBRT_SEED);
        let apart = compare(&ours, &pbrt).mrse;
        let noise = compare(&pbrt, &reference).mrse;
        eprintln!(
            "{name} @ {spp} spp: MRSE against pbrt-v4's render {apart:.6}, {:.4} of its noise",
            apart / noise
        );
        if same_samples {
            assert!(
                apart <= 0.1 * noise,
                "{name} @ {spp}: MRSE {apart} against pbrt-v4's render at its seed (noise {noise})"
            );
        }
    }
}
