//! Behaviour-preserving rewrites of flight-plan XML, written independently of the code under
//! test (a lexical pass over the text, no XML library): re-indentation, attributes one per line
//! in reverse order, the other quote where that changes nothing, self-closing tags spelled out,
//! a comment added. Attribute values and `<header>` text are kept byte for byte.

/// A start tag's attribute: name and raw value (without quotes) and its quote character.
struct Attr<'a> {
    name: &'a str,
    value: &'a str,
    quote: char,
}

/// Splits the inside of a start tag (`name a="1" b='2'`) into the name and attributes.
fn split_tag(inner: &str) -> Option<(&str, Vec<Attr<'_>>)> {
    let name_end = inner.find(|c: char| c.is_whitespace()).unwrap_or(inner.len());
    let name = &inner[..name_end];
    let mut rest = &inner[name_end..];
    let mut attrs = Vec::new();
    loop {
        rest = rest.trim_start();
        if rest.is_empty() {
            return Some((name, attrs));
        }
        let eq = rest.find('=')?;
        let aname = rest[..eq].trim();
        let after = rest[eq + 1..].trim_start();
        let quote = after.chars().next()?;
        if quote != '"' && quote != '\'' {
            return None;
        }
        // xml-light: a backslash escapes the quote and itself.
        let body = &after[1..];
        let mut end = None;
        let mut escaped = false;
        for (i, c) in body.char_indices() {
            if escaped {
                escaped = false;
            } else if c == '\\' {
                escaped = true;
            } else if c == quote {
                end = Some(i);
                break;
            }
        }
        let end = end?;
        attrs.push(Attr { name: aname, value: &body[..end], quote });
        rest = &body[end + 1..];
    }
}

/// The end of the tag that starts at `text[start]` (`<`), quotes respected.
fn tag_end(text: &str, start: usize) -> Option<usize> {
    let mut quote: Option<char> = None;
    let mut escaped = false;
    for (i, c) in text[start..].char_indices() {
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                } else if c == '\\' {
                    escaped = true;
                } else if c == q {
                    quote = None;
                }
            }
            None if c == '"' || c == '\'' => quote = Some(c),
            None if c == '>' => return Some(start + i),
            None => {}
        }
    }
    None
}

/// The reformatted text (see the module documentation).
pub fn reformat(text: &str) -> String {
    let mut out = String::with_capacity(text.len() * 2);
    let mut depth: usize = 0;
    let mut i = 0;
    let mut in_header = false;
    let mut first_element = true;
    while i < text.len() {
        let rest = &text[i..];
        if rest.starts_with("<!--") {
            let end = rest.find("-->").map_or(text.len(), |e| i + e + 3);
            out.push_str(&text[i..end]);
            i = end;
            continue;
        }
        if rest.starts_with("<!") || rest.starts_with("<?") {
            let end = tag_end(text, i).map_or(text.len(), |e| e + 1);
            out.push_str(&text[i..end]);
            out.push('\n');
            i = end;
            continue;
        }
        if rest.starts_with("</") {
            let end = tag_end(text, i).map_or(text.len(), |e| e + 1);
            depth = depth.saturating_sub(1);
            if !in_header {
                out.push('\n');
                out.push_str(&"    ".repeat(depth));
            }
            in_header = false;
            out.push_str(&text[i..end]);
            i = end;
            continue;
        }
        if rest.starts_with('<') {
            let Some(end) = tag_end(text, i) else {
                out.push_str(rest);
                break;
            };
            let raw = &text[i + 1..end];
            let closed = raw.ends_with('/');
            let inner = raw.trim_end_matches('/');
            match split_tag(inner) {
                Some((name, attrs)) => {
                    write_tag(&mut out, depth, name, attrs, closed);
                    if first_element {
                        out.push_str("<!-- reformatted copy -->");
                        first_element = false;
                    }
                    if !closed {
                        depth += 1;
                        in_header = name.eq_ignore_ascii_case("header");
                    }
                }
                None => out.push_str(&text[i..=end]),
            }
            i = end + 1;
            continue;
        }
        // Text: blanks between tags are layout; other text (the header) is kept as it is.
        let end = rest.find('<').map_or(text.len(), |e| i + e);
        let t = &text[i..end];
        if !t.trim().is_empty() {
            out.push_str(t);
        }
        i = end;
    }
    out.push('\n');
    out
}

fn write_tag(out: &mut String, depth: usize, name: &str, attrs: Vec<Attr<'_>>, closed: bool) {
    if !out.is_empty() && !out.ends_with('\n') {
        out.push('\n');
    }
    let pad = "    ".repeat(depth);
    out.push_str(&pad);
    out.push('<');
    out.push_str(name);
    // Duplicates: the first occurrence wins, so later ones are dropped before reversing.
    let mut kept: Vec<&Attr<'_>> = Vec::new();
    for a in &attrs {
        if !kept.iter().any(|k| k.name.eq_ignore_ascii_case(a.name)) {
            kept.push(a);
        }
    }
    for a in kept.iter().rev() {
        // The other quote only where the value has neither quote nor backslash.
        let other = if a.quote == '"' { '\'' } else { '"' };
        let q = if a.value.contains(['"', '\'', '\\']) { a.quote } else { other };
        out.push_str(&format!("\n{pad}      {} = {q}{}{q}", a.name, a.value));
    }
    if closed {
        // `<x/>` spelled `<x></x>`.
        out.push_str(&format!("\n{pad}></{name}>"));
    } else {
        out.push('>');
    }
}
