//! The tolerant pre-pass: turns what upstream's lenient xml-light accepts into well-formed XML
//! for roxmltree, **without changing the length or the offsets of the text**, so every
//! position roxmltree reports is a position in the original file.
//!
//! It is not an XML parser: it only tracks enough lexical state (text, tag, quoted value,
//! comment, CDATA, processing instruction, DOCTYPE) to neutralise, byte for byte:
//! * raw `<` and `&` inside attribute values (replaced by `_`; values are later read from the
//!   *original* text, so nothing is lost);
//! * backslash-escaped quotes inside values (xml-light reads `\"` as a quote);
//! * `--` inside comments (replaced by spaces; comments end at the first `-->`);
//! * `&` in text that does not start a predefined or numeric entity;
//! * duplicate attributes (the later ones are blanked out: first one wins, as upstream).
//!
//! Anything else that is broken is left alone, so roxmltree reports it with its position.

/// A byte range of the original text the pre-pass rewrote, with what it did.
#[derive(Debug, Clone, PartialEq)]
pub struct Fix {
    pub start: usize,
    pub end: usize,
    pub what: FixKind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FixKind {
    /// A duplicate attribute was dropped (first occurrence wins).
    DuplicateAttribute,
    /// Raw `<` / `&` / escaped quote in an attribute value.
    RawCharInValue,
    /// `--` inside a comment.
    DashesInComment,
    /// A bare `&` in text.
    RawAmpersandInText,
}

/// Result of the pre-pass.
#[derive(Debug, Clone)]
pub struct Sanitized {
    /// Same length as the source; only ASCII bytes replaced by ASCII bytes.
    pub text: String,
    pub fixes: Vec<Fix>,
    /// Root name declared by a real (not commented-out) `<!DOCTYPE name ...>`.
    pub doctype: Option<String>,
    /// The DTD file a `SYSTEM` (or `PUBLIC`) DOCTYPE names, and the DOCTYPE's byte offset.
    pub dtd_file: Option<(String, usize)>,
    /// Offset of the first start tag nested deeper than [`MAX_DEPTH`], if any. roxmltree
    /// recurses per nesting level, so such inputs are refused before it runs.
    pub too_deep_at: Option<usize>,
    /// Offset of an `<!ENTITY` declaration in the DOCTYPE. Entity text expands into elements
    /// the nesting count above cannot see, so such declarations are refused (the corpus has none).
    pub entity_at: Option<usize>,
}

/// Nesting depth accepted (real plans nest fewer than 10 levels).
pub const MAX_DEPTH: usize = 200;

/// The last quoted text of a DOCTYPE declaration before any internal subset (the system
/// identifier of `SYSTEM "f"` and of `PUBLIC "id" "f"`).
fn system_file(decl: &str) -> Option<String> {
    let head = decl.split('[').next().unwrap_or(decl);
    if !(head.contains("SYSTEM") || head.contains("PUBLIC")) {
        return None;
    }
    let quoted: Vec<&str> = head.split(['"', '\'']).collect();
    (quoted.len() >= 3).then(|| quoted[quoted.len() - 2].to_string())
}

/// Runs the pre-pass over `src`.
pub fn sanitize(src: &str) -> Sanitized {
    let mut out: Vec<u8> = src.as_bytes().to_vec();
    let mut fixes = Vec::new();
    let mut doctype = None;
    let mut dtd_file = None;
    let mut depth = 0usize;
    let mut too_deep_at = None;
    let mut entity_at = None;
    let b = src.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'<' {
            if b[i..].starts_with(b"<!--") {
                i = comment(b, &mut out, i, &mut fixes);
            } else if b[i..].starts_with(b"<![CDATA[") {
                i = find(b, i + 9, b"]]>").map(|p| p + 3).unwrap_or(b.len());
            } else if b[i..].starts_with(b"<?") {
                i = find(b, i + 2, b"?>").map(|p| p + 2).unwrap_or(b.len());
            } else if b[i..].starts_with(b"<!") {
                if b[i..].starts_with(b"<!DOCTYPE") && doctype.is_none() {
                    let name: String = src[i + 9..]
                        .trim_start()
                        .chars()
                        .take_while(|c| !c.is_whitespace() && *c != '>' && *c != '[')
                        .collect();
                    doctype = Some(name);
                }
                let end = declaration(b, i);
                if dtd_file.is_none() && b[i..].starts_with(b"<!DOCTYPE") {
                    dtd_file = system_file(&src[i..end]).map(|f| (f, i));
                }
                if entity_at.is_none() {
                    entity_at = find(&b[..end], i, b"<!ENTITY");
                }
                i = end;
            } else {
                let start = i;
                i = tag(b, &mut out, i, &mut fixes);
                if b.get(start + 1) == Some(&b'/') {
                    depth = depth.saturating_sub(1);
                } else if !b[..i].ends_with(b"/>") {
                    depth += 1;
                    if depth > MAX_DEPTH && too_deep_at.is_none() {
                        too_deep_at = Some(start);
                    }
                }
            }
        } else if b[i] == b'&' {
            if !starts_entity(&b[i..]) {
                out[i] = b'_';
                fixes.push(Fix { start: i, end: i + 1, what: FixKind::RawAmpersandInText });
            }
            i += 1;
        } else {
            i += 1;
        }
    }
    // Only ASCII bytes were replaced by ASCII bytes, so UTF-8 validity is preserved.
    let text = String::from_utf8(out).unwrap_or_else(|_| src.to_string());
    Sanitized { text, fixes, doctype, dtd_file, too_deep_at, entity_at }
}

fn find(b: &[u8], from: usize, pat: &[u8]) -> Option<usize> {
    if from > b.len() {
        return None;
    }
    b[from..].windows(pat.len()).position(|w| w == pat).map(|p| p + from)
}

/// `&name;` with a predefined name, or `&#..;` / `&#x..;`.
fn starts_entity(s: &[u8]) -> bool {
    for e in [&b"&amp;"[..], b"&lt;", b"&gt;", b"&quot;", b"&apos;"] {
        if s.starts_with(e) {
            return true;
        }
    }
    if s.starts_with(b"&#x") {
        let n = s[3..].iter().take_while(|c| c.is_ascii_hexdigit()).count();
        return n > 0 && s.get(3 + n) == Some(&b';');
    }
    if s.starts_with(b"&#") {
        let n = s[2..].iter().take_while(|c| c.is_ascii_digit()).count();
        return n > 0 && s.get(2 + n) == Some(&b';');
    }
    false
}

/// Comment from `<!--` at `i` to the first `-->`; dashes inside are blanked.
fn comment(b: &[u8], out: &mut [u8], i: usize, fixes: &mut Vec<Fix>) -> usize {
    let body = i + 4;
    let Some(end) = find(b, body, b"-->") else {
        return b.len(); // unterminated: roxmltree will report it
    };
    let mut fixed = false;
    for k in body..end {
        if b[k] == b'-'
            && (b.get(k + 1) == Some(&b'-') || k + 1 == end || (k > body && b[k - 1] == b'-'))
        {
            out[k] = b' ';
            fixed = true;
        }
    }
    if fixed {
        fixes.push(Fix { start: i, end: end + 3, what: FixKind::DashesInComment });
    }
    end + 3
}

/// `<!DOCTYPE ...>` possibly with an internal subset `[...]`; skipped untouched.
fn declaration(b: &[u8], i: usize) -> usize {
    let mut k = i + 2;
    let mut depth = 0i32;
    let mut quote: Option<u8> = None;
    while k < b.len() {
        let c = b[k];
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None => match c {
                b'"' | b'\'' => quote = Some(c),
                b'[' => depth += 1,
                b']' => depth -= 1,
                b'>' if depth <= 0 => return k + 1,
                _ => {}
            },
        }
        k += 1;
    }
    b.len()
}

fn is_name_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, b'_' | b'-' | b'.' | b':') || c >= 0x80
}

/// A start or end tag at `i`. Returns the index after it.
fn tag(b: &[u8], out: &mut [u8], i: usize, fixes: &mut Vec<Fix>) -> usize {
    let mut k = i + 1;
    if b.get(k) == Some(&b'/') {
        // End tag: nothing to fix.
        return find(b, k, b">").map(|p| p + 1).unwrap_or(b.len());
    }
    while k < b.len() && is_name_char(b[k]) {
        k += 1;
    }
    let mut seen: Vec<&[u8]> = Vec::new();
    loop {
        while k < b.len() && b[k].is_ascii_whitespace() {
            k += 1;
        }
        if k >= b.len() {
            return k;
        }
        if b[k] == b'>' {
            return k + 1;
        }
        if b[k..].starts_with(b"/>") {
            return k + 2;
        }
        let attr_start = k;
        while k < b.len() && is_name_char(b[k]) {
            k += 1;
        }
        if k == attr_start {
            return k; // malformed: let roxmltree report it
        }
        let name = &b[attr_start..k];
        while k < b.len() && b[k].is_ascii_whitespace() {
            k += 1;
        }
        if b.get(k) != Some(&b'=') {
            return k;
        }
        k += 1;
        while k < b.len() && b[k].is_ascii_whitespace() {
            k += 1;
        }
        let q = match b.get(k) {
            Some(&q @ (b'"' | b'\'')) => q,
            _ => return k,
        };
        k += 1;
        let value_start = k;
        while k < b.len() && b[k] != q {
            if b[k] == b'\\' && (b.get(k + 1) == Some(&q) || b.get(k + 1) == Some(&b'\\')) {
                if b[k + 1] == q {
                    out[k + 1] = b'_';
                    fixes.push(Fix { start: k, end: k + 2, what: FixKind::RawCharInValue });
                }
                k += 2;
                continue;
            }
            if b[k] == b'<' || b[k] == b'&' {
                out[k] = b'_';
                fixes.push(Fix { start: k, end: k + 1, what: FixKind::RawCharInValue });
            }
            k += 1;
        }
        if k >= b.len() {
            return k;
        }
        let _ = value_start;
        k += 1; // closing quote
        if seen.contains(&name) {
            for c in out.iter_mut().take(k).skip(attr_start) {
                *c = b' ';
            }
            fixes.push(Fix { start: attr_start, end: k, what: FixKind::DuplicateAttribute });
        } else {
            seen.push(name);
        }
    }
}
