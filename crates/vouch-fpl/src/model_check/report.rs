//! One model-checking run as `vouch fpl check` does it: what to check ([`Spec`]), the state
//! graph, every outcome ([`CheckReport`]), and the errors that stop it ([`CheckError`]).

use serde::Serialize;

use super::check::{self, Outcome};
use super::property::PropertyError;
use super::{BuildOptions, Graph, build_with};
use crate::passes::fp::Fp;
use crate::semantics::StepError;

/// What to check. With no property, no safe block and neither flag, the default is
/// `no_blocked` and `deadlock_free`.
#[derive(Debug, Clone)]
pub struct Spec {
    /// Temporal properties in the language of [`super::property`].
    pub properties: Vec<String>,
    /// Every reachable state can reach one of these blocks (names).
    pub safe_blocks: Vec<String>,
    /// No block change is ever refused by a forbidden deroute.
    pub no_blocked: bool,
    /// No reachable state where every successor is forbidden.
    pub deadlock_free: bool,
    /// State budget: the graph is cut (and "holds" not established) beyond it.
    pub max_states: usize,
    /// Also model ground-station jumps to any block at any call.
    pub operator: bool,
}

impl Default for Spec {
    fn default() -> Self {
        Spec {
            properties: Vec::new(),
            safe_blocks: Vec::new(),
            no_blocked: false,
            deadlock_free: false,
            max_states: 1_000_000,
            operator: false,
        }
    }
}

/// Why a check could not run.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum CheckError {
    /// A property text that does not parse.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Property(#[from] PropertyError),
    /// A safe block name that the plan does not have.
    #[error("safe block '{name}' is not a block of the plan (blocks: {known})")]
    #[diagnostic(code(fpl::E043))]
    UnknownBlock {
        /// The name given.
        name: String,
        /// The plan's block names.
        known: String,
    },
    /// The interpreter stopped while the graph was built.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Interpreter(#[from] StepError),
}

/// The state graph's size and every outcome.
#[derive(Debug, Clone, Serialize)]
pub struct CheckReport {
    /// Every reachable state was expanded: the properties are decided on the whole graph.
    pub fixpoint: bool,
    /// States reached.
    pub states: usize,
    /// Distinct transitions between them.
    pub transitions: usize,
    /// Why the graph is incomplete, when the budget cut it.
    pub cut: Option<String>,
    /// One per property checked, in the order of the [`Spec`].
    pub outcomes: Vec<Outcome>,
}

impl CheckReport {
    /// Whether every property holds (on the explored part when the graph is cut).
    pub fn holds(&self) -> bool {
        self.outcomes.iter().all(|o| o.holds)
    }

    /// Every property holds on the whole state space: none fails and none holds only on a part
    /// a budget cut (a cut walk establishes failures, never that a property holds).
    pub fn established(&self) -> bool {
        self.outcomes.iter().all(|o| o.holds && o.complete)
    }

    /// The text of `vouch fpl check`: a summary line for `name`, then every outcome.
    pub fn render(&self, name: &str) -> String {
        let reached = match &self.cut {
            None if self.fixpoint => "fixpoint reached".to_string(),
            None => "not a fixpoint".to_string(),
            Some(c) => format!("cut: {c}, not a fixpoint"),
        };
        let mut s = format!(
            "{name}: {} states, {} transitions, {reached}\n",
            self.states, self.transitions
        );
        for o in &self.outcomes {
            s.push_str(&check::render(o));
        }
        s
    }
}

/// Builds the state graph of `fp` and checks everything `spec` asks for.
pub fn run(fp: &Fp, spec: &Spec) -> Result<CheckReport, CheckError> {
    let names: Vec<String> = fp.blocks.iter().map(|b| b.name.clone()).collect();
    let properties = spec
        .properties
        .iter()
        .map(|t| super::property::parse(t, &names).map(|p| (t, p)))
        .collect::<Result<Vec<_>, _>>()?;
    let last_block = properties.iter().any(|(_, p)| p.formula.uses_last_block());
    let g = build_with(
        fp,
        BuildOptions { max_states: spec.max_states, operator: spec.operator, last_block },
    )?;
    let mut outcomes = Vec::new();
    for (text, p) in &properties {
        outcomes.push(check::check_property(&g, text, p));
    }
    if !spec.safe_blocks.is_empty() {
        let ids = spec
            .safe_blocks
            .iter()
            .map(|n| g.block_index(n).ok_or_else(|| unknown_block(&g, n)))
            .collect::<Result<Vec<_>, _>>()?;
        outcomes.push(check::check_safe_blocks(&g, &ids));
    }
    let defaults = spec.properties.is_empty()
        && spec.safe_blocks.is_empty()
        && !spec.no_blocked
        && !spec.deadlock_free;
    if spec.no_blocked || defaults {
        outcomes.push(check::check_no_blocked(&g));
    }
    if spec.deadlock_free || defaults {
        outcomes.push(check::check_deadlock_free(&g));
    }
    Ok(CheckReport {
        fixpoint: g.fixpoint,
        states: g.states.len(),
        transitions: g.edges.iter().map(Vec::len).sum(),
        cut: g.cut.clone(),
        outcomes,
    })
}

fn unknown_block(g: &Graph, name: &str) -> CheckError {
    CheckError::UnknownBlock { name: name.to_string(), known: g.block_names.join(", ") }
}
