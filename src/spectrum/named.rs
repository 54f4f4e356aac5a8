//! The spectra scene files may name instead of listing samples: CIE
//! illuminants, optical glasses' refractive indices, and metals' complex
//! refractive indices (pbrt-v4's `GetNamedSpectrum`).

use std::collections::HashMap;
use std::sync::{Arc, OnceLock};

use super::data::glasses::{
    GLASS_BAF10, GLASS_BK7, GLASS_FK51A, GLASS_LASF9, GLASS_SF10, GLASS_SF11, GLASS_SF5,
};
use super::data::illuminants::{
    ILLUMINANT_A, ILLUMINANT_ACES_D60, ILLUMINANT_D50, ILLUMINANT_D65, ILLUMINANT_F1,
    ILLUMINANT_F10, ILLUMINANT_F11, ILLUMINANT_F12, ILLUMINANT_F2, ILLUMINANT_F3, ILLUMINANT_F4,
    ILLUMINANT_F5, ILLUMINANT_F6, ILLUMINANT_F7, ILLUMINANT_F8, ILLUMINANT_F9,
};
use super::data::metals::{
    METAL_AG_ETA, METAL_AG_K, METAL_AL_ETA, METAL_AL_K, METAL_AU_ETA, METAL_AU_K, METAL_CUZN_ETA,
    METAL_CUZN_K, METAL_CU_ETA, METAL_CU_K, METAL_MGO_ETA, METAL_MGO_K, METAL_TIO2_ETA,
    METAL_TIO2_K,
};
use super::data::{SellmeierGlass, UniformTable};
use super::piecewise_linear::PiecewiseLinear;
use super::sampled::{LAMBDA_MAX, LAMBDA_MIN};
use super::spectrum::Spectrum;

/// The illuminants, normalised to unit luminance as pbrt-v4 does.
const ILLUMINANTS: [(&str, &UniformTable); 16] = [
    ("stdillum-A", &ILLUMINANT_A),
    ("stdillum-D50", &ILLUMINANT_D50),
    ("stdillum-D65", &ILLUMINANT_D65),
    ("stdillum-F1", &ILLUMINANT_F1),
    ("stdillum-F2", &ILLUMINANT_F2),
    ("stdillum-F3", &ILLUMINANT_F3),
    ("stdillum-F4", &ILLUMINANT_F4),
    ("stdillum-F5", &ILLUMINANT_F5),
    ("stdillum-F6", &ILLUMINANT_F6),
    ("stdillum-F7", &ILLUMINANT_F7),
    ("stdillum-F8", &ILLUMINANT_F8),
    ("stdillum-F9", &ILLUMINANT_F9),
    ("stdillum-F10", &ILLUMINANT_F10),
    ("stdillum-F11", &ILLUMINANT_F11),
    ("stdillum-F12", &ILLUMINANT_F12),
    ("illum-acesD60", &ILLUMINANT_ACES_D60),
];

/// Glasses under pbrt-v4's names; pbrt calls the Schott flints SF5, SF10
/// and SF11 "glass-F5" etc., and both spellings are accepted.
const GLASSES: [(&[&str], &SellmeierGlass); 7] = [
    (&["glass-BK7"], &GLASS_BK7),
    (&["glass-BAF10"], &GLASS_BAF10),
    (&["glass-FK51A"], &GLASS_FK51A),
    (&["glass-LASF9"], &GLASS_LASF9),
    (&["glass-F5", "glass-SF5"], &GLASS_SF5),
    (&["glass-F10", "glass-SF10"], &GLASS_SF10),
    (&["glass-F11", "glass-SF11"], &GLASS_SF11),
];

/// Metals' (and two oxides') refractive index η and absorption k.
const METALS: [(&str, &[f32]); 14] = [
    ("metal-Ag-eta", METAL_AG_ETA),
    ("metal-Ag-k", METAL_AG_K),
    ("metal-Al-eta", METAL_AL_ETA),
    ("metal-Al-k", METAL_AL_K),
    ("metal-Au-eta", METAL_AU_ETA),
    ("metal-Au-k", METAL_AU_K),
    ("metal-Cu-eta", METAL_CU_ETA),
    ("metal-Cu-k", METAL_CU_K),
    ("metal-CuZn-eta", METAL_CUZN_ETA),
    ("metal-CuZn-k", METAL_CUZN_K),
    ("metal-MgO-eta", METAL_MGO_ETA),
    ("metal-MgO-k", METAL_MGO_K),
    ("metal-TiO2-eta", METAL_TIO2_ETA),
    ("metal-TiO2-k", METAL_TIO2_K),
];

/// The spectrum pbrt-v4 knows by `name`, or `None` for an unknown name.
/// Built once on first use; clones share the tables.
pub fn named_spectrum(name: &str) -> Option<Spectrum> {
    all_named_spectra().get(name).cloned()
}

/// Every name [`named_spectrum`] accepts.
pub fn named_spectrum_names() -> impl Iterator<Item = &'static str> {
    ILLUMINANTS
        .iter()
        .map(|(n, _)| *n)
        .chain(GLASSES.iter().flat_map(|(names, _)| names.iter().copied()))
        .chain(METALS.iter().map(|(n, _)| *n))
}

fn all_named_spectra() -> &'static HashMap<&'static str, Spectrum> {
    static NAMED: OnceLock<HashMap<&'static str, Spectrum>> = OnceLock::new();
    NAMED.get_or_init(build_named_spectra)
}

fn build_named_spectra() -> HashMap<&'static str, Spectrum> {
    let mut named = HashMap::new();
    for (name, table) in ILLUMINANTS {
        // Compiled-in tables are well formed; a failure would be caught by
        // the tests, and leaves the name unknown rather than aborting.
        if let Ok(s) = PiecewiseLinear::from_interleaved(&table.interleaved(), true) {
            named.insert(name, Spectrum::PiecewiseLinear(Arc::new(s)));
        }
    }
    for (names, glass) in GLASSES {
        if let Some(s) = glass_spectrum(glass) {
            for name in names {
                named.insert(*name, s.clone());
            }
        }
    }
    for (name, pairs) in METALS {
        let samples: Vec<f64> = pairs.iter().map(|&v| f64::from(v)).collect();
        if let Ok(s) = PiecewiseLinear::from_interleaved(&samples, false) {
            named.insert(name, Spectrum::PiecewiseLinear(Arc::new(s)));
        }
    }
    named
}

/// A glass's index from its Sellmeier formula, tabulated at each whole
/// nanometre over (a little beyond) the visible range.
fn glass_spectrum(glass: &SellmeierGlass) -> Option<Spectrum> {
    let samples: Vec<f64> = (LAMBDA_MIN as i32 - 1..=LAMBDA_MAX as i32 + 1)
        .flat_map(|l| [f64::from(l), glass.refractive_index(f64::from(l))])
        .collect();
    PiecewiseLinear::from_interleaved(&samples, false)
        .ok()
        .map(|s| Spectrum::PiecewiseLinear(Arc::new(s)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::xyz::{spectrum_to_xyz, xyz_to_xy};

    #[test]
    fn every_name_resolves() {
        let names: Vec<_> = named_spectrum_names().collect();
        assert_eq!(names.len(), 16 + 10 + 14);
        for name in names {
            let s = named_spectrum(name).unwrap_or_else(|| panic!("{name} missing"));
            // Defined over the whole visible range.
            for l in [360.0, 500.0, 830.0] {
                assert!(s.eval(l).is_finite(), "{name} at {l}");
            }
        }
        assert!(named_spectrum("stdillum-D66").is_none());
        assert!(named_spectrum("").is_none());
    }

    #[test]
    fn illuminants_have_their_published_chromaticities() {
        // CIE 015 chromaticities of the 2° observer, and ACES's white.
        let expected = [
            ("stdillum-A", 0.44757, 0.40745),
            ("stdillum-D50", 0.34567, 0.35850),
            ("stdillum-D65", 0.31271, 0.32902),
            ("stdillum-F2", 0.3721, 0.3751),
            ("stdillum-F7", 0.3129, 0.3292),
            ("stdillum-F11", 0.3805, 0.3769),
            ("illum-acesD60", 0.32168, 0.33767),
        ];
        for (name, x, y) in expected {
            let s = named_spectrum(name).unwrap();
            let xyz = spectrum_to_xyz(&s);
            let xy = xyz_to_xy(xyz);
            assert!(
                (xy.x - x).abs() < 5e-4 && (xy.y - y).abs() < 5e-4,
                "{name}: {xy} vs ({x}, {y})"
            );
            assert!((xyz.y - 1.0).abs() < 1e-4, "{name} luminance {}", xyz.y);
        }
    }

    #[test]
    fn glasses_match_their_catalogue_indices() {
        // Schott catalogue n_d at the helium d line, 587.56 nm.
        let expected = [
            ("glass-BK7", 1.5168),
            ("glass-BAF10", 1.6700),
            ("glass-FK51A", 1.4866),
            ("glass-LASF9", 1.8503),
            ("glass-F5", 1.6727),
            ("glass-SF10", 1.7283),
            ("glass-F11", 1.7847),
        ];
        for (name, n_d) in expected {
            let n = named_spectrum(name).unwrap().eval(587.56);
            assert!((n - n_d).abs() < 2e-4, "{name}: {n} vs {n_d}");
        }
        // Normal dispersion: blue bends more.
        let bk7 = named_spectrum("glass-BK7").unwrap();
        assert!(bk7.eval(400.0) > bk7.eval(700.0));
    }

    #[test]
    fn metals_have_plausible_optical_constants() {
        // Gold and copper reflect red far better than blue; silver and
        // aluminium are bright and nearly neutral.
        let reflectance = |metal: &str, lambda: f32| {
            let n = named_spectrum(&format!("metal-{metal}-eta"))
                .unwrap()
                .eval(lambda);
            let k = named_spectrum(&format!("metal-{metal}-k"))
                .unwrap()
                .eval(lambda);
            ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k)
        };
        for metal in ["Au", "Cu", "CuZn"] {
            assert!(
                reflectance(metal, 650.0) > reflectance(metal, 450.0) + 0.2,
                "{metal}"
            );
        }
        for metal in ["Ag", "Al"] {
            let (blue, red) = (reflectance(metal, 450.0), reflectance(metal, 650.0));
            assert!(blue > 0.85 && red > 0.85, "{metal}: {blue} {red}");
        }
        // The oxides are dielectrics.
        assert!((named_spectrum("metal-MgO-eta").unwrap().eval(589.0) - 1.7374).abs() < 1e-3);
        assert_eq!(named_spectrum("metal-TiO2-k").unwrap().eval(589.0), 0.0);
    }
}
