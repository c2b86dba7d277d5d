//! The expanded `<flight_plan>` element as upstream's generator holds it before numbering
//! ([`Node`]), rebuilt from the main document and the expanded lists:
//! * `<includes>` removed; with includes, the header and the six lists (`waypoints`, `blocks`,
//!   `modules`, `variables`, `exceptions`, `sectors`) are new elements without attributes,
//!   put where the plan had them, the missing ones first (upstream prepends them);
//! * `<waypoints>` and `<blocks>` without attributes (upstream rebuilds both), the implicit
//!   `HOME` block last.

use crate::ast::expanded::Node;

use super::include::Merged;
use super::tree::Elem;

/// The lists upstream prepends when an include adds them to a plan without them, in the order
/// they end up.
const PREPENDED: [&str; 5] = ["modules", "variables", "exceptions", "sectors", "header"];

/// Attribute order and spelling of upstream's DTD validation: sorted by upper-cased name, last
/// first, names upper-cased.
pub fn sort_validated(e: &mut Elem) {
    e.attrs.0.sort_by_key(|a| std::cmp::Reverse(a.name.to_ascii_uppercase()));
    for a in e.attrs.0.iter_mut() {
        a.upper = true;
    }
    for c in e.children.iter_mut() {
        sort_validated(c);
    }
}

fn node(e: &Elem) -> Node {
    Node { children: e.children.iter().map(node).collect(), ..leaf(e) }
}

/// The element without its children.
fn leaf(e: &Elem) -> Node {
    let name = |a: &crate::ast::RawAttr| {
        if a.upper { a.name.to_ascii_uppercase() } else { a.name.clone() }
    };
    let attrs = e.attrs.0.iter().map(|a| (name(a), a.value.clone())).collect();
    Node { tag: e.tag.clone(), attrs, children: Vec::new(), text: None }
}

fn list(tag: &str, elems: &[Elem]) -> Node {
    Node::new(tag, Vec::new(), elems.iter().map(node).collect())
}

fn header(text: &Option<(String, crate::span::Span)>, tag: &str) -> Node {
    Node { text: text.as_ref().map(|(t, _)| t.clone()), ..Node::new(tag, Vec::new(), Vec::new()) }
}

/// The merged list of a top-level tag (lower-case), when it is one.
fn merged<'a>(m: &'a Merged, tag: &str) -> Option<&'a [Elem]> {
    Some(match tag {
        "waypoints" => &m.waypoints,
        "blocks" => &m.blocks,
        "modules" => &m.modules,
        "variables" => &m.variables,
        "exceptions" => &m.exceptions,
        "sectors" => &m.sectors,
        _ => return None,
    })
}

/// The expanded plan: `root` is the main document's root, `m` the lists after includes, paths
/// and relative waypoints.
pub fn build(root: &Elem, m: &Merged, had_includes: bool) -> Node {
    let mut children = Vec::new();
    let mut seen: Vec<String> = Vec::new();
    for c in &root.children {
        let lc = c.tag.to_ascii_lowercase();
        if lc == "includes" {
            continue;
        }
        seen.push(lc.clone());
        let n = match (lc.as_str(), merged(m, &lc)) {
            ("waypoints" | "blocks", Some(l)) => list(&lc, l),
            (_, Some(l)) if had_includes => list(&lc, l),
            ("header", _) if had_includes => header(&m.header, "header"),
            ("header", _) => Node { text: m.header.as_ref().map(|(t, _)| t.clone()), ..leaf(c) },
            _ => node(c),
        };
        children.push(n);
    }
    if had_includes {
        let missing: Vec<Node> = PREPENDED
            .iter()
            .filter(|t| !seen.iter().any(|s| s == *t))
            .map(|t| match merged(m, t) {
                Some(l) => list(t, l),
                None => header(&m.header, "header"),
            })
            .collect();
        children.splice(0..0, missing);
    }
    if let Some(blocks) = children.iter_mut().find(|c| c.tag.eq_ignore_ascii_case("blocks")) {
        let home = Node::new("home", Vec::new(), Vec::new());
        blocks.children.push(Node::new("block", vec![("name".into(), "HOME".into())], vec![home]));
    }
    Node { children, ..leaf(root) }
}
