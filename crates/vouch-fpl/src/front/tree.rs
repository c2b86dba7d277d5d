//! Reads one file into a small owned element tree ([`Elem`]) with spans into the original
//! text: tolerant pre-pass, then roxmltree, then attribute values taken from the *original*
//! text (not entity-decoded, backslash escapes applied), as upstream's xml-light does.

use crate::ast::{Attrs, RawAttr};
use crate::diag::{Diagnostic, ErrorKind};
use crate::span::{FileId, Span};

use super::tolerant::{FixKind, sanitize};

/// Maps byte offsets to 1-based line/column quickly (binary search over line starts).
pub struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    pub fn new(text: &str) -> Self {
        let mut starts = vec![0];
        starts.extend(text.bytes().enumerate().filter(|(_, b)| *b == b'\n').map(|(i, _)| i + 1));
        LineIndex { starts }
    }
    pub fn span(&self, text: &str, file: FileId, start: usize, end: usize) -> Span {
        let line = self.starts.partition_point(|&s| s <= start).max(1);
        let ls = self.starts[line - 1];
        let col = text.get(ls..start).map(|s| s.chars().count()).unwrap_or(start - ls) + 1;
        Span { file, start: start as u32, end: end as u32, line: line as u32, col: col as u32 }
    }
    /// Byte offset of a 1-based (row, col) position as roxmltree reports it.
    pub fn offset(&self, text: &str, row: u32, col: u32) -> usize {
        let ls = self.starts.get((row.max(1) - 1) as usize).copied().unwrap_or(text.len());
        let rest = text.get(ls..).unwrap_or("");
        let off: usize = rest.chars().take((col.max(1) - 1) as usize).map(|c| c.len_utf8()).sum();
        (ls + off).min(text.len())
    }
}

/// An element as upstream sees it.
#[derive(Debug, Clone)]
pub struct Elem {
    /// Tag as written (case preserved: stage dispatch is case-sensitive upstream).
    pub tag: String,
    pub attrs: Attrs,
    pub children: Vec<Elem>,
    /// Text content (only used for `<header>`): entity-decoded, whitespace-only lines dropped.
    pub text: String,
    /// Span of `<tag`.
    pub span: Span,
    /// Include name when the element comes from a procedure.
    pub origin: Option<String>,
    /// True for `go` stages generated from `<path>`.
    pub from_path: bool,
    /// For waypoints created from `wp_qdr`/`wp_dist`: (base, qdr, dist).
    pub relative: Option<(String, f64, f64)>,
}

impl Elem {
    pub fn tag_is(&self, t: &str) -> bool {
        self.tag.eq_ignore_ascii_case(t)
    }
    pub fn attr(&self, name: &str) -> Option<&RawAttr> {
        self.attrs.get(name)
    }
    pub fn attr_value(&self, name: &str) -> Option<&str> {
        self.attrs.get(name).map(|a| a.value.as_str())
    }
    pub fn child(&self, t: &str) -> Option<&Elem> {
        self.children.iter().find(|c| c.tag_is(t))
    }
    /// Upstream's `subst_attrib`: every `name` attribute removed, the new value appended last
    /// (keeping the first one's spans).
    pub fn subst_attr(&mut self, name: &str, value: String) {
        let Some(pos) = self.attrs.0.iter().position(|a| a.name == name) else { return };
        let mut a = self.attrs.0.remove(pos);
        self.attrs.0.retain(|x| x.name != name);
        a.value = value;
        self.attrs.0.push(a);
    }
}

/// A parsed file.
pub struct Document {
    pub root: Elem,
    pub doctype: Option<String>,
    /// The DTD file the DOCTYPE names (relative to the file) and the span of the DOCTYPE.
    pub dtd_file: Option<(String, Span)>,
    /// Non-fatal notes (duplicate attributes dropped, raw characters accepted).
    pub warnings: Vec<Diagnostic>,
}

/// Parses `text` (the original file content) as file `file`.
pub fn read_document(file: FileId, text: &str) -> Result<Document, Box<Diagnostic>> {
    let lines = LineIndex::new(text);
    let san = sanitize(text);
    let mut warnings = Vec::new();
    for f in &san.fixes {
        if f.what == FixKind::DuplicateAttribute {
            warnings.push(Diagnostic::warning(
                "duplicate attribute ignored (the first occurrence wins, as in upstream's parser)",
                Some(lines.span(text, file, f.start, f.end)),
            ));
        }
    }
    if let Some(at) = san.too_deep_at {
        return Err(Box::new(Diagnostic::error(
            ErrorKind::Xml,
            format!("elements nested more than {} levels deep", super::tolerant::MAX_DEPTH),
            Some(lines.span(text, file, at, at + 1)),
        )));
    }
    if let Some(at) = san.entity_at {
        return Err(Box::new(Diagnostic::error(
            ErrorKind::Xml,
            "entity declarations are not supported in flight plans",
            Some(lines.span(text, file, at, at + 8)),
        )));
    }
    let opts =
        roxmltree::ParsingOptions { allow_dtd: true, nodes_limit: u32::MAX, ..Default::default() };
    let doc = roxmltree::Document::parse_with_options(&san.text, opts).map_err(|e| {
        let off = match e {
            // roxmltree reports these at 1:1; the problem is at the end of the content.
            roxmltree::Error::UnclosedRootNode | roxmltree::Error::UnexpectedEndOfStream => {
                text.trim_end().char_indices().last().map_or(0, |(i, _)| i)
            }
            _ => {
                let pos = e.pos();
                lines.offset(text, pos.row, pos.col)
            }
        };
        let end = (off + text.get(off..).and_then(|t| t.chars().next()).map_or(0, char::len_utf8))
            .min(text.len());
        Box::new(Diagnostic::error(
            ErrorKind::Xml,
            format!("malformed XML: {e}"),
            Some(lines.span(text, file, off, end)),
        ))
    })?;
    let root = convert(doc.root_element(), text, file, &lines, &mut warnings, 0)?;
    let dtd_file = san.dtd_file.map(|(f, at)| (f, lines.span(text, file, at, at + 9)));
    Ok(Document { root, doctype: san.doctype, dtd_file, warnings })
}

/// Element nesting limit: real plans nest a handful of levels; the limit keeps hostile inputs
/// from exhausting the stack in the recursive passes.
pub const MAX_NESTING: usize = 200;

fn convert(
    n: roxmltree::Node<'_, '_>,
    text: &str,
    file: FileId,
    lines: &LineIndex,
    warnings: &mut Vec<Diagnostic>,
    depth: usize,
) -> Result<Elem, Box<Diagnostic>> {
    let tag = n.tag_name().name().to_string();
    let start = n.range().start;
    let span = lines.span(text, file, start, (start + 1 + tag.len()).min(text.len()));
    if depth > MAX_NESTING {
        return Err(Box::new(Diagnostic::error(
            ErrorKind::Xml,
            format!("elements nested more than {MAX_NESTING} levels deep"),
            Some(span),
        )));
    }
    let mut attrs: Vec<RawAttr> = Vec::new();
    for a in n.attributes() {
        let name = a.name().to_ascii_lowercase();
        let r = a.range();
        let rv = a.range_value();
        let raw = text.get(rv.clone()).unwrap_or("");
        let attr_span = lines.span(text, file, r.start, r.end);
        if attrs.iter().any(|x| x.name == name) {
            // Same name in another case (`name` / `NAME`): upstream's case-insensitive lookup
            // finds the first one.
            warnings.push(Diagnostic::warning(
                format!("duplicate attribute '{name}' ignored (first occurrence wins)"),
                Some(attr_span),
            ));
            continue;
        }
        attrs.push(RawAttr {
            name,
            value: unescape(raw),
            span: attr_span,
            value_span: lines.span(text, file, rv.start, rv.end),
            upper: false,
        });
    }
    let mut children = Vec::new();
    let mut raw_text = String::new();
    for c in n.children() {
        if c.is_element() {
            children.push(convert(c, text, file, lines, warnings, depth + 1)?);
        } else if c.is_text() {
            raw_text.push_str(text.get(c.range()).unwrap_or(""));
        }
    }
    Ok(Elem {
        tag,
        attrs: Attrs(attrs),
        children,
        text: clean_text(&raw_text),
        span,
        origin: None,
        from_path: false,
        relative: None,
    })
}

/// xml-light's only processing of attribute values: `\"`, `\'` and `\\`.
fn unescape(raw: &str) -> String {
    if !raw.contains('\\') {
        return raw.to_string();
    }
    let mut out = String::with_capacity(raw.len());
    let mut it = raw.chars().peekable();
    while let Some(c) = it.next() {
        if c == '\\'
            && let Some(&n) = it.peek()
            && (n == '"' || n == '\'' || n == '\\')
        {
            out.push(n);
            it.next();
            continue;
        }
        out.push(c);
    }
    out
}

/// Text content as upstream keeps it. xml-light reads text a line at a time: a carriage return
/// ends a line like a newline does (both are separators, never content), a line of blanks
/// (spaces and tabs only) is dropped, and the lines left are joined with `\n`. So a plan saved
/// with Windows line endings has the same text as with Unix ones. Predefined and numeric
/// entities are decoded, an unknown `&name;` is kept.
fn clean_text(raw: &str) -> String {
    raw.split(['\r', '\n'])
        .filter(|l| !l.chars().all(|c| c == ' ' || c == '\t'))
        .map(decode_entities)
        .collect::<Vec<_>>()
        .join("\n")
}

fn decode_entities(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(p) = rest.find('&') {
        out.push_str(&rest[..p]);
        rest = &rest[p..];
        let Some(semi) = rest.find(';') else { break };
        let name = &rest[1..semi];
        let rep = match name {
            "amp" => Some('&'),
            "lt" => Some('<'),
            "gt" => Some('>'),
            "quot" => Some('"'),
            "apos" => Some('\''),
            _ => name
                .strip_prefix("#x")
                .and_then(|h| u32::from_str_radix(h, 16).ok())
                .or_else(|| name.strip_prefix('#').and_then(|d| d.parse().ok()))
                .and_then(char::from_u32),
        };
        match rep {
            Some(c) => {
                out.push(c);
                rest = &rest[semi + 1..];
            }
            None => {
                out.push('&');
                rest = &rest[1..];
            }
        }
    }
    out.push_str(rest);
    out
}
