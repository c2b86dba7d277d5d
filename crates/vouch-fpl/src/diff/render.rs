//! The text of `vouch fpl diff`: the structural summary, the verdict, and for a difference the
//! distinguishing run side by side (the table of `vouch fpl sim`, one pair of columns per plan).

use std::fmt::Write;

use super::structure::{AttrChange, BlockChange, StageChange, Structure, WaypointChange};
use super::{DiffReport, Divergence, Location, PartingKind, StepSide, Verdict};
use crate::semantics::trace::Event;

fn cell(e: &Event) -> String {
    match e {
        Event::Cond { text, value } => format!("{text} ⇑ {value}"),
        Event::Code { text } => text.clone(),
        Event::Value { text, value } => format!("{text} = {value}"),
    }
}

fn loc(l: &Location) -> String {
    format!("{}:{}:{}", l.file, l.line, l.col)
}

fn attrs(list: &[AttrChange]) -> String {
    let show =
        |v: &Option<String>| v.as_deref().map_or("(none)".to_string(), |v| format!("\"{v}\""));
    list.iter()
        .map(|a| format!("{}: {} → {}", a.name, show(&a.old), show(&a.new)))
        .collect::<Vec<_>>()
        .join(", ")
}

fn stage_lines(out: &mut String, indent: &str, list: &[StageChange]) {
    for c in list {
        let _ = match c {
            StageChange::Added { tag, at } => writeln!(out, "{indent}+ {tag} ({})", loc(at)),
            StageChange::Removed { tag, at } => writeln!(out, "{indent}- {tag} ({})", loc(at)),
            StageChange::Changed { tag, attrs: a, old_at, new_at } => {
                writeln!(out, "{indent}~ {tag}: {} ({} → {})", attrs(a), loc(old_at), loc(new_at))
            }
        };
    }
}

/// The structural summary as text (empty when nothing changed).
pub fn summary(s: &Structure) -> String {
    let mut out = String::new();
    if !s.plan.is_empty() {
        let _ = writeln!(out, "  plan: {}", attrs(&s.plan));
    }
    if s.header_changed {
        out.push_str("  <header> C text changed (not observed by the comparison)\n");
    }
    for b in &s.blocks {
        let _ = match b {
            BlockChange::Added { name, number, at } => {
                writeln!(out, "  + block {number} '{name}' ({})", loc(at))
            }
            BlockChange::Removed { name, number, at } => {
                writeln!(out, "  - block {number} '{name}' ({})", loc(at))
            }
            BlockChange::Renamed { old, new, old_number, new_number } => writeln!(
                out,
                "  = block '{old}' renamed '{new}' (same content; number {old_number} → {new_number})"
            ),
            BlockChange::Renumbered { name, old_number, new_number } => {
                writeln!(out, "  = block '{name}' renumbered {old_number} → {new_number}")
            }
            BlockChange::Changed { name, old_number, new_number, attrs: a, stages, exceptions } => {
                let num = if old_number == new_number {
                    format!("{old_number}")
                } else {
                    format!("{old_number} → {new_number}")
                };
                let _ = writeln!(out, "  ~ block {num} '{name}'");
                if !a.is_empty() {
                    let _ = writeln!(out, "      attributes: {}", attrs(a));
                }
                stage_lines(&mut out, "      ", stages);
                stage_lines(&mut out, "      exception ", exceptions);
                Ok(())
            }
        };
    }
    stage_lines(&mut out, "  global exception ", &s.exceptions);
    for w in &s.waypoints {
        let _ = match w {
            WaypointChange::Added { name, number } => {
                writeln!(out, "  + waypoint {number} '{name}'")
            }
            WaypointChange::Removed { name, number } => {
                writeln!(out, "  - waypoint {number} '{name}'")
            }
            WaypointChange::Renamed { old, new, number } => {
                writeln!(out, "  = waypoint {number} '{old}' renamed '{new}'")
            }
            WaypointChange::Renumbered { name, old_number, new_number } => {
                writeln!(out, "  = waypoint '{name}' renumbered {old_number} → {new_number}")
            }
            WaypointChange::Moved { name, metres } => {
                writeln!(out, "  ~ waypoint '{name}' moved {metres:.1} m")
            }
            WaypointChange::Altitude { name, old, new } => writeln!(
                out,
                "  ~ waypoint '{name}' altitude {} → {}",
                old.as_deref().unwrap_or("(default)"),
                new.as_deref().unwrap_or("(default)")
            ),
        };
    }
    out
}

fn side_cells(s: &StepSide) -> (String, String, String) {
    (
        format!("{} {}", s.block, s.block_name),
        s.stage.to_string(),
        s.events.iter().map(cell).collect::<Vec<_>>().join("; "),
    )
}

/// The distinguishing run side by side: one row per step (tab-separated, like `fpl sim`).
pub fn table(d: &Divergence) -> String {
    let mut out =
        String::from("step\told block\tstage\tcode executed\tnew block\tstage\tcode executed\n");
    for (i, s) in d.steps.iter().enumerate() {
        let what = match (s.call, s.jump) {
            (_, Some(b)) => format!("jump {b}"),
            (Some(c), None) => format!("call {c}"),
            (None, None) => String::new(),
        };
        let mark = if i + 1 == d.steps.len() { " ≠" } else { "" };
        let (a, b) = (side_cells(&s.old), side_cells(&s.new));
        let _ = writeln!(out, "{what}{mark}\t{}\t{}\t{}\t{}\t{}\t{}", a.0, a.1, a.2, b.0, b.1, b.2);
    }
    if let Some(last) = d.steps.last() {
        let (a, b) = (last.old.after, last.new.after);
        let _ = writeln!(
            out,
            "after\tblock {} stage {}\t\t\tblock {} stage {}",
            a.block, a.stage, b.block, b.stage
        );
    }
    out
}

/// The whole text report (summary, verdict, run, locations).
pub fn render(r: &DiffReport) -> String {
    let mut out = format!("{} → {}\n", r.old, r.new);
    let s = summary(&r.structure);
    if s.is_empty() {
        out.push_str("structure: no change\n");
    } else {
        out.push_str("structure:\n");
        out.push_str(&s);
    }
    let env =
        if r.operator_jumps { "with ground-station jumps" } else { "without ground-station jumps" };
    let _ = match r.verdict {
        Verdict::Equivalent => writeln!(
            out,
            "behaviour: EQUIVALENT — same observations from all {} reachable state pairs ({} transitions, {env}; fixpoint reached; tested over the abstraction of `vouch fpl diff`, not proved)",
            r.state_pairs, r.transitions
        ),
        Verdict::Undecided => writeln!(
            out,
            "behaviour: UNDECIDED — no difference on the {} state pairs explored, but the walk was cut: {}",
            r.state_pairs,
            r.cut.as_deref().unwrap_or("budget")
        ),
        Verdict::Different => writeln!(out, "behaviour: DIFFERENT"),
    };
    if let Some(d) = &r.divergence {
        let n = d.steps.len();
        let what = match d.kind {
            PartingKind::Init => "auto_nav_init() runs other code".to_string(),
            PartingKind::Event => {
                format!("event {} of the last step differs", d.event_index.unwrap_or(0) + 1)
            }
            PartingKind::State => {
                "same events, another block or stage after the last step".to_string()
            }
        };
        let _ = writeln!(out, "first difference after {n} step(s): {what}");
        let show = |o: &super::Observed| {
            format!(
                "{} at {}",
                o.text.as_deref().unwrap_or("(nothing)"),
                o.location.as_ref().map_or("?".to_string(), loc)
            )
        };
        let _ = writeln!(out, "  old: {}", show(&d.old));
        let _ = writeln!(out, "  new: {}", show(&d.new));
        if n > 0 {
            out.push_str(&table(d));
        }
    }
    out
}

/// The `vouch fpl sim` options that replay the run on either plan.
pub fn replay_args(d: &Divergence) -> String {
    let mut s = String::new();
    if !d.answers.is_empty() {
        let answers: Vec<String> = d.answers.iter().map(i64::to_string).collect();
        let _ = write!(s, " --answers '{}'", answers.join(" "));
    }
    for (c, b) in &d.jumps {
        let _ = write!(s, " --jump {c}:{b}");
    }
    let _ = write!(s, " --steps {}", d.calls.max(1));
    s
}
