//! pbrt-v4's `measured` material: a BRDF measured by the RGL material
//! database, read from its `.bsdf` tensor file (Dupuy & Jakob 2018, "An
//! adaptive parameterization for efficient material acquisition and
//! rendering"; the BxDF is [`crate::bxdfs::measured`]).
//!
//! | parameter | type | default | what |
//! |---|---|---|---|
//! | `filename` | string | required | the `.bsdf` file, relative to the scene file's directory |
//! | `displacement` | float texture | none | a bump map ([`super::shading_normal`]) |
//! | `normalmap` | string | none | a normal map image ([`super::shading_normal`]) |
//!
//! Each file is read once per run however many materials name it, as
//! pbrt-v4 keeps one copy per filename: the tables (megabytes) are shared
//! by every hit. They live until the process ends, as pbrt-v4's do, so a
//! BxDF can hold them by plain reference and stay a copyable value; a file
//! changed on disk (another length or modification time) is read again.

use crate::bxdfs::measured::tensor_file::{TensorError, TensorFile};
use crate::bxdfs::measured::{DataError, MeasuredBxDFData};
use crate::bxdfs::{BxDF, MeasuredBxDF};
use crate::error::{scene_error, unreadable_file, Result};
use crate::spectrum::SampledWavelengths;
use crate::textures::TextureParams;
use pbrt_parser::Location;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};
use std::time::SystemTime;

/// The material: the tables of its file.
#[derive(Clone, Debug)]
pub struct MeasuredMaterial {
    data: &'static MeasuredBxDFData,
}

/// A file as it was when read: its path, length and modification time.
type FileKey = (PathBuf, u64, Option<SystemTime>);

/// Every file read so far in this process.
fn loaded() -> &'static Mutex<HashMap<FileKey, &'static MeasuredBxDFData>> {
    static LOADED: OnceLock<Mutex<HashMap<FileKey, &'static MeasuredBxDFData>>> = OnceLock::new();
    LOADED.get_or_init(Default::default)
}

/// Why a file could not be used: the operating system's reason (reported
/// as the file being unreadable) or what is wrong with its contents.
enum LoadError {
    Io(std::io::Error),
    Data(DataError),
}

impl From<DataError> for LoadError {
    fn from(e: DataError) -> Self {
        match e {
            DataError::Tensor(TensorError::Io(e)) => LoadError::Io(e),
            e => LoadError::Data(e),
        }
    }
}

/// The tables of the file at `path`, read on first use and shared after.
fn load_shared(path: &Path) -> std::result::Result<&'static MeasuredBxDFData, LoadError> {
    let meta = std::fs::metadata(path).map_err(LoadError::Io)?;
    let key = (path.to_path_buf(), meta.len(), meta.modified().ok());
    // One reader at a time: two materials naming one file read it once. A
    // panic elsewhere while the lock was held leaves the map intact.
    let mut cache = loaded()
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(data) = cache.get(&key) {
        return Ok(data);
    }
    let file = TensorFile::read(path).map_err(DataError::from)?;
    let data: &'static MeasuredBxDFData =
        Box::leak(Box::new(MeasuredBxDFData::from_tensor(&file)?));
    cache.insert(key, data);
    Ok(data)
}

impl MeasuredMaterial {
    /// The material of `tp`'s parameters (`displacement` and `normalmap`
    /// are read by [`super::Material::create`], as for every material that
    /// takes them); `loc` is the material's directive.
    pub fn create(tp: &TextureParams, loc: &Location) -> Result<Self> {
        let Some((name, at)) = tp.params.string_at("filename")? else {
            return scene_error(
                "material \"measured\": \"string filename\" is required",
                loc,
            );
        };
        if name.is_empty() {
            return scene_error("material \"measured\": \"string filename\" is empty", &at);
        }
        let path = pbrt_parser::resolve_path(tp.base_directory, &name);
        match load_shared(&path) {
            Ok(data) => Ok(MeasuredMaterial { data }),
            Err(LoadError::Io(e)) => Err(unreadable_file("measured material", &path, &e, &at)),
            Err(LoadError::Data(e)) => scene_error(
                format!("measured material: \"{}\": {e}", path.display()),
                &at,
            ),
        }
    }

    /// The BxDF at the path's wavelengths (the material has no textures).
    pub fn bxdf(&self, lambda: &SampledWavelengths) -> BxDF {
        BxDF::Measured(MeasuredBxDF::new(self.data, lambda))
    }
}

#[cfg(test)]
mod tests {
    use crate::bxdfs::measured::synthetic::Synthetic;
    use crate::bxdfs::measured::tensor_file::{encode, f32_bytes, DType};
    use crate::image::Image;
    use crate::materials::Material;
    use crate::scene::build::{build, BuiltScene, RenderOverrides};
    use crate::scene::load_text;
    use std::path::{Path, PathBuf};

    /// An empty folder for one test's files.
    fn fresh_dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("rpbrt-measured-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn built(dir: &Path, world: &str) -> crate::error::Result<BuiltScene> {
        let text = format!("Camera \"perspective\"\nWorldBegin\n{world}");
        let loaded = load_text(&dir.join("scene.pbrt"), &text)?;
        build(loaded.scene, &RenderOverrides::default())
    }

    /// The error of a scene whose material names `file` written with
    /// `bytes`, and the error's text.
    fn error_for(name: &str, bytes: &[u8]) -> String {
        let dir = fresh_dir(name);
        std::fs::write(dir.join("m.bsdf"), bytes).unwrap();
        let world = "Material \"measured\" \"string filename\" \"m.bsdf\"\nShape \"sphere\"\n";
        match built(&dir, world) {
            Ok(_) => panic!("{name}: expected an error"),
            Err(e) => e.to_string(),
        }
    }

    fn measured(scene: &BuiltScene, index: usize) -> &super::MeasuredMaterial {
        match &scene.materials[index] {
            Material::Measured(m) => m,
            other => panic!("not measured: {other:?}"),
        }
    }

    #[test]
    fn a_file_beside_the_scene_is_read_once_for_every_material_naming_it() {
        let dir = fresh_dir("shared");
        std::fs::create_dir_all(dir.join("brdfs")).unwrap();
        std::fs::write(dir.join("brdfs/a.bsdf"), Synthetic::ggx(0.3).bytes()).unwrap();
        let world = "Material \"measured\" \"string filename\" \"brdfs/a.bsdf\"\nShape \"sphere\"\n\
                     Material \"measured\" \"string filename\" \"brdfs/a.bsdf\"\nShape \"sphere\"\n\
                     Material \"measured\" \"string filename\" \"brdfs/a.bsdf\" \"float displacement\" 0.1\nShape \"sphere\"\n";
        let scene = built(&dir, world).unwrap();
        let n = scene.materials.len();
        let (a, b) = (measured(&scene, n - 3), measured(&scene, n - 2));
        assert!(std::ptr::eq(a.data, b.data));
        let Material::Bumped(bumped) = &scene.materials[n - 1] else {
            panic!("a displacement wraps the material");
        };
        assert!(matches!(bumped.material, Material::Measured(_)));
    }

    #[test]
    fn a_missing_or_absent_file_is_a_located_error() {
        let dir = fresh_dir("missing");
        let e = built(
            &dir,
            "Material \"measured\" \"string filename\" \"nothere.bsdf\"\nShape \"sphere\"\n",
        )
        .err()
        .unwrap()
        .to_string();
        assert!(
            e.contains("scene.pbrt:3:21")
                && e.contains("cannot read \"")
                && e.contains("nothere.bsdf"),
            "{e}"
        );
        let e = built(&dir, "Material \"measured\"\nShape \"sphere\"\n")
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("scene.pbrt:3:1") && e.contains("\"string filename\" is required"),
            "{e}"
        );
    }

    #[test]
    fn truncated_and_corrupt_files_are_located_errors() {
        let bytes = Synthetic::ggx(0.3).bytes();
        let e = error_for("truncated", &bytes[..bytes.len() - 100]);
        assert!(
            e.contains("scene.pbrt:3:21") && e.contains("m.bsdf") && e.contains("truncated"),
            "{e}"
        );
        let e = error_for("header", &bytes[..40]);
        assert!(e.contains("truncated tensor file"), "{e}");
        let e = error_for("text", b"# not a tensor file at all\n");
        assert!(e.contains("not a tensor file"), "{e}");
    }

    /// The synthetic file with one field replaced (or removed).
    fn with_field(name: &str, replacement: Option<(DType, Vec<usize>, Vec<u8>)>) -> Vec<u8> {
        let mut fields = Synthetic::ggx(0.3).fields();
        let index = fields.iter().position(|f| f.0 == name).unwrap();
        match replacement {
            Some((dtype, shape, data)) => fields[index] = (fields[index].0, dtype, shape, data),
            None => {
                fields.remove(index);
            }
        }
        encode(&fields)
    }

    #[test]
    fn missing_fields_wrong_types_and_shapes_are_located_errors() {
        let e = error_for("no-sigma", &with_field("sigma", None));
        assert!(
            e.contains("scene.pbrt:3:21") && e.contains("field \"sigma\" is missing"),
            "{e}"
        );
        let e = error_for("no-jacobian", &with_field("jacobian", None));
        assert!(e.contains("field \"jacobian\" is missing"), "{e}");
        let e = error_for(
            "f64",
            &with_field(
                "theta_i",
                Some((DType::F64, vec![1], 0.5f64.to_le_bytes().to_vec())),
            ),
        );
        assert!(e.contains("\"theta_i\" is float64, not float32"), "{e}");
        let e = error_for(
            "rank",
            &with_field("ndf", Some((DType::F32, vec![4], f32_bytes(&[1.0; 4])))),
        );
        assert!(e.contains("\"ndf\" has shape [4]"), "{e}");
        // A VNDF for 3 incident elevations where theta_i has 10.
        let e = error_for(
            "shape",
            &with_field(
                "vndf",
                Some((DType::F32, vec![1, 3, 2, 2], f32_bytes(&[1.0; 12]))),
            ),
        );
        assert!(
            e.contains("\"vndf\" has shape [1, 3, 2, 2]") && e.contains("10 (theta_i)"),
            "{e}"
        );
        let e = error_for(
            "small",
            &with_field("ndf", Some((DType::F32, vec![1, 4], f32_bytes(&[1.0; 4])))),
        );
        assert!(e.contains("\"ndf\"") && e.contains("at least 2 × 2"), "{e}");
        let e = error_for(
            "zero",
            &with_field(
                "luminance",
                Some((DType::F32, vec![1, 10, 17, 17], vec![0; 4 * 10 * 17 * 17])),
            ),
        );
        assert!(
            e.contains("\"luminance\"") && e.contains("positive, finite mass"),
            "{e}"
        );
        let falling: Vec<f32> = (0..10).map(|k| 1.0 - k as f32 * 0.1).collect();
        let e = error_for(
            "falling",
            &with_field("theta_i", Some((DType::F32, vec![10], f32_bytes(&falling)))),
        );
        assert!(e.contains("\"theta_i\" must increase"), "{e}");
        let mut half = Synthetic::ggx(0.3);
        half.anisotropic = true;
        let mut fields = half.fields();
        let phi: Vec<f32> = (0..9)
            .map(|k| k as f32 * std::f32::consts::PI / 8.0)
            .collect();
        fields[3] = ("phi_i", DType::F32, vec![9], f32_bytes(&phi));
        let e = error_for("reduction", &encode(&fields));
        assert!(e.contains("1/2 of the circle"), "{e}");
    }

    /// A plane of a constant-spectrum file seen from straight above, lit
    /// by a white point light far away at 45° whose irradiance at the
    /// origin (facing it) is 1: its radiance is f cos θi = R D(ωm) / (4
    /// σ(ωo)), with ωm at 22.5°, a grid point of the file's NDF (so no
    /// interpolation error), and σ(ωo) = 1 for GGX at normal incidence.
    #[test]
    fn a_lit_plane_has_the_radiance_of_its_tables() {
        let dir = fresh_dir("render");
        let file = Synthetic::ggx(0.25);
        std::fs::write(dir.join("grey.bsdf"), file.bytes()).unwrap();
        let expected = 0.8 * file.d(22.5f64.to_radians(), 0.0) / (4.0 * file.sigma(0.0, 0.0));
        for integrator in ["path", "volpath", "bdpt"] {
            let scene = format!(
                "LookAt 0 0 50  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 1\n\
                 Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4 \"string filename\" \"{integrator}.exr\"\n\
                 Sampler \"zsobol\" \"integer pixelsamples\" 16\n\
                 Integrator \"{integrator}\" \"integer maxdepth\" 1\nWorldBegin\n\
                 LightSource \"point\" \"point3 from\" [-1000 0 1000] \"rgb I\" [1 1 1] \"float scale\" 2e6\n\
                 Material \"measured\" \"string filename\" \"grey.bsdf\"\n\
                 Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n\
                 \"point3 P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\n"
            );
            let path = dir.join(format!("{integrator}.pbrt"));
            std::fs::write(&path, scene).unwrap();
            let overrides = RenderOverrides {
                outfile: Some(dir.join(format!("{integrator}.exr"))),
                ..Default::default()
            };
            crate::pipeline::render_file(&path, &overrides, 1, false).unwrap();
            let pixels = Image::read(dir.join(format!("{integrator}.exr")))
                .unwrap()
                .rgb_data();
            let mean = pixels.iter().map(|&v| v as f64).sum::<f64>() / pixels.len() as f64;
            eprintln!("{integrator}: {mean:.5} (expected {expected:.5})");
            assert!(
                (mean / expected - 1.0).abs() < 0.005,
                "{integrator}: {mean} vs {expected}"
            );
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
