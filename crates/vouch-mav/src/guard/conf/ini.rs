//! The INI dialect of mavlink-router's configuration files, read with the position of every
//! section and key so that whatever is wrong is reported at `file:line:col`.
//!
//! The syntax, as mavlink-router reads it: one item per line; blank lines and lines whose first
//! non-blank character is `#` or `;` are ignored (no comments after a value); `[Type]` or
//! `[Type name]` starts a section (no blanks just inside the brackets, one single space between
//! type and name); `Key = Value` with blanks around both trimmed, nothing else on the line (no
//! quotes, no escapes). Section types and names and keys are case-insensitive. A section given
//! again — in the same file or a later one — adds to the first; a key given again replaces its
//! value. A key before any section, a line without `=`, an empty key or value are errors.

use std::sync::Arc;

use miette::NamedSource;

use super::error::{ConfError, ConfErrorKind};

/// One file's text.
#[derive(Clone, Debug)]
pub struct Source {
    /// The path as given (used in messages).
    pub name: String,
    /// Its contents.
    pub text: String,
}

/// A place in one of the sources.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Place {
    /// Index of the source.
    pub file: usize,
    /// Byte offset in its text.
    pub offset: usize,
    /// Length in bytes.
    pub len: usize,
}

/// `Key = Value`, with where each part is.
#[derive(Clone, Debug)]
pub struct Entry {
    /// The key as written.
    pub key: String,
    /// The value, trimmed.
    pub value: String,
    /// Where the key is.
    pub key_at: Place,
    /// Where the value is.
    pub value_at: Place,
}

/// A section and its entries (the last value of each key).
#[derive(Clone, Debug)]
pub struct Section {
    /// The type, as first written (`UdpEndpoint`).
    pub kind: String,
    /// The name after the type, if any.
    pub name: Option<String>,
    /// Where its first header is.
    pub at: Place,
    /// Entries in the order their keys first appeared.
    pub entries: Vec<Entry>,
}

impl Section {
    /// The entry of `key` (case-insensitive).
    pub fn get(&self, key: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.key.eq_ignore_ascii_case(key))
    }
}

/// Everything read from one or more files.
#[derive(Clone, Debug, Default)]
pub struct Ini {
    /// The files, in the order read.
    pub sources: Vec<Source>,
    /// The same files as diagnostics show them, shared by every diagnostic of a file.
    named: Vec<Arc<NamedSource<String>>>,
    /// The sections, in the order they first appeared.
    pub sections: Vec<Section>,
}

impl Ini {
    /// Reads one more file into the sections read so far.
    pub fn add(&mut self, source: Source) -> Result<(), ConfError> {
        let file = self.sources.len();
        self.named.push(super::error::named(&source.name, &source.text));
        self.sources.push(source);
        let text = self.sources[file].text.clone();
        let mut current: Option<usize> = None;
        let mut offset = 0;
        for raw in text.split_inclusive('\n') {
            let line_start = offset;
            offset += raw.len();
            let body = raw.trim_end_matches(['\n', '\r']);
            let trimmed = body.trim();
            if trimmed.is_empty() || trimmed.starts_with('#') || trimmed.starts_with(';') {
                continue;
            }
            let start = line_start + (body.len() - body.trim_start().len());
            let at = |from: usize, len: usize| Place { file, offset: start + from, len };
            if trimmed.starts_with('[') {
                current = Some(self.section(trimmed, at(0, trimmed.len()))?);
                continue;
            }
            let Some(sec) = current else {
                return Err(self.err(
                    ConfErrorKind::Syntax,
                    at(0, trimmed.len()),
                    "a key before any section".into(),
                ));
            };
            let Some(eq) = trimmed.find('=') else {
                return Err(self.err(
                    ConfErrorKind::Syntax,
                    at(0, trimmed.len()),
                    "missing `=` (expected Key = Value)".into(),
                ));
            };
            let key_raw = &trimmed[..eq];
            let key = key_raw.trim_end();
            let value_raw = &trimmed[eq + 1..];
            let value = value_raw.trim_start();
            if key.is_empty() {
                return Err(self.err(
                    ConfErrorKind::Syntax,
                    at(eq, 1),
                    "missing key before `=`".into(),
                ));
            }
            if value.is_empty() {
                return Err(self.err(
                    ConfErrorKind::Syntax,
                    at(eq, 1),
                    format!("missing value for `{key}`"),
                ));
            }
            let value_from = eq + 1 + (value_raw.len() - value.len());
            let entry = Entry {
                key: key.to_string(),
                value: value.to_string(),
                key_at: at(0, key.len()),
                value_at: at(value_from, value.len()),
            };
            let entries = &mut self.sections[sec].entries;
            match entries.iter_mut().find(|e| e.key.eq_ignore_ascii_case(key)) {
                Some(old) => *old = entry,
                None => entries.push(entry),
            }
        }
        Ok(())
    }

    /// The index of the section a `[…]` line opens (an existing one of the same name, or new).
    fn section(&mut self, line: &str, at: Place) -> Result<usize, ConfError> {
        let syntax = |this: &Self, msg: &str| this.err(ConfErrorKind::Syntax, at, msg.into());
        let Some(close) = line.find(']') else {
            return Err(syntax(self, "unfinished section name: expected `]`"));
        };
        if close != line.len() - 1 {
            return Err(syntax(self, "characters after the section name"));
        }
        let inner = &line[1..close];
        if inner.is_empty()
            || inner.starts_with(char::is_whitespace)
            || inner.ends_with(char::is_whitespace)
        {
            return Err(syntax(
                self,
                "no blanks allowed just inside the brackets of a section name",
            ));
        }
        if inner.chars().any(|c| c.is_whitespace() && c != ' ') || inner.matches(' ').count() > 1 {
            return Err(syntax(
                self,
                "a section name is `[Type]` or `[Type name]` with one single space",
            ));
        }
        let (kind, name) = match inner.split_once(' ') {
            Some((k, n)) => (k, Some(n)),
            None => (inner, None),
        };
        let same = |s: &Section| {
            s.kind.eq_ignore_ascii_case(kind)
                && match (&s.name, name) {
                    (Some(a), Some(b)) => a.eq_ignore_ascii_case(b),
                    (None, None) => true,
                    _ => false,
                }
        };
        if let Some(i) = self.sections.iter().position(same) {
            return Ok(i);
        }
        self.sections.push(Section {
            kind: kind.to_string(),
            name: name.map(str::to_string),
            at,
            entries: Vec::new(),
        });
        Ok(self.sections.len() - 1)
    }

    /// An error of `kind` at `at`.
    pub fn err(&self, kind: ConfErrorKind, at: Place, message: String) -> ConfError {
        ConfError::in_file(kind, message, self.named[at.file].clone(), at.offset, at.len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Ini, ConfError> {
        let mut ini = Ini::default();
        ini.add(Source { name: "main.conf".into(), text: text.into() })?;
        Ok(ini)
    }

    #[test]
    fn sections_keys_comments_and_merging() {
        let ini = read(
            "# comment\n; another\n\n[General]\nTcpServerPort = 5760\n  ReportStats=true  \n\
             [UdpEndpoint qgc]\nMode = Normal\nAddress = 127.0.0.1\n[general]\ntcpserverport = 0\n\
             [UdpEndpoint QGC]\nPort = 14550",
        )
        .unwrap();
        assert_eq!(ini.sections.len(), 2, "[general] and [UdpEndpoint QGC] add to the first ones");
        let g = &ini.sections[0];
        assert_eq!(g.get("TCPSERVERPORT").unwrap().value, "0", "a later value replaces");
        assert_eq!(g.get("reportstats").unwrap().value, "true");
        let u = &ini.sections[1];
        assert_eq!((u.kind.as_str(), u.name.as_deref()), ("UdpEndpoint", Some("qgc")));
        assert_eq!(u.entries.len(), 3, "the last line counts without a newline");
        // positions point at the text
        let e = u.get("address").unwrap();
        let t = &ini.sources[0].text;
        assert_eq!(&t[e.value_at.offset..e.value_at.offset + e.value_at.len], "127.0.0.1");
        assert_eq!(&t[e.key_at.offset..e.key_at.offset + e.key_at.len], "Address");
    }

    #[test]
    fn what_mavlink_router_refuses_is_a_located_error() {
        for (text, line, col, what) in [
            ("Port = 1\n", 1, 1, "before any section"),
            ("[General]\nReportStats\n", 2, 1, "missing `=`"),
            ("[General]\n = 1\n", 2, 2, "missing key"),
            ("[General]\nReportStats =\n", 2, 13, "missing value"),
            ("[General\n", 1, 1, "expected `]`"),
            ("[General] x\n", 1, 1, "after the section name"),
            ("[ General]\n", 1, 1, "inside the brackets"),
            ("[UdpEndpoint  a]\n", 1, 1, "one single space"),
            ("[UdpEndpoint a b]\n", 1, 1, "one single space"),
        ] {
            let e = read(text).unwrap_err();
            assert!(e.to_string().contains(what), "{text:?}: {e}");
            assert_eq!(e.line_col(), (line, col), "{text:?}: {e}");
        }
    }
}
