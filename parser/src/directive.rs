//! The directives of a pbrt scene file, and their canonical pbrt-v4 text.

use crate::location::Location;
use crate::param::{Param, Values};
use std::fmt;

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

/// Appends a string with pbrt's escapes.
fn quote(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c => out.push(c),
        }
    }
    out.push('"');
}

/// Shortest text that reads back as the same f64 (ryu/itoa: printing is
/// most of `--format`'s time on a hair file).
fn number(out: &mut String, x: f64) {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        out.push_str(itoa::Buffer::new().format(x as i64))
    } else {
        out.push_str(ryu::Buffer::new().format(x))
    }
}

fn numbers(out: &mut String, xs: &[f64]) {
    for (i, &x) in xs.iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        number(out, x);
    }
}

impl Param {
    /// Appends the values, space-separated, without brackets.
    fn write_values(&self, out: &mut String) {
        match &self.values {
            Values::Numbers(v) => numbers(out, v),
            Values::Strings(v) => {
                for (i, s) in v.iter().enumerate() {
                    if i > 0 {
                        out.push(' ');
                    }
                    quote(out, s);
                }
            }
            Values::Bools(v) => {
                for (i, b) in v.iter().enumerate() {
                    if i > 0 {
                        out.push(' ');
                    }
                    out.push_str(if *b { "true" } else { "false" });
                }
            }
        }
    }

    /// Appends `"type name" [ values ]`.
    pub fn write_to(&self, out: &mut String) {
        out.push('"');
        out.push_str(self.ty.name());
        out.push(' ');
        out.push_str(&self.name);
        out.push_str("\" [ ");
        self.write_values(out);
        out.push_str(" ]");
    }
}

impl fmt::Display for Param {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut out = String::new();
        self.write_to(&mut out);
        f.write_str(&out)
    }
}

fn params(out: &mut String, params: &[Param], indent: &str) {
    for p in params {
        out.push('\n');
        out.push_str(indent);
        out.push_str("    ");
        p.write_to(out);
    }
}

impl Directive {
    /// Appends the directive in canonical pbrt-v4 syntax, indented by
    /// `indent` (no final newline).
    pub fn write_to(&self, out: &mut String, indent: &str) {
        use Directive::*;
        out.push_str(indent);
        out.push_str(self.keyword());
        match self {
            Accelerator(e) | AreaLightSource(e) | Camera(e) | Film(e) | Integrator(e)
            | LightSource(e) | Material(e) | PixelFilter(e) | Sampler(e) | Shape(e)
            | Attribute(e) | MakeNamedMaterial(e) | MakeNamedMedium(e) => {
                out.push(' ');
                quote(out, &e.kind);
                params(out, &e.params, indent);
            }
            ColorSpace(s) | CoordinateSystem(s) | CoordSysTransform(s) | Include(s) | Import(s)
            | NamedMaterial(s) | ObjectBegin(s) | ObjectInstance(s) => {
                out.push(' ');
                quote(out, s);
            }
            ActiveTransform(t) => out.push_str(match t {
                self::ActiveTransform::StartTime => " StartTime",
                self::ActiveTransform::EndTime => " EndTime",
                self::ActiveTransform::All => " All",
            }),
            ConcatTransform(m) | Transform(m) => {
                out.push_str(" [ ");
                numbers(out, m);
                out.push_str(" ]");
            }
            LookAt(v) => {
                out.push(' ');
                numbers(out, v);
            }
            Rotate(v) => {
                out.push(' ');
                numbers(out, v);
            }
            Scale(v) | Translate(v) => {
                out.push(' ');
                numbers(out, v);
            }
            TransformTimes(a, b) => {
                out.push(' ');
                numbers(out, &[*a, *b]);
            }
            MediumInterface { inside, outside } => {
                out.push(' ');
                quote(out, inside);
                out.push(' ');
                quote(out, outside);
            }
            // pbrt-v4 writes options as `Option "name" value`.
            Option(p) => {
                out.push(' ');
                quote(out, &p.name);
                out.push(' ');
                if p.values.len() == 1 {
                    p.write_values(out);
                } else {
                    out.push_str("[ ");
                    p.write_values(out);
                    out.push_str(" ]");
                }
            }
            Texture {
                name,
                value_type,
                class,
            } => {
                out.push(' ');
                quote(out, name);
                out.push(' ');
                quote(out, value_type);
                out.push(' ');
                quote(out, &class.kind);
                params(out, &class.params, indent);
            }
            AttributeBegin | AttributeEnd | Identity | ObjectEnd | ReverseOrientation
            | WorldBegin | WorldEnd => {}
        }
    }
}

impl fmt::Display for Directive {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut out = String::new();
        self.write_to(&mut out, "");
        f.write_str(&out)
    }
}
