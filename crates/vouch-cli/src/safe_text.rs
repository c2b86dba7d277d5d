//! Text from the input never reaches the terminal raw: control characters (C0 except tab and
//! line ends, DEL, C1) and the bidirectional embedding, override and isolate characters are
//! shown escaped, `\u{1b}`, in every message, source excerpt, note and JSON string the command
//! line prints, whatever the family. A crafted input (`ESC ] 0 ; … BEL` in a flight-plan
//! attribute, control bytes in a map or a recording) therefore cannot retitle the terminal,
//! move its cursor or reorder what a reader sees.
//!
//! [`SafeDiagnostic`] is a copy of a diagnostic with every text escaped and its source excerpt
//! escaped with the labels moved to match, so miette's renderers (and the short and JSON
//! formats) need no change. [`escape`] is the one rule; [`EscapingWriter`] applies it to
//! formatted output, [`JsonEscapes`] to JSON strings beyond what JSON itself escapes.

use std::borrow::Cow;
use std::fmt;

use miette::{
    Diagnostic, LabeledSpan, MietteError, MietteSpanContents, Severity, SourceCode, SourceSpan,
    SpanContents,
};

/// Whether `c` is shown escaped: control characters (tab and line feed excepted; a carriage
/// return is decided by [`escape`], which keeps it before a line feed) and the bidirectional
/// formatting characters (U+202A–U+202E, U+2066–U+2069) that reorder text on display.
pub fn is_unsafe(c: char) -> bool {
    (c.is_control() && c != '\n' && c != '\t')
        || ('\u{202a}'..='\u{202e}').contains(&c)
        || ('\u{2066}'..='\u{2069}').contains(&c)
}

/// `s` with every unsafe character as `\u{…}` (a carriage return before a line feed stays: CRLF
/// files are ordinary). Borrowed when nothing needs escaping.
pub fn escape(s: &str) -> Cow<'_, str> {
    if !s.chars().any(is_unsafe) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '\r' && chars.peek() == Some(&'\n') {
            out.push(c);
        } else if is_unsafe(c) {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// A `fmt::Write` / `io::Write` adapter target: escapes each piece of formatted text before it
/// reaches `inner` (used by the pipe-safe standard output for everything written with
/// `write!`).
pub struct EscapingWriter<'a, W: std::io::Write> {
    /// Where the escaped text goes.
    pub inner: &'a mut W,
    /// The first I/O error, kept because `fmt::Write` can only say that something failed.
    pub error: Option<std::io::Error>,
}

impl<W: std::io::Write> fmt::Write for EscapingWriter<'_, W> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.inner.write_all(escape(s).as_bytes()).map_err(|e| {
            self.error = Some(e);
            fmt::Error
        })
    }
}

/// serde_json's compact and pretty formatters with one addition: DEL, the C1 controls and the
/// bidirectional formatting characters, which JSON leaves raw, are written as `\uXXXX` (the
/// same JSON value; JSON itself escapes C0).
pub struct JsonEscapes<F>(pub F);

impl<F: serde_json::ser::Formatter> serde_json::ser::Formatter for JsonEscapes<F> {
    fn write_string_fragment<W: ?Sized + std::io::Write>(
        &mut self,
        writer: &mut W,
        fragment: &str,
    ) -> std::io::Result<()> {
        let mut rest = fragment;
        while let Some((i, c)) = rest.char_indices().find(|&(_, c)| is_unsafe(c)) {
            writer.write_all(&rest.as_bytes()[..i])?;
            write!(writer, "\\u{:04x}", u32::from(c))?;
            rest = &rest[i + c.len_utf8()..];
        }
        writer.write_all(rest.as_bytes())
    }

    // Every other method keeps serde_json's behaviour for `F`.
    fn begin_array<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.0.begin_array(w)
    }
    fn end_array<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.0.end_array(w)
    }
    fn begin_array_value<W: ?Sized + std::io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> std::io::Result<()> {
        self.0.begin_array_value(w, first)
    }
    fn end_array_value<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.0.end_array_value(w)
    }
    fn begin_object<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.0.begin_object(w)
    }
    fn end_object<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.0.end_object(w)
    }
    fn begin_object_key<W: ?Sized + std::io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> std::io::Result<()> {
        self.0.begin_object_key(w, first)
    }
    fn begin_object_value<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.0.begin_object_value(w)
    }
    fn end_object_value<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.0.end_object_value(w)
    }
}

/// Serialises `value` as JSON (pretty or compact) with [`JsonEscapes`].
pub fn to_json_writer<W: std::io::Write, T: serde::Serialize + ?Sized>(
    writer: W,
    value: &T,
    pretty: bool,
) -> serde_json::Result<()> {
    if pretty {
        let f = JsonEscapes(serde_json::ser::PrettyFormatter::new());
        value.serialize(&mut serde_json::Serializer::with_formatter(writer, f))
    } else {
        let f = JsonEscapes(serde_json::ser::CompactFormatter);
        value.serialize(&mut serde_json::Serializer::with_formatter(writer, f))
    }
}

/// A plain error message in an escaped cause chain.
#[derive(Debug)]
struct Cause {
    message: String,
    next: Option<Box<Cause>>,
}

impl fmt::Display for Cause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Cause {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.next.as_deref().map(|c| c as &(dyn std::error::Error + 'static))
    }
}

fn causes(e: Option<&dyn std::error::Error>) -> Option<Box<Cause>> {
    let e = e?;
    Some(Box::new(Cause { message: escape(&e.to_string()).into_owned(), next: causes(e.source()) }))
}

/// A line longer than this (bytes) is shown cut: windows around its labels, `…` between.
const LONG_LINE: usize = 240;
/// Bytes kept on each side of a label's ends on a long line, and at the start of one without.
const KEEP: usize = 60;

/// A source text with its unsafe characters escaped and its overlong lines cut, and the map
/// between original byte offsets and offsets in the shown text (the labels are moved with it).
#[derive(Debug)]
struct SafeSource {
    name: Option<String>,
    text: String,
    /// Original text, for the columns of the location line (miette counts bytes).
    original: Vec<u8>,
    /// The rewritten pieces, in order: `(original start, original end, shown start, shown end)`
    /// of each escaped character and each cut-out run; the text between them is copied.
    pieces: Vec<(usize, usize, usize, usize)>,
}

/// The byte ranges of `text` left out: on each line longer than [`LONG_LINE`], everything but
/// [`KEEP`] bytes around the ends of the labels on it (the line's start when it has none).
fn cut_ranges(text: &[u8], labels: &[SourceSpan]) -> Vec<(usize, usize)> {
    let mut cuts = Vec::new();
    let mut start = 0;
    for line in text.split_inclusive(|&b| b == b'\n') {
        let end = start + line.len();
        if line.len() > LONG_LINE {
            let mut keep: Vec<(usize, usize)> = labels
                .iter()
                .filter(|l| l.offset() < end && l.offset() + l.len() >= start)
                .flat_map(|l| {
                    let (a, b) = (l.offset(), l.offset() + l.len());
                    [(a.saturating_sub(KEEP), a + KEEP), (b.saturating_sub(KEEP), b + KEEP)]
                })
                .collect();
            if keep.is_empty() {
                keep.push((start, start + KEEP));
            }
            keep.push((end.saturating_sub(1), end)); // the line end stays
            keep.sort_unstable();
            let mut at = start;
            for (a, b) in keep {
                let (a, b) = (a.max(start), b.min(end));
                if a > at + 8 {
                    cuts.push((at, a));
                }
                at = at.max(b);
            }
        }
        start = end;
    }
    cuts
}

impl SafeSource {
    /// The whole text of `source` (read as one span with unlimited context), escaped and cut
    /// around `labels`; `None` when the source cannot give its whole text from offset 0.
    fn of(source: &dyn SourceCode, labels: &[SourceSpan]) -> Option<SafeSource> {
        let all = source.read_span(&SourceSpan::from((0, 0)), usize::MAX, usize::MAX).ok()?;
        if all.span().offset() != 0 {
            return None;
        }
        let original = all.data().to_vec();
        let name = all.name().map(|n| escape(n).into_owned());
        let cuts = cut_ranges(&original, labels);
        let mut shown =
            SafeSource { name, text: String::new(), original: Vec::new(), pieces: vec![] };
        let mut cut = cuts.iter().peekable();
        let mut at = 0;
        for chunk in original.utf8_chunks() {
            let mut chars = chunk.valid().chars().peekable();
            while let Some(c) = chars.next() {
                let crlf = c == '\r' && chars.peek() == Some(&'\n');
                let escaped = (is_unsafe(c) && !crlf).then(|| c.escape_unicode().to_string());
                shown.push(&mut cut, at, c.len_utf8(), escaped, c);
                at += c.len_utf8();
            }
            for b in chunk.invalid() {
                shown.push(&mut cut, at, 1, Some(format!("\\x{b:02x}")), '?');
                at += 1;
            }
        }
        shown.original = original;
        Some(shown)
    }

    /// Appends the character `c` of `len` bytes at original offset `at`: left out inside a cut
    /// (one `…` per cut), else escaped (`escaped`) or copied.
    fn push(
        &mut self,
        cut: &mut std::iter::Peekable<std::slice::Iter<'_, (usize, usize)>>,
        at: usize,
        len: usize,
        escaped: Option<String>,
        c: char,
    ) {
        while cut.peek().is_some_and(|&&(_, b)| b <= at) {
            cut.next();
        }
        if let Some(&&(a, _)) = cut.peek()
            && a <= at
        {
            match self.pieces.last_mut() {
                // the run of this cut goes on
                Some(p) if p.1 == at && p.0 >= a => p.1 = at + len,
                _ => {
                    let s = self.text.len();
                    self.text.push('…');
                    self.pieces.push((at, at + len, s, self.text.len()));
                }
            }
            return;
        }
        match escaped {
            Some(e) => {
                let s = self.text.len();
                self.text.push_str(&e);
                self.pieces.push((at, at + len, s, self.text.len()));
            }
            None => self.text.push(c),
        }
    }

    /// Shown offset of an original offset (inside a rewritten piece: the piece's start).
    fn to_escaped(&self, offset: usize) -> usize {
        let i = self.pieces.partition_point(|&(o, ..)| o <= offset);
        match i.checked_sub(1).and_then(|i| self.pieces.get(i)) {
            Some(&(_, o_end, e, _)) if offset < o_end => e,
            Some(&(_, o_end, _, e_end)) => e_end + (offset - o_end),
            None => offset,
        }
    }

    /// Original offset of a shown offset (inside a rewritten piece: the piece's start).
    fn to_original(&self, offset: usize) -> usize {
        let i = self.pieces.partition_point(|&(_, _, e, _)| e <= offset);
        match i.checked_sub(1).and_then(|i| self.pieces.get(i)) {
            Some(&(o, _, _, e_end)) if offset < e_end => o,
            Some(&(_, o_end, _, e_end)) => o_end + (offset - e_end),
            None => offset,
        }
        .min(self.original.len())
    }

    fn span(&self, s: SourceSpan) -> SourceSpan {
        let start = self.to_escaped(s.offset());
        let end = self.to_escaped(s.offset() + s.len());
        SourceSpan::from((start, end.saturating_sub(start)))
    }
}

impl SourceCode for SafeSource {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        before: usize,
        after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let c = self.text.read_span(span, before, after)?;
        // The column of the location line is the one in the user's file, not in the escaped
        // text.
        let start = self.to_original(c.span().offset());
        let line_start = self.original[..start]
            .iter()
            .rposition(|&b| b == b'\n' || b == b'\r')
            .map_or(0, |p| p + 1);
        let column = if c.column() == 0 { 0 } else { start - line_start };
        let data = c.data();
        let contents = match &self.name {
            Some(n) => MietteSpanContents::new_named(
                n.clone(),
                data,
                *c.span(),
                c.line(),
                column,
                c.line_count(),
            ),
            None => MietteSpanContents::new(data, *c.span(), c.line(), column, c.line_count()),
        };
        Ok(Box::new(contents))
    }
}

/// A diagnostic with every text escaped: message, code, help, URL, labels, cause chain,
/// related diagnostics and the source excerpt.
#[derive(Debug)]
pub struct SafeDiagnostic {
    message: String,
    code: Option<String>,
    severity: Option<Severity>,
    help: Option<String>,
    url: Option<String>,
    source_code: Option<SafeSource>,
    labels: Vec<LabeledSpan>,
    related: Vec<SafeDiagnostic>,
    inner: Option<Box<SafeDiagnostic>>,
    cause: Option<Box<Cause>>,
}

impl SafeDiagnostic {
    /// The escaped copy of `d` (related diagnostics and the diagnostic source included).
    pub fn new(d: &dyn Diagnostic) -> SafeDiagnostic {
        let text =
            |t: Option<Box<dyn fmt::Display + '_>>| t.map(|t| escape(&t.to_string()).into_owned());
        let spans: Vec<SourceSpan> = d.labels().into_iter().flatten().map(|l| *l.inner()).collect();
        let source_code = d.source_code().and_then(|s| SafeSource::of(s, &spans));
        let labels = d
            .labels()
            .into_iter()
            .flatten()
            .map(|l| {
                let label = l.label().map(|t| escape(t).into_owned());
                let span = source_code.as_ref().map_or(*l.inner(), |s| s.span(*l.inner()));
                if l.primary() {
                    LabeledSpan::new_primary_with_span(label, span)
                } else {
                    LabeledSpan::new_with_span(label, span)
                }
            })
            .collect();
        // Without its text the excerpt cannot be shown escaped: it is left out (the location
        // is lost, never the safety).
        let labels =
            if d.source_code().is_some() && source_code.is_none() { vec![] } else { labels };
        SafeDiagnostic {
            message: escape(&d.to_string()).into_owned(),
            code: text(d.code()),
            severity: d.severity(),
            help: text(d.help()),
            url: text(d.url()),
            source_code,
            labels,
            related: d.related().into_iter().flatten().map(SafeDiagnostic::new).collect(),
            inner: d.diagnostic_source().map(|s| Box::new(SafeDiagnostic::new(s))),
            cause: if d.diagnostic_source().is_some() { None } else { causes(d.source()) },
        }
    }
}

impl fmt::Display for SafeDiagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for SafeDiagnostic {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.inner {
            Some(d) => Some(d.as_ref()),
            None => self.cause.as_deref().map(|c| c as &(dyn std::error::Error + 'static)),
        }
    }
}

impl Diagnostic for SafeDiagnostic {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.code.as_ref().map(|c| Box::new(c) as Box<dyn fmt::Display>)
    }
    fn severity(&self) -> Option<Severity> {
        self.severity
    }
    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help.as_ref().map(|c| Box::new(c) as Box<dyn fmt::Display>)
    }
    fn url<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.url.as_ref().map(|c| Box::new(c) as Box<dyn fmt::Display>)
    }
    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.source_code.as_ref().map(|s| s as &dyn SourceCode)
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        if self.labels.is_empty() { None } else { Some(Box::new(self.labels.iter().cloned())) }
    }
    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn Diagnostic> + 'a>> {
        if self.related.is_empty() {
            None
        } else {
            Some(Box::new(self.related.iter().map(|d| d as &dyn Diagnostic)))
        }
    }
    fn diagnostic_source(&self) -> Option<&dyn Diagnostic> {
        self.inner.as_deref().map(|d| d as &dyn Diagnostic)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped_and_line_ends_kept() {
        assert_eq!(escape("a\u{1b}]0;x\u{7}b"), "a\\u{1b}]0;x\\u{7}b");
        assert_eq!(escape("l1\r\nl2\n\tx"), "l1\r\nl2\n\tx");
        assert_eq!(escape("over\rwrite"), "over\\u{d}write");
        assert_eq!(escape("\u{7f}\u{9b}\u{202e}"), "\\u{7f}\\u{9b}\\u{202e}");
        assert!(matches!(escape("plain ünïcode"), Cow::Borrowed(_)));
    }

    #[test]
    fn json_keeps_the_value_and_escapes_what_json_leaves_raw() {
        let v = serde_json::json!({"k": "a\u{7f}b\u{9b}c\u{1b}"});
        let mut out = Vec::new();
        to_json_writer(&mut out, &v, false).expect("writes");
        let text = String::from_utf8(out).expect("utf-8");
        assert_eq!(text, r#"{"k":"a\u007fb\u009bc\u001b"}"#);
        let back: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        assert_eq!(back, v);
    }

    #[derive(Debug, thiserror::Error, miette::Diagnostic)]
    #[error("bad name `{name}`")]
    #[diagnostic(code(test::E1), help("rename {name}"))]
    struct Crafted {
        name: String,
        #[source_code]
        src: miette::NamedSource<String>,
        #[label("here: {name}")]
        at: SourceSpan,
    }

    #[test]
    fn a_diagnostic_is_escaped_everywhere_and_its_label_still_points_at_the_same_text() {
        let text = "<a x=\"\u{1b}]0;t\u{7}\"/>\n<b name=\"q\"/>\n".to_string();
        let at = text.find("name").expect("in text");
        let d = Crafted {
            name: "\u{1b}[2J".into(),
            src: miette::NamedSource::new("p\u{7}.xml", text),
            at: (at, 4).into(),
        };
        let safe = SafeDiagnostic::new(&d);
        let mut out = String::new();
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            .render_report(&mut out, &safe)
            .expect("renders");
        assert!(!out.chars().any(|c| c == '\u{1b}' || c == '\u{7}'), "{out}");
        assert!(out.contains("\\u{1b}[2J"), "{out}");
        assert!(out.contains("<a x=\"\\u{1b}]0;t\\u{7}\"/>"), "{out}");
        // the location line is the user's file's: line 2, column 4
        assert!(out.contains("p\\u{7}.xml:2:4"), "{out}");
        // the label's span covers `name` in the escaped text
        let s = safe.labels().expect("labels").next().expect("one");
        let src = safe.source_code.as_ref().expect("source");
        assert_eq!(&src.text[s.offset()..s.offset() + s.len()], "name");
    }

    #[test]
    fn a_long_line_is_cut_around_its_label_which_still_points_at_the_same_text() {
        let mut text = "x".repeat(100_000);
        text.push_str("<bad\u{1b}/>");
        text.push_str(&"y".repeat(100_000));
        text.push('\n');
        let at = text.find("<bad").expect("in text");
        let d = Crafted {
            name: "n".into(),
            src: miette::NamedSource::new("huge.xml", text),
            at: (at, 7).into(),
        };
        let safe = SafeDiagnostic::new(&d);
        let mut out = String::new();
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            .render_report(&mut out, &safe)
            .expect("renders");
        assert!(out.len() < 2_000, "{} bytes", out.len());
        assert!(out.contains("huge.xml:1:100001"), "{out}");
        assert!(out.contains("…xxxx") && out.contains("<bad\\u{1b}/>yyy"), "{out}");
        let s = safe.labels().expect("labels").next().expect("one");
        let src = safe.source_code.as_ref().expect("source");
        assert_eq!(&src.text[s.offset()..s.offset() + s.len()], "<bad\\u{1b}/>");
    }

    #[test]
    fn escaped_offsets_map_back() {
        let src = "a\u{1b}b\u{7}c";
        let s = SafeSource::of(&src.to_string(), &[]).expect("whole text");
        assert_eq!(s.text, "a\\u{1b}b\\u{7}c");
        for (o, ch) in [(0, 'a'), (2, 'b'), (4, 'c')] {
            let e = s.to_escaped(o);
            assert_eq!(s.text[e..].chars().next(), Some(ch));
            assert_eq!(s.to_original(e), o);
        }
    }
}
