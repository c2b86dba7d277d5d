//! Upstream's tree rewrites that happen after include expansion: `<path>` stages become `go`
//! stages, and `wp_qdr`/`wp_dist` (`from_qdr`/`from_dist`) create relative waypoints.

use crate::ast::{Attrs, RawAttr};
use crate::diag::ErrorKind;
use crate::expr::ocaml_float_text;

use super::ctx::Ctx;
use super::tree::Elem;
use super::values::ocaml_float;

/// Expands `<path wpts="A,B,C" ...>` into `go from=A hmode=route wp=B`, `go from=B hmode=route
/// wp=C` (a single point gives `go wp=A`), the path's other attributes following the generated
/// ones. Applied in blocks and recursively inside `while`/`for`.
pub fn expand_paths(ctx: &mut Ctx, stages: Vec<Elem>) -> Vec<Elem> {
    let mut out = Vec::with_capacity(stages.len());
    for mut s in stages {
        if s.tag == "path" {
            out.extend(path_to_gos(ctx, &s));
        } else {
            if s.tag_is("while") || s.tag_is("for") {
                let body = std::mem::take(&mut s.children);
                s.children = expand_paths(ctx, body);
            }
            out.push(s);
        }
    }
    out
}

fn path_to_gos(ctx: &mut Ctx, path: &Elem) -> Vec<Elem> {
    let Some(wpts) = path.attr("wpts").cloned() else {
        ctx.error(ErrorKind::MissingAttribute, "<path> needs 'wpts'", path.span);
        return Vec::new();
    };
    let names: Vec<&str> = wpts.value.split([' ', '\t', ',']).filter(|s| !s.is_empty()).collect();
    if names.is_empty() {
        ctx.error(ErrorKind::MissingAttribute, "waypoint expected in path stage", wpts.value_span);
        return Vec::new();
    }
    let synth = |name: &str, value: &str| RawAttr {
        name: name.to_string(),
        value: value.to_string(),
        span: wpts.span,
        value_span: wpts.value_span,
        upper: false,
    };
    let make = |generated: Vec<RawAttr>| {
        // Upstream appends every attribute of the path (`wpts` too) after the generated ones;
        // lookups find the first of a name, so the generated ones win.
        let mut attrs = generated;
        attrs.extend(path.attrs.0.iter().cloned());
        Elem {
            tag: "go".to_string(),
            attrs: Attrs(attrs),
            children: Vec::new(),
            text: String::new(),
            span: path.span,
            origin: path.origin.clone(),
            from_path: true,
            relative: None,
        }
    };
    if names.len() == 1 {
        return vec![make(vec![synth("wp", names[0])])];
    }
    names
        .windows(2)
        .map(|w| make(vec![synth("from", w[0]), synth("hmode", "route"), synth("wp", w[1])]))
        .collect()
}

/// Creates relative waypoints for `go`/`stay`/`circle` stages directly in blocks or inside
/// `while` (not `for`, as upstream). New waypoints are prepended, in reverse creation order.
pub fn relative_waypoints(blocks: &mut [Elem], waypoints: &mut Vec<Elem>) {
    for b in blocks.iter_mut() {
        for s in b.children.iter_mut() {
            relative_in_stage(s, waypoints);
        }
    }
}

fn relative_in_stage(s: &mut Elem, waypoints: &mut Vec<Elem>) {
    let tag = s.tag.to_ascii_lowercase();
    match tag.as_str() {
        "go" | "stay" | "circle" => {
            replace(s, waypoints, "wp", "wp_qdr", "wp_dist");
            replace(s, waypoints, "from", "from_qdr", "from_dist");
        }
        "while" => {
            for c in s.children.iter_mut() {
                relative_in_stage(c, waypoints);
            }
        }
        _ => {}
    }
}

/// Upstream silently leaves the stage unchanged when anything is missing or not numeric
/// (including a base waypoint given only by lat/lon).
fn replace(s: &mut Elem, waypoints: &mut Vec<Elem>, key: &str, qdr_key: &str, dist_key: &str) {
    let (Some(qdr), Some(dist)) =
        (s.attr_value(qdr_key).and_then(ocaml_float), s.attr_value(dist_key).and_then(ocaml_float))
    else {
        return;
    };
    let Some(base_attr) = s.attr(key).cloned() else { return };
    let Some(base) =
        waypoints.iter().find(|w| w.attr_value("name") == Some(base_attr.value.as_str()))
    else {
        return;
    };
    let (Some(bx), Some(by)) =
        (base.attr_value("x").and_then(ocaml_float), base.attr_value("y").and_then(ocaml_float))
    else {
        return;
    };
    let angle = (90.0 - qdr) * std::f64::consts::PI / 180.0;
    let (x, y) = (bx + dist * angle.cos(), by + dist * angle.sin());
    let name = format!("{}_{:.0}_{:.0}", base_attr.value, qdr, dist);
    let synth = |n: &str, v: String| RawAttr {
        name: n.to_string(),
        value: v,
        span: s.span,
        value_span: base_attr.value_span,
        upper: false,
    };
    let mut attrs = vec![
        synth("name", name.clone()),
        synth("x", ocaml_float_text(x)),
        synth("y", ocaml_float_text(y)),
    ];
    if let Some(alt) = base.attr("alt") {
        attrs.push(alt.clone());
    }
    let wp = Elem {
        tag: "waypoint".to_string(),
        attrs: Attrs(attrs),
        children: Vec::new(),
        text: String::new(),
        span: s.span,
        origin: s.origin.clone(),
        from_path: false,
        relative: Some((base_attr.value.clone(), qdr, dist)),
    };
    waypoints.insert(0, wp);
    let mut rest: Vec<RawAttr> = s
        .attrs
        .0
        .iter()
        .filter(|a| a.name != key && a.name != qdr_key && a.name != dist_key)
        .cloned()
        .collect();
    rest.insert(
        0,
        RawAttr {
            name: key.to_string(),
            value: name,
            span: base_attr.span,
            value_span: base_attr.value_span,
            upper: false,
        },
    );
    s.attrs = Attrs(rest);
}
