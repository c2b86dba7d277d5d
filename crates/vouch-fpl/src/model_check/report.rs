//! One model-checking run as `vouch fpl check` does it: what to check ([`Spec`]), the state
//! graph, every outcome ([`CheckReport`]), and the errors that stop it ([`CheckError`]).

use serde::Serialize;

use super::check::{self, Outcome};
use super::property::PropertyError;
use super::{build, Graph};
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
            max_states: 200_000,
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
    /// Abstract states reached.
    pub states: usize,
    /// Transitions between them.
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

    /// The text of `vouch fpl check`: a summary line for `name`, then every outcome.
    pub fn render(&self, name: &str) -> String {
        let cut = self.cut.as_ref().map(|c| format!(" (cut: {c})")).unwrap_or_default();
        let mut s = format!(
            "{name}: {} abstract states, {} transitions{cut}\n",
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
    let g = build(fp, spec.max_states, spec.operator)?;
    let mut outcomes = Vec::new();
    for text in &spec.properties {
        outcomes.push(check::check_text(&g, text)?);
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
        states: g.states.len(),
        transitions: g.edges.iter().map(Vec::len).sum(),
        cut: g.cut.clone(),
        outcomes,
    })
}

fn unknown_block(g: &Graph, name: &str) -> CheckError {
    CheckError::UnknownBlock { name: name.to_string(), known: g.block_names.join(", ") }
}
