//! The scene description: what the scene file says, as plain typed data,
//! each entity with its transform and file location, its parameters
//! ([`params`]) checked against pbrt-v4's ([`schema`]). Nothing is built
//! yet (no meshes read, no spectra made): that is `scene::build`'s job.
//!
//! The layer below the families: cameras, film, filters, lights,
//! materials, samplers, shapes, spectra and textures read their entities
//! from here, and `scene` (the builder that writes a description, and the
//! build that makes the families from it) sits above them all, as
//! pbrt-v4's `paramdict` sits below `scene.cpp`. Nothing here imports a
//! family or `scene`.

pub mod params;
pub mod schema;

use crate::math::Transform;
pub use params::ParamSet;
use pbrt_parser::{Location, Name};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A file location that does not take part in comparisons: two
/// descriptions are the same scene wherever their text was written.
#[derive(Clone, Debug)]
pub struct Loc(pub Location);

impl PartialEq for Loc {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Display for Loc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

/// A directive's type name and parameters (already checked against
/// pbrt-v4's parameters for that type).
#[derive(Clone, Debug, PartialEq)]
pub struct Entity {
    /// The type: `"sphere"`, `"diffuse"`, `"perspective"`, ... (shared:
    /// a hair file's million shapes are all `"curve"`).
    pub kind: Name,
    pub params: ParamSet,
    /// The colour space in force where the entity was declared.
    pub color_space: ColorSpaceName,
    pub location: Loc,
}

/// The RGB colour spaces pbrt-v4 names (`ColorSpace`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ColorSpaceName {
    #[default]
    Srgb,
    DciP3,
    Rec2020,
    Aces2065_1,
}

impl ColorSpaceName {
    pub const ALL: [(&'static str, ColorSpaceName); 4] = [
        ("srgb", ColorSpaceName::Srgb),
        ("dci-p3", ColorSpaceName::DciP3),
        ("rec2020", ColorSpaceName::Rec2020),
        ("aces2065-1", ColorSpaceName::Aces2065_1),
    ];

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(n, _)| *n == name).map(|(_, c)| *c)
    }
}

/// Index into [`SceneDescription::transforms`]: shapes written under one
/// transform share it (a hair file has one transform for a million curves).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TransformId(pub u32);

/// A time-varying transform (`ActiveTransform`/`TransformTimes`); `end` is
/// `None` when it does not vary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnimatedTransform {
    pub start: Transform,
    pub end: Option<Transform>,
    pub start_time: f64,
    pub end_time: f64,
}

impl AnimatedTransform {
    pub fn is_animated(&self) -> bool {
        self.end.is_some()
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub entity: Entity,
    /// The CTM at `Camera`.
    pub camera_from_world: AnimatedTransform,
    /// The outside medium at `Camera`.
    pub medium: String,
}

/// Which material a shape uses.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialRef {
    /// Index into [`SceneDescription::materials`].
    Anonymous(u32),
    /// A name in [`SceneDescription::named_materials`] (shared by the
    /// shapes that use it).
    Named(Name),
}

/// A `Shape` directive (about 150 bytes besides its parameters: a hair
/// file holds a million of these, so names are shared and indices small).
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    pub entity: Entity,
    pub world_from_object: TransformId,
    pub reverse_orientation: bool,
    pub material: MaterialRef,
    /// Index into [`SceneDescription::area_lights`].
    pub area_light: Option<u32>,
    pub inside_medium: Name,
    pub outside_medium: Name,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub entity: Entity,
    pub world_from_light: Transform,
    /// The outside medium at the light.
    pub medium: String,
}

/// What a texture produces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum TextureValue {
    Float,
    Spectrum,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub name: String,
    pub value: TextureValue,
    pub entity: Entity,
    pub world_from_texture: Transform,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    pub name: String,
    pub entity: Entity,
    pub world_from_medium: Transform,
}

/// Shapes defined between `ObjectBegin` and `ObjectEnd`, in world space as
/// they were defined; instances place them.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    pub name: String,
    pub shapes: Vec<Shape>,
    pub location: Loc,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// Index into [`SceneDescription::objects`].
    pub object: usize,
    pub world_from_instance: TransformId,
    pub location: Loc,
}

/// `Option` directives (and their command-line equivalents).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Options {
    pub seed: i32,
    pub disable_pixel_jitter: bool,
    pub disable_texture_filtering: bool,
    pub disable_wavelength_jitter: bool,
    pub force_diffuse: bool,
    pub pixel_stats: bool,
    pub wavefront: bool,
    pub displacement_edge_scale: Option<f64>,
    pub mse_reference_image: Option<String>,
    pub mse_reference_out: Option<String>,
    pub render_coord_sys: Option<String>,
}

/// Everything a scene file describes.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneDescription {
    /// Directory of the main scene file (relative file names resolve here).
    pub base_directory: PathBuf,
    pub options: Options,
    /// Transforms of shapes and instances, shared.
    pub transforms: Vec<AnimatedTransform>,
    pub camera: Camera,
    pub film: Entity,
    pub sampler: Entity,
    pub filter: Entity,
    pub integrator: Entity,
    pub accelerator: Entity,
    /// Materials from `Material`, referred to by index.
    pub materials: Vec<Entity>,
    /// Materials from `MakeNamedMaterial`, by name (the type is `kind`).
    pub named_materials: BTreeMap<String, Entity>,
    pub textures: Vec<Texture>,
    pub media: Vec<Medium>,
    pub lights: Vec<Light>,
    /// `AreaLightSource`s, one per shape that carries one.
    pub area_lights: Vec<Entity>,
    pub shapes: Vec<Shape>,
    pub objects: Vec<Object>,
    pub instances: Vec<Instance>,
}

impl SceneDescription {
    pub fn transform(&self, id: TransformId) -> &AnimatedTransform {
        &self.transforms[id.0 as usize]
    }

    /// Shape counts by type, over top-level shapes and object definitions.
    pub fn shape_counts(&self) -> BTreeMap<&str, usize> {
        let mut counts = BTreeMap::new();
        let all = self
            .shapes
            .iter()
            .chain(self.objects.iter().flat_map(|o| o.shapes.iter()));
        for s in all {
            *counts.entry(s.entity.kind.as_str()).or_insert(0) += 1;
        }
        counts
    }

    /// A short human-readable summary of the scene.
    pub fn summary(&self) -> String {
        let mut out = String::new();
        let shapes: usize = self.shape_counts().values().sum();
        out.push_str(&format!("shapes: {shapes}"));
        for (kind, n) in self.shape_counts() {
            out.push_str(&format!("\n  {kind}: {n}"));
        }
        out.push_str(&format!(
            "\nobject definitions: {}, instances: {}",
            self.objects.len(),
            self.instances.len()
        ));
        out.push_str(&format!(
            "\nmaterials: {} ({} named)",
            self.materials.len() + self.named_materials.len(),
            self.named_materials.len()
        ));
        out.push_str(&format!("\ntextures: {}", self.textures.len()));
        out.push_str(&format!(
            "\nlights: {} ({} area lights on shapes)",
            self.lights.len() + self.area_lights.len(),
            self.area_lights.len()
        ));
        out.push_str(&format!("\nmedia: {}", self.media.len()));
        out.push_str(&format!(
            "\ncamera \"{}\", film \"{}\", sampler \"{}\", filter \"{}\", integrator \"{}\"",
            self.camera.entity.kind,
            self.film.kind,
            self.sampler.kind,
            self.filter.kind,
            self.integrator.kind
        ));
        out
    }
}
