//! The plan as upstream's generator holds it once everything is expanded, before numbering: a
//! plain tree of elements (tag, attributes in upstream's order, children, optional text). The
//! dump (`--dump`, Paparazzi's `flight_plan.xml`) and the elements quoted in upstream's SRTM
//! NOTICE are printed from it.
//!
//! Attribute order and spelling follow upstream's reader: in a file validated against its DTD
//! the attributes are sorted by upper-cased name, last first, and their names upper-cased;
//! elsewhere they stay as written (lower-cased); rewritten elements put their new attributes,
//! lower-case, where upstream does.

use serde::Serialize;

/// One element of the expanded plan.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Node {
    /// Tag as written (the dump lower-cases it).
    pub tag: String,
    /// (name, value) pairs, names spelt as upstream's tree holds them, values raw.
    pub attrs: Vec<(String, String)>,
    /// Child elements.
    pub children: Vec<Node>,
    /// Text content, when the element holds text (only `<header>` does).
    pub text: Option<String>,
}

impl Node {
    /// An element without text.
    pub fn new(tag: &str, attrs: Vec<(String, String)>, children: Vec<Node>) -> Node {
        Node { tag: tag.to_string(), attrs, children, text: None }
    }
    /// First attribute of that name (case-insensitive, as upstream's lookup).
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)).map(|(_, v)| v.as_str())
    }
    /// Replaces an attribute the way upstream's `subst_attrib` does: every occurrence removed,
    /// the new value appended last.
    pub fn subst_attr(&mut self, name: &str, value: String) {
        self.attrs.retain(|(n, _)| !n.eq_ignore_ascii_case(name));
        self.attrs.push((name.to_string(), value));
    }
}
