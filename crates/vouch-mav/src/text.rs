//! Text that came from input (frames, file names) made safe to show: a control character
//! reaching a terminal raw could retitle it, move the cursor or hide what follows.

use std::borrow::Cow;

/// `s` with every control character (C0, DEL, C1) written as `\u{…}`; borrowed when there is
/// none.
pub fn escape_controls(s: &str) -> Cow<'_, str> {
    if !s.chars().any(char::is_control) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if c.is_control() {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::escape_controls;

    #[test]
    fn controls_are_escaped_and_other_text_kept() {
        assert_eq!(escape_controls("plain ↔ text"), "plain ↔ text");
        assert_eq!(escape_controls("a\u{1b}]0;x\u{7}b"), "a\\u{1b}]0;x\\u{7}b");
        assert_eq!(escape_controls("\u{9b}\u{7f}\n"), "\\u{9b}\\u{7f}\\u{a}");
    }
}
