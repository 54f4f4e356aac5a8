//! Directives → scene description.
//!
//! Keeps pbrt-v4's graphics state: the current transform(s), reverse
//! orientation, material, area light, media, colour space and `Attribute`
//! parameters, saved and restored by `AttributeBegin`/`AttributeEnd`; the
//! named coordinate systems, materials, textures, media and objects, which
//! are global. Every entity is checked against pbrt-v4's parameters for its
//! type as it is read.

use crate::error::{scene_error, Error, Result};
use crate::math::Transform;
use crate::scene_description::params::ParamSet;
use crate::scene_description::schema::{self, Category};
use crate::scene_description::*;
use glam::DVec3;
use pbrt_parser::{
    ActiveTransform, Directive, Entity as ParsedEntity, Located, Location, Name, Param, Parser,
    Warning,
};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};

/// What an `Attribute` directive sets defaults for; the index (`as
/// usize`) of its parameters in [`GraphicsState::attributes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum AttributeTarget {
    Shape,
    Light,
    Material,
    Medium,
    Texture,
}

impl AttributeTarget {
    const ALL: [AttributeTarget; 5] = [
        AttributeTarget::Shape,
        AttributeTarget::Light,
        AttributeTarget::Material,
        AttributeTarget::Medium,
        AttributeTarget::Texture,
    ];

    /// The target's name in the `Attribute` directive.
    fn name(self) -> &'static str {
        match self {
            AttributeTarget::Shape => "shape",
            AttributeTarget::Light => "light",
            AttributeTarget::Material => "material",
            AttributeTarget::Medium => "medium",
            AttributeTarget::Texture => "texture",
        }
    }

    fn from_name(name: &str) -> Option<AttributeTarget> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }
}

#[derive(Clone, Debug)]
struct GraphicsState {
    /// Start- and end-time transforms (`ActiveTransform` picks which change).
    ctm: [Transform; 2],
    active: [bool; 2],
    reverse_orientation: bool,
    material: MaterialRef,
    area_light: Option<(ParsedEntity, Location)>,
    inside_medium: Name,
    outside_medium: Name,
    color_space: ColorSpaceName,
    /// The `Attribute` parameters, indexed by [`AttributeTarget`].
    attributes: [Vec<Param>; AttributeTarget::ALL.len()],
}

impl Default for GraphicsState {
    fn default() -> Self {
        GraphicsState {
            ctm: [Transform::IDENTITY; 2],
            active: [true; 2],
            reverse_orientation: false,
            // pbrt starts with an anonymous default "diffuse" material.
            material: MaterialRef::Anonymous(0),
            area_light: None,
            inside_medium: Name::new(""),
            outside_medium: Name::new(""),
            color_space: ColorSpaceName::Srgb,
            attributes: Default::default(),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Block {
    Options,
    World,
}

/// What a saved state was pushed by, for mismatch errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Nesting {
    Attribute,
    Object,
}

/// Walks directives and assembles a [`SceneDescription`].
pub struct SceneBuilder {
    block: Block,
    state: GraphicsState,
    stack: Vec<(GraphicsState, Nesting, Location)>,
    transform_times: (f64, f64),
    named_coordinate_systems: HashMap<String, [Transform; 2]>,
    current_object: Option<Object>,
    object_names: HashSet<String>,
    /// Instances by object name (resolved at the end, as pbrt does).
    pending_instances: Vec<(String, TransformId, Location)>,
    texture_names: HashSet<(TextureValue, String)>,
    warnings: Vec<Warning>,
    scene: SceneDescription,
    world_begun: bool,
    /// The CTM interned last, to share it with the next shape.
    last_transform: Option<(AnimatedTransform, TransformId)>,
    checker: schema::Checker,
}

/// The `"string type"` of a named material or medium (whose directive
/// names the thing, not its type).
fn declared_type(e: &ParsedEntity, what: &str, loc: &Location) -> Result<String> {
    match e.param("type").map(|p| p.strings()) {
        Some([kind]) => Ok(kind.to_string()),
        _ => scene_error(
            format!("{what} \"{}\": \"string type\" not provided", e.kind),
            loc,
        ),
    }
}

/// The transform of a `Transform` or `ConcatTransform` matrix, which must
/// be invertible.
fn invertible(matrix: &[f64; 16], keyword: &str, loc: &Location) -> Result<Transform> {
    match Transform::from_pbrt_array(matrix) {
        Some(t) => Ok(t),
        None => scene_error(format!("{keyword}: the matrix is not invertible"), loc),
    }
}

fn default_entity(kind: &str) -> Entity {
    Entity {
        kind: Name::new(kind),
        params: ParamSet::default(),
        color_space: ColorSpaceName::Srgb,
        location: Loc(Location::nowhere()),
    }
}

impl SceneBuilder {
    /// `base_directory`: where the main scene file is.
    pub fn new(base_directory: PathBuf) -> Self {
        let static_identity = AnimatedTransform {
            start: Transform::IDENTITY,
            end: None,
            start_time: 0.0,
            end_time: 1.0,
        };
        SceneBuilder {
            block: Block::Options,
            state: GraphicsState::default(),
            stack: Vec::new(),
            transform_times: (0.0, 1.0),
            named_coordinate_systems: HashMap::new(),
            current_object: None,
            object_names: HashSet::new(),
            pending_instances: Vec::new(),
            texture_names: HashSet::new(),
            warnings: Vec::new(),
            world_begun: false,
            last_transform: None,
            checker: schema::Checker::default(),
            scene: SceneDescription {
                base_directory,
                options: Options::default(),
                transforms: Vec::new(),
                camera: Camera {
                    entity: default_entity("perspective"),
                    camera_from_world: static_identity,
                    medium: String::new(),
                },
                film: default_entity("rgb"),
                sampler: default_entity("zsobol"),
                filter: default_entity("gaussian"),
                integrator: default_entity("volpath"),
                accelerator: default_entity("bvh"),
                materials: vec![default_entity("diffuse")],
                named_materials: BTreeMap::new(),
                textures: Vec::new(),
                media: Vec::new(),
                lights: Vec::new(),
                area_lights: Vec::new(),
                shapes: Vec::new(),
                objects: Vec::new(),
                instances: Vec::new(),
            },
        }
    }

    pub fn take_warnings(&mut self) -> Vec<Warning> {
        std::mem::take(&mut self.warnings)
    }

    fn warn(&mut self, message: impl Into<String>, location: &Location) {
        self.warnings.push(Warning {
            message: message.into(),
            location: location.clone(),
        });
    }

    fn require(&self, block: Block, keyword: &str, location: &Location) -> Result<()> {
        match (block, self.block) {
            (Block::Options, Block::World) => scene_error(
                format!("options cannot be set inside the world block; \"{keyword}\" is not allowed after WorldBegin"),
                location,
            ),
            (Block::World, Block::Options) => scene_error(
                format!("\"{keyword}\" is only allowed inside the world block (after WorldBegin)"),
                location,
            ),
            _ => Ok(()),
        }
    }

    /// Applies `op` to the active transforms (`ctm = ctm * op`).
    fn concat(&mut self, op: Transform) {
        for i in 0..2 {
            if self.state.active[i] {
                self.state.ctm[i] = self.state.ctm[i].then(&op);
            }
        }
    }

    fn set_ctm(&mut self, t: Transform) {
        for i in 0..2 {
            if self.state.active[i] {
                self.state.ctm[i] = t;
            }
        }
    }

    fn animated_ctm(&self) -> AnimatedTransform {
        let [start, end] = self.state.ctm;
        AnimatedTransform {
            start,
            end: (start != end).then_some(end),
            start_time: self.transform_times.0,
            end_time: self.transform_times.1,
        }
    }

    /// The CTM as a shared transform.
    fn current_transform(&mut self) -> TransformId {
        let t = self.animated_ctm();
        if let Some((last, id)) = self.last_transform {
            if last == t {
                return id;
            }
        }
        let id = TransformId(self.scene.transforms.len() as u32);
        self.scene.transforms.push(t);
        self.last_transform = Some((t, id));
        id
    }

    /// An entity from a parsed one, checked against pbrt-v4's parameters.
    fn entity(
        &self,
        category: Category,
        kind: &str,
        params: Vec<Param>,
        attributes: Option<AttributeTarget>,
        location: &Location,
    ) -> Result<Entity> {
        let attributes: &[Param] =
            attributes.map_or(&[], |target| &self.state.attributes[target as usize]);
        let params = ParamSet::new(params, attributes);
        self.checker.check(category, kind, &params, location)?;
        Ok(Entity {
            kind: Name::new(kind),
            params,
            color_space: self.state.color_space,
            location: Loc(location.clone()),
        })
    }

    /// `WorldBegin`: the world block starts with the identity transform.
    pub fn begin_world(&mut self) {
        self.block = Block::World;
        self.world_begun = true;
        self.state.ctm = [Transform::IDENTITY; 2];
        self.state.active = [true; 2];
        self.named_coordinate_systems
            .insert("world".to_string(), [Transform::IDENTITY; 2]);
    }

    /// Applies one directive: transforms and the graphics state here, the
    /// rest through one method per directive (as pbrt-v4's
    /// `BasicSceneBuilder`).
    pub fn apply(&mut self, located: Located) -> Result<()> {
        let Located {
            directive,
            location,
        } = located;
        let loc = &location;
        let keyword = directive.keyword();
        use Directive as D;
        match directive {
            D::Identity => self.set_ctm(Transform::IDENTITY),
            D::Translate([x, y, z]) => self.concat(Transform::translate(DVec3::new(x, y, z))),
            D::Scale([x, y, z]) => match Transform::scale(DVec3::new(x, y, z)) {
                Some(t) => self.concat(t),
                None => return scene_error("Scale by zero makes the transform singular", loc),
            },
            D::Rotate([angle, x, y, z]) => {
                match Transform::rotate(angle.to_radians(), DVec3::new(x, y, z)) {
                    Some(t) => self.concat(t),
                    None => return scene_error("Rotate needs a non-zero axis", loc),
                }
            }
            D::LookAt(v) => self.look_at(v, loc)?,
            D::ConcatTransform(m) => self.concat(invertible(&m, keyword, loc)?),
            D::Transform(m) => self.set_ctm(invertible(&m, keyword, loc)?),
            D::ActiveTransform(t) => {
                self.state.active = match t {
                    ActiveTransform::StartTime => [true, false],
                    ActiveTransform::EndTime => [false, true],
                    ActiveTransform::All => [true, true],
                }
            }
            D::TransformTimes(start, end) => self.transform_times(start, end, loc)?,
            D::CoordinateSystem(name) => {
                self.named_coordinate_systems.insert(name, self.state.ctm);
            }
            D::CoordSysTransform(name) => match self.named_coordinate_systems.get(&name) {
                Some(ctm) => self.state.ctm = *ctm,
                None => self.warn(
                    format!("couldn't find named coordinate system \"{name}\""),
                    loc,
                ),
            },
            D::ColorSpace(name) => self.color_space(&name, loc)?,
            D::Option(param) => self.option(param)?,
            D::Camera(e) => self.camera(e, loc)?,
            D::Film(e)
            | D::Sampler(e)
            | D::PixelFilter(e)
            | D::Integrator(e)
            | D::Accelerator(e) => self.render_setting(e, keyword, loc)?,
            D::WorldBegin => {
                self.require(Block::Options, keyword, loc)?;
                self.begin_world();
            }
            D::WorldEnd => {}
            D::AttributeBegin => {
                self.require(Block::World, keyword, loc)?;
                self.stack
                    .push((self.state.clone(), Nesting::Attribute, location.clone()));
            }
            D::AttributeEnd => self.attribute_end(keyword, loc)?,
            D::Attribute(e) => self.attribute(e, loc)?,
            D::ReverseOrientation => {
                self.require(Block::World, keyword, loc)?;
                self.state.reverse_orientation = !self.state.reverse_orientation;
            }
            D::Material(e) => self.material(e, keyword, loc)?,
            D::MakeNamedMaterial(e) => self.make_named_material(e, keyword, loc)?,
            D::NamedMaterial(name) => {
                self.require(Block::World, keyword, loc)?;
                self.state.material = MaterialRef::Named(name.into());
            }
            D::Texture {
                name,
                value_type,
                class,
            } => self.texture(name, &value_type, class, keyword, loc)?,
            D::MakeNamedMedium(e) => self.make_named_medium(e, loc)?,
            D::MediumInterface { inside, outside } => {
                self.state.inside_medium = inside.into();
                self.state.outside_medium = outside.into();
            }
            D::LightSource(e) => self.light_source(e, keyword, loc)?,
            D::AreaLightSource(e) => {
                self.require(Block::World, keyword, loc)?;
                // Check now, so the error points here rather than at a shape.
                self.entity(
                    Category::AreaLight,
                    &e.kind,
                    e.params.clone(),
                    Some(AttributeTarget::Light),
                    loc,
                )?;
                self.state.area_light = Some((e, location.clone()));
            }
            D::Shape(e) => {
                self.require(Block::World, keyword, loc)?;
                self.shape(e, loc)?;
            }
            D::ObjectBegin(name) => self.object_begin(name, keyword, loc)?,
            D::ObjectEnd => self.object_end(keyword, loc)?,
            D::ObjectInstance(name) => self.object_instance(name, keyword, loc)?,
            D::Include(_) | D::Import(_) => {
                return scene_error(
                    format!(
                        "{keyword} reached the scene builder: the parser should have followed it"
                    ),
                    loc,
                )
            }
        }
        Ok(())
    }

    /// `LookAt`: eye, look-at point and up vector.
    fn look_at(&mut self, v: [f64; 9], loc: &Location) -> Result<()> {
        let [ex, ey, ez, lx, ly, lz, ux, uy, uz] = v;
        match Transform::look_at(
            DVec3::new(ex, ey, ez),
            DVec3::new(lx, ly, lz),
            DVec3::new(ux, uy, uz),
        ) {
            Some(t) => {
                self.concat(t);
                Ok(())
            }
            None => scene_error(
                "LookAt: the up vector is parallel to the viewing direction (or eye = look)",
                loc,
            ),
        }
    }

    /// `TransformTimes`: the times of the start and end transforms.
    fn transform_times(&mut self, start: f64, end: f64, loc: &Location) -> Result<()> {
        self.require(Block::Options, "TransformTimes", loc)?;
        if end < start {
            return scene_error("TransformTimes: the end time is before the start time", loc);
        }
        self.transform_times = (start, end);
        Ok(())
    }

    /// `ColorSpace`: the colour space of the entities that follow.
    fn color_space(&mut self, name: &str, loc: &Location) -> Result<()> {
        let Some(space) = ColorSpaceName::from_name(name) else {
            let known: Vec<&str> = ColorSpaceName::ALL.iter().map(|(n, _)| *n).collect();
            return scene_error(
                format!(
                    "unknown colour space \"{name}\" (expected one of {})",
                    known.join(", ")
                ),
                loc,
            );
        };
        self.state.color_space = space;
        Ok(())
    }

    /// `Camera`: also names the `"camera"` coordinate system.
    fn camera(&mut self, e: ParsedEntity, loc: &Location) -> Result<()> {
        self.require(Block::Options, "Camera", loc)?;
        let entity = self.entity(Category::Camera, &e.kind, e.params, None, loc)?;
        let camera_from_world = self.animated_ctm();
        let inverse = [self.state.ctm[0].inverse(), self.state.ctm[1].inverse()];
        self.named_coordinate_systems
            .insert("camera".to_string(), inverse);
        self.scene.camera = Camera {
            entity,
            camera_from_world,
            medium: self.state.outside_medium.to_string(),
        };
        Ok(())
    }

    /// `Film`, `Sampler`, `PixelFilter`, `Integrator` and `Accelerator`:
    /// each replaces the scene's one entity of its kind.
    fn render_setting(&mut self, e: ParsedEntity, keyword: &str, loc: &Location) -> Result<()> {
        self.require(Block::Options, keyword, loc)?;
        let category = match keyword {
            "Film" => Category::Film,
            "Sampler" => Category::Sampler,
            "PixelFilter" => Category::Filter,
            "Integrator" => Category::Integrator,
            _ => Category::Accelerator,
        };
        let entity = self.entity(category, &e.kind, e.params, None, loc)?;
        let slot = match category {
            Category::Film => &mut self.scene.film,
            Category::Sampler => &mut self.scene.sampler,
            Category::Filter => &mut self.scene.filter,
            Category::Integrator => &mut self.scene.integrator,
            _ => &mut self.scene.accelerator,
        };
        *slot = entity;
        Ok(())
    }

    /// `AttributeEnd`: restores the state saved by the matching
    /// `AttributeBegin`.
    fn attribute_end(&mut self, keyword: &str, loc: &Location) -> Result<()> {
        self.require(Block::World, keyword, loc)?;
        match self.stack.last() {
            None => scene_error(
                format!("unmatched {keyword} (no AttributeBegin is open)"),
                loc,
            ),
            Some((_, Nesting::Object, begin)) => scene_error(
                format!("mismatched nesting: {keyword} while the ObjectBegin at {begin} is open"),
                loc,
            ),
            Some((_, Nesting::Attribute, _)) => {
                if let Some((state, _, _)) = self.stack.pop() {
                    self.state = state;
                }
                Ok(())
            }
        }
    }

    /// `Attribute "target" ...`: parameters every later entity of the
    /// target's kind gets unless it sets them itself.
    fn attribute(&mut self, e: ParsedEntity, loc: &Location) -> Result<()> {
        let Some(target) = AttributeTarget::from_name(&e.kind) else {
            return scene_error(
                format!(
                    "unknown Attribute target \"{}\" (expected \"shape\", \"light\", \"material\", \"medium\" or \"texture\")",
                    e.kind
                ),
                loc,
            );
        };
        self.state.attributes[target as usize].extend(e.params);
        Ok(())
    }

    /// `Material`: an anonymous material, the current one from here on.
    fn material(&mut self, e: ParsedEntity, keyword: &str, loc: &Location) -> Result<()> {
        self.require(Block::World, keyword, loc)?;
        let entity = self.entity(
            Category::Material,
            &e.kind,
            e.params,
            Some(AttributeTarget::Material),
            loc,
        )?;
        self.scene.materials.push(entity);
        self.state.material = MaterialRef::Anonymous(self.scene.materials.len() as u32 - 1);
        Ok(())
    }

    /// `MakeNamedMaterial`: a named material (a name is defined once).
    fn make_named_material(
        &mut self,
        e: ParsedEntity,
        keyword: &str,
        loc: &Location,
    ) -> Result<()> {
        self.require(Block::World, keyword, loc)?;
        let name = e.kind.clone();
        if self.scene.named_materials.contains_key(&name) {
            return scene_error(format!("named material \"{name}\" redefined"), loc);
        }
        let kind = declared_type(&e, "named material", loc)?;
        let entity = self.entity(
            Category::Material,
            &kind,
            e.params,
            Some(AttributeTarget::Material),
            loc,
        )?;
        self.scene.named_materials.insert(name, entity);
        Ok(())
    }

    /// `Texture "name" "float"|"spectrum" "class" ...`: a named texture
    /// (a name is defined once per value type).
    fn texture(
        &mut self,
        name: String,
        value_type: &str,
        class: ParsedEntity,
        keyword: &str,
        loc: &Location,
    ) -> Result<()> {
        self.require(Block::World, keyword, loc)?;
        let value = match value_type {
            "float" => TextureValue::Float,
            "spectrum" => TextureValue::Spectrum,
            other => {
                return scene_error(
                    format!("texture type \"{other}\" unknown: expected \"float\" or \"spectrum\""),
                    loc,
                )
            }
        };
        if !self.texture_names.insert((value, name.clone())) {
            return scene_error(format!("texture \"{name}\" redefined"), loc);
        }
        let entity = self.entity(
            Category::Texture,
            &class.kind,
            class.params,
            Some(AttributeTarget::Texture),
            loc,
        )?;
        self.scene.textures.push(Texture {
            name,
            value,
            entity,
            world_from_texture: self.state.ctm[0],
        });
        Ok(())
    }

    /// `MakeNamedMedium`: a named medium (a name is defined once).
    fn make_named_medium(&mut self, e: ParsedEntity, loc: &Location) -> Result<()> {
        let name = e.kind.clone();
        if self.scene.media.iter().any(|m| m.name == name) {
            return scene_error(format!("named medium \"{name}\" redefined"), loc);
        }
        let kind = declared_type(&e, "medium", loc)?;
        let entity = self.entity(
            Category::Medium,
            &kind,
            e.params,
            Some(AttributeTarget::Medium),
            loc,
        )?;
        self.scene.media.push(Medium {
            name,
            entity,
            world_from_medium: self.state.ctm[0],
        });
        Ok(())
    }

    /// `LightSource`: a light at the CTM's start transform.
    fn light_source(&mut self, e: ParsedEntity, keyword: &str, loc: &Location) -> Result<()> {
        self.require(Block::World, keyword, loc)?;
        let entity = self.entity(
            Category::Light,
            &e.kind,
            e.params,
            Some(AttributeTarget::Light),
            loc,
        )?;
        if self.animated_ctm().is_animated() {
            self.warn(
                "animated lights aren't supported; using the start transform",
                loc,
            );
        }
        self.scene.lights.push(Light {
            entity,
            world_from_light: self.state.ctm[0],
            medium: self.state.outside_medium.to_string(),
        });
        Ok(())
    }

    /// `ObjectBegin`: starts an object definition (objects do not nest;
    /// a name is defined once), saving the graphics state.
    fn object_begin(&mut self, name: String, keyword: &str, loc: &Location) -> Result<()> {
        self.require(Block::World, keyword, loc)?;
        if self.current_object.is_some() {
            return scene_error(
                "ObjectBegin inside an object definition (objects cannot nest)",
                loc,
            );
        }
        if !self.object_names.insert(name.clone()) {
            return scene_error(format!("object \"{name}\" redefined"), loc);
        }
        self.stack
            .push((self.state.clone(), Nesting::Object, loc.clone()));
        self.current_object = Some(Object {
            name,
            shapes: Vec::new(),
            location: Loc(loc.clone()),
        });
        Ok(())
    }

    /// `ObjectEnd`: ends the object definition, restoring the graphics
    /// state.
    fn object_end(&mut self, keyword: &str, loc: &Location) -> Result<()> {
        self.require(Block::World, keyword, loc)?;
        let Some(object) = self.current_object.take() else {
            return scene_error("ObjectEnd outside an object definition", loc);
        };
        match self.stack.pop() {
            Some((state, Nesting::Object, _)) => self.state = state,
            Some((_, Nesting::Attribute, begin)) => {
                return scene_error(
                    format!(
                        "mismatched nesting: ObjectEnd while the AttributeBegin at {begin} is open"
                    ),
                    loc,
                )
            }
            None => return scene_error("ObjectEnd without ObjectBegin", loc),
        }
        self.scene.objects.push(object);
        Ok(())
    }

    /// `ObjectInstance`: an instance of a named object at the CTM,
    /// resolved at the end (an object may be defined after its use).
    fn object_instance(&mut self, name: String, keyword: &str, loc: &Location) -> Result<()> {
        self.require(Block::World, keyword, loc)?;
        if self.current_object.is_some() {
            return scene_error(
                "ObjectInstance inside an object definition (instances cannot nest)",
                loc,
            );
        }
        let t = self.current_transform();
        self.pending_instances.push((name, t, loc.clone()));
        Ok(())
    }

    fn option(&mut self, param: Param) -> Result<()> {
        use pbrt_parser::ParamType as T;
        let loc = param.location.clone();
        let key: String = param
            .name
            .to_lowercase()
            .chars()
            .filter(|c| *c != '-' && *c != '_')
            .collect();
        let set = ParamSet::new(vec![param], &[]);
        let name = set
            .iter()
            .next()
            .map(|p| p.name.to_string())
            .unwrap_or_default();
        let o = &mut self.scene.options;
        let expect = |ty: T| -> Result<()> { set.find(&name, &[ty]).map(|_| ()) };
        match key.as_str() {
            "seed" => {
                expect(T::Integer)?;
                o.seed = set.int(&name, 0)?;
            }
            "disablepixeljitter" => o.disable_pixel_jitter = set.bool(&name, false)?,
            "disabletexturefiltering" => o.disable_texture_filtering = set.bool(&name, false)?,
            "disablewavelengthjitter" => o.disable_wavelength_jitter = set.bool(&name, false)?,
            "forcediffuse" => o.force_diffuse = set.bool(&name, false)?,
            "pixelstats" => o.pixel_stats = set.bool(&name, false)?,
            "wavefront" => o.wavefront = set.bool(&name, false)?,
            "displacementedgescale" => {
                // `Option "displacementedgescale" 1` reads as an integer.
                let p = set.find(&name, &[T::Float, T::Integer])?;
                o.displacement_edge_scale = p.and_then(|p| p.numbers().first().copied());
            }
            "msereferenceimage" => o.mse_reference_image = Some(set.string(&name, "")?),
            "msereferenceout" => o.mse_reference_out = Some(set.string(&name, "")?),
            "rendercoordsys" => {
                let value = set.string(&name, "cameraworld")?;
                if !["camera", "cameraworld", "world"].contains(&value.as_str()) {
                    return scene_error(
                        format!("unknown rendering coordinate system \"{value}\" (expected camera, cameraworld or world)"),
                        &loc,
                    );
                }
                o.render_coord_sys = Some(value);
            }
            _ => return scene_error(format!("unknown option \"{name}\""), &loc),
        }
        Ok(())
    }

    fn shape(&mut self, mut e: ParsedEntity, loc: &Location) -> Result<()> {
        // Written by the Houdini exporter; pbrt-v4 has no such parameter.
        if let Some(p) = e.params.iter().find(|p| p.name == "emissionfilename") {
            let at = p.location.clone();
            self.warn(
                "\"emissionfilename\" is not a pbrt-v4 shape parameter; ignored",
                &at,
            );
            e.params.retain(|p| p.name != "emissionfilename");
        }
        let entity = self.entity(
            Category::Shape,
            &e.kind,
            e.params,
            Some(AttributeTarget::Shape),
            loc,
        )?;
        let world_from_object = self.current_transform();
        let mut area_light = None;
        if let Some((light, light_loc)) = &self.state.area_light {
            if self.current_object.is_some() {
                self.warn(
                    "area lights are not supported with object instancing; the shape does not emit",
                    loc,
                );
            } else {
                let light = self.entity(
                    Category::AreaLight,
                    &light.kind,
                    light.params.clone(),
                    Some(AttributeTarget::Light),
                    light_loc,
                )?;
                self.scene.area_lights.push(light);
                area_light = Some(self.scene.area_lights.len() as u32 - 1);
            }
        }
        let shape = Shape {
            entity,
            world_from_object,
            reverse_orientation: self.state.reverse_orientation,
            material: self.state.material.clone(),
            area_light,
            inside_medium: self.state.inside_medium.clone(),
            outside_medium: self.state.outside_medium.clone(),
        };
        match &mut self.current_object {
            Some(object) => object.shapes.push(shape),
            None => self.scene.shapes.push(shape),
        }
        Ok(())
    }

    /// Ends the description: checks what could only be checked once the
    /// whole file was read (references to named things).
    pub fn finish(mut self, end: &Location) -> Result<(SceneDescription, Vec<Warning>)> {
        if let Some(object) = &self.current_object {
            return scene_error(
                format!("ObjectBegin \"{}\" is never closed", object.name),
                &object.location.0,
            );
        }
        // pbrt-v4 rejects this; the scene is unambiguous, so (like pbrt-v3)
        // rpbrt only warns.
        for (_, _, begin) in std::mem::take(&mut self.stack) {
            self.warn(
                "AttributeBegin is never closed (missing AttributeEnd)",
                &begin,
            );
        }
        if !self.world_begun {
            return scene_error("end of file before WorldBegin", end);
        }
        let index: HashMap<&str, usize> = self
            .scene
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| (o.name.as_str(), i))
            .collect();
        for (name, t, loc) in std::mem::take(&mut self.pending_instances) {
            let Some(&object) = index.get(name.as_str()) else {
                return scene_error(
                    format!("ObjectInstance: object \"{name}\" is not defined"),
                    &loc,
                );
            };
            self.scene.instances.push(Instance {
                object,
                world_from_instance: t,
                location: Loc(loc),
            });
        }
        self.check_references()?;
        Ok((self.scene, self.warnings))
    }

    fn check_references(&self) -> Result<()> {
        let s = &self.scene;
        let media: HashSet<&str> = s.media.iter().map(|m| m.name.as_str()).collect();
        let medium_ok = |name: &str| name.is_empty() || media.contains(name);
        let textures: HashSet<&str> = s.textures.iter().map(|t| t.name.as_str()).collect();
        let all_shapes = s
            .shapes
            .iter()
            .chain(s.objects.iter().flat_map(|o| o.shapes.iter()));
        for shape in all_shapes {
            let loc = &shape.entity.location.0;
            if let MaterialRef::Named(name) = &shape.material {
                if !s.named_materials.contains_key(name.as_str()) {
                    return scene_error(format!("NamedMaterial \"{name}\" is not defined"), loc);
                }
            }
            for m in [&shape.inside_medium, &shape.outside_medium] {
                if !medium_ok(m) {
                    return scene_error(format!("medium \"{m}\" is not defined"), loc);
                }
            }
        }
        if !medium_ok(&s.camera.medium) {
            return scene_error(
                format!("camera medium \"{}\" is not defined", s.camera.medium),
                &s.camera.entity.location.0,
            );
        }
        for light in &s.lights {
            if !medium_ok(&light.medium) {
                return scene_error(
                    format!("light medium \"{}\" is not defined", light.medium),
                    &light.entity.location.0,
                );
            }
        }
        // Texture parameters must name a texture.
        let with_textures = s
            .materials
            .iter()
            .chain(s.named_materials.values())
            .chain(s.textures.iter().map(|t| &t.entity))
            .chain(s.shapes.iter().map(|sh| &sh.entity));
        for entity in with_textures {
            for p in entity.params.iter() {
                if p.ty == pbrt_parser::ParamType::Texture {
                    for name in p.strings() {
                        if !textures.contains(name.as_str()) {
                            return scene_error(
                                format!(
                                    "\"texture {}\": texture \"{name}\" is not defined",
                                    p.name
                                ),
                                &p.location,
                            );
                        }
                    }
                }
            }
        }
        // Mix materials name other materials.
        for entity in s.materials.iter().chain(s.named_materials.values()) {
            if entity.kind == "mix" {
                if let Some(pbrt_parser::Values::Strings(names)) = entity.params.values("materials")
                {
                    for name in names {
                        if !s.named_materials.contains_key(name.as_str()) {
                            return scene_error(
                                format!("mix material: material \"{name}\" is not defined"),
                                &entity.location.0,
                            );
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// What loading a scene file gives: the description and the warnings.
pub struct Loaded {
    pub scene: SceneDescription,
    pub warnings: Vec<Warning>,
}

/// Parses and describes a scene file.
pub fn load(path: &Path) -> Result<Loaded> {
    let parser = Parser::open(path)?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    describe(parser, SceneBuilder::new(base))
}

/// Parses and describes a file meant to be included inside the world block
/// (a geometry file): it is read as if `WorldBegin` came just before it.
pub fn load_fragment(path: &Path) -> Result<Loaded> {
    let parser = Parser::open(path)?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut builder = SceneBuilder::new(base);
    builder.begin_world();
    describe(parser, builder)
}

/// Parses and describes scene text held in memory (`name` stands for its
/// path: includes resolve against its directory).
pub fn load_text(name: &Path, text: &str) -> Result<Loaded> {
    let parser = Parser::from_text(name, text);
    let base = name.parent().map(Path::to_path_buf).unwrap_or_default();
    describe(parser, SceneBuilder::new(base))
}

/// Feeds every directive of `parser` to `builder`.
pub fn describe(mut parser: Parser, mut builder: SceneBuilder) -> Result<Loaded> {
    let mut last = None;
    for directive in parser.by_ref() {
        let directive = directive.map_err(Error::from)?;
        last = Some(directive.location.clone());
        builder.apply(directive)?;
    }
    let mut warnings = parser.take_warnings();
    let end = last.unwrap_or_else(Location::nowhere);
    let (scene, mut more) = builder.finish(&end)?;
    warnings.append(&mut more);
    Ok(Loaded { scene, warnings })
}
