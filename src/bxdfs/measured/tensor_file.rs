//! The tensor file: the container of the RGL material database's `.bsdf`
//! files (Dupuy & Jakob 2018, "An adaptive parameterization for efficient
//! material acquisition and rendering"), as pbrt-v4's `Tensor` reads it.
//!
//! Layout (little-endian):
//!
//! | bytes | what |
//! |---|---|
//! | 12 | `tensor_file` and a NUL |
//! | 2 | version, major then minor: 1, 0 |
//! | 4 | number of fields (u32) |
//! | per field | name length (u16), name, rank (u16), type code (u8), data offset from the file's start (u64), then the size along each dimension (u64 each) |
//!
//! Type codes: 1 u8, 2 i8, 3 u16, 4 i16, 5 u32, 6 i32, 7 u64, 8 i64,
//! 9 f16, 10 f32, 11 f64. A field's data are its elements in C order
//! (last index fastest) at its offset.
//!
//! No crate reads this format, so this is a small reader of its own. The
//! whole file is read at once (the database's files are a few megabytes);
//! every size and offset is checked against the file's length before any
//! field is copied, so a truncated or corrupt file is an error, never an
//! out-of-bounds read or an allocation the file's size does not back.

use std::collections::HashMap;
use std::path::Path;

const MAGIC: &[u8; 12] = b"tensor_file\0";

/// A field's element type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DType {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    U64,
    I64,
    F16,
    F32,
    F64,
}

impl DType {
    fn from_code(code: u8) -> Option<DType> {
        use DType::*;
        Some(match code {
            1 => U8,
            2 => I8,
            3 => U16,
            4 => I16,
            5 => U32,
            6 => I32,
            7 => U64,
            8 => I64,
            9 => F16,
            10 => F32,
            11 => F64,
            _ => return None,
        })
    }

    /// The type's code in the file.
    pub fn code(self) -> u8 {
        self as u8 + 1
    }

    /// Bytes per element.
    pub fn size(self) -> usize {
        use DType::*;
        match self {
            U8 | I8 => 1,
            U16 | I16 | F16 => 2,
            U32 | I32 | F32 => 4,
            U64 | I64 | F64 => 8,
        }
    }

    pub fn name(self) -> &'static str {
        use DType::*;
        match self {
            U8 => "uint8",
            I8 => "int8",
            U16 => "uint16",
            I16 => "int16",
            U32 => "uint32",
            I32 => "int32",
            U64 => "uint64",
            I64 => "int64",
            F16 => "float16",
            F32 => "float32",
            F64 => "float64",
        }
    }
}

/// Why a tensor file cannot be read or used.
#[derive(Debug, thiserror::Error)]
pub enum TensorError {
    #[error("{0}")]
    Io(#[from] std::io::Error),
    #[error("not a tensor file (its first 12 bytes are not \"tensor_file\")")]
    NotATensorFile,
    #[error("tensor file version {0}.{1} (only 1.0 is known)")]
    Version(u8, u8),
    #[error("truncated tensor file: it ends inside {0}")]
    Truncated(String),
    #[error("field \"{field}\" has unknown type code {code}")]
    UnknownType { field: String, code: u8 },
    #[error("field \"{field}\": its data ({bytes} bytes at offset {offset}) lie past the file's end ({len} bytes): truncated or corrupt")]
    DataOutside {
        field: String,
        offset: u64,
        bytes: u128,
        len: usize,
    },
    #[error("field \"{0}\" is missing")]
    Missing(String),
    #[error("field \"{field}\" is {got}, not {want}")]
    WrongType {
        field: String,
        want: &'static str,
        got: &'static str,
    },
    #[error("field \"{field}\" has shape {got:?}: {want}")]
    WrongShape {
        field: String,
        got: Vec<usize>,
        want: String,
    },
}

/// One field: its type, its shape and its raw little-endian bytes.
#[derive(Clone, Debug)]
pub struct Field {
    pub dtype: DType,
    pub shape: Vec<usize>,
    bytes: Vec<u8>,
}

impl Field {
    /// The elements as f32 (the type must be f32: see
    /// [`TensorFile::field_of`]).
    pub fn f32s(&self) -> Vec<f32> {
        self.bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    }

    /// The raw bytes (for u8 fields, the elements).
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }
}

/// A tensor file's fields by name.
#[derive(Clone, Debug)]
pub struct TensorFile {
    fields: HashMap<String, Field>,
}

/// Reads little-endian values from the header, naming what it reads when
/// the file ends first.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, what: &dyn Fn() -> String) -> Result<&'a [u8], TensorError> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&end| end <= self.bytes.len())
            .ok_or_else(|| TensorError::Truncated(what()))?;
        let slice = &self.bytes[self.at..end];
        self.at = end;
        Ok(slice)
    }

    fn u16(&mut self, what: &dyn Fn() -> String) -> Result<u16, TensorError> {
        let b = self.take(2, what)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    fn u64(&mut self, what: &dyn Fn() -> String) -> Result<u64, TensorError> {
        let b = self.take(8, what)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
}

impl TensorFile {
    /// Reads the file at `path`.
    pub fn read(path: &Path) -> Result<TensorFile, TensorError> {
        Self::parse(&std::fs::read(path)?)
    }

    /// Reads a tensor file's bytes.
    pub fn parse(bytes: &[u8]) -> Result<TensorFile, TensorError> {
        let mut c = Cursor { bytes, at: 0 };
        let header = || "the header".to_string();
        if c.take(12, &header)? != MAGIC {
            return Err(TensorError::NotATensorFile);
        }
        let version = c.take(2, &header)?;
        if version != [1, 0] {
            return Err(TensorError::Version(version[0], version[1]));
        }
        let count = c.take(4, &header)?;
        let count = u32::from_le_bytes([count[0], count[1], count[2], count[3]]);
        let mut fields = HashMap::new();
        for index in 0..count {
            let entry = || format!("the description of field {index}");
            let name_len = c.u16(&entry)? as usize;
            let name = String::from_utf8_lossy(c.take(name_len, &entry)?).into_owned();
            let of_name = || format!("the description of field \"{name}\"");
            let rank = c.u16(&of_name)?;
            let code = c.take(1, &of_name)?[0];
            let offset = c.u64(&of_name)?;
            let dtype = DType::from_code(code).ok_or_else(|| TensorError::UnknownType {
                field: name.clone(),
                code,
            })?;
            let mut shape = Vec::with_capacity(rank as usize);
            let mut elements: u128 = 1;
            for _ in 0..rank {
                let n = c.u64(&of_name)?;
                elements = elements.saturating_mul(n as u128);
                shape.push(usize::try_from(n).unwrap_or(usize::MAX));
            }
            let size = elements.saturating_mul(dtype.size() as u128);
            let outside = || TensorError::DataOutside {
                field: name.clone(),
                offset,
                bytes: size,
                len: bytes.len(),
            };
            let start = usize::try_from(offset).map_err(|_| outside())?;
            let end = usize::try_from(size)
                .ok()
                .and_then(|size| start.checked_add(size))
                .filter(|&end| end <= bytes.len())
                .ok_or_else(outside)?;
            let field = Field {
                dtype,
                shape,
                bytes: bytes[start..end].to_vec(),
            };
            fields.insert(name, field);
        }
        Ok(TensorFile { fields })
    }

    /// The field `name`, which must be of type `dtype` and of rank
    /// `rank`.
    pub fn field_of(&self, name: &str, dtype: DType, rank: usize) -> Result<&Field, TensorError> {
        let field = self
            .fields
            .get(name)
            .ok_or_else(|| TensorError::Missing(name.to_string()))?;
        if field.dtype != dtype {
            return Err(TensorError::WrongType {
                field: name.to_string(),
                want: dtype.name(),
                got: field.dtype.name(),
            });
        }
        if field.shape.len() != rank {
            return Err(TensorError::WrongShape {
                field: name.to_string(),
                got: field.shape.clone(),
                want: format!(
                    "expected {rank} dimension{}",
                    if rank == 1 { "" } else { "s" }
                ),
            });
        }
        Ok(field)
    }
}

/// The bytes of a tensor file holding `fields` (name, type, shape, raw
/// little-endian data), for tests that write their own files.
#[cfg(test)]
pub fn encode(fields: &[(&str, DType, Vec<usize>, Vec<u8>)]) -> Vec<u8> {
    let header_len: usize = 18
        + fields
            .iter()
            .map(|(name, _, shape, _)| 2 + name.len() + 2 + 1 + 8 + 8 * shape.len())
            .sum::<usize>();
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(fields.len() as u32).to_le_bytes());
    let mut offset = header_len as u64;
    for (name, dtype, shape, data) in fields {
        out.extend_from_slice(&(name.len() as u16).to_le_bytes());
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(&(shape.len() as u16).to_le_bytes());
        out.push(dtype.code());
        out.extend_from_slice(&offset.to_le_bytes());
        for &n in shape {
            out.extend_from_slice(&(n as u64).to_le_bytes());
        }
        offset += data.len() as u64;
    }
    for (_, _, _, data) in fields {
        out.extend_from_slice(data);
    }
    out
}

/// Little-endian bytes of f32 values.
#[cfg(test)]
pub fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Vec<u8> {
        encode(&[
            (
                "a",
                DType::F32,
                vec![2, 3],
                f32_bytes(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
            ),
            ("flag", DType::U8, vec![1], vec![1]),
            ("wide", DType::F64, vec![1], 2.5f64.to_le_bytes().to_vec()),
        ])
    }

    #[test]
    fn fields_read_back_with_their_types_and_shapes() {
        let file = TensorFile::parse(&sample()).unwrap();
        let a = file.field_of("a", DType::F32, 2).unwrap();
        assert_eq!(a.shape, vec![2, 3]);
        assert_eq!(a.f32s(), vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(file.field_of("flag", DType::U8, 1).unwrap().bytes(), &[1]);
        assert_eq!(DType::from_code(DType::F64.code()), Some(DType::F64));
    }

    #[test]
    fn wrong_fields_are_named() {
        let file = TensorFile::parse(&sample()).unwrap();
        let e = file.field_of("b", DType::F32, 1).unwrap_err().to_string();
        assert!(e.contains("\"b\" is missing"), "{e}");
        let e = file
            .field_of("wide", DType::F32, 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("float64, not float32"), "{e}");
        let e = file.field_of("a", DType::F32, 4).unwrap_err().to_string();
        assert!(e.contains("[2, 3]") && e.contains("4 dimensions"), "{e}");
    }

    #[test]
    fn every_truncation_is_an_error() {
        let bytes = sample();
        for len in 0..bytes.len() {
            let e = TensorFile::parse(&bytes[..len]).unwrap_err();
            assert!(
                matches!(
                    e,
                    TensorError::Truncated(_) | TensorError::DataOutside { .. }
                ),
                "{len}: {e}"
            );
        }
    }

    #[test]
    fn corrupt_headers_are_errors() {
        let mut bytes = sample();
        bytes[0] = b'x';
        assert!(matches!(
            TensorFile::parse(&bytes),
            Err(TensorError::NotATensorFile)
        ));
        let mut bytes = sample();
        bytes[12] = 2;
        assert!(matches!(
            TensorFile::parse(&bytes),
            Err(TensorError::Version(2, 0))
        ));
        // The first field's type code (after magic, version, count, name
        // length, name "a", rank).
        let mut bytes = sample();
        bytes[18 + 2 + 1 + 2] = 12;
        assert!(matches!(
            TensorFile::parse(&bytes),
            Err(TensorError::UnknownType { code: 12, .. })
        ));
        // A huge shape: refused without allocating it.
        let huge = encode(&[("h", DType::F64, vec![1 << 40, 1 << 40], vec![])]);
        let e = TensorFile::parse(&huge).unwrap_err().to_string();
        assert!(e.contains("past the file's end"), "{e}");
    }
}
