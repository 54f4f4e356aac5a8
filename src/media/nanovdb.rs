//! pbrt-v4's `nanovdb` medium: σa and σs scaled by the `density` grid of
//! a NanoVDB file, with blackbody emission from its optional
//! `temperature` grid (pbrt-v4's `NanoVDBMedium`).
//!
//! | parameter | type | default | meaning |
//! |-----------|------|---------|---------|
//! | `filename` | string | required | the `.nvdb` file, relative to the scene file's directory |
//! | `sigma_a`, `sigma_s` | spectrum | 1 | coefficients at density 1 |
//! | `scale`   | float | 1 | multiplies σa and σs |
//! | `g`       | float | 0 | Henyey–Greenstein asymmetry |
//! | `Lescale` | float | 1 | multiplies the blackbody emission |
//! | `temperatureoffset` | float | `temperaturecutoff` | kelvin = (T − offset)·scale |
//! | `temperaturecutoff` | float | 0 | the offset's old name (read when `temperatureoffset` is absent) |
//! | `temperaturescale` | float | 1 | see above |
//!
//! The grids are looked up by name ("density", required, and
//! "temperature"), must hold floats and be fog volumes (or of unknown
//! class), as pbrt-v4 requires. The medium's space is the grids' world
//! space; a point is taken to each grid's index space by the grid's map
//! and the voxel values there are interpolated trilinearly (NanoVDB's
//! `SampleFromVoxels`, order 1). The medium's box is the union of the
//! grids' stored world boxes. Emission is `Lescale` times the normalised
//! blackbody at the kelvin above, none at or below 100 K.
//!
//! One majorant covers the box (the largest density value in the grid
//! times σt), where pbrt-v4 builds a 64³ majorant grid: unbiased either
//! way, only the number of null collisions differs. The file reader is
//! [`super::nanovdb_file`]: NanoVDB 32.x files, as pbrt-v4 reads, and
//! also those of the layout before NanoVDB 29 (0.0.x), which pbrt-v4
//! refuses; codecs NONE and ZIP (BLOSC is an error).

use super::cuboid::Cuboid;
use super::nanovdb_file::{grid_class_name, read_grid, FloatGrid};
use super::{
    blackbody_glow, extinction, scattering_coefficients, MajorantSegment, MediumProperties,
};
use crate::error::{scene_error, unreadable_file, Result};
use crate::math::{Ray, Transform};
use crate::scene_description::Entity;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{DVec3, Vec3};
use pbrt_parser::Location;
use std::path::Path;
use std::sync::Arc;

#[derive(Clone, Debug)]
pub struct NanoVdbMedium {
    cuboid: Cuboid,
    sigma_a: Spectrum,
    sigma_s: Spectrum,
    scale: f32,
    g: f32,
    density: Arc<FloatGrid>,
    max_density: f32,
    temperature: Option<Temperature>,
}

#[derive(Clone, Debug)]
struct Temperature {
    grid: Arc<FloatGrid>,
    offset: f32,
    scale: f32,
    le_scale: f32,
}

/// The float grid `name` of the file, checked as pbrt-v4 checks it.
fn load(file: &[u8], name: &str, path: &Path, loc: &Location) -> Result<Option<FloatGrid>> {
    let grid = read_grid(file, name)
        .or_else(|e| scene_error(format!("nanovdb: \"{}\": {e}", path.display()), loc))?;
    if let Some(g) = &grid {
        // Fog volumes (2) or unknown (0).
        if g.class != 2 && g.class != 0 {
            return scene_error(
                format!(
                    "nanovdb: \"{}\": grid \"{name}\" is a {} grid, not a fog volume",
                    path.display(),
                    grid_class_name(g.class)
                ),
                loc,
            );
        }
    }
    Ok(grid)
}

impl NanoVdbMedium {
    pub fn create(entity: &Entity, render_from_medium: &Transform, base: &Path) -> Result<Self> {
        let p = &entity.params;
        let loc = &entity.location.0;
        let Some((filename, file_loc)) = p.string_at("filename")?.filter(|(f, _)| !f.is_empty())
        else {
            return scene_error("medium \"nanovdb\" needs a \"string filename\"", loc);
        };
        let path = pbrt_parser::resolve_path(base, &filename);
        let bytes =
            std::fs::read(&path).map_err(|e| unreadable_file("nanovdb", &path, &e, &file_loc))?;
        let Some(density) = load(&bytes, "density", &path, &file_loc)? else {
            return scene_error(
                format!("nanovdb: \"{}\" has no \"density\" grid", path.display()),
                &file_loc,
            );
        };
        let temperature = load(&bytes, "temperature", &path, &file_loc)?;
        let le_scale = p.float("Lescale", 1.0)? as f32;
        let cutoff = p.float("temperaturecutoff", 0.0)?;
        let t_offset = p.float("temperatureoffset", cutoff)? as f32;
        let t_scale = p.float("temperaturescale", 1.0)? as f32;
        let (sigma_a, sigma_s, scale) = scattering_coefficients(entity, base)?;
        let g = p.float("g", 0.0)? as f32;

        let mut min = DVec3::from(density.world_min);
        let mut max = DVec3::from(density.world_max);
        if let Some(t) = &temperature {
            min = min.min(DVec3::from(t.world_min));
            max = max.max(DVec3::from(t.world_max));
        }
        if !(min.is_finite() && max.is_finite()) {
            return scene_error(
                format!(
                    "nanovdb: \"{}\": the grids' bounds are not finite",
                    path.display()
                ),
                &file_loc,
            );
        }
        let max_density = density.max_value();
        Ok(NanoVdbMedium {
            cuboid: Cuboid::new(render_from_medium, min, max),
            sigma_a,
            sigma_s,
            scale,
            g,
            density: Arc::new(density),
            max_density,
            temperature: temperature
                .filter(|_| le_scale > 0.0)
                .map(|grid| Temperature {
                    grid: Arc::new(grid),
                    offset: t_offset,
                    scale: t_scale,
                    le_scale,
                }),
        })
    }

    pub fn is_emissive(&self) -> bool {
        self.temperature.is_some()
    }

    pub fn sample_point(&self, p: Vec3, lambda: &SampledWavelengths) -> MediumProperties {
        let q = self.cuboid.medium_point(p);
        let d = self.density.sample(q) * self.scale;
        let le = match &self.temperature {
            None => SampledSpectrum::ZERO,
            Some(t) => {
                let kelvin = (t.grid.sample(q) - t.offset) * t.scale;
                blackbody_glow(kelvin, t.le_scale, lambda)
            }
        };
        MediumProperties::at_density(&self.sigma_a, &self.sigma_s, d, le, self.g, lambda)
    }

    pub fn majorant(
        &self,
        ray: &Ray,
        t_max: f32,
        lambda: &SampledWavelengths,
    ) -> Option<MajorantSegment> {
        self.cuboid.majorant(ray, t_max, || {
            extinction(&self.sigma_a, &self.sigma_s, lambda) * (self.scale * self.max_density)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::nanovdb_file::test_writer::{file_bytes, ramp};
    use super::super::Medium;
    use super::*;
    use crate::spectrum::{BlackbodySpectrum, SampledWavelengths};

    /// A fresh directory for this test's files.
    fn temp_dir(tag: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("rpbrt-nanovdb-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// The medium of one `MakeNamedMedium` line (`params` after the type),
    /// in a scene file in `dir`.
    fn medium(dir: &Path, params: &str) -> Result<Medium> {
        let text =
            format!("WorldBegin\nMakeNamedMedium \"m\" \"string type\" \"nanovdb\" {params}\n");
        let scene = crate::scene::load_text(&dir.join("scene.pbrt"), &text)
            .unwrap()
            .scene;
        let m = &scene.media[0];
        Medium::create(&m.entity, &m.world_from_medium, dir)
    }

    fn lambda() -> SampledWavelengths {
        SampledWavelengths::sample_visible(0.4)
    }

    #[test]
    fn density_scales_sigma_at_medium_space_points() {
        let dir = temp_dir("density");
        let linear = |i: i32, j: i32, k: i32| 0.1 * (i + j + k) as f32;
        std::fs::write(
            dir.join("ramp.nvdb"),
            file_bytes(&[ramp("density", 0.0, linear)], 1, true),
        )
        .unwrap();
        let m = medium(
            &dir,
            "\"string filename\" \"ramp.nvdb\" \"spectrum sigma_a\" [300 2 900 2] \"spectrum sigma_s\" [300 0.5 900 0.5] \"float scale\" 3",
        )
        .unwrap();
        assert!(!m.is_emissive());
        let l = lambda();
        // Density at (1, 2, 3.5) is 0.1 · 6.5; σ = scale · σ · density.
        let mp = m.sample_point(Vec3::new(1.0, 2.0, 3.5), &l);
        assert!(
            (mp.sigma_a[0] - 3.0 * 2.0 * 0.65).abs() < 1e-4,
            "{:?}",
            mp.sigma_a
        );
        assert!(
            (mp.sigma_s[0] - 3.0 * 0.5 * 0.65).abs() < 1e-4,
            "{:?}",
            mp.sigma_s
        );
        // The box is the stored world box, 0..7: a ray along x through it.
        let ray = Ray::new(Vec3::new(-5.0, 1.0, 1.0), Vec3::X, 0.0);
        let seg = m.majorant(&ray, 100.0, &l).unwrap();
        assert!((seg.t_min - 5.0).abs() < 1e-4 && (seg.t_max - 12.0).abs() < 1e-4);
        // Majorant: the largest density, 0.1 · 21, times σt.
        assert!(
            (seg.sigma_maj[0] - 3.0 * 2.5 * 2.1).abs() < 1e-3,
            "{:?}",
            seg.sigma_maj
        );
        let miss = Ray::new(Vec3::new(-5.0, 9.0, 1.0), Vec3::X, 0.0);
        assert!(m.majorant(&miss, 100.0, &l).is_none());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn temperature_grid_emits_a_scaled_blackbody() {
        let dir = temp_dir("temperature");
        let grids = [
            ramp("density", 0.0, |_, _, _| 1.0),
            ramp(
                "temperature",
                0.0,
                |i, _, _| if i < 4 { 1000.0 } else { 50.0 },
            ),
        ];
        std::fs::write(dir.join("fire.nvdb"), file_bytes(&grids, 0, true)).unwrap();
        let m = medium(
            &dir,
            "\"string filename\" \"fire.nvdb\" \"float Lescale\" 2 \"float temperaturecutoff\" 100 \"float temperaturescale\" 3",
        )
        .unwrap();
        assert!(m.is_emissive());
        let l = lambda();
        // (1000 − 100) · 3 = 2700 K where the grid holds 1000.
        let le = m.sample_point(Vec3::new(1.0, 3.0, 3.0), &l).le;
        let expected = BlackbodySpectrum::new(2700.0).sample(&l) * 2.0;
        for i in 0..4 {
            assert!(
                (le[i] - expected[i]).abs() < 1e-5 * (1.0 + expected[i]),
                "{le:?}"
            );
        }
        // (50 − 100) · 3 < 100 K: none.
        let le = m.sample_point(Vec3::new(6.0, 3.0, 3.0), &l).le;
        assert_eq!(le.max_component(), 0.0);
        // `temperatureoffset` wins over `temperaturecutoff`; Lescale 0
        // turns emission off.
        let m = medium(
            &dir,
            "\"string filename\" \"fire.nvdb\" \"float temperatureoffset\" 0 \"float temperaturecutoff\" 999",
        )
        .unwrap();
        let le = m.sample_point(Vec3::new(1.0, 3.0, 3.0), &l).le;
        let expected = BlackbodySpectrum::new(1000.0).sample(&l);
        assert!((le[0] - expected[0]).abs() < 1e-5, "{le:?}");
        let m = medium(
            &dir,
            "\"string filename\" \"fire.nvdb\" \"float Lescale\" 0",
        )
        .unwrap();
        assert!(!m.is_emissive());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn file_problems_are_located_errors() {
        let dir = temp_dir("errors");
        let error = |params: &str| medium(&dir, params).unwrap_err().to_string();
        let e = error("\"string filename\" \"missing.nvdb\"");
        assert!(
            e.contains("scene.pbrt:2:") && e.contains("cannot read") && e.contains("missing.nvdb"),
            "{e}"
        );
        let e = error("\"float g\" 0.5");
        assert!(e.contains("filename"), "{e}");
        // No density grid.
        std::fs::write(
            dir.join("t.nvdb"),
            file_bytes(&[ramp("temperature", 0.0, |_, _, _| 1.0)], 0, false),
        )
        .unwrap();
        let e = error("\"string filename\" \"t.nvdb\"");
        assert!(
            e.contains("no \"density\" grid") && e.contains("scene.pbrt:2:"),
            "{e}"
        );
        // A level set.
        let mut spec = ramp("density", 0.0, |_, _, _| 1.0);
        spec.class = 1;
        std::fs::write(dir.join("ls.nvdb"), file_bytes(&[spec], 0, true)).unwrap();
        let e = error("\"string filename\" \"ls.nvdb\"");
        assert!(e.contains("LevelSet"), "{e}");
        // Truncated.
        let full = file_bytes(&[ramp("density", 0.0, |_, _, _| 1.0)], 1, false);
        std::fs::write(dir.join("cut.nvdb"), &full[..full.len() - 100]).unwrap();
        let e = error("\"string filename\" \"cut.nvdb\"");
        assert!(e.contains("ends early") && e.contains("cut.nvdb"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
