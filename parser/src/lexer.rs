//! Tokens: whitespace and `#` comments, quoted strings, numbers, bare words
//! and brackets.
//!
//! Small nom parsers over bytes. Whitespace skipping and numbers are the hot
//! path of a large scene (hair files are mostly numbers), so those two are
//! written as tight loops, with numbers converted by `fast-float2`.

use crate::error::ErrorKind;
use nom::bytes::complete::take_while1;
use nom::IResult;
use std::borrow::Cow;

/// A lexical error: where (the remaining input) and what.
#[derive(Debug, PartialEq)]
pub struct LexError<'a> {
    pub input: &'a [u8],
    pub kind: ErrorKind,
}

impl<'a> LexError<'a> {
    pub fn new(input: &'a [u8], kind: ErrorKind) -> Self {
        LexError { input, kind }
    }
}

impl<'a> nom::error::ParseError<&'a [u8]> for LexError<'a> {
    fn from_error_kind(input: &'a [u8], _kind: nom::error::ErrorKind) -> Self {
        LexError::new(
            input,
            ErrorKind::Expected {
                expected: "a token",
                found: describe(input),
            },
        )
    }
    fn append(_: &'a [u8], _: nom::error::ErrorKind, other: Self) -> Self {
        other
    }
}

pub type PResult<'a, T> = IResult<&'a [u8], T, LexError<'a>>;

/// A `nom::Err::Failure` (no backtracking: the error is final).
pub fn fail<T>(input: &[u8], kind: ErrorKind) -> PResult<'_, T> {
    Err(nom::Err::Failure(LexError::new(input, kind)))
}

/// A short description of what starts `input`, for "expected X, found Y".
pub fn describe(input: &[u8]) -> String {
    let input = skip_space(input);
    if input.is_empty() {
        return "end of file".to_string();
    }
    let end = input
        .iter()
        .position(|&b| is_delimiter(b))
        .unwrap_or(input.len())
        .clamp(1, 40);
    format!("\"{}\"", String::from_utf8_lossy(&input[..end]))
}

/// Bytes that end a bare word or number.
#[inline]
pub fn is_delimiter(b: u8) -> bool {
    matches!(
        b,
        b' ' | b'\t' | b'\n' | b'\r' | b'\x0b' | b'\x0c' | b'[' | b']' | b'"' | b'#'
    )
}

/// Skips whitespace and `#` comments (to the end of the line).
#[inline]
pub fn skip_space(mut input: &[u8]) -> &[u8] {
    loop {
        match input.first() {
            Some(b' ' | b'\t' | b'\n' | b'\r' | b'\x0b' | b'\x0c') => input = &input[1..],
            Some(b'#') => {
                let end = input
                    .iter()
                    .position(|&b| b == b'\n' || b == b'\r')
                    .unwrap_or(input.len());
                input = &input[end..];
            }
            _ => return input,
        }
    }
}

/// A bare word: a directive name, or `true`/`false`.
pub fn word(input: &[u8]) -> PResult<'_, &[u8]> {
    take_while1(|b: u8| b.is_ascii_alphanumeric() || b == b'_')(input)
}

/// A quoted string, with pbrt's backslash escapes (`\n \t \r \b \f \\ \"`
/// and `\` before a newline, the one way a string spans lines). Borrowed from
/// the input unless it has escapes: most strings are names looked up or
/// interned at once, and a scene of a million curves has millions of them.
pub fn quoted_string(input: &[u8]) -> PResult<'_, Cow<'_, str>> {
    let Some(rest) = input.strip_prefix(b"\"") else {
        return Err(nom::Err::Error(LexError::new(
            input,
            ErrorKind::Expected {
                expected: "a quoted string",
                found: describe(input),
            },
        )));
    };
    // Fast path: no escapes.
    let end = rest
        .iter()
        .position(|&b| b == b'"' || b == b'\\' || b == b'\n' || b == b'\r');
    match end {
        Some(n) if rest[n] == b'"' => {
            let text = std::str::from_utf8(&rest[..n])
                .map_err(|_| nom::Err::Failure(LexError::new(input, ErrorKind::InvalidUtf8)))?;
            Ok((&rest[n + 1..], Cow::Borrowed(text)))
        }
        Some(n) if rest[n] == b'\\' => escaped_string(input, rest),
        _ => fail(input, ErrorKind::UnterminatedString),
    }
}

fn escaped_string<'a>(start: &'a [u8], mut rest: &'a [u8]) -> PResult<'a, Cow<'a, str>> {
    let mut bytes = Vec::new();
    loop {
        match rest {
            [b'"', tail @ ..] => {
                let text = String::from_utf8(bytes)
                    .map_err(|_| nom::Err::Failure(LexError::new(start, ErrorKind::InvalidUtf8)))?;
                return Ok((tail, Cow::Owned(text)));
            }
            [b'\\', c, tail @ ..] => {
                bytes.push(match c {
                    b'n' => b'\n',
                    b't' => b'\t',
                    b'r' => b'\r',
                    b'b' => 8,
                    b'f' => 12,
                    other => *other,
                });
                rest = tail;
            }
            [b'\n' | b'\r', ..] | [] | [b'\\'] => {
                return fail(start, ErrorKind::UnterminatedString)
            }
            [c, tail @ ..] => {
                bytes.push(*c);
                rest = tail;
            }
        }
    }
}

#[inline]
fn is_number_byte(b: u8) -> bool {
    b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E')
}

/// Whether `input` starts like a number (`-.5`, `+2`, `1e-3`, `.5`).
#[inline]
pub fn starts_number(input: &[u8]) -> bool {
    matches!(input.first(), Some(b) if b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+'))
}

/// A number in any form pbrt accepts. The whole token (up to a delimiter)
/// must be a number: `1.5x` and `nan` are errors, not `1.5` then `x`.
#[inline]
pub fn number(input: &[u8]) -> PResult<'_, f64> {
    if let Some((len, value)) = plain_decimal(input) {
        if input.get(len).is_none_or(|&b| is_delimiter(b)) {
            return Ok((&input[len..], value));
        }
    }
    let len = input
        .iter()
        .position(|&b| !is_number_byte(b))
        .unwrap_or(input.len());
    let token_end = input[len..]
        .iter()
        .position(|&b| is_delimiter(b))
        .map_or(input.len(), |p| len + p);
    if len == 0 || token_end != len {
        return bad_number(input, token_end);
    }
    match fast_float2::parse::<f64, _>(&input[..len]) {
        Ok(value) if value.is_finite() => Ok((&input[len..], value)),
        _ => bad_number(input, token_end),
    }
}

/// Most digits [`plain_decimal`] reads: below 2⁵³, so the digits are an
/// exact `f64`.
const PLAIN_DIGITS: u32 = 15;

/// Powers of ten up to 10^[`PLAIN_DIGITS`], each an exact `f64`.
const POWERS_OF_TEN: [f64; PLAIN_DIGITS as usize + 1] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// The number at the start of `input` and its length, when it is written
/// as scene files mostly write them: a sign, digits and a decimal point, no
/// exponent, at most [`PLAIN_DIGITS`] digits (else `None`, and
/// [`number`] reads it in full). The digits and the power of ten are then
/// both exact, and one correctly rounded division gives the correctly
/// rounded value (Clinger 1990, "How to read floating point numbers
/// accurately"): bit for bit what `fast_float2` returns, in one pass over
/// the bytes instead of two and its own. Numbers are two thirds of a curve
/// file's bytes, and reading them was a quarter of its parse.
#[inline]
fn plain_decimal(input: &[u8]) -> Option<(usize, f64)> {
    let (negative, mut i) = match input.first() {
        Some(b'-') => (true, 1),
        Some(b'+') => (false, 1),
        _ => (false, 0),
    };
    let mut digits: u64 = 0;
    let (mut count, mut fraction) = (0u32, None);
    while let Some(&b) = input.get(i) {
        if b.is_ascii_digit() {
            if count == PLAIN_DIGITS {
                return None;
            }
            digits = digits * 10 + u64::from(b - b'0');
            count += 1;
        } else if b == b'.' && fraction.is_none() {
            fraction = Some(count);
        } else {
            break;
        }
        i += 1;
    }
    if count == 0 {
        return None;
    }
    let magnitude = digits as f64 / POWERS_OF_TEN[(count - fraction.unwrap_or(count)) as usize];
    Some((i, if negative { -magnitude } else { magnitude }))
}

fn bad_number(input: &[u8], token_end: usize) -> PResult<'_, f64> {
    let token = String::from_utf8_lossy(&input[..token_end.max(1).min(input.len())]).into_owned();
    fail(input, ErrorKind::BadNumber(token))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_every_form() {
        for (text, value) in [
            ("-.5", -0.5),
            ("1e-3", 1e-3),
            ("+2", 2.0),
            ("5.", 5.0),
            (".25", 0.25),
            ("-1.5E+2", -150.0),
            ("42", 42.0),
        ] {
            assert_eq!(number(text.as_bytes()).unwrap().1, value, "{text}");
        }
        let (rest, v) = number(b"3]").unwrap();
        assert_eq!((rest, v), (&b"]"[..], 3.0));
    }

    /// The plain decimals read in one pass are the values `fast_float2`
    /// reads, to the bit: signs, leading and trailing points, leading
    /// zeros, 1 to 15 digits, around every power of ten they can write.
    #[test]
    fn plain_decimals_read_as_fast_float2_reads_them() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut checked = 0;
        for _ in 0..400_000 {
            let r = next();
            let count = 1 + (r % 15) as usize;
            let digits: String = (0..count)
                .map(|k| {
                    let d = (next() % 10) as u8;
                    // Runs of zeros and nines: values near powers of ten.
                    let d = match (r >> 8) % 4 {
                        0 if k > 0 => 0,
                        1 if k > 0 => 9,
                        _ => d,
                    };
                    char::from(b'0' + d)
                })
                .collect();
            let point = (r >> 16) as usize % (count + 2);
            let mut text = String::new();
            text.push_str(["", "-", "+"][(r >> 24) as usize % 3]);
            if point <= count {
                text.push_str(&digits[..point]);
                text.push('.');
                text.push_str(&digits[point..]);
            } else {
                text.push_str(&digits);
            }
            let expected: f64 = fast_float2::parse(text.as_bytes()).unwrap();
            let (rest, value) = number(text.as_bytes()).unwrap();
            assert!(rest.is_empty(), "{text}");
            assert_eq!(value.to_bits(), expected.to_bits(), "{text}");
            assert!(plain_decimal(text.as_bytes()).is_some(), "{text}");
            checked += 1;
        }
        assert_eq!(checked, 400_000);
        // Beyond the plain form: the full reader, the same values.
        for text in [
            "1234567890123456",
            "1.5e3",
            "0.1234567890123456789",
            "-7E-2",
            "123456789012345678901234567890",
        ] {
            let expected: f64 = fast_float2::parse(text.as_bytes()).unwrap();
            assert_eq!(number(text.as_bytes()).unwrap().1, expected, "{text}");
            assert!(plain_decimal(text.as_bytes()).is_none_or(|(n, _)| n < text.len()));
        }
    }

    #[test]
    fn bad_numbers_are_errors_naming_the_token() {
        for text in ["1.2.3", "1.5x", "-", "1e", "+-3", "1e999"] {
            match number(text.as_bytes()) {
                Err(nom::Err::Failure(e)) => {
                    assert!(matches!(e.kind, ErrorKind::BadNumber(_)), "{text}: {e:?}")
                }
                other => panic!("{text}: {other:?}"),
            }
        }
    }

    #[test]
    fn strings_with_escapes() {
        assert_eq!(
            quoted_string(b"\"abc\" x").unwrap(),
            (&b" x"[..], Cow::Borrowed("abc"))
        );
        assert_eq!(quoted_string(b"\"a\\\"b\\n\"").unwrap().1, "a\"b\n");
        assert_eq!(quoted_string(b"\"\"").unwrap().1, "");
    }

    #[test]
    fn unterminated_strings() {
        for text in ["\"abc", "\"abc\nd\"", "\"a\\"] {
            match quoted_string(text.as_bytes()) {
                Err(nom::Err::Failure(e)) => assert_eq!(e.kind, ErrorKind::UnterminatedString),
                other => panic!("{text}: {other:?}"),
            }
        }
    }

    #[test]
    fn comments_and_space() {
        assert_eq!(skip_space(b"  # comment\n\t x"), b"x");
        assert_eq!(skip_space(b"# only a comment"), b"");
        assert_eq!(
            word(b"WorldBegin\n").unwrap(),
            (&b"\n"[..], &b"WorldBegin"[..])
        );
    }
}
