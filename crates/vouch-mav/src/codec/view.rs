//! Decoded view of a frame's payload: field access by name or by precomputed position.
//!
//! Nothing is copied: reads go straight to the payload bytes, and bytes beyond a zero-truncated
//! payload read as zero, exactly as MAVLink 2 requires.

use crate::dialect::{FieldDef, MessageDef, MsgIndex, PrimType};

use super::frame::Frame;

/// A scalar field value.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum Value {
    U(u64),
    I(i64),
    F(f64),
}

impl Value {
    pub fn as_f64(self) -> f64 {
        match self {
            Value::U(v) => v as f64,
            Value::I(v) => v as f64,
            Value::F(v) => v,
        }
    }
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::U(v) => write!(f, "{v}"),
            Value::I(v) => write!(f, "{v}"),
            Value::F(v) => write!(f, "{v}"),
        }
    }
}

/// Reads `size` little-endian bytes at `offset`, zero-padded past the end of `payload`.
#[inline]
fn read_le(payload: &[u8], offset: usize, size: usize) -> u64 {
    let mut b = [0u8; 8];
    if offset < payload.len() {
        let n = size.min(payload.len() - offset);
        b[..n].copy_from_slice(&payload[offset..offset + n]);
    }
    u64::from_le_bytes(b)
}

/// Reads element `index` of a field (0 for scalars) from a payload.
#[inline]
pub fn read_field(payload: &[u8], field: &FieldDef, index: usize) -> Value {
    read_prim(payload, field.ty, usize::from(field.offset) + index * field.ty.size())
}

/// Reads a primitive at a byte offset (used with offsets precomputed at protocol load time).
#[inline]
pub fn read_prim(payload: &[u8], ty: PrimType, offset: usize) -> Value {
    let raw = read_le(payload, offset, ty.size());
    match ty {
        PrimType::U8 | PrimType::Char | PrimType::U16 | PrimType::U32 | PrimType::U64 => {
            Value::U(raw)
        }
        PrimType::I8 => Value::I(i64::from(raw as u8 as i8)),
        PrimType::I16 => Value::I(i64::from(raw as u16 as i16)),
        PrimType::I32 => Value::I(i64::from(raw as u32 as i32)),
        PrimType::I64 => Value::I(raw as i64),
        PrimType::F32 => Value::F(f64::from(f32::from_bits(raw as u32))),
        PrimType::F64 => Value::F(f64::from_bits(raw)),
    }
}

/// The bytes of a char array up to its first NUL (zero-padded reads beyond truncation).
pub fn read_chars<'p>(payload: &'p [u8], field: &FieldDef) -> &'p [u8] {
    let start = usize::from(field.offset).min(payload.len());
    let end = (usize::from(field.offset) + field.wire_size()).min(payload.len());
    let s = &payload[start..end];
    match s.iter().position(|&b| b == 0) {
        Some(n) => &s[..n],
        None => s,
    }
}

/// A frame's payload interpreted with its message definition.
#[derive(Debug, Clone, Copy)]
pub struct MessageView<'a> {
    pub index: MsgIndex,
    pub def: &'a MessageDef,
    pub payload: &'a [u8],
}

impl<'a> MessageView<'a> {
    /// Views a frame of a known message; `None` for an unknown id.
    pub fn of_frame(
        frame: &Frame<'a>,
        dialect: &'a crate::dialect::Dialect,
    ) -> Option<MessageView<'a>> {
        let index = frame.msg?;
        Some(MessageView { index, def: dialect.message(index), payload: frame.payload })
    }

    pub fn name(&self) -> &'a str {
        &self.def.name
    }

    /// Scalar field (or first element of an array) by name.
    pub fn get(&self, field: &str) -> Option<Value> {
        self.def.field(field).map(|f| read_field(self.payload, f, 0))
    }

    pub fn get_f64(&self, field: &str) -> Option<f64> {
        self.get(field).map(Value::as_f64)
    }

    /// Element `i` of an array field.
    pub fn get_elem(&self, field: &str, i: usize) -> Option<Value> {
        let f = self.def.field(field)?;
        (i < usize::from(f.array_len.max(1))).then(|| read_field(self.payload, f, i))
    }

    /// A char array field as text (up to the first NUL; lossy UTF-8).
    pub fn get_str(&self, field: &str) -> Option<String> {
        let f = self.def.field(field)?;
        Some(String::from_utf8_lossy(read_chars(self.payload, f)).into_owned())
    }

    /// Name of the enum entry a field holds (fields declared with `enum="…"`), if any.
    pub fn get_enum_name<'d>(
        &self,
        field: &str,
        dialect: &'d crate::dialect::Dialect,
    ) -> Option<&'d str> {
        let f = self.def.field(field)?;
        let v = read_field(self.payload, f, 0);
        let raw = match v {
            Value::U(u) => u,
            Value::I(i) if i >= 0 => i as u64,
            _ => return None,
        };
        dialect.enum_value_name(f.enum_name.as_deref()?, raw)
    }

    /// All fields as (name, rendered value), for reports and JSON output.
    pub fn render_fields(&self) -> Vec<(String, String)> {
        self.def
            .fields
            .iter()
            .map(|f| {
                let v = if f.ty == PrimType::Char {
                    format!("{:?}", String::from_utf8_lossy(read_chars(self.payload, f)))
                } else if f.array_len > 0 {
                    let items: Vec<String> = (0..usize::from(f.array_len))
                        .map(|i| read_field(self.payload, f, i).to_string())
                        .collect();
                    format!("[{}]", items.join(", "))
                } else {
                    read_field(self.payload, f, 0).to_string()
                };
                (f.name.clone(), v)
            })
            .collect()
    }
}
