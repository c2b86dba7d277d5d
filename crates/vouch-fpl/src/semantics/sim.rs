//! `vouch fpl sim`: runs the reference interpreter; the table of the VFPG paper's Fig. 2 (call,
//! current block, stage, code executed with conditions and their values) and the JSON document
//! of a run (the shared trace format is [`super::trace::Run::to_text`]).

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

/// The JSON document of `vouch fpl sim --json`: block names plus the run (init events, steps
/// with before/after states).
#[derive(Debug, Serialize)]
pub struct Document<'a> {
    /// Block names by number.
    pub blocks: Vec<&'a str>,
    /// The run.
    #[serde(flatten)]
    pub run: &'a Run,
}

/// The JSON document of a run.
pub fn document<'a>(fp: &'a Fp, run: &'a Run) -> Document<'a> {
    Document { blocks: fp.blocks.iter().map(|b| b.name.as_str()).collect(), run }
}
