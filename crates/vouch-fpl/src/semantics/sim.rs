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

/// [`simulate`] with operator jumps: (call, block) pairs, each applied just before that call.
pub fn simulate_with_jumps(
    fp: &Fp,
    oracle: &mut dyn Oracle,
    steps: usize,
    jumps: &[(usize, usize)],
) -> Result<Run, StepError> {
    Interp::new(fp).run_with_jumps(oracle, steps, jumps)
}

/// A jumps file that is not "call block" pairs of block numbers.
#[derive(Debug, Clone, thiserror::Error, miette::Diagnostic)]
#[error("{message}")]
#[diagnostic(
    code(fpl::E044),
    help(
        "a jumps file holds \"call block\" pairs of whole numbers: an operator jump to the block just before that call"
    )
)]
pub struct JumpsError {
    /// What is wrong.
    pub message: String,
    /// The whole text.
    #[source_code]
    pub text: String,
    /// Where.
    #[label("here")]
    pub at: miette::SourceSpan,
}

/// Parses a jumps file ("call block" pairs, whitespace separated) for a plan of `blocks`
/// blocks.
pub fn parse_jumps(text: &str, blocks: usize) -> Result<Vec<(usize, usize)>, JumpsError> {
    let err = |message: String, at: (usize, usize)| JumpsError {
        message,
        text: text.to_string(),
        at: at.into(),
    };
    let mut words = Vec::new();
    let mut rest = text;
    while let Some(start) = rest.find(|c: char| !c.is_whitespace()) {
        let offset = text.len() - rest.len() + start;
        let len = rest[start..].find(char::is_whitespace).unwrap_or(rest.len() - start);
        let word = &rest[start..start + len];
        let n = word.parse::<usize>().map_err(|_| {
            err(format!("not a whole number: '{}'", crate::diag::quote(word)), (offset, len))
        })?;
        words.push((n, offset, len));
        rest = &rest[start + len..];
    }
    if words.len() % 2 == 1 {
        let (_, o, l) = words[words.len() - 1];
        return Err(err("a call number without its block".into(), (o, l)));
    }
    words
        .chunks(2)
        .map(|p| {
            let (b, o, l) = p[1];
            if b >= blocks {
                return Err(err(
                    format!("block {b} does not exist (the plan has {blocks})"),
                    (o, l),
                ));
            }
            Ok((p[0].0, b))
        })
        .collect()
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

#[cfg(test)]
mod tests {
    use super::parse_jumps;

    #[test]
    fn jumps_files_are_pairs_of_whole_numbers() {
        assert_eq!(
            parse_jumps(" 3 1\n3 0\t7 2 ", 3).expect("parses"),
            vec![(3, 1), (3, 0), (7, 2)]
        );
        assert_eq!(parse_jumps("", 3).expect("empty"), vec![]);
        // (text, message, offset of the word)
        let bad = [
            ("1 x", "not a whole number: 'x'", 2),
            ("1 -2", "not a whole number: '-2'", 2),
            ("1 2 3", "a call number without its block", 4),
            ("1 3", "block 3 does not exist (the plan has 3)", 2),
            ("1.5 0", "not a whole number: '1.5'", 0),
        ];
        for (text, message, at) in bad {
            let e = parse_jumps(text, 3).expect_err(text);
            assert_eq!((e.message.as_str(), e.at.offset()), (message, at), "{text}");
        }
    }
}
