//! `vouch fpl sim`: the reference interpreter on one plan.

use std::path::PathBuf;

use clap::Args;
use vouch_fpl::semantics::oracle::{Oracle, Scripted, Seeded};
use vouch_fpl::semantics::sim;

use super::{PlanArgs, lowered};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch fpl sim`.
#[derive(Args)]
pub struct SimArgs {
    #[command(flatten)]
    plan: PlanArgs,
    /// Number of auto_nav calls
    #[arg(long, default_value_t = 20)]
    steps: usize,
    /// File of answers: integers, one consumed per condition (odd = true) or value (n/2)
    #[arg(long, value_name = "FILE", conflicts_with = "seed")]
    conditions: Option<PathBuf>,
    /// The answers inline, as in a --conditions file (`--answers '0 1 1'`; what `vouch fpl
    /// diff` prints to replay a run)
    #[arg(long, value_name = "NUMBERS", conflicts_with_all = ["conditions", "seed"])]
    answers: Option<String>,
    /// Seed of the random oracle
    #[arg(long)]
    seed: Option<u64>,
    /// File of operator jumps: "call block" pairs, each a ground-station jump to the block just
    /// before that call (the jumps of a `vouch fpl validate` counterexample)
    #[arg(long, value_name = "FILE")]
    jumps: Option<PathBuf>,
    /// One operator jump inline, CALL:BLOCK (repeatable; added to those of --jumps)
    #[arg(long = "jump", value_name = "CALL:BLOCK")]
    jump: Vec<String>,
    /// Percentage of true conditions for --seed
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u64).range(0..=100))]
    percent_true: u64,
    /// Print the run as one JSON document (block names, init events, every call)
    #[arg(long)]
    json: bool,
    /// Print the trace format shared with the C stub driver
    #[arg(long, conflicts_with = "json")]
    trace: bool,
}

/// `vouch fpl sim`: runs the calls and prints the table, the trace or JSON.
pub fn sim(a: SimArgs, ctx: &mut Ctx) -> CmdResult {
    let plan = a.plan.load(ctx, true)?;
    let fp = lowered(&plan)?;
    let mut oracle: Box<dyn Oracle> = match (&a.conditions, a.seed) {
        _ if a.answers.is_some() => {
            let text = a.answers.as_deref().unwrap_or_default();
            Box::new(Scripted::parse(text).map_err(Failure::rejected)?)
        }
        (Some(path), _) => {
            let text = Failure::read_text(path)?;
            Box::new(Scripted::parse(&text).map_err(Failure::rejected)?)
        }
        (None, Some(s)) => Box::new(Seeded::new(s, a.percent_true)),
        (None, None) => Box::new(Scripted::default()),
    };
    let mut jumps = match &a.jumps {
        Some(path) => {
            let text = Failure::read_text(path)?;
            sim::parse_jumps(&text, fp.blocks.len()).map_err(Failure::rejected)?
        }
        None => Vec::new(),
    };
    for j in &a.jump {
        let text = j.replace(':', " ");
        jumps.extend(sim::parse_jumps(&text, fp.blocks.len()).map_err(Failure::rejected)?);
    }
    let run = sim::simulate_with_jumps(&fp, oracle.as_mut(), a.steps, &jumps)
        .map_err(Failure::rejected)?;
    if a.json {
        ctx.out.json(&sim::document(&fp, &run))?;
    } else if a.trace {
        ctx.out.text(&run.to_text())?;
    } else {
        ctx.out.text(&sim::table(&fp, &run))?;
    }
    Ok(Exit::Ok)
}
