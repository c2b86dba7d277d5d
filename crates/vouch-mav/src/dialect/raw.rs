//! XML → raw dialect records, and the compact text form ("digest") of those records.
//!
//! This file is compiled twice: into the library (for `--dialect FILE.xml`) and into `build.rs`
//! (`#[path]` include), which digests the embedded ardupilotmega dialect at build time. The
//! default dialect is then rebuilt from the digest at start-up without building an XML DOM,
//! which keeps the guard's peak RSS low (the DOM of common.xml alone is several MB).
//! Hence: std and roxmltree only, nothing from the crate.

use std::fmt::Write as _;

/// A field as written in the XML (type still as text; wire order is computed later).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RawField {
    pub name: String,
    pub ty: String,
    pub is_extension: bool,
    pub enum_name: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RawMessage {
    pub id: u32,
    pub name: String,
    /// File the message was defined in (for error messages).
    pub file: String,
    /// Fields in XML order.
    pub fields: Vec<RawField>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RawEnum {
    pub name: String,
    pub bitmask: bool,
    pub entries: Vec<(String, u64)>,
}

/// All messages (a later definition of an id replaces an earlier one) and merged enums.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct RawDialect {
    pub messages: Vec<RawMessage>,
    pub enums: Vec<RawEnum>,
}

/// Why XML could not be read into raw records.
#[derive(Debug)]
pub enum RawError<E> {
    Read(E),
    Xml { file: String, line: u32, col: u32, message: String },
    Message { file: String, message: String, problem: String, offset: usize },
}

/// Reads `root` through `read` (file name → text), following `<include>`s depth-first, once each.
pub fn read_xml<E>(
    root: &str,
    read: &dyn Fn(&str) -> Result<String, E>,
) -> Result<RawDialect, RawError<E>> {
    let mut acc = RawDialect::default();
    let mut seen = Vec::new();
    load_one(root, read, &mut acc, &mut seen)?;
    Ok(acc)
}

fn load_one<E>(
    file: &str,
    read: &dyn Fn(&str) -> Result<String, E>,
    acc: &mut RawDialect,
    seen: &mut Vec<String>,
) -> Result<(), RawError<E>> {
    if seen.iter().any(|f| f == file) {
        return Ok(());
    }
    seen.push(file.to_string());
    let text = read(file).map_err(RawError::Read)?;
    let doc = roxmltree::Document::parse(&text).map_err(|e| {
        let pos = e.pos();
        RawError::Xml {
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
            load_one(name, read, acc, seen)?;
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

fn read_enum(e: roxmltree::Node, acc: &mut RawDialect) {
    let Some(name) = e.attribute("name") else {
        return;
    };
    let bitmask = e.attribute("bitmask") == Some("true");
    let idx = match acc.enums.iter().position(|x| x.name == name) {
        Some(i) => i,
        None => {
            acc.enums.push(RawEnum { name: name.to_string(), bitmask, entries: Vec::new() });
            acc.enums.len() - 1
        }
    };
    // Entries without a value continue from the previous one (MAVLink generator convention).
    let mut next = acc.enums[idx].entries.last().map(|(_, v)| v + 1).unwrap_or(0);
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

fn read_message<E>(file: &str, m: roxmltree::Node) -> Result<RawMessage, RawError<E>> {
    let name = m.attribute("name").unwrap_or("").to_string();
    let bad = |problem: String| RawError::Message {
        file: file.to_string(),
        message: name.clone(),
        problem,
        offset: m.range().start,
    };
    let id: u32 = m
        .attribute("id")
        .and_then(|s| s.trim().parse().ok())
        .ok_or_else(|| bad("missing or invalid id".into()))?;
    let mut fields = Vec::new();
    let mut in_ext = false;
    for c in m.children().filter(|n| n.is_element()) {
        if c.has_tag_name("extensions") {
            in_ext = true;
            continue;
        }
        if !c.has_tag_name("field") {
            continue;
        }
        let fname = c.attribute("name").ok_or_else(|| bad("field without name".into()))?;
        let ty = c.attribute("type").ok_or_else(|| bad(format!("field {fname} without type")))?;
        fields.push(RawField {
            name: fname.to_string(),
            ty: ty.trim().to_string(),
            is_extension: in_ext,
            enum_name: c.attribute("enum").map(str::to_string),
        });
    }
    Ok(RawMessage { id, name, file: file.to_string(), fields })
}

// ---- digest: one record per line, space-separated tokens (MAVLink names have no spaces) ----
//   M <id> <name> <file>        message
//   F <name> <type> <0|1 extension> <enum or ->
//   E <name> <0|1 bitmask>      enum
//   V <name> <value>            entry of the last enum

/// Writes the digest of `d`. Returns `None` if a token would contain whitespace (then the
/// digest could not be read back; the caller falls back to embedding nothing).
pub fn write_digest(d: &RawDialect) -> Option<String> {
    let ok = |s: &str| !s.is_empty() && !s.chars().any(char::is_whitespace) && s != "-";
    let mut out = String::new();
    for m in &d.messages {
        if !ok(&m.name) || !ok(&m.file) {
            return None;
        }
        let _ = writeln!(out, "M {} {} {}", m.id, m.name, m.file);
        for f in &m.fields {
            if !ok(&f.name) || !ok(&f.ty) || f.enum_name.as_deref().is_some_and(|e| !ok(e)) {
                return None;
            }
            let _ = writeln!(
                out,
                "F {} {} {} {}",
                f.name,
                f.ty,
                u8::from(f.is_extension),
                f.enum_name.as_deref().unwrap_or("-")
            );
        }
    }
    for e in &d.enums {
        if !ok(&e.name) {
            return None;
        }
        let _ = writeln!(out, "E {} {}", e.name, u8::from(e.bitmask));
        for (n, v) in &e.entries {
            if !ok(n) {
                return None;
            }
            let _ = writeln!(out, "V {n} {v}");
        }
    }
    Some(out)
}

/// Reads a digest back; `Err(line number)` on the first line that does not fit the format.
pub fn read_digest(text: &str) -> Result<RawDialect, usize> {
    let mut d = RawDialect::default();
    for (i, line) in text.lines().enumerate() {
        let bad = i + 1;
        let mut t = line.split(' ');
        match (t.next(), t.next(), t.next(), t.next(), t.next(), t.next()) {
            (Some("M"), Some(id), Some(name), Some(file), None, None) => {
                d.messages.push(RawMessage {
                    id: id.parse().map_err(|_| bad)?,
                    name: name.to_string(),
                    file: file.to_string(),
                    fields: Vec::new(),
                })
            }
            (Some("F"), Some(name), Some(ty), Some(ext), Some(en), None) => {
                d.messages.last_mut().ok_or(bad)?.fields.push(RawField {
                    name: name.to_string(),
                    ty: ty.to_string(),
                    is_extension: ext == "1",
                    enum_name: (en != "-").then(|| en.to_string()),
                })
            }
            (Some("E"), Some(name), Some(bm), None, None, None) => d.enums.push(RawEnum {
                name: name.to_string(),
                bitmask: bm == "1",
                entries: Vec::new(),
            }),
            (Some("V"), Some(name), Some(v), None, None, None) => d
                .enums
                .last_mut()
                .ok_or(bad)?
                .entries
                .push((name.to_string(), v.parse().map_err(|_| bad)?)),
            (Some(""), None, ..) => {}
            _ => return Err(bad),
        }
    }
    Ok(d)
}
