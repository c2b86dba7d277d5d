//! XML front of the dialect loader (roxmltree): root file plus relative `<include>`s.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::{compute_crc_extra, Dialect, EnumDef, FieldDef, MessageDef, PrimType};

include!(concat!(env!("OUT_DIR"), "/embedded_dialect.rs"));

/// Why a dialect could not be loaded; names the file and, for XML errors, the position.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum DialectError {
    #[error("cannot read dialect file {path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{file}:{line}:{col}: invalid XML: {message}")]
    Xml {
        file: String,
        line: u32,
        col: u32,
        message: String,
    },
    #[error("{file}: message {message}: {problem}")]
    Message {
        file: String,
        message: String,
        problem: String,
    },
    #[error("no default dialect was embedded at build time (set VOUCH_MAV_DEFINITIONS when building, or pass --dialect FILE.xml)")]
    NoEmbedded,
    #[error("include {name} (from {from}) not found")]
    MissingInclude { name: String, from: String },
}

/// Folder the embedded default dialect was taken from at build time ("none" if none).
pub fn embedded_origin() -> &'static str {
    EMBEDDED_ORIGIN
}

/// Loads a dialect file and its includes from disk.
pub fn load_dialect_file(path: &Path) -> Result<Dialect, DialectError> {
    let dir = path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let root = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("dialect.xml")
        .to_string();
    let read = |name: &str| -> Result<String, DialectError> {
        let p = dir.join(name);
        std::fs::read_to_string(&p).map_err(|source| DialectError::Io {
            path: p.display().to_string(),
            source,
        })
    };
    load_dialect_from(&root, &read)
}

pub(super) fn load_embedded() -> Result<Dialect, DialectError> {
    if EMBEDDED_XML.is_empty() {
        return Err(DialectError::NoEmbedded);
    }
    let read = |name: &str| -> Result<String, DialectError> {
        EMBEDDED_XML
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, t)| t.to_string())
            .ok_or_else(|| DialectError::MissingInclude {
                name: name.to_string(),
                from: "embedded".into(),
            })
    };
    load_dialect_from(EMBEDDED_XML[0].0, &read)
}

#[derive(Default)]
struct Acc {
    messages: Vec<MessageDef>,
    enums: Vec<EnumDef>,
    enum_index: HashMap<String, usize>,
    seen_files: Vec<String>,
}

/// Loads `root` through `read` (file name → text), following includes depth-first.
pub fn load_dialect_from(
    root: &str,
    read: &dyn Fn(&str) -> Result<String, DialectError>,
) -> Result<Dialect, DialectError> {
    let mut acc = Acc::default();
    load_one(root, read, &mut acc)?;
    let name = root.trim_end_matches(".xml").to_string();
    Ok(Dialect::build(name, acc.messages, acc.enums))
}

fn load_one(
    file: &str,
    read: &dyn Fn(&str) -> Result<String, DialectError>,
    acc: &mut Acc,
) -> Result<(), DialectError> {
    if acc.seen_files.iter().any(|f| f == file) {
        return Ok(());
    }
    acc.seen_files.push(file.to_string());
    let text = read(file)?;
    let doc = roxmltree::Document::parse(&text).map_err(|e| {
        let pos = e.pos();
        DialectError::Xml {
            file: file.to_string(),
            line: pos.row,
            col: pos.col,
            message: e.to_string(),
        }
    })?;
    let root = doc.root_element();
    for inc in root.children().filter(|n| n.has_tag_name("include")) {
        let name = inc.text().unwrap_or("").trim();
        if !name.is_empty() {
            load_one(name, read, acc)?;
        }
    }
    for enums in root.children().filter(|n| n.has_tag_name("enums")) {
        for e in enums.children().filter(|n| n.has_tag_name("enum")) {
            read_enum(e, acc);
        }
    }
    for msgs in root.children().filter(|n| n.has_tag_name("messages")) {
        for m in msgs.children().filter(|n| n.has_tag_name("message")) {
            let def = read_message(file, m)?;
            acc.messages.retain(|old| old.id != def.id);
            acc.messages.push(def);
        }
    }
    Ok(())
}

fn read_enum(e: roxmltree::Node, acc: &mut Acc) {
    let Some(name) = e.attribute("name") else {
        return;
    };
    let bitmask = e.attribute("bitmask") == Some("true");
    let idx = *acc.enum_index.entry(name.to_string()).or_insert_with(|| {
        acc.enums.push(EnumDef {
            name: name.to_string(),
            bitmask,
            entries: Vec::new(),
        });
        acc.enums.len() - 1
    });
    // Entries without a value continue from the previous one (MAVLink generator convention).
    let mut next = acc.enums[idx]
        .entries
        .last()
        .map(|(_, v)| v + 1)
        .unwrap_or(0);
    for entry in e.children().filter(|n| n.has_tag_name("entry")) {
        let Some(en) = entry.attribute("name") else {
            continue;
        };
        let value = entry.attribute("value").and_then(parse_int).unwrap_or(next);
        next = value + 1;
        acc.enums[idx].entries.push((en.to_string(), value));
    }
}

fn parse_int(s: &str) -> Option<u64> {
    let s = s.trim();
    if let Some(h) = s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        u64::from_str_radix(h, 16).ok()
    } else if let Some(b) = s.strip_prefix("0b") {
        u64::from_str_radix(b, 2).ok()
    } else if let Some(p) = s.strip_prefix("2**") {
        p.parse::<u32>().ok().and_then(|p| 1u64.checked_shl(p))
    } else {
        s.parse().ok()
    }
}

fn read_message(file: &str, m: roxmltree::Node) -> Result<MessageDef, DialectError> {
    let name = m.attribute("name").unwrap_or("").to_string();
    let bad = |problem: String| DialectError::Message {
        file: file.to_string(),
        message: name.clone(),
        problem,
    };
    let id: u32 = m
        .attribute("id")
        .and_then(|s| s.trim().parse().ok())
        .ok_or_else(|| bad("missing or invalid id".into()))?;
    let mut base = Vec::new();
    let mut ext = Vec::new();
    let mut in_ext = false;
    for c in m.children().filter(|n| n.is_element()) {
        if c.has_tag_name("extensions") {
            in_ext = true;
            continue;
        }
        if !c.has_tag_name("field") {
            continue;
        }
        let fname = c
            .attribute("name")
            .ok_or_else(|| bad("field without name".into()))?;
        let ty = c
            .attribute("type")
            .ok_or_else(|| bad(format!("field {fname} without type")))?;
        let (prim, array_len) =
            parse_type(ty).ok_or_else(|| bad(format!("field {fname}: unknown type {ty}")))?;
        let f = FieldDef {
            name: fname.to_string(),
            ty: prim,
            array_len,
            offset: 0,
            is_extension: in_ext,
            enum_name: c.attribute("enum").map(str::to_string),
        };
        if in_ext {
            ext.push(f)
        } else {
            base.push(f)
        }
    }
    // Wire order: base fields by element size, largest first; stable, so ties keep XML order.
    base.sort_by_key(|f| std::cmp::Reverse(f.ty.size()));
    let mut fields = base;
    fields.extend(ext);
    let mut off = 0usize;
    let mut base_len = 0usize;
    for f in &mut fields {
        f.offset = off as u16;
        off += f.wire_size();
        if !f.is_extension {
            base_len = off;
        }
    }
    if off > 255 {
        return Err(bad(format!("payload of {off} bytes exceeds 255")));
    }
    let crc_extra = compute_crc_extra(&name, &fields);
    Ok(MessageDef {
        id,
        name,
        crc_extra,
        base_len: base_len as u16,
        max_len: off as u16,
        fields,
        field_index: HashMap::new(),
    })
}

fn parse_type(ty: &str) -> Option<(PrimType, u16)> {
    let ty = ty.trim();
    if let Some(open) = ty.find('[') {
        let prim = PrimType::from_c_name(&ty[..open])?;
        let len: u16 = ty[open + 1..].trim_end_matches(']').parse().ok()?;
        Some((prim, len))
    } else {
        Some((PrimType::from_c_name(ty)?, 0))
    }
}
