//! The `--dump` file: what upstream's build writes as `var/aircrafts/AC/flight_plan.xml` for
//! the server and the ground station, byte for byte. It is the expanded plan
//! ([`crate::ast::expanded::Node`]: procedures included, paths expanded, relative waypoints
//! created, `HOME` appended) with
//! * waypoints given by `lat`/`lon` localised (`x`, `y` as `%.2f` metres from the reference,
//!   appended last, in the UTM frame only),
//! * blocks and stages numbered with a `no` attribute appended last (upstream's `index_blocks`:
//!   a `for` takes its test stage's number, a `while` its test, a two-step stage its second),
//! * followed by a `<stages>` index: one `<stage block= block_name= stage=>` element per
//!   numbered stage, holding the stage element, in reverse order of a pre-order walk.
//!
//! Printing follows upstream's `ExtXml.to_string_fmt`: tags and attribute names lower-cased,
//! two spaces of indentation per level, an element without children as `<tag …/>`, text
//! printed raw, in attribute values only `\` and `"` escaped with a backslash.

use crate::ast::expanded::Node;
use crate::ast::{FlightPlan, WpFrame};
use crate::front::values::degrees;
use crate::passes::CompileError;

use super::geo::{self, Geo};

/// The dump of a parsed plan (its expanded tree is kept by the front end).
pub fn dump(plan: &FlightPlan) -> Result<String, CompileError> {
    let (fp, stages) = processed(plan)?;
    let root = Node::new("dump", Vec::new(), vec![fp, Node::new("stages", Vec::new(), stages)]);
    let mut out = String::with_capacity(64 * 1024);
    print_node(&mut out, &root);
    Ok(out)
}

/// The plan as upstream's generator holds it while it writes the header or the dump: the
/// expanded tree with waypoints localised and blocks and stages numbered; and the `<stages>`
/// index of the dump.
pub(crate) fn processed(plan: &FlightPlan) -> Result<(Node, Vec<Node>), CompileError> {
    let Some(expanded) = plan.expanded.as_deref() else {
        return Err(CompileError::new("the plan keeps no expanded tree to dump", plan.span));
    };
    let mut fp = expanded.clone();
    if !matches!(plan.wp_frame.as_ref().map(|f| f.value), Some(WpFrame::Ltp)) {
        localize(&mut fp, plan);
    }
    let stages = number(&mut fp);
    Ok((fp, stages))
}

/// A whole document the way upstream writes it (`ExtXml.to_string_fmt`, then a newline).
pub(crate) fn print_node(out: &mut String, root: &Node) {
    print(out, root, "", false);
    out.push('\n');
}

/// `x`/`y` of waypoints given by latitude and longitude, relative to the reference UTM
/// position, projected in the reference zone (upstream's `localize_waypoint`).
fn localize(fp: &mut Node, plan: &FlightPlan) {
    let reference =
        Geo { lat: geo::rad_of_deg(plan.lat0.value), lon: geo::rad_of_deg(plan.lon0.value) };
    let utm0 = geo::utm_of(reference, None);
    let Some(wps) = fp.children.iter_mut().find(|c| c.tag.eq_ignore_ascii_case("waypoints")) else {
        return;
    };
    for w in wps.children.iter_mut() {
        let (Some(lat), Some(lon)) =
            (w.attr("lat").and_then(degrees), w.attr("lon").and_then(degrees))
        else {
            continue;
        };
        let u = geo::utm_of(geo::geo_of_deg(lat, lon), Some(utm0.zone));
        w.subst_attr("x", format!("{:.2}", u.x - utm0.x));
        w.subst_attr("y", format!("{:.2}", u.y - utm0.y));
    }
}

/// Appends `no` to blocks and stages and returns the `<stages>` index.
fn number(fp: &mut Node) -> Vec<Node> {
    let mut index = Vec::new();
    let Some(blocks) = fp.children.iter_mut().find(|c| c.tag.eq_ignore_ascii_case("blocks")) else {
        return index;
    };
    for (i, b) in blocks.children.iter_mut().enumerate() {
        b.attrs.push(("no".into(), i.to_string()));
        let mut counter: i64 = -1;
        for s in b.children.iter_mut() {
            number_stage(s, &mut counter);
        }
        let name = b.attr("name").unwrap_or_default().to_string();
        for s in &b.children {
            collect(s, i, &name, &mut index);
        }
    }
    index.reverse();
    index
}

fn number_stage(s: &mut Node, counter: &mut i64) {
    let tag = s.tag.to_ascii_lowercase();
    let no = match tag.as_str() {
        "exception" => return,
        "for" | "while" => {
            *counter += if tag == "for" { 2 } else { 1 };
            let n = *counter;
            for c in s.children.iter_mut() {
                number_stage(c, counter);
            }
            *counter += 1;
            n
        }
        "survey_rectangle" | "eight" | "oval" => {
            *counter += 2;
            *counter
        }
        _ => {
            *counter += 1;
            *counter
        }
    };
    s.attrs.push(("no".into(), no.to_string()));
}

/// Pre-order walk of the numbered stages (exceptions have no number).
fn collect(s: &Node, block: usize, name: &str, index: &mut Vec<Node>) {
    let Some(no) = s.attrs.iter().rev().find(|(n, _)| n == "no").map(|(_, v)| v.clone()) else {
        return;
    };
    let attrs = vec![
        ("block".to_string(), block.to_string()),
        ("block_name".to_string(), name.to_string()),
        ("stage".to_string(), no),
    ];
    index.push(Node::new("stage", attrs, vec![s.clone()]));
    if s.tag.eq_ignore_ascii_case("for") || s.tag.eq_ignore_ascii_case("while") {
        for c in &s.children {
            collect(c, block, name, index);
        }
    }
}

fn print(out: &mut String, n: &Node, tab: &str, newline: bool) {
    out.push_str(tab);
    out.push('<');
    out.push_str(&n.tag.to_ascii_lowercase());
    for (name, value) in &n.attrs {
        super::xml_light::attribute(out, &name.to_ascii_lowercase(), value);
    }
    match (&n.text, n.children.is_empty()) {
        (Some(text), true) => {
            out.push('>');
            out.push_str(text);
            out.push_str("</");
            out.push_str(&n.tag.to_ascii_lowercase());
            out.push('>');
        }
        (None, true) => out.push_str("/>"),
        (_, false) => {
            out.push_str(">\n");
            let inner = format!("{tab}  ");
            for c in &n.children {
                print(out, c, &inner, true);
            }
            out.push_str(tab);
            out.push_str("</");
            out.push_str(&n.tag.to_ascii_lowercase());
            out.push('>');
        }
    }
    if newline {
        out.push('\n');
    }
}
