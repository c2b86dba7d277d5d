//! Dialect loading: XML files (`--dialect`, through `raw.rs` and roxmltree) or the digest of the
//! default dialect that `build.rs` produced from the embedded XML; both end in `from_raw`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use miette::{NamedSource, SourceSpan};

use super::raw::{RawDialect, RawError, RawMessage, read_digest, read_xml};
use super::{Dialect, EnumDef, FieldDef, MessageDef, PrimType, compute_crc_extra};

include!(concat!(env!("OUT_DIR"), "/embedded_dialect.rs"));

/// Why a dialect could not be loaded; names the file and, where the XML has a position, points
/// at it.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum DialectError {
    /// A dialect file (or one it includes) cannot be read.
    #[error("cannot read dialect file {path}: {source}")]
    #[diagnostic(code(mav::D001))]
    Io {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// A file is not well-formed XML.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Xml(Box<XmlError>),
    /// A message definition that cannot be used.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Message(Box<MessageError>),
    /// The library was built without the default dialect.
    #[error(
        "no default dialect was embedded at build time (the build set VOUCH_MAV_NO_DEFAULT_DIALECT); pass a dialect file"
    )]
    #[diagnostic(code(mav::D004))]
    NoEmbedded,
    /// The embedded digest does not read back (the build script and the loader disagree).
    #[error("embedded dialect digest, line {line}: unreadable record")]
    #[diagnostic(code(mav::D005))]
    Digest {
        /// 1-based line of the digest.
        line: usize,
    },
}

/// A dialect file that is not well-formed XML, located.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error("invalid XML in {file}: {message}")]
#[diagnostic(code(mav::D002))]
pub struct XmlError {
    /// The file.
    pub file: String,
    /// 1-based line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
    /// The XML reader's message.
    pub message: String,
    /// The file's text, when it could be read again for the report.
    #[source_code]
    pub src: Option<NamedSource<String>>,
    /// Where.
    #[label("here")]
    pub span: Option<SourceSpan>,
}

/// A message definition that cannot be used (no id, a field without name or type, an unknown
/// type, a payload over 255 bytes), located when the XML position is known.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error("{file}: message {message}: {problem}")]
#[diagnostic(code(mav::D003))]
pub struct MessageError {
    /// The file.
    pub file: String,
    /// The message's name.
    pub message: String,
    /// What is wrong.
    pub problem: String,
    /// The file's text, when the position is known.
    #[source_code]
    pub src: Option<NamedSource<String>>,
    /// The message element.
    #[label("this message")]
    pub span: Option<SourceSpan>,
}

impl DialectError {
    /// Whether the error is about reading files (an I/O problem) rather than their content.
    pub fn is_io(&self) -> bool {
        matches!(self, DialectError::Io { .. })
    }
}

/// Byte offset of a 1-based line and column in `text`.
fn offset_of(text: &str, line: u32, col: u32) -> usize {
    let start: usize =
        text.split_inclusive('\n').take(line.saturating_sub(1) as usize).map(str::len).sum();
    let col = text[start.min(text.len())..]
        .chars()
        .take(col.saturating_sub(1) as usize)
        .map(char::len_utf8)
        .sum::<usize>();
    (start + col).min(text.len())
}

/// Folder the embedded default dialect was taken from at build time ("none" if none).
pub fn embedded_origin() -> &'static str {
    EMBEDDED_ORIGIN
}

/// Loads a dialect file and its includes from disk.
pub fn load_dialect_file(path: &Path) -> Result<Dialect, DialectError> {
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_else(|| PathBuf::from("."));
    let root = path.file_name().and_then(|n| n.to_str()).unwrap_or("dialect.xml").to_string();
    let read = |name: &str| -> Result<String, DialectError> {
        let p = dir.join(name);
        std::fs::read_to_string(&p)
            .map_err(|source| DialectError::Io { path: p.display().to_string(), source })
    };
    load_dialect_from(&root, &read)
}

pub(super) fn load_embedded() -> Result<Dialect, DialectError> {
    if EMBEDDED_DIGEST.is_empty() {
        return Err(DialectError::NoEmbedded);
    }
    let raw = read_digest(EMBEDDED_DIGEST).map_err(|line| DialectError::Digest { line })?;
    from_raw(EMBEDDED_ROOT, raw)
}

/// Loads `root` through `read` (file name → text), following includes depth-first.
pub fn load_dialect_from(
    root: &str,
    read: &dyn Fn(&str) -> Result<String, DialectError>,
) -> Result<Dialect, DialectError> {
    let raw = read_xml(root, read).map_err(|e| match e {
        RawError::Read(e) => e,
        RawError::Xml { file, line, col, message } => {
            // Read again only to show where: the error path is cold.
            let text = read(&file).ok();
            let span = text.as_deref().map(|t| SourceSpan::from((offset_of(t, line, col), 0)));
            let src = text.map(|t| NamedSource::new(&file, t));
            DialectError::Xml(Box::new(XmlError { file, line, col, message, src, span }))
        }
        RawError::Message { file, message, problem, offset } => {
            let text = read(&file).ok();
            let span = text.as_ref().map(|_| SourceSpan::from((offset, 0)));
            let src = text.map(|t| NamedSource::new(&file, t));
            DialectError::Message(Box::new(MessageError { file, message, problem, src, span }))
        }
    })?;
    from_raw(root, raw)
}

/// Raw records → dialect tables (wire order, offsets, CRC_EXTRA): shared by XML and digest.
fn from_raw(root: &str, raw: RawDialect) -> Result<Dialect, DialectError> {
    let mut messages = Vec::with_capacity(raw.messages.len());
    for m in raw.messages {
        messages.push(finish_message(m)?);
    }
    let enums = raw
        .enums
        .into_iter()
        .map(|e| EnumDef { name: e.name, bitmask: e.bitmask, entries: e.entries })
        .collect();
    let name = root.trim_end_matches(".xml").to_string();
    Ok(Dialect::build(name, messages, enums))
}

fn finish_message(m: RawMessage) -> Result<MessageDef, DialectError> {
    let RawMessage { id, name, file, fields: raw_fields } = m;
    let bad = |problem: String| {
        DialectError::Message(Box::new(MessageError {
            file: file.clone(),
            message: name.clone(),
            problem,
            src: None,
            span: None,
        }))
    };
    let mut base = Vec::new();
    let mut ext = Vec::new();
    for f in raw_fields {
        let (prim, array_len) = parse_type(&f.ty)
            .ok_or_else(|| bad(format!("field {}: unknown type {}", f.name, f.ty)))?;
        let def = FieldDef {
            name: f.name,
            ty: prim,
            array_len,
            offset: 0,
            is_extension: f.is_extension,
            enum_name: f.enum_name,
        };
        if def.is_extension { ext.push(def) } else { base.push(def) }
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
