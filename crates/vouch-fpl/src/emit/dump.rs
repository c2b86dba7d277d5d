//! The `--dump` file. Upstream's build writes, beside `flight_plan.h`, the *expanded* plan for
//! the ground station (GENERATOR_FACTS.md §1): procedures included (blocks renamed `N.block`,
//! parameters substituted), `<path>` stages expanded into `go` stages, relative waypoints
//! created, the implicit `HOME` block appended, blocks and stages numbered with a `no`
//! attribute, followed by a `<stages>` index (block number, block name, stage number, stage
//! element) that the GCS uses to name the current stage.
//!
//! vouch writes the same content from the resolved AST: every element with its attributes as
//! the front end kept them (after include/path rewriting), block references printed by their
//! resolved block name. Stage numbers follow upstream's dump pre-pass: a loop is numbered at its
//! test stage, a two-step stage at its main stage.
//!
//! Attribute values are written the way upstream's XML reader reads them back (values are not
//! entity-decoded there, so they are copied raw; only `\` and `"` are backslash-escaped), so
//! the `<flight_plan>` element of a dump, without its `HOME` block, parses again with vouch's
//! front end (tested). Header text and the index are ordinary XML text (entities escaped).

use crate::ast::{Attrs, Block, Exception, FlightPlan, Stage, StageKind};

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// An attribute value as upstream's reader reads it (see the module comment).
fn raw_value(s: &str) -> String {
    s.replace('\\', "\\\\").replace('"', "\\\"")
}

/// ` name="value"` for every attribute, with `overrides` replacing (or adding) some of them.
fn attrs_text(attrs: &Attrs, overrides: &[(&str, String)]) -> String {
    let mut out = String::new();
    for a in &attrs.0 {
        if overrides.iter().any(|(n, _)| a.name.eq_ignore_ascii_case(n)) {
            continue;
        }
        out.push_str(&format!(" {}=\"{}\"", a.name, raw_value(&a.value)));
    }
    for (n, v) in overrides {
        out.push_str(&format!(" {n}=\"{}\"", raw_value(v)));
    }
    out
}

struct Out {
    text: String,
    indent: usize,
}

impl Out {
    fn line(&mut self, s: &str) {
        self.text.push_str(&"  ".repeat(self.indent));
        self.text.push_str(s);
        self.text.push('\n');
    }
    /// `<tag attrs>` … `</tag>` around `body`, or `<tag attrs/>` when `body` writes nothing.
    fn element(&mut self, tag: &str, attrs: &str, body: impl FnOnce(&mut Out)) {
        let mark = self.text.len();
        self.indent += 1;
        body(self);
        self.indent -= 1;
        let inner = self.text.split_off(mark);
        if inner.is_empty() {
            self.line(&format!("<{tag}{attrs}/>"));
        } else {
            self.line(&format!("<{tag}{attrs}>"));
            self.text.push_str(&inner);
            self.line(&format!("</{tag}>"));
        }
    }
}

fn exception(out: &mut Out, plan: &FlightPlan, e: &Exception) {
    let target = plan.block(e.deroute.id).name.value.clone();
    out.line(&format!("<exception{}/>", attrs_text(&e.attrs, &[("deroute", target)])));
}

/// Writes `stages` with their numbers; `next` is the last number used in the block.
fn stages(out: &mut Out, plan: &FlightPlan, list: &[Stage], next: &mut i64) {
    for s in list {
        let tag = s.kind.tag();
        match &s.kind {
            StageKind::For(f) => {
                *next += 2;
                let attrs = attrs_text(&s.attrs, &[("no", next.to_string())]);
                out.element(tag, &attrs, |o| stages(o, plan, &f.body, next));
                *next += 1;
            }
            StageKind::While(w) => {
                *next += 1;
                let attrs = attrs_text(&s.attrs, &[("no", next.to_string())]);
                out.element(tag, &attrs, |o| stages(o, plan, &w.body, next));
                *next += 1;
            }
            kind => {
                *next += match kind {
                    StageKind::Eight(_) | StageKind::Oval(_) | StageKind::SurveyRectangle(_) => 2,
                    _ => 1,
                };
                let mut overrides = Vec::new();
                if let StageKind::Deroute(d) = kind {
                    overrides.push(("block", plan.block(d.block.id).name.value.clone()));
                }
                overrides.push(("no", next.to_string()));
                out.line(&format!("<{tag}{}/>", attrs_text(&s.attrs, &overrides)));
            }
        }
    }
}

fn block(out: &mut Out, plan: &FlightPlan, i: usize, b: &Block) {
    // The appended HOME block has no source element, hence no attributes of its own.
    let attrs = if b.implicit {
        attrs_text(&b.attrs, &[("name", b.name.value.clone()), ("no", i.to_string())])
    } else {
        attrs_text(&b.attrs, &[("no", i.to_string())])
    };
    out.element("block", &attrs, |o| {
        for e in &b.exceptions {
            exception(o, plan, e);
        }
        let mut next = -1;
        stages(o, plan, &b.stages, &mut next);
    });
}

fn plan_element(out: &mut Out, plan: &FlightPlan) {
    out.element("flight_plan", &attrs_text(&plan.attrs, &[]), |o| {
        if let Some(h) = &plan.header {
            o.line(&format!("<header>{}</header>", xml_escape(&h.text)));
        }
        o.element("waypoints", &attrs_text(&plan.waypoints_attrs, &[]), |o| {
            for w in &plan.waypoints {
                o.line(&format!("<waypoint{}/>", attrs_text(&w.attrs, &[])));
            }
        });
        if !plan.sectors.is_empty() || !plan.kml.is_empty() {
            o.element("sectors", "", |o| {
                for s in &plan.sectors {
                    o.element("sector", &attrs_text(&s.attrs, &[]), |o| {
                        for c in &s.corners {
                            o.line(&format!(
                                "<corner name=\"{}\"/>",
                                raw_value(&plan.waypoint(c.id).name.value)
                            ));
                        }
                    });
                }
                for k in &plan.kml {
                    o.line(&format!("<kml file=\"{}\"/>", raw_value(&k.value)));
                }
            });
        }
        if !plan.variables.is_empty() {
            o.element("variables", "", |o| {
                for v in &plan.variables {
                    match v {
                        crate::ast::VariableDecl::Var(v) => {
                            o.line(&format!("<variable{}/>", attrs_text(&v.attrs, &[])))
                        }
                        crate::ast::VariableDecl::Abi(a) => {
                            o.line(&format!("<abi_binding{}/>", attrs_text(&a.attrs, &[])))
                        }
                    }
                }
            });
        }
        if !plan.modules.is_empty() {
            o.element("modules", "", |o| {
                for m in &plan.modules {
                    o.element("module", &attrs_text(&m.attrs, &[]), |o| {
                        for (tag, list) in [("configure", &m.configures), ("define", &m.defines)] {
                            for nv in list.iter() {
                                let value = nv
                                    .value
                                    .as_ref()
                                    .map(|v| format!(" value=\"{}\"", raw_value(&v.value)));
                                o.line(&format!(
                                    "<{tag} name=\"{}\"{}/>",
                                    raw_value(&nv.name.value),
                                    value.unwrap_or_default()
                                ));
                            }
                        }
                    });
                }
            });
        }
        if !plan.exceptions.is_empty() {
            o.element("exceptions", "", |o| {
                for e in &plan.exceptions {
                    exception(o, plan, e);
                }
            });
        }
        if !plan.forbidden_deroutes.is_empty() {
            o.element("forbidden_deroutes", "", |o| {
                for f in &plan.forbidden_deroutes {
                    let from = plan.block(f.from.id).name.value.clone();
                    let to = plan.block(f.to.id).name.value.clone();
                    o.line(&format!(
                        "<forbidden_deroute{}/>",
                        attrs_text(&f.attrs, &[("from", from), ("to", to)])
                    ));
                }
            });
        }
        o.element("blocks", "", |o| {
            for (i, b) in plan.blocks.iter().enumerate() {
                block(o, plan, i, b);
            }
        });
    });
}

/// The `<stages>` index: one entry per numbered stage (loops at their test stage).
fn index(stages: &[Stage], next: &mut i64, out: &mut Vec<(i64, &'static str)>) {
    for s in stages {
        match &s.kind {
            StageKind::For(f) => {
                *next += 2;
                out.push((*next, "for"));
                index(&f.body, next, out);
                *next += 1;
            }
            StageKind::While(w) => {
                *next += 1;
                out.push((*next, "while"));
                index(&w.body, next, out);
                *next += 1;
            }
            StageKind::Eight(_) | StageKind::Oval(_) | StageKind::SurveyRectangle(_) => {
                *next += 2;
                out.push((*next, s.kind.tag()));
            }
            k => {
                *next += 1;
                out.push((*next, k.tag()));
            }
        }
    }
}

/// The whole dump: `<dump>` holding the expanded, numbered `<flight_plan>` and the `<stages>`
/// index.
pub fn dump(plan: &FlightPlan) -> String {
    let mut out = Out { text: String::new(), indent: 0 };
    out.line("<dump>");
    out.indent += 1;
    plan_element(&mut out, plan);
    out.line("<stages>");
    for (i, b) in plan.blocks.iter().enumerate() {
        let mut next = -1;
        let mut list = Vec::new();
        index(&b.stages, &mut next, &mut list);
        for (no, tag) in list {
            out.line(&format!(
                "  <stage block=\"{i}\" block_name=\"{}\" stage=\"{no}\"><{tag}/></stage>",
                xml_escape(&b.name.value)
            ));
        }
    }
    out.line("</stages>");
    out.indent -= 1;
    out.line("</dump>");
    out.text
}
