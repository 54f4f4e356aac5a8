//! The parameters pbrt-v4 defines for each type of each directive, and the
//! value types each accepts.
//!
//! The scene description checks every entity against this table as it is
//! read, so a misspelt or mistyped parameter is an error naming its
//! file:line:col before anything is built (pbrt-v4 reports the same, as
//! "unused parameter", once it creates the object). Each type's own
//! `create` function still reads its parameters with typed lookups.

use super::params::ParamSet;
use crate::error::{scene_error, Result};
use pbrt_parser::{Location, Name, ParamType as T};
use std::cell::RefCell;

/// What a parameter slot accepts.
type Slot = (&'static str, &'static [T]);

const F: &[T] = &[T::Float];
const I: &[T] = &[T::Integer];
const B: &[T] = &[T::Bool];
const S: &[T] = &[T::String];
const P2: &[T] = &[T::Point2];
const P3: &[T] = &[T::Point3];
const V3: &[T] = &[T::Vector3];
const N3: &[T] = &[T::Normal3];
/// A float or a float texture.
const FT: &[T] = &[T::Float, T::Texture];
/// A spectrum: rgb, blackbody or spectrum.
const SP: &[T] = &[T::Rgb, T::Spectrum, T::Blackbody];
/// A spectrum or a spectrum texture.
const ST: &[T] = &[T::Rgb, T::Spectrum, T::Blackbody, T::Texture];
/// A constant float or spectrum (`bilerp`'s corner values).
const VALUE: &[T] = &[T::Float, T::Rgb, T::Spectrum, T::Blackbody];
/// Any value a texture or an index of refraction may be.
const ANY: &[T] = &[T::Float, T::Rgb, T::Spectrum, T::Blackbody, T::Texture];

/// Directive families with typed entities.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    Camera,
    Film,
    Sampler,
    Filter,
    Integrator,
    Accelerator,
    Shape,
    Material,
    Texture,
    Light,
    AreaLight,
    Medium,
}

impl Category {
    pub fn name(self) -> &'static str {
        match self {
            Category::Camera => "camera",
            Category::Film => "film",
            Category::Sampler => "sampler",
            Category::Filter => "filter",
            Category::Integrator => "integrator",
            Category::Accelerator => "accelerator",
            Category::Shape => "shape",
            Category::Material => "material",
            Category::Texture => "texture",
            Category::Light => "light",
            Category::AreaLight => "area light",
            Category::Medium => "medium",
        }
    }
}

const SHUTTER: &[Slot] = &[("shutteropen", F), ("shutterclose", F)];
const PROJECTIVE: &[Slot] = &[
    ("lensradius", F),
    ("focaldistance", F),
    ("frameaspectratio", F),
    ("screenwindow", F),
];
const FILM: &[Slot] = &[
    ("xresolution", I),
    ("yresolution", I),
    ("cropwindow", F),
    ("pixelbounds", I),
    ("diagonal", F),
    ("filename", S),
    ("savefp16", B),
    ("iso", F),
    ("whitebalance", F),
    ("sensor", S),
    ("maxcomponentvalue", F),
];
/// Read by the low-discrepancy samplers (halton, sobol, paddedsobol, zsobol).
const LOW_DISCREPANCY: &[Slot] = &[("pixelsamples", I), ("seed", I), ("randomization", S)];
const FILTER: &[Slot] = &[("xradius", F), ("yradius", F)];
const MAX_DEPTH: &[Slot] = &[("maxdepth", I)];
/// Read by path and volpath.
const PATH: &[Slot] = &[
    ("maxdepth", I),
    ("regularize", B),
    ("lightsampler", S),
    ("connectdiffraction", B),
];
const SHAPE: &[Slot] = &[("alpha", FT)];
const ROUGHNESS: &[Slot] = &[
    ("roughness", FT),
    ("uroughness", FT),
    ("vroughness", FT),
    ("remaproughness", B),
];
const MATERIAL: &[Slot] = &[("type", S), ("displacement", FT), ("normalmap", S)];
/// pbrt-v4's `TextureMapping2D::Create` reads `mapping`, then only the
/// parameters of the mapping it names.
const UV_MAPPING: &[Slot] = &[
    ("mapping", S),
    ("uscale", F),
    ("vscale", F),
    ("udelta", F),
    ("vdelta", F),
];
const PLANAR_MAPPING: &[Slot] = &[
    ("mapping", S),
    ("v1", V3),
    ("v2", V3),
    ("udelta", F),
    ("vdelta", F),
];
const OTHER_MAPPING: &[Slot] = &[("mapping", S)];
/// Read by every light.
const LIGHT: &[Slot] = &[("scale", F)];
const MEDIUM: &[Slot] = &[
    ("type", S),
    ("sigma_a", SP),
    ("sigma_s", SP),
    ("scale", F),
    ("g", F),
    ("preset", S),
    ("Le", &[T::Float, T::Rgb, T::Spectrum, T::Blackbody]),
    ("Lescale", F),
];
const GRID: &[Slot] = &[
    ("nx", I),
    ("ny", I),
    ("nz", I),
    ("p0", P3),
    ("p1", P3),
    ("density", F),
    ("temperature", F),
    ("temperaturecutoff", F),
    ("temperaturescale", F),
    ("temperatureoffset", F),
];

/// The slots of a type: its own, then the family's common ones.
fn slots(category: Category, kind: &str) -> Option<[&'static [Slot]; 3]> {
    use Category::*;
    let none: &[Slot] = &[];
    let own: &[Slot] = match (category, kind) {
        (Camera, "perspective") => &[("fov", F)],
        (Camera, "orthographic") => none,
        (Camera, "realistic") => &[
            ("lensfile", S),
            ("aperturediameter", F),
            ("focusdistance", F),
            ("aperture", S),
        ],
        (Camera, "spherical") => &[("mapping", S)],
        (Film, "rgb") => none,
        (Film, "gbuffer") => &[("coordinatesystem", S)],
        (Film, "spectral") => &[("nbuckets", I), ("lambdamin", F), ("lambdamax", F)],
        (Sampler, "halton" | "paddedsobol" | "sobol" | "zsobol") => LOW_DISCREPANCY,
        (Sampler, "independent" | "pmj02bn") => &[("pixelsamples", I), ("seed", I)],
        (Sampler, "stratified") => &[("xsamples", I), ("ysamples", I), ("jitter", B), ("seed", I)],
        (Filter, "box" | "triangle") => none,
        (Filter, "gaussian") => &[("sigma", F)],
        (Filter, "mitchell") => &[("B", F), ("C", F)],
        (Filter, "sinc") => &[("tau", F)],
        (Integrator, "path" | "volpath") => PATH,
        (Integrator, "lightpath" | "randomwalk" | "simplevolpath") => MAX_DEPTH,
        (Integrator, "simplepath") => &[("maxdepth", I), ("samplelights", B), ("samplebsdf", B)],
        (Integrator, "bdpt") => &[
            ("maxdepth", I),
            ("regularize", B),
            ("visualizestrategies", B),
            ("visualizeweights", B),
        ],
        (Integrator, "mlt") => &[
            ("maxdepth", I),
            ("regularize", B),
            ("bootstrapsamples", I),
            ("chains", I),
            ("mutationsperpixel", I),
            ("largestepprobability", F),
            ("sigma", F),
        ],
        (Integrator, "sppm") => &[
            ("maxdepth", I),
            ("photonsperiteration", I),
            ("radius", F),
            ("seed", I),
        ],
        (Integrator, "ambientocclusion") => &[("cossample", B), ("maxdistance", F)],
        (Accelerator, "bvh") => &[("maxnodeprims", I), ("splitmethod", S)],
        (Accelerator, "kdtree") => &[
            ("intersectcost", I),
            ("traversalcost", I),
            ("emptybonus", F),
            ("maxprims", I),
            ("maxdepth", I),
        ],
        (Shape, "sphere" | "cylinder") => &[("radius", F), ("zmin", F), ("zmax", F), ("phimax", F)],
        (Shape, "disk") => &[
            ("height", F),
            ("radius", F),
            ("innerradius", F),
            ("phimax", F),
        ],
        (Shape, "trianglemesh") => &[
            ("P", P3),
            ("indices", I),
            ("uv", P2),
            ("N", N3),
            ("S", V3),
            ("faceIndices", I),
        ],
        (Shape, "bilinearmesh") => &[
            ("P", P3),
            ("indices", I),
            ("uv", P2),
            ("N", N3),
            ("faceIndices", I),
        ],
        (Shape, "plymesh") => &[("filename", S), ("displacement", FT), ("edgelength", F)],
        (Shape, "curve" | "bcurve") => &[
            ("P", P3),
            ("basis", S),
            ("degree", I),
            ("type", S),
            ("N", N3),
            ("width", F),
            ("width0", F),
            ("width1", F),
            ("splitdepth", I),
        ],
        // rpbrt's: Cem Yuksel's HAIR files as curves (`shapes::cyhair`).
        (Shape, "cyhair") => &[
            ("filename", S),
            ("scale", F),
            ("width", F),
            ("type", S),
            ("basis", S),
            ("splitdepth", I),
        ],
        (Shape, "loopsubdiv") => &[("levels", I), ("indices", I), ("P", P3), ("scheme", S)],
        (Material, "interface" | "") => none,
        (Material, "diffuse") => &[("reflectance", ST)],
        (Material, "coateddiffuse") => &[
            ("reflectance", ST),
            ("thickness", FT),
            ("eta", ANY),
            ("maxdepth", I),
            ("nsamples", I),
            ("g", FT),
            ("albedo", ST),
        ],
        (Material, "coatedconductor") => &[
            ("interface.roughness", FT),
            ("interface.uroughness", FT),
            ("interface.vroughness", FT),
            ("interface.eta", ANY),
            ("thickness", FT),
            ("conductor.eta", ST),
            ("conductor.k", ST),
            ("conductor.roughness", FT),
            ("conductor.uroughness", FT),
            ("conductor.vroughness", FT),
            ("reflectance", ST),
            ("maxdepth", I),
            ("nsamples", I),
            ("g", FT),
            ("albedo", ST),
            ("remaproughness", B),
        ],
        (Material, "conductor") => &[("eta", ST), ("k", ST), ("reflectance", ST)],
        (Material, "dielectric" | "thindielectric") => &[("eta", ANY)],
        (Material, "diffusetransmission") => {
            &[("reflectance", ST), ("transmittance", ST), ("scale", F)]
        }
        (Material, "hair") => &[
            ("sigma_a", ST),
            ("reflectance", ST),
            ("eumelanin", FT),
            ("pheomelanin", FT),
            ("eta", FT),
            ("beta_m", FT),
            ("beta_n", FT),
            ("alpha", FT),
            // The dual model (src/materials/dual_hair.rs).
            ("ellipse_a", F),
            ("ellipse_b", F),
            ("d_diff", F),
            ("s_diff", F),
            ("ellipse_orientation", F),
            ("ellipse_reference", V3),
            ("ellipse_random", B),
            ("diffraction", S),
            ("variant", S),
            ("internal_fresnel", S),
            ("fresnel", S),
            ("residual", S),
        ],
        (Material, "measured") => &[("filename", S)],
        (Material, "mix") => &[("materials", S), ("amount", FT)],
        (Material, "subsurface") => &[
            ("eta", F),
            ("g", F),
            ("mfp", ST),
            ("name", S),
            ("reflectance", ST),
            ("sigma_a", ST),
            ("sigma_s", ST),
            ("scale", F),
        ],
        (Texture, "constant") => &[("value", ANY)],
        (Texture, "scale") => &[("tex", ANY), ("scale", FT)],
        (Texture, "mix") => &[("tex1", ANY), ("tex2", ANY), ("amount", FT)],
        (Texture, "directionmix") => &[("tex1", ANY), ("tex2", ANY), ("dir", V3)],
        (Texture, "checkerboard") => &[("dimension", I), ("tex1", ANY), ("tex2", ANY)],
        (Texture, "dots") => &[("inside", ANY), ("outside", ANY)],
        (Texture, "fbm" | "wrinkled") => &[("octaves", I), ("roughness", F)],
        (Texture, "windy") => none,
        (Texture, "marble") => &[
            ("octaves", I),
            ("roughness", F),
            ("scale", F),
            ("variation", F),
        ],
        (Texture, "imagemap") => &[
            ("filename", S),
            ("maxanisotropy", F),
            ("filter", S),
            ("encoding", S),
            ("invert", B),
            ("scale", F),
            ("wrap", S),
        ],
        (Texture, "ptex") => &[("filename", S), ("encoding", S), ("scale", F)],
        (Texture, "bilerp") => &[
            ("v00", VALUE),
            ("v01", VALUE),
            ("v10", VALUE),
            ("v11", VALUE),
        ],
        (Light, "point") => &[("I", SP), ("from", P3), ("power", F)],
        (Light, "spot") => &[
            ("I", SP),
            ("from", P3),
            ("to", P3),
            ("coneangle", F),
            ("conedeltaangle", F),
            ("power", F),
        ],
        (Light, "goniometric") => &[("I", SP), ("filename", S), ("power", F)],
        (Light, "projection") => &[("fov", F), ("filename", S), ("power", F)],
        (Light, "distant") => &[("L", SP), ("from", P3), ("to", P3), ("illuminance", F)],
        (Light, "infinite") => &[
            ("L", SP),
            ("filename", S),
            ("illuminance", F),
            ("portal", P3),
        ],
        (AreaLight, "diffuse") => &[("L", SP), ("twosided", B), ("filename", S), ("power", F)],
        (Medium, "homogeneous") => none,
        (Medium, "uniformgrid") => GRID,
        (Medium, "rgbgrid") => &[
            ("nx", I),
            ("ny", I),
            ("nz", I),
            ("p0", P3),
            ("p1", P3),
            ("sigma_a", &[T::Rgb, T::Spectrum]),
            ("sigma_s", &[T::Rgb, T::Spectrum]),
            ("Le", &[T::Rgb, T::Spectrum]),
        ],
        (Medium, "cloud") => &[
            ("density", F),
            ("wispiness", F),
            ("frequency", F),
            ("p0", P3),
            ("p1", P3),
        ],
        (Medium, "nanovdb") => &[
            ("filename", S),
            ("temperaturecutoff", F),
            ("temperaturescale", F),
            ("temperatureoffset", F),
        ],
        _ => return None,
    };
    let common: [&'static [Slot]; 2] = match category {
        Camera if kind == "realistic" => [SHUTTER, none],
        Camera => [SHUTTER, PROJECTIVE],
        Film => [FILM, none],
        Sampler => [none, none],
        Filter => [FILTER, none],
        Integrator => [none, none],
        Accelerator => [none, none],
        Shape => [SHAPE, none],
        Material => match kind {
            "conductor" | "dielectric" | "coateddiffuse" | "subsurface" => [MATERIAL, ROUGHNESS],
            _ => [MATERIAL, none],
        },
        Texture => [none, none],
        Light | AreaLight => [LIGHT, none],
        Medium => [MEDIUM, none],
    };
    Some([own, common[0], common[1]])
}

/// Whether pbrt-v4 has a type of this name in this family.
pub fn is_known(category: Category, kind: &str) -> bool {
    slots(category, kind).is_some()
}

/// Checks `params` against the type's parameters: an unknown type, a
/// parameter of the wrong type, or one the type does not have is an error
/// (pbrt-v4's "unused parameter", at the parameter's location), found as
/// the directive is read. The lookups are then forgotten: whether the
/// create function reads each parameter is checked when it runs (its
/// `report_unused`), so a parameter listed here but not read is reported.
pub fn check(category: Category, kind: &str, params: &ParamSet, location: &Location) -> Result<()> {
    let Some(groups) = slots(category, kind) else {
        return scene_error(
            format!("unknown {} type \"{kind}\"", category.name()),
            location,
        );
    };
    for (name, types) in groups.iter().flat_map(|g| g.iter()) {
        params.find(name, types)?;
    }
    if category == Category::Texture {
        for (name, types) in texture_mapping_slots(kind, params)? {
            params.find(name, types)?;
        }
    }
    params.report_unused(|| format!("{} \"{kind}\"", category.name()))?;
    params.forget_used();
    Ok(())
}

/// [`check`] that passes at once an entity whose category, type and
/// parameters' names and types (in order, own and from `Attribute`) are
/// those of the last one it passed: whether [`check`] passes depends on
/// nothing else (except a texture's, whose mapping is read from a value;
/// textures are always checked). A hair file's hundreds of thousands of
/// curves mostly share one signature; checking each was over a third of
/// the scene builder's instructions, which runs on one core while the parser's
/// segments are read on all of them.
#[derive(Default)]
pub struct Checker {
    passed: RefCell<Option<Signature>>,
}

/// What [`Checker`] compares.
struct Signature {
    category: Category,
    kind: String,
    own: usize,
    params: Vec<(Name, T)>,
}

impl Signature {
    fn matches(&self, category: Category, kind: &str, params: &ParamSet) -> bool {
        self.category == category
            && self.kind == kind
            && self.own == params.own_count()
            && self.params.len() == params.iter().len()
            && self
                .params
                .iter()
                .zip(params.iter())
                .all(|((name, ty), p)| *ty == p.ty && *name == p.name)
    }
}

impl Checker {
    /// As [`check`].
    pub fn check(
        &self,
        category: Category,
        kind: &str,
        params: &ParamSet,
        location: &Location,
    ) -> Result<()> {
        let remembered = category != Category::Texture;
        let passed = self.passed.borrow();
        if remembered
            && passed
                .as_ref()
                .is_some_and(|s| s.matches(category, kind, params))
        {
            return Ok(());
        }
        drop(passed);
        check(category, kind, params, location)?;
        if remembered {
            *self.passed.borrow_mut() = Some(Signature {
                category,
                kind: kind.to_string(),
                own: params.own_count(),
                params: params.iter().map(|p| (p.name.clone(), p.ty)).collect(),
            });
        }
        Ok(())
    }
}

/// The 2D mapping parameters a texture reads: none for textures without a
/// 2D mapping (a 3D checkerboard, the noise textures), otherwise those of
/// the mapping named (an unknown mapping name is reported when the
/// texture is created).
fn texture_mapping_slots(kind: &str, params: &ParamSet) -> Result<&'static [Slot]> {
    let two_d = match kind {
        "imagemap" | "bilerp" | "dots" => true,
        "checkerboard" => params.int("dimension", 2)? == 2,
        _ => false,
    };
    if !two_d {
        return Ok(&[]);
    }
    Ok(match params.string("mapping", "uv")?.as_str() {
        "uv" => UV_MAPPING,
        "planar" => PLANAR_MAPPING,
        _ => OTHER_MAPPING,
    })
}
