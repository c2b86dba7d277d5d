//! Elements printed on one line the way upstream's NOTICEs quote them (xml-light's
//! `Xml.to_string`): tag and attribute names as the tree holds them, attribute values with `\`
//! and `"` escaped by a backslash, an element without children as `<tag …/>`, text with
//! `<`, `>`, `&` (unless it starts a `&#` reference), `'` and `"` written as entities.

use crate::ast::expanded::Node;

/// One element and everything below it, on one line.
pub fn to_string(n: &Node) -> String {
    let mut out = String::new();
    element(&mut out, n);
    out
}

fn element(out: &mut String, n: &Node) {
    out.push('<');
    out.push_str(&n.tag);
    for (name, value) in &n.attrs {
        attribute(out, name, value);
    }
    if n.children.is_empty() && n.text.is_none() {
        out.push_str("/>");
        return;
    }
    out.push('>');
    if let Some(t) = &n.text {
        text(out, t);
    }
    for c in &n.children {
        element(out, c);
    }
    out.push_str("</");
    out.push_str(&n.tag);
    out.push('>');
}

/// ` name="value"`, with `\` and `"` escaped by a backslash (both of upstream's printers).
pub(super) fn attribute(out: &mut String, name: &str, value: &str) {
    out.push(' ');
    out.push_str(name);
    out.push_str("=\"");
    for c in value.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '"' => out.push_str("\\\""),
            c => out.push(c),
        }
    }
    out.push('"');
}

fn text(out: &mut String, t: &str) {
    let mut chars = t.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '>' => out.push_str("&gt;"),
            '<' => out.push_str("&lt;"),
            '&' if chars.peek() == Some(&'#') => out.push('&'),
            '&' => out.push_str("&amp;"),
            '\'' => out.push_str("&apos;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prints_like_xml_light() {
        let a = |n: &str, v: &str| (n.to_string(), v.to_string());
        let wp = Node::new("waypoint", vec![a("Y", "57.0"), a("NAME", "T\"D\\")], Vec::new());
        let header = Node { text: Some("#include \"a.h\" <&#38;>".into()), ..Node::default() };
        let header = Node { tag: "header".into(), ..header };
        let root = Node::new("flight_plan", vec![a("ALT", "1")], vec![header, wp]);
        assert_eq!(
            to_string(&root),
            "<flight_plan ALT=\"1\"><header>#include &quot;a.h&quot; &lt;&#38;&gt;</header>\
             <waypoint Y=\"57.0\" NAME=\"T\\\"D\\\\\"/></flight_plan>"
        );
    }
}
