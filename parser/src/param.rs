//! Parameter lists: `"type name" value` or `"type name" [ values ]`.

use crate::error::ErrorKind;
use crate::lexer::{self, describe, fail, LexError, PResult};
use crate::list::List;
use crate::location::Location;
use crate::name::Name;

/// The declared type of a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParamType {
    Integer,
    Float,
    Point2,
    Vector2,
    Point3,
    Vector3,
    Normal3,
    Bool,
    String,
    Texture,
    Rgb,
    Spectrum,
    Blackbody,
}

impl ParamType {
    /// The pbrt-v4 name, as printed by `--format`.
    pub fn name(self) -> &'static str {
        match self {
            ParamType::Integer => "integer",
            ParamType::Float => "float",
            ParamType::Point2 => "point2",
            ParamType::Vector2 => "vector2",
            ParamType::Point3 => "point3",
            ParamType::Vector3 => "vector3",
            ParamType::Normal3 => "normal",
            ParamType::Bool => "bool",
            ParamType::String => "string",
            ParamType::Texture => "texture",
            ParamType::Rgb => "rgb",
            ParamType::Spectrum => "spectrum",
            ParamType::Blackbody => "blackbody",
        }
    }

    /// Parses a pbrt-v4 type name; pbrt-v3 names come back with `true`
    /// (the caller warns that they were upgraded).
    pub fn from_name(name: &str) -> Option<(ParamType, bool)> {
        Some(match name {
            "integer" => (ParamType::Integer, false),
            "float" => (ParamType::Float, false),
            "point2" => (ParamType::Point2, false),
            "vector2" => (ParamType::Vector2, false),
            "point3" => (ParamType::Point3, false),
            "vector3" => (ParamType::Vector3, false),
            "normal" | "normal3" => (ParamType::Normal3, false),
            "bool" => (ParamType::Bool, false),
            "string" => (ParamType::String, false),
            "texture" => (ParamType::Texture, false),
            "rgb" => (ParamType::Rgb, false),
            "spectrum" => (ParamType::Spectrum, false),
            "blackbody" => (ParamType::Blackbody, false),
            // pbrt-v3 spellings.
            "point" => (ParamType::Point3, true),
            "vector" => (ParamType::Vector3, true),
            "color" => (ParamType::Rgb, true),
            _ => return None,
        })
    }

    /// The pbrt-v3 spelling that [`ParamType::from_name`] reads as this
    /// type, if there is one (for the upgrade's note).
    pub fn v3_name(self) -> Option<&'static str> {
        match self {
            ParamType::Point3 => Some("point"),
            ParamType::Vector3 => Some("vector"),
            ParamType::Rgb => Some("color"),
            _ => None,
        }
    }

    /// Number of values per element (3 for a point3), for numeric types.
    pub fn arity(self) -> usize {
        match self {
            ParamType::Point2 | ParamType::Vector2 => 2,
            ParamType::Point3 | ParamType::Vector3 | ParamType::Normal3 | ParamType::Rgb => 3,
            _ => 1,
        }
    }
}

/// The values of a parameter, as written (24 bytes, a single value
/// inline: a scene description holds millions of them). Strings are
/// shared names: a hair file's every curve says `"cylinder"`.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Numbers(List<f64>),
    Strings(List<Name>),
    Bools(List<bool>),
}

impl Values {
    pub fn len(&self) -> usize {
        match self {
            Values::Numbers(v) => v.len(),
            Values::Strings(v) => v.len(),
            Values::Bools(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One parameter of a directive (64 bytes: a hair file's description is
/// mostly these).
#[derive(Clone, Debug)]
pub struct Param {
    pub ty: ParamType,
    /// Whether the declaration used `ty`'s pbrt-v3 name
    /// ([`ParamType::v3_name`]: `point`, `vector`, `color`).
    pub v3_type: bool,
    pub name: Name,
    pub values: Values,
    /// Where the `"type name"` declaration starts.
    pub location: Location,
}

// The sizes promised above (on 64-bit targets), kept by the build.
#[cfg(target_pointer_width = "64")]
const _: () = assert!(std::mem::size_of::<Param>() == 64 && std::mem::size_of::<Values>() == 24);

impl PartialEq for Param {
    /// Parameters compare by meaning, not by where they were written.
    fn eq(&self, other: &Self) -> bool {
        self.ty == other.ty && self.name == other.name && self.values == other.values
    }
}

impl Param {
    pub fn numbers(&self) -> &[f64] {
        match &self.values {
            Values::Numbers(v) => v,
            _ => &[],
        }
    }

    pub fn strings(&self) -> &[Name] {
        match &self.values {
            Values::Strings(v) => v,
            _ => &[],
        }
    }

    pub fn bools(&self) -> &[bool] {
        match &self.values {
            Values::Bools(v) => v,
            _ => &[],
        }
    }
}

/// Splits a `"type name"` declaration (any whitespace, tabs included, around
/// and between the two words).
pub fn split_declaration(declaration: &str) -> Option<(&str, &str)> {
    let mut words = declaration.split_ascii_whitespace();
    let ty = words.next()?;
    let name = words.next()?;
    if words.next().is_some() {
        return None;
    }
    Some((ty, name))
}

/// A value list: either one bare value or `[ ... ]`. All values of one kind.
pub fn value_list(input: &[u8]) -> PResult<'_, Values> {
    let input = lexer::skip_space(input);
    match input.first() {
        Some(b'[') => bracketed_values(input),
        Some(b'"') => {
            let (rest, s) = lexer::quoted_string(input)?;
            Ok((rest, Values::Strings(List::one(Name::new(&s)))))
        }
        Some(_) if lexer::starts_number(input) => {
            let (rest, x) = lexer::number(input)?;
            Ok((rest, Values::Numbers(List::one(x))))
        }
        Some(_) => match boolean(input) {
            Some((rest, b)) => Ok((rest, Values::Bools(List::one(b)))),
            None => fail(
                input,
                ErrorKind::Expected {
                    expected: "a value or '['",
                    found: describe(input),
                },
            ),
        },
        None => fail(input, ErrorKind::UnexpectedEof("a value or '['")),
    }
}

/// A bare `true` or `false`.
fn boolean(input: &[u8]) -> Option<(&[u8], bool)> {
    let (rest, w) = lexer::word(input).ok()?;
    match w {
        b"true" => Some((rest, true)),
        b"false" => Some((rest, false)),
        _ => None,
    }
}

/// `[ ... ]`; `open` starts at the `[` (where an unclosed list is reported).
fn bracketed_values(open: &[u8]) -> PResult<'_, Values> {
    let rest = lexer::skip_space(&open[1..]);
    // The first element decides the kind of the list.
    match rest.first() {
        Some(b']') => Ok((&rest[1..], Values::Numbers(List::empty()))),
        Some(b'"') => {
            let (rest, v) = listed(open, rest, "strings", |r| {
                if r[0] != b'"' {
                    return Ok((r, None));
                }
                lexer::quoted_string(r).map(|(r, s)| (r, Some(Name::new(&s))))
            })?;
            Ok((rest, Values::Strings(v)))
        }
        Some(b't' | b'f') => {
            let (rest, v) = listed(open, rest, "bools (true or false)", |r| {
                Ok(boolean(r).map_or((r, None), |(r, b)| (r, Some(b))))
            })?;
            Ok((rest, Values::Bools(v)))
        }
        _ => bracketed_numbers(open, rest),
    }
}

/// The values of a list of strings or bools, `value` reading one (`None`
/// when the text is not one); `rest` is past the `[` that `open` starts at.
/// A list of one (a curve's `"string type" [ "cylinder" ]`) allocates no
/// vector.
fn listed<'a, T>(
    open: &'a [u8],
    mut rest: &'a [u8],
    expected: &'static str,
    value: impl Fn(&'a [u8]) -> PResult<'a, Option<T>>,
) -> PResult<'a, List<T>> {
    let mut first = None;
    let mut all = Vec::new();
    loop {
        match rest.first() {
            Some(b']') => {
                let list = match first {
                    Some(one) => List::one(one),
                    None => List::from(all),
                };
                return Ok((&rest[1..], list));
            }
            None => return fail(open, unclosed_bracket(open)),
            _ => {}
        }
        match value(rest)? {
            (r, Some(v)) => {
                match first.take() {
                    None if all.is_empty() => first = Some(v),
                    None => all.push(v),
                    Some(one) => all.extend([one, v]),
                }
                rest = lexer::skip_space(r);
            }
            (_, None) => return fail(rest, mixed_or_bad(open, rest, expected)),
        }
    }
}

/// Numbers up to this many are gathered on the stack, so that a list's one
/// allocation is its final, exact one (a curve's `P` has 12).
const STACK_NUMBERS: usize = 32;

/// A list of numbers; `rest` is past the `[` that `open` starts at.
fn bracketed_numbers<'a>(open: &'a [u8], mut rest: &'a [u8]) -> PResult<'a, Values> {
    let mut first = [0.0; STACK_NUMBERS];
    let mut count = 0;
    // The numbers past the first `STACK_NUMBERS`, all of them once there
    // are more.
    let mut all: Vec<f64> = Vec::new();
    loop {
        match rest.first() {
            Some(b']') => break,
            None => return fail(open, unclosed_bracket(open)),
            _ => {}
        }
        if !lexer::starts_number(rest) {
            return fail(rest, mixed_or_bad(open, rest, "numbers"));
        }
        let (r, x) = lexer::number(rest)?;
        if count < STACK_NUMBERS {
            first[count] = x;
        } else {
            if all.is_empty() {
                all.reserve(4 * STACK_NUMBERS);
                all.extend_from_slice(&first);
            }
            all.push(x);
        }
        count += 1;
        rest = lexer::skip_space(r);
    }
    let values = if count <= STACK_NUMBERS {
        List::from(&first[..count])
    } else {
        List::from(all)
    };
    Ok((&rest[1..], Values::Numbers(values)))
}

/// The error for a `[` (starting `open`) that the input ends inside.
pub(crate) fn unclosed_bracket(open: &[u8]) -> ErrorKind {
    ErrorKind::UnclosedBracket { to_end: open.len() }
}

/// Something other than a value or `]` at `input` inside the list `open`
/// starts: a value of another kind, or no value at all.
pub(crate) fn not_in_list(open: &[u8], input: &[u8], expected: &'static str) -> ErrorKind {
    ErrorKind::NotInList {
        expected,
        found: describe(input),
        back: open.len() - input.len(),
    }
}

fn mixed_or_bad(open: &[u8], input: &[u8], expected: &'static str) -> ErrorKind {
    let looks_like_value =
        input[0] == b'"' || lexer::starts_number(input) || boolean(input).is_some();
    if looks_like_value {
        ErrorKind::MixedValues { expected }
    } else {
        not_in_list(open, input, "a value or ']'")
    }
}

/// Checks a parameter's values against its declared type: kind, count,
/// integrality. Returns the error kind to report at the declaration.
pub fn validate(ty: ParamType, name: &str, values: &mut Values) -> Result<(), ErrorKind> {
    let tyname = ty.name();
    let wrong_kind = |expected| ErrorKind::WrongValueKind {
        ty: tyname,
        name: name.to_string(),
        expected,
    };
    // An empty list `[ ]` is a list of whatever kind is wanted.
    if values.is_empty() {
        *values = match ty {
            ParamType::Bool => Values::Bools(List::empty()),
            ParamType::String | ParamType::Texture => Values::Strings(List::empty()),
            _ => Values::Numbers(List::empty()),
        };
    }
    match (ty, &*values) {
        (ParamType::Bool, Values::Bools(_)) => Ok(()),
        // pbrt-v4 also accepts quoted "true" / "false" for bools.
        (ParamType::Bool, Values::Strings(s)) => {
            let bools: Option<List<bool>> = s
                .iter()
                .map(|s| match s.as_str() {
                    "true" => Some(true),
                    "false" => Some(false),
                    _ => None,
                })
                .collect();
            *values = Values::Bools(bools.ok_or_else(|| wrong_kind("bool (true or false)"))?);
            Ok(())
        }
        (ParamType::Bool, _) => Err(wrong_kind("bool (true or false)")),
        (ParamType::String | ParamType::Texture, Values::Strings(_)) => Ok(()),
        (ParamType::String | ParamType::Texture, _) => Err(wrong_kind("string")),
        (ParamType::Spectrum, Values::Strings(s)) if s.len() == 1 => Ok(()),
        (ParamType::Spectrum, Values::Strings(_)) => {
            Err(wrong_kind("one named spectrum or file name, or λ/value"))
        }
        (ParamType::Spectrum, Values::Numbers(v)) => {
            if v.len() % 2 != 0 {
                Err(ErrorKind::WrongValueCount {
                    ty: tyname,
                    name: name.to_string(),
                    count: v.len(),
                    multiple: 2,
                })
            } else {
                Ok(())
            }
        }
        (_, Values::Numbers(v)) => {
            if ty == ParamType::Integer {
                if let Some(&bad) = v
                    .iter()
                    .find(|x| x.fract() != 0.0 || x.abs() > i32::MAX as f64)
                {
                    return Err(ErrorKind::NonIntegerValue {
                        name: name.to_string(),
                        value: bad,
                    });
                }
            }
            if v.len() % ty.arity() != 0 {
                return Err(ErrorKind::WrongValueCount {
                    ty: tyname,
                    name: name.to_string(),
                    count: v.len(),
                    multiple: ty.arity(),
                });
            }
            Ok(())
        }
        (_, _) => Err(wrong_kind("numeric")),
    }
}

/// A parsed declaration: remaining input, type, name, values, and whether
/// the type was written with its pbrt-v3 name.
pub type Declaration<'a> = (&'a [u8], ParamType, Name, Values, bool);

/// Parses a `"type name"` declaration and its values.
pub fn declaration_and_values(input: &[u8]) -> Result<Declaration<'_>, nom::Err<LexError<'_>>> {
    let start = input;
    let (rest, declaration) = lexer::quoted_string(input)?;
    let Some((tyname, name)) = split_declaration(&declaration) else {
        return Err(nom::Err::Failure(LexError::new(
            start,
            ErrorKind::MalformedDeclaration(declaration.into_owned()),
        )));
    };
    let Some((ty, is_v3)) = ParamType::from_name(tyname) else {
        return Err(nom::Err::Failure(LexError::new(
            start,
            ErrorKind::UnknownParameterType {
                ty: tyname.to_string(),
                name: name.to_string(),
            },
        )));
    };
    let (rest, mut values) = value_list(rest)?;
    validate(ty, name, &mut values)
        .map_err(|kind| nom::Err::Failure(LexError::new(start, kind)))?;
    Ok((rest, ty, Name::new(name), values, is_v3))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<(ParamType, Name, Values), ErrorKind> {
        match declaration_and_values(text.as_bytes()) {
            Ok((_, ty, name, values, _)) => Ok((ty, name, values)),
            Err(nom::Err::Failure(e) | nom::Err::Error(e)) => Err(e.kind),
            Err(e) => panic!("{e:?}"),
        }
    }

    #[test]
    fn declarations_with_any_whitespace() {
        let (ty, name, values) = parse("\"float\tradius \" 2").unwrap();
        assert_eq!((ty, name.as_str()), (ParamType::Float, "radius"));
        assert_eq!(values, Values::Numbers(List::one(2.0)));
        let (ty, _, values) = parse("\" point3  P\" [ 1 2 3 4 5 6 ]").unwrap();
        assert_eq!(ty, ParamType::Point3);
        assert_eq!(values.len(), 6);
    }

    #[test]
    fn bools_bare_or_quoted() {
        assert_eq!(
            parse("\"bool b\" true").unwrap().2,
            Values::Bools(List::one(true))
        );
        assert_eq!(
            parse("\"bool b\" [ \"false\" ]").unwrap().2,
            Values::Bools(List::one(false))
        );
        assert!(parse("\"bool b\" 1").is_err());
    }

    #[test]
    fn wrong_counts_and_kinds() {
        assert!(matches!(
            parse("\"point3 P\" [1 2 3 4]"),
            Err(ErrorKind::WrongValueCount {
                count: 4,
                multiple: 3,
                ..
            })
        ));
        assert!(matches!(
            parse("\"integer n\" 1.5"),
            Err(ErrorKind::NonIntegerValue { .. })
        ));
        assert!(matches!(
            parse("\"float x\" \"a\""),
            Err(ErrorKind::WrongValueKind { .. })
        ));
        assert!(matches!(
            parse("\"float x\" [1 \"a\"]"),
            Err(ErrorKind::MixedValues { .. })
        ));
        assert!(matches!(
            parse("\"floaty x\" 1"),
            Err(ErrorKind::UnknownParameterType { .. })
        ));
        assert!(matches!(
            parse("\"float\" 1"),
            Err(ErrorKind::MalformedDeclaration(_))
        ));
        assert!(matches!(
            parse("\"spectrum s\" [300 1 400]"),
            Err(ErrorKind::WrongValueCount { .. })
        ));
    }

    #[test]
    fn v3_types_map_to_v4() {
        let (ty, _, _) = parse("\"color Kd\" [.5 .5 .5]").unwrap();
        assert_eq!(ty, ParamType::Rgb);
    }
}
