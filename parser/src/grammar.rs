//! The directive grammar: a keyword and its arguments.

use crate::directive::{ActiveTransform, Directive, Entity};
use crate::error::ErrorKind;
use crate::lexer::{self, describe, fail, LexError, PResult};
use crate::location::Location;
use crate::param::{self, Param};
use std::borrow::Cow;

/// Builds the location of a position (the remaining input) in the buffer.
pub(crate) type Locate<'l> = dyn Fn(&[u8]) -> Location + 'l;

/// Parses one directive at the start of `input` (no leading space).
pub(crate) fn directive<'a>(input: &'a [u8], locate: &Locate<'_>) -> PResult<'a, Directive> {
    let (rest, keyword) = match lexer::word(input) {
        Ok(ok) => ok,
        Err(_) => {
            let kind = if input.first() == Some(&b'"')
                || lexer::starts_number(input)
                || input.first() == Some(&b'[')
            {
                ErrorKind::Expected {
                    expected: "a directive",
                    found: describe(input),
                }
            } else {
                ErrorKind::UnknownDirective(describe(input).trim_matches('"').to_string())
            };
            return fail(input, kind);
        }
    };
    if !rest.first().is_none_or(|&b| lexer::is_delimiter(b)) {
        let end = input
            .iter()
            .position(|&b| lexer::is_delimiter(b))
            .unwrap_or(input.len());
        return fail(
            input,
            ErrorKind::UnknownDirective(String::from_utf8_lossy(&input[..end]).into_owned()),
        );
    }
    use Directive as D;
    let entity_of = |make: fn(Entity) -> Directive| -> PResult<'a, Directive> {
        let (rest, e) = entity(rest, locate)?;
        Ok((rest, make(e)))
    };
    let string = |make: fn(String) -> Directive| -> PResult<'a, Directive> {
        let (rest, s) = string_argument(rest)?;
        Ok((rest, make(s.into_owned())))
    };
    match keyword {
        b"Accelerator" => entity_of(D::Accelerator),
        b"ActiveTransform" => {
            let r = lexer::skip_space(rest);
            let (r2, w) = lexer::word(r).map_err(|_| expected(r, "StartTime, EndTime or All"))?;
            let t = match w {
                b"StartTime" => ActiveTransform::StartTime,
                b"EndTime" => ActiveTransform::EndTime,
                b"All" => ActiveTransform::All,
                _ => return Err(expected(r, "StartTime, EndTime or All")),
            };
            Ok((r2, D::ActiveTransform(t)))
        }
        b"AreaLightSource" => entity_of(D::AreaLightSource),
        b"Attribute" => entity_of(D::Attribute),
        b"AttributeBegin" => Ok((rest, D::AttributeBegin)),
        b"AttributeEnd" => Ok((rest, D::AttributeEnd)),
        b"Camera" => entity_of(D::Camera),
        b"ColorSpace" => string(D::ColorSpace),
        b"ConcatTransform" => {
            let (r, m) = fixed_numbers::<16>(input, rest, "ConcatTransform")?;
            Ok((r, D::ConcatTransform(m)))
        }
        b"CoordinateSystem" => string(D::CoordinateSystem),
        b"CoordSysTransform" => string(D::CoordSysTransform),
        b"Film" => entity_of(D::Film),
        b"Identity" => Ok((rest, D::Identity)),
        b"Include" => string(D::Include),
        b"Import" => string(D::Import),
        b"Integrator" => entity_of(D::Integrator),
        b"LightSource" => entity_of(D::LightSource),
        b"LookAt" => {
            let (r, v) = fixed_numbers::<9>(input, rest, "LookAt")?;
            Ok((r, D::LookAt(v)))
        }
        b"MakeNamedMaterial" => entity_of(D::MakeNamedMaterial),
        b"MakeNamedMedium" => entity_of(D::MakeNamedMedium),
        b"Material" => entity_of(D::Material),
        b"MediumInterface" => {
            let (r, inside) = string_argument(rest)?;
            let r1 = lexer::skip_space(r);
            if r1.first() == Some(&b'"') {
                let (r2, outside) = lexer::quoted_string(r1)?;
                Ok((
                    r2,
                    D::MediumInterface {
                        inside: inside.into_owned(),
                        outside: outside.into_owned(),
                    },
                ))
            } else {
                Ok((
                    r,
                    D::MediumInterface {
                        outside: inside.to_string(),
                        inside: inside.into_owned(),
                    },
                ))
            }
        }
        b"NamedMaterial" => string(D::NamedMaterial),
        b"ObjectBegin" => string(D::ObjectBegin),
        b"ObjectEnd" => Ok((rest, D::ObjectEnd)),
        b"ObjectInstance" => string(D::ObjectInstance),
        b"Option" => {
            let r = lexer::skip_space(rest);
            let (_, declaration) = string_argument(r)?;
            if declaration.split_ascii_whitespace().count() == 1 {
                let (r2, p) = untyped_option(r, locate)?;
                return Ok((r2, D::Option(p)));
            }
            let p = param(r, locate)?;
            Ok((p.0, D::Option(p.1)))
        }
        b"PixelFilter" => entity_of(D::PixelFilter),
        b"ReverseOrientation" => Ok((rest, D::ReverseOrientation)),
        b"Rotate" => {
            let (r, v) = fixed_numbers::<4>(input, rest, "Rotate")?;
            Ok((r, D::Rotate(v)))
        }
        b"Sampler" => entity_of(D::Sampler),
        b"Scale" => {
            let (r, v) = fixed_numbers::<3>(input, rest, "Scale")?;
            Ok((r, D::Scale(v)))
        }
        b"Shape" => entity_of(D::Shape),
        b"Texture" => {
            let (r, name) = string_argument(rest)?;
            let (r, value_type) = string_argument(r)?;
            let (r, class) = entity(r, locate)?;
            Ok((
                r,
                D::Texture {
                    name: name.into_owned(),
                    value_type: value_type.into_owned(),
                    class,
                },
            ))
        }
        b"Transform" => {
            let (r, m) = fixed_numbers::<16>(input, rest, "Transform")?;
            Ok((r, D::Transform(m)))
        }
        // Deprecated; pbrt-v4 treats them as AttributeBegin/End (the parser
        // warns).
        b"TransformBegin" => Ok((rest, D::AttributeBegin)),
        b"TransformEnd" => Ok((rest, D::AttributeEnd)),
        b"TransformTimes" => {
            let (r, [a, b]) = fixed_numbers::<2>(input, rest, "TransformTimes")?;
            Ok((r, D::TransformTimes(a, b)))
        }
        b"Translate" => {
            let (r, v) = fixed_numbers::<3>(input, rest, "Translate")?;
            Ok((r, D::Translate(v)))
        }
        b"WorldBegin" => Ok((rest, D::WorldBegin)),
        b"WorldEnd" => Ok((rest, D::WorldEnd)),
        other => fail(
            input,
            ErrorKind::UnknownDirective(String::from_utf8_lossy(other).into_owned()),
        ),
    }
}

fn expected<'a>(input: &'a [u8], what: &'static str) -> nom::Err<LexError<'a>> {
    let kind = if input.is_empty() {
        ErrorKind::UnexpectedEof(what)
    } else {
        ErrorKind::Expected {
            expected: what,
            found: describe(input),
        }
    };
    nom::Err::Failure(LexError::new(input, kind))
}

/// A quoted string argument (after optional space).
fn string_argument(input: &[u8]) -> PResult<'_, Cow<'_, str>> {
    let input = lexer::skip_space(input);
    if input.first() != Some(&b'"') {
        return Err(expected(input, "a quoted string"));
    }
    lexer::quoted_string(input)
}

/// `N` numbers, bare or in brackets. A wrong count is reported at the
/// directive (`keyword` is where it starts).
fn fixed_numbers<'a, const N: usize>(
    keyword: &'a [u8],
    input: &'a [u8],
    directive: &'static str,
) -> PResult<'a, [f64; N]> {
    let mut rest = lexer::skip_space(input);
    let open = rest;
    let bracketed = rest.first() == Some(&b'[');
    if bracketed {
        rest = lexer::skip_space(&rest[1..]);
    }
    let mut values = [0.0; N];
    let mut found = 0;
    while lexer::starts_number(rest) {
        let (r, x) = lexer::number(rest)?;
        if found < N {
            values[found] = x;
        }
        found += 1;
        rest = lexer::skip_space(r);
    }
    if bracketed {
        if rest.is_empty() {
            return fail(open, param::unclosed_bracket(open));
        }
        if rest.first() != Some(&b']') {
            return fail(rest, param::not_in_list(open, rest, "a number or ']'"));
        }
        rest = &rest[1..];
    }
    if found != N {
        return fail(
            keyword,
            ErrorKind::WrongArgumentCount {
                directive,
                expected: N,
                found,
            },
        );
    }
    Ok((rest, values))
}

/// `"type"` then a parameter list.
fn entity<'a>(input: &'a [u8], locate: &Locate<'_>) -> PResult<'a, Entity> {
    let (rest, kind) = string_argument(input)?;
    let (rest, params) = param_list(rest, locate)?;
    Ok((
        rest,
        Entity {
            kind: kind.into_owned(),
            params,
        },
    ))
}

/// Parameters for as long as the next token is a quoted string.
pub(crate) fn param_list<'a>(mut input: &'a [u8], locate: &Locate<'_>) -> PResult<'a, Vec<Param>> {
    let mut params = Vec::new();
    loop {
        let r = lexer::skip_space(input);
        if r.first() != Some(&b'"') {
            return Ok((input, params));
        }
        let (r, p) = param(r, locate)?;
        params.push(p);
        input = r;
    }
}

/// pbrt-v4's own form, `Option "name" value`: the type follows the value
/// (a whole number is an integer).
fn untyped_option<'a>(input: &'a [u8], locate: &Locate<'_>) -> PResult<'a, Param> {
    use crate::param::{ParamType, Values};
    let (rest, name) = lexer::quoted_string(input)?;
    let (rest, values) = param::value_list(rest)?;
    let ty = match &values {
        Values::Numbers(v) if v.iter().all(|x| x.fract() == 0.0) => ParamType::Integer,
        Values::Numbers(_) => ParamType::Float,
        Values::Strings(_) => ParamType::String,
        Values::Bools(_) => ParamType::Bool,
    };
    Ok((
        rest,
        Param {
            ty,
            v3_type: false,
            name: crate::Name::new(name.trim()),
            values,
            location: locate(input),
        },
    ))
}

fn param<'a>(input: &'a [u8], locate: &Locate<'_>) -> PResult<'a, Param> {
    let (rest, ty, name, values, v3_type) = param::declaration_and_values(input)?;
    Ok((
        rest,
        Param {
            ty,
            v3_type,
            name,
            values,
            location: locate(input),
        },
    ))
}
