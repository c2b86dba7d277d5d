//! Source locations shared by every reader: a line (and, when known, a field on it) of a text
//! file as a miette span, so that errors render with the offending line and a caret.

use miette::{NamedSource, SourceSpan};

/// Span of `field` on the 1-based `line` of `text` (the first occurrence on that line), or of
/// the whole line (trimmed) when `field` is empty or not found. Never fails: a line past the end
/// yields an empty span at the end of the text.
pub fn field_span(text: &str, line: usize, field: &str) -> SourceSpan {
    let mut offset = 0;
    for (i, l) in text.split_inclusive('\n').enumerate() {
        if i + 1 == line {
            let body = l.trim_end_matches(['\n', '\r']);
            if !field.is_empty()
                && let Some(at) = body.find(field)
            {
                return (offset + at, field.len()).into();
            }
            let start = body.len() - body.trim_start().len();
            return (offset + start, body.trim().len()).into();
        }
        offset += l.len();
    }
    (text.len(), 0).into()
}

/// The named source of a text file for a diagnostic.
pub fn named_source(path: &std::path::Path, text: &str) -> NamedSource<String> {
    NamedSource::new(path.display().to_string(), text.to_string())
}

/// A piece of the input quoted in a message: control characters escaped and at most 40
/// characters (a binary file's "token" or a huge line can be megabytes; the excerpt under
/// the message shows where it is).
pub fn quote(s: &str) -> String {
    const MAX: usize = 40;
    let head: String = s.chars().take(MAX).collect();
    let more = if head.len() < s.len() { "…" } else { "" };
    format!("{}{more}", head.escape_debug())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_point_at_the_field_or_the_line() {
        let t = "a: 1\n  resolution: x\n";
        assert_eq!(field_span(t, 2, "x"), (19, 1).into());
        assert_eq!(field_span(t, 2, ""), (7, 13).into());
        assert_eq!(field_span(t, 9, "x"), (t.len(), 0).into());
    }
}
