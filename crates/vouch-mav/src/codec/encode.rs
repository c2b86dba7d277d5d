//! Encoder: builds MAVLink 1/2 frames from field values (replies, alerts, crafted test traffic).

use crate::dialect::{Dialect, FieldDef, MessageDef, PrimType};

use super::frame::{MAGIC_V1, MAGIC_V2, V2_HEADER_LEN};
use super::view::Value;
use crate::crc::frame_crc;

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum EncodeError {
    #[error("unknown message {0}")]
    UnknownMessage(String),
    #[error("message {msg} has no field {field}")]
    UnknownField { msg: String, field: String },
    #[error("message {0} (id > 255) cannot be sent as MAVLink 1")]
    NotV1(String),
    #[error("field {0} is a text field: use set_str")]
    TextField(String),
}

/// A payload under construction for one message definition.
#[derive(Debug, Clone)]
pub struct MessageBuilder<'d> {
    def: &'d MessageDef,
    payload: [u8; 255],
}

impl<'d> MessageBuilder<'d> {
    pub fn new(dialect: &'d Dialect, name: &str) -> Result<Self, EncodeError> {
        let def =
            dialect.by_name(name).ok_or_else(|| EncodeError::UnknownMessage(name.to_string()))?;
        Ok(Self::for_def(def))
    }

    pub fn for_def(def: &'d MessageDef) -> Self {
        MessageBuilder { def, payload: [0; 255] }
    }

    pub fn def(&self) -> &'d MessageDef {
        self.def
    }

    fn field(&self, name: &str) -> Result<&'d FieldDef, EncodeError> {
        self.def.field(name).ok_or_else(|| EncodeError::UnknownField {
            msg: self.def.name.clone(),
            field: name.to_string(),
        })
    }

    /// Sets a numeric field (element 0 of an array); the value is converted to the wire type
    /// with Rust `as` semantics (saturating for float → int).
    pub fn set(mut self, field: &str, value: impl Into<f64>) -> Result<Self, EncodeError> {
        self.set_value(field, 0, Value::F(value.into()))?;
        Ok(self)
    }

    pub fn set_value(
        &mut self,
        field: &str,
        index: usize,
        value: Value,
    ) -> Result<(), EncodeError> {
        let f = self.field(field)?;
        if f.ty == PrimType::Char && f.array_len > 0 {
            return Err(EncodeError::TextField(field.to_string()));
        }
        let off = usize::from(f.offset) + index * f.ty.size();
        let v = value.as_f64();
        let exact_u = |v: Value| match v {
            Value::U(u) => u,
            Value::I(i) => i as u64,
            Value::F(x) => x as u64,
        };
        let exact_i = |v: Value| match v {
            Value::U(u) => u as i64,
            Value::I(i) => i,
            Value::F(x) => x as i64,
        };
        let bytes: ([u8; 8], usize) = match f.ty {
            PrimType::U8 | PrimType::Char => (((exact_u(value)) as u8 as u64).to_le_bytes(), 1),
            PrimType::I8 => ((exact_i(value) as i8 as u8 as u64).to_le_bytes(), 1),
            PrimType::U16 => ((exact_u(value) as u16 as u64).to_le_bytes(), 2),
            PrimType::I16 => ((exact_i(value) as i16 as u16 as u64).to_le_bytes(), 2),
            PrimType::U32 => ((exact_u(value) as u32 as u64).to_le_bytes(), 4),
            PrimType::I32 => ((exact_i(value) as i32 as u32 as u64).to_le_bytes(), 4),
            PrimType::U64 => (exact_u(value).to_le_bytes(), 8),
            PrimType::I64 => ((exact_i(value) as u64).to_le_bytes(), 8),
            PrimType::F32 => ((u64::from((v as f32).to_bits())).to_le_bytes(), 4),
            PrimType::F64 => (v.to_bits().to_le_bytes(), 8),
        };
        if off + bytes.1 <= self.payload.len() {
            self.payload[off..off + bytes.1].copy_from_slice(&bytes.0[..bytes.1]);
        }
        Ok(())
    }

    /// Sets a char array field from text (truncated to the field size; NUL-padded).
    pub fn set_str(mut self, field: &str, text: &str) -> Result<Self, EncodeError> {
        let f = self.field(field)?;
        let off = usize::from(f.offset);
        let size = f.wire_size();
        let src = text.as_bytes();
        for i in 0..size {
            self.payload[off + i] = src.get(i).copied().unwrap_or(0);
        }
        Ok(self)
    }

    /// The full (untruncated) payload including extensions.
    pub fn payload(&self) -> &[u8] {
        &self.payload[..usize::from(self.def.max_len)]
    }

    /// MAVLink 2 frame, with trailing zero bytes of the payload truncated (first byte kept).
    pub fn frame_v2(&self, seq: u8, sysid: u8, compid: u8) -> Vec<u8> {
        self.frame_v2_len(seq, sysid, compid, zero_truncated_len(self.payload()))
    }

    /// MAVLink 2 frame with an explicit payload length (no truncation when `len` is the full length).
    pub fn frame_v2_len(&self, seq: u8, sysid: u8, compid: u8, len: usize) -> Vec<u8> {
        let len = len.min(self.payload().len());
        let def = self.def;
        frame_v2_raw(def.id, def.crc_extra, &self.payload[..len], seq, sysid, compid)
    }

    /// MAVLink 1 frame: base fields only, never truncated.
    pub fn frame_v1(&self, seq: u8, sysid: u8, compid: u8) -> Result<Vec<u8>, EncodeError> {
        if self.def.id > 255 {
            return Err(EncodeError::NotV1(self.def.name.clone()));
        }
        let len = usize::from(self.def.base_len);
        let mut out = Vec::with_capacity(8 + len);
        out.extend_from_slice(&[MAGIC_V1, len as u8, seq, sysid, compid, self.def.id as u8]);
        out.extend_from_slice(&self.payload[..len]);
        let crc = frame_crc(&out[1..], self.def.crc_extra);
        out.extend_from_slice(&crc.to_le_bytes());
        Ok(out)
    }
}

/// Length of `payload` without its trailing zero bytes (MAVLink 2 payload truncation; the first
/// byte is always kept).
pub fn zero_truncated_len(payload: &[u8]) -> usize {
    let mut len = payload.len();
    while len > 1 && payload[len - 1] == 0 {
        len -= 1;
    }
    len
}

/// Unsigned MAVLink 2 frame of `payload` with its trailing zero bytes truncated (first byte kept),
/// as senders put it on the wire; the id and CRC_EXTRA come from the caller (no dialect needed).
pub fn frame_v2_truncated(
    msgid: u32,
    crc_extra: u8,
    payload: &[u8],
    seq: u8,
    sysid: u8,
    compid: u8,
) -> Vec<u8> {
    frame_v2_raw(msgid, crc_extra, &payload[..zero_truncated_len(payload)], seq, sysid, compid)
}

/// Unsigned MAVLink 2 frame of `payload` exactly as given (the caller truncates). Needs no
/// dialect: the id and CRC_EXTRA come from the caller, which lets the guard frame its own
/// alerts and acknowledgements without loading one.
pub fn frame_v2_raw(
    msgid: u32,
    crc_extra: u8,
    payload: &[u8],
    seq: u8,
    sysid: u8,
    compid: u8,
) -> Vec<u8> {
    let id = msgid.to_le_bytes();
    let mut out = Vec::with_capacity(V2_HEADER_LEN + payload.len() + 2);
    out.extend_from_slice(&[
        MAGIC_V2,
        payload.len() as u8,
        0,
        0,
        seq,
        sysid,
        compid,
        id[0],
        id[1],
        id[2],
    ]);
    out.extend_from_slice(payload);
    let crc = frame_crc(&out[1..], crc_extra);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}
