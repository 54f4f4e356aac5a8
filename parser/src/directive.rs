//! The directives of a pbrt scene file, and their canonical pbrt-v4 text.

use crate::location::Location;
use crate::param::{Param, Values};
use std::fmt::{self, Write};

/// `ActiveTransform` targets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ActiveTransform {
    StartTime,
    EndTime,
    All,
}

/// A directive with a type name and parameters (`Shape "sphere" ...`).
#[derive(Clone, Debug, PartialEq)]
pub struct Entity {
    pub kind: String,
    pub params: Vec<Param>,
}

impl Entity {
    pub fn param(&self, name: &str) -> Option<&Param> {
        self.params.iter().find(|p| p.name == name)
    }
}

/// One directive, as written (after pbrt-v3 names are upgraded).
#[derive(Clone, Debug, PartialEq)]
pub enum Directive {
    Accelerator(Entity),
    ActiveTransform(ActiveTransform),
    AreaLightSource(Entity),
    /// `Attribute "shape"|"light"|"material"|"medium"|"texture" params`.
    Attribute(Entity),
    AttributeBegin,
    AttributeEnd,
    Camera(Entity),
    ColorSpace(String),
    ConcatTransform([f64; 16]),
    CoordinateSystem(String),
    CoordSysTransform(String),
    Film(Entity),
    Identity,
    /// Only produced when the parser does not follow includes.
    Include(String),
    /// Only produced when the parser does not follow includes.
    Import(String),
    Integrator(Entity),
    LightSource(Entity),
    LookAt([f64; 9]),
    /// `MakeNamedMaterial "name" params` (the type is the `string type` parameter).
    MakeNamedMaterial(Entity),
    /// `MakeNamedMedium "name" params`.
    MakeNamedMedium(Entity),
    Material(Entity),
    MediumInterface {
        inside: String,
        outside: String,
    },
    NamedMaterial(String),
    ObjectBegin(String),
    ObjectEnd,
    ObjectInstance(String),
    Option(Param),
    PixelFilter(Entity),
    ReverseOrientation,
    Rotate([f64; 4]),
    Sampler(Entity),
    Scale([f64; 3]),
    Shape(Entity),
    Texture {
        name: String,
        /// "float" or "spectrum".
        value_type: String,
        class: Entity,
    },
    Transform([f64; 16]),
    TransformTimes(f64, f64),
    Translate([f64; 3]),
    WorldBegin,
    /// pbrt-v3 only; ignored.
    WorldEnd,
}

/// A directive and where it starts.
#[derive(Clone, Debug)]
pub struct Located {
    pub directive: Directive,
    pub location: Location,
}

impl Directive {
    /// The directive's keyword.
    pub fn keyword(&self) -> &'static str {
        use Directive::*;
        match self {
            Accelerator(_) => "Accelerator",
            ActiveTransform(_) => "ActiveTransform",
            AreaLightSource(_) => "AreaLightSource",
            Attribute(_) => "Attribute",
            AttributeBegin => "AttributeBegin",
            AttributeEnd => "AttributeEnd",
            Camera(_) => "Camera",
            ColorSpace(_) => "ColorSpace",
            ConcatTransform(_) => "ConcatTransform",
            CoordinateSystem(_) => "CoordinateSystem",
            CoordSysTransform(_) => "CoordSysTransform",
            Film(_) => "Film",
            Identity => "Identity",
            Include(_) => "Include",
            Import(_) => "Import",
            Integrator(_) => "Integrator",
            LightSource(_) => "LightSource",
            LookAt(_) => "LookAt",
            MakeNamedMaterial(_) => "MakeNamedMaterial",
            MakeNamedMedium(_) => "MakeNamedMedium",
            Material(_) => "Material",
            MediumInterface { .. } => "MediumInterface",
            NamedMaterial(_) => "NamedMaterial",
            ObjectBegin(_) => "ObjectBegin",
            ObjectEnd => "ObjectEnd",
            ObjectInstance(_) => "ObjectInstance",
            Option(_) => "Option",
            PixelFilter(_) => "PixelFilter",
            ReverseOrientation => "ReverseOrientation",
            Rotate(_) => "Rotate",
            Sampler(_) => "Sampler",
            Scale(_) => "Scale",
            Shape(_) => "Shape",
            Texture { .. } => "Texture",
            Transform(_) => "Transform",
            TransformTimes(..) => "TransformTimes",
            Translate(_) => "Translate",
            WorldBegin => "WorldBegin",
            WorldEnd => "WorldEnd",
        }
    }
}

/// Writes a string with pbrt's escapes.
fn quote(out: &mut impl Write, s: &str) -> fmt::Result {
    out.write_char('"')?;
    for c in s.chars() {
        match c {
            '"' => out.write_str("\\\"")?,
            '\\' => out.write_str("\\\\")?,
            '\n' => out.write_str("\\n")?,
            '\t' => out.write_str("\\t")?,
            '\r' => out.write_str("\\r")?,
            c => out.write_char(c)?,
        }
    }
    out.write_char('"')
}

/// Shortest text that reads back as the same f64.
fn number(out: &mut impl Write, x: f64) -> fmt::Result {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        write!(out, "{}", x as i64)
    } else {
        write!(out, "{x}")
    }
}

fn numbers(out: &mut impl Write, xs: &[f64]) -> fmt::Result {
    for (i, &x) in xs.iter().enumerate() {
        if i > 0 {
            out.write_char(' ')?;
        }
        number(out, x)?;
    }
    Ok(())
}

impl fmt::Display for Param {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "\"{} {}\" [ ", self.ty.name(), self.name)?;
        match &self.values {
            Values::Numbers(v) => numbers(f, v)?,
            Values::Strings(v) => {
                for (i, s) in v.iter().enumerate() {
                    if i > 0 {
                        f.write_char(' ')?;
                    }
                    quote(f, s)?;
                }
            }
            Values::Bools(v) => {
                for (i, b) in v.iter().enumerate() {
                    if i > 0 {
                        f.write_char(' ')?;
                    }
                    write!(f, "{b}")?;
                }
            }
        }
        f.write_str(" ]")
    }
}

fn params(f: &mut fmt::Formatter<'_>, params: &[Param], indent: &str) -> fmt::Result {
    for p in params {
        write!(f, "\n{indent}    {p}")?;
    }
    Ok(())
}

impl Directive {
    /// Writes the directive in canonical pbrt-v4 syntax, indented by `indent`.
    pub fn write(&self, f: &mut fmt::Formatter<'_>, indent: &str) -> fmt::Result {
        use Directive::*;
        f.write_str(indent)?;
        f.write_str(self.keyword())?;
        match self {
            Accelerator(e) | AreaLightSource(e) | Camera(e) | Film(e) | Integrator(e)
            | LightSource(e) | Material(e) | PixelFilter(e) | Sampler(e) | Shape(e)
            | Attribute(e) | MakeNamedMaterial(e) | MakeNamedMedium(e) => {
                f.write_char(' ')?;
                quote(f, &e.kind)?;
                params(f, &e.params, indent)
            }
            ColorSpace(s) | CoordinateSystem(s) | CoordSysTransform(s) | Include(s)
            | Import(s) | NamedMaterial(s) | ObjectBegin(s) | ObjectInstance(s) => {
                f.write_char(' ')?;
                quote(f, s)
            }
            ActiveTransform(t) => write!(
                f,
                " {}",
                match t {
                    self::ActiveTransform::StartTime => "StartTime",
                    self::ActiveTransform::EndTime => "EndTime",
                    self::ActiveTransform::All => "All",
                }
            ),
            ConcatTransform(m) | Transform(m) => {
                f.write_str(" [ ")?;
                numbers(f, m)?;
                f.write_str(" ]")
            }
            LookAt(v) => {
                f.write_char(' ')?;
                numbers(f, v)
            }
            Rotate(v) => {
                f.write_char(' ')?;
                numbers(f, v)
            }
            Scale(v) | Translate(v) => {
                f.write_char(' ')?;
                numbers(f, v)
            }
            TransformTimes(a, b) => {
                f.write_char(' ')?;
                numbers(f, &[*a, *b])
            }
            MediumInterface { inside, outside } => {
                f.write_char(' ')?;
                quote(f, inside)?;
                f.write_char(' ')?;
                quote(f, outside)
            }
            // pbrt-v4 writes options as `Option "name" value`.
            Option(p) => {
                f.write_char(' ')?;
                quote(f, &p.name)?;
                let text = p.to_string();
                let values = text.split_once(" [ ").map_or("", |(_, v)| v.trim_end_matches(" ]"));
                write!(f, " {values}")
            }
            Texture {
                name,
                value_type,
                class,
            } => {
                f.write_char(' ')?;
                quote(f, name)?;
                f.write_char(' ')?;
                quote(f, value_type)?;
                f.write_char(' ')?;
                quote(f, &class.kind)?;
                params(f, &class.params, indent)
            }
            AttributeBegin | AttributeEnd | Identity | ObjectEnd | ReverseOrientation
            | WorldBegin | WorldEnd => Ok(()),
        }
    }
}

impl fmt::Display for Directive {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write(f, "")
    }
}
