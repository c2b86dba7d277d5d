//! MAVLink dialects loaded at run time from XML, flattened into lookup tables.
//!
//! Everything the hot path needs is precomputed here: wire offsets, CRC_EXTRA, payload lengths and
//! a dense id → message table, so decoding a frame is a table lookup plus bounded byte reads.

pub mod raw;
mod xml;

pub use xml::{
    DialectError, MessageError, XmlError, embedded_origin, load_dialect_file, load_dialect_from,
};

use std::collections::HashMap;

/// Index of a message definition inside a [`Dialect`] (dense, 0-based).
pub type MsgIndex = u16;

/// Primitive wire type of a field (arrays are described by [`FieldDef::array_len`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum PrimType {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    U64,
    I64,
    F32,
    F64,
    Char,
}

impl PrimType {
    pub fn size(self) -> usize {
        match self {
            PrimType::U8 | PrimType::I8 | PrimType::Char => 1,
            PrimType::U16 | PrimType::I16 => 2,
            PrimType::U32 | PrimType::I32 | PrimType::F32 => 4,
            PrimType::U64 | PrimType::I64 | PrimType::F64 => 8,
        }
    }

    /// C type name as used in the CRC_EXTRA computation.
    pub fn c_name(self) -> &'static str {
        match self {
            PrimType::U8 => "uint8_t",
            PrimType::I8 => "int8_t",
            PrimType::U16 => "uint16_t",
            PrimType::I16 => "int16_t",
            PrimType::U32 => "uint32_t",
            PrimType::I32 => "int32_t",
            PrimType::U64 => "uint64_t",
            PrimType::I64 => "int64_t",
            PrimType::F32 => "float",
            PrimType::F64 => "double",
            PrimType::Char => "char",
        }
    }

    pub fn from_c_name(s: &str) -> Option<PrimType> {
        Some(match s {
            "uint8_t" | "uint8_t_mavlink_version" => PrimType::U8,
            "int8_t" => PrimType::I8,
            "uint16_t" => PrimType::U16,
            "int16_t" => PrimType::I16,
            "uint32_t" => PrimType::U32,
            "int32_t" => PrimType::I32,
            "uint64_t" => PrimType::U64,
            "int64_t" => PrimType::I64,
            "float" => PrimType::F32,
            "double" => PrimType::F64,
            "char" => PrimType::Char,
            _ => return None,
        })
    }

    pub fn is_float(self) -> bool {
        matches!(self, PrimType::F32 | PrimType::F64)
    }
}

/// One field of a message, with its position in the (untruncated) payload.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FieldDef {
    pub name: String,
    pub ty: PrimType,
    /// 0 for a scalar, else the number of elements.
    pub array_len: u16,
    /// Byte offset in the untruncated payload.
    pub offset: u16,
    pub is_extension: bool,
    /// Name of the enum this field takes values from (`enum="…"` in the XML), if any.
    pub enum_name: Option<String>,
}

impl FieldDef {
    pub fn wire_size(&self) -> usize {
        self.ty.size() * usize::from(self.array_len.max(1))
    }
}

/// One message definition.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MessageDef {
    pub id: u32,
    pub name: String,
    pub crc_extra: u8,
    /// Payload length without extension fields (what MAVLink 1 carries).
    pub base_len: u16,
    /// Payload length with extension fields.
    pub max_len: u16,
    /// Fields in wire order (base fields sorted by size, then extensions in XML order).
    pub fields: Vec<FieldDef>,
    field_index: HashMap<String, u16>,
}

impl MessageDef {
    pub fn field(&self, name: &str) -> Option<&FieldDef> {
        self.field_index.get(name).map(|&i| &self.fields[usize::from(i)])
    }

    pub fn field_position(&self, name: &str) -> Option<usize> {
        self.field_index.get(name).map(|&i| usize::from(i))
    }
}

/// One enum with its entries.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EnumDef {
    pub name: String,
    pub bitmask: bool,
    pub entries: Vec<(String, u64)>,
}

/// A loaded dialect: all messages and enums of a root XML file and its includes.
#[derive(Debug, Clone)]
pub struct Dialect {
    pub name: String,
    messages: Vec<MessageDef>,
    /// Dense table indexed by message id; `u16::MAX` = unknown.
    by_id: Vec<MsgIndex>,
    by_name: HashMap<String, MsgIndex>,
    enums: Vec<EnumDef>,
    enum_by_name: HashMap<String, usize>,
    /// Entry name → (enum index, value). MAVLink entry names are globally unique by convention.
    entry_by_name: HashMap<String, (usize, u64)>,
}

const NO_MSG: MsgIndex = MsgIndex::MAX;

impl Dialect {
    pub(crate) fn build(
        name: String,
        mut messages: Vec<MessageDef>,
        enums: Vec<EnumDef>,
    ) -> Dialect {
        messages.sort_by_key(|m| m.id);
        messages.dedup_by_key(|m| m.id);
        for m in &mut messages {
            m.field_index =
                m.fields.iter().enumerate().map(|(i, f)| (f.name.clone(), i as u16)).collect();
        }
        let max_id = messages.iter().map(|m| m.id).max().unwrap_or(0) as usize;
        let mut by_id = vec![NO_MSG; max_id + 1];
        let mut by_name = HashMap::new();
        for (i, m) in messages.iter().enumerate() {
            by_id[m.id as usize] = i as MsgIndex;
            by_name.insert(m.name.clone(), i as MsgIndex);
        }
        let mut enum_by_name = HashMap::new();
        let mut entry_by_name = HashMap::new();
        for (i, e) in enums.iter().enumerate() {
            enum_by_name.insert(e.name.clone(), i);
            for (n, v) in &e.entries {
                entry_by_name.entry(n.clone()).or_insert((i, *v));
            }
        }
        Dialect { name, messages, by_id, by_name, enums, enum_by_name, entry_by_name }
    }

    /// The default dialect: ardupilotmega.xml with its includes, embedded at build time.
    pub fn default_dialect() -> Result<Dialect, DialectError> {
        xml::load_embedded()
    }

    #[inline]
    pub fn index_of_id(&self, id: u32) -> Option<MsgIndex> {
        match self.by_id.get(id as usize) {
            Some(&i) if i != NO_MSG => Some(i),
            _ => None,
        }
    }

    #[inline]
    pub fn message(&self, idx: MsgIndex) -> &MessageDef {
        &self.messages[usize::from(idx)]
    }

    #[inline]
    pub fn by_id(&self, id: u32) -> Option<&MessageDef> {
        self.index_of_id(id).map(|i| self.message(i))
    }

    pub fn index_of_name(&self, name: &str) -> Option<MsgIndex> {
        self.by_name.get(name).copied()
    }

    pub fn by_name(&self, name: &str) -> Option<&MessageDef> {
        self.index_of_name(name).map(|i| self.message(i))
    }

    pub fn messages(&self) -> &[MessageDef] {
        &self.messages
    }

    pub fn enum_def(&self, name: &str) -> Option<&EnumDef> {
        self.enum_by_name.get(name).map(|&i| &self.enums[i])
    }

    pub fn enums(&self) -> &[EnumDef] {
        &self.enums
    }

    /// Looks up an enum entry by its (globally unique) name: (enum name, value).
    pub fn enum_entry(&self, entry: &str) -> Option<(&str, u64)> {
        self.entry_by_name.get(entry).map(|&(i, v)| (self.enums[i].name.as_str(), v))
    }

    /// Name of the entry of `enum_name` whose value is `value` (first match), for reports.
    pub fn enum_value_name(&self, enum_name: &str, value: u64) -> Option<&str> {
        self.enum_def(enum_name)?.entries.iter().find(|(_, v)| *v == value).map(|(n, _)| n.as_str())
    }
}

/// The MAVLink CRC_EXTRA of a message, from its name and base fields in wire order.
pub fn compute_crc_extra(name: &str, fields: &[FieldDef]) -> u8 {
    let mut crc = crate::crc::X25::new();
    crc.update(name.as_bytes());
    crc.update(b" ");
    for f in fields.iter().filter(|f| !f.is_extension) {
        crc.update(f.ty.c_name().as_bytes());
        crc.update(b" ");
        crc.update(f.name.as_bytes());
        crc.update(b" ");
        if f.array_len > 0 {
            crc.update(&[f.array_len as u8]);
        }
    }
    let v = crc.get();
    ((v & 0xFF) ^ (v >> 8)) as u8
}
