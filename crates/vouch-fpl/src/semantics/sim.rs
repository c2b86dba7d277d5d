//! `vouch fpl sim`: runs the reference interpreter and prints the table of the VFPG paper's
//! Fig. 2 (call, current block, stage, code executed with conditions and their values), the
//! shared trace format, or JSON.

use serde::Serialize;

use super::oracle::Oracle;
use super::trace::{Event, Run};
use super::{Interp, StepError};
use crate::passes::fp::Fp;

/// Runs `steps` calls of `auto_nav` from the initial state.
pub fn simulate(fp: &Fp, oracle: &mut dyn Oracle, steps: usize) -> Result<Run, StepError> {
    Interp::new(fp).run(oracle, steps)
}

fn event_cell(e: &Event) -> String {
    match e {
        Event::Cond { text, value } => format!("{text} ⇑ {value}"),
        Event::Code { text } => text.clone(),
        Event::Value { text, value } => format!("{text} = {value}"),
    }
}

/// The Fig. 2 table: one row per call, consecutive identical rows folded as `a → b`.
pub fn table(fp: &Fp, run: &Run) -> String {
    let name = |b: usize| fp.blocks.get(b).map(|x| x.name.as_str()).unwrap_or("?");
    let mut rows: Vec<(usize, usize, String, String, String)> = Vec::new();
    for s in &run.steps {
        let code = s.events.iter().map(event_cell).collect::<Vec<_>>().join("; ");
        let block = format!("{} {}", s.before.block, name(s.before.block));
        let stage = s.before.stage.to_string();
        match rows.last_mut() {
            Some(last) if last.2 == block && last.3 == stage && last.4 == code => last.1 = s.call,
            _ => rows.push((s.call, s.call, block, stage, code)),
        }
    }
    let mut out = String::from("call\tblock\tstage\tcode executed\n");
    for (a, b, block, stage, code) in rows {
        let calls = if a == b { a.to_string() } else { format!("{a} → {b}") };
        out.push_str(&format!("{calls}\t{block}\t{stage}\t{code}\n"));
    }
    if let Some(last) = run.steps.last() {
        let a = last.after;
        out.push_str(&format!(
            "after call {}: block {} ({}), stage {}, last block {}, last stage {}\n",
            last.call,
            a.block,
            name(a.block),
            a.stage,
            a.last_block,
            a.last_stage
        ));
    }
    out
}

#[derive(Serialize)]
struct JsonRun<'a> {
    blocks: Vec<&'a str>,
    #[serde(flatten)]
    run: &'a Run,
}

/// JSON for tools: block names plus the run (init events, steps with before/after states).
pub fn json(fp: &Fp, run: &Run) -> String {
    let j = JsonRun { blocks: fp.blocks.iter().map(|b| b.name.as_str()).collect(), run };
    serde_json::to_string_pretty(&j).unwrap_or_default()
}
