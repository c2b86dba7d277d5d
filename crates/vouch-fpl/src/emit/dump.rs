//! The `--dump` file: upstream writes the expanded plan plus a `<stages>` index that the ground
//! station uses to name the current stage. vouch writes the index part (block number, block
//! name, stage number, stage tag), numbered as upstream's dump pre-pass does: a loop is
//! numbered at its test stage, a two-step stage at its main stage.

use crate::ast::{FlightPlan, Stage, StageKind};

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

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

pub fn dump(plan: &FlightPlan) -> String {
    let mut out = String::from("<dump>\n");
    out.push_str(&format!("  <flight_plan name=\"{}\"/>\n  <stages>\n", xml_escape(&plan.name.value)));
    for (i, b) in plan.blocks.iter().enumerate() {
        let mut next = -1;
        let mut list = Vec::new();
        index(&b.stages, &mut next, &mut list);
        for (no, tag) in list {
            out.push_str(&format!(
                "    <stage block=\"{i}\" block_name=\"{}\" stage=\"{no}\"><{tag}/></stage>\n",
                xml_escape(&b.name.value)
            ));
        }
    }
    out.push_str("  </stages>\n</dump>\n");
    out
}
