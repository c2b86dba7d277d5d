//! `vouch fpl validate`, `lint`, `check` and `graph`: evidence about one plan.

use std::path::PathBuf;

use clap::Args;
use vouch_fpl::emit::EmitOptions;
use vouch_fpl::evidence::validate::{self, ValidateError};
use vouch_fpl::model_check::{self, Spec};

use super::{PlanArgs, lowered, write_file};
use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch fpl validate`.
#[derive(Args)]
pub struct ValidateArgs {
    #[command(flatten)]
    plan: PlanArgs,
    /// Bound the walk to N transitions (calls and operator jumps) from the start; the result is
    /// then labelled "bounded". Default: explore every reachable state (fixpoint)
    #[arg(long, value_name = "N")]
    depth: Option<usize>,
    /// Leave operator jumps (the ground station's "go to block") out of the walk
    #[arg(long)]
    no_operator_jumps: bool,
    /// Seeded random runs compared after the walk
    #[arg(long, default_value_t = 3)]
    random_runs: usize,
    /// Calls in each random run
    #[arg(long, default_value_t = 500)]
    random_steps: usize,
    /// State budget: beyond it the walk is cut (reported as not a fixpoint, exit 3)
    #[arg(long, default_value_t = 200_000)]
    max_states: usize,
    /// Runs of one call (its paths, joined where they reach a stage in the same state): beyond
    /// it the call is cut (reported as not a fixpoint, exit 3)
    #[arg(long, value_name = "N", default_value_t = 1_000_000)]
    max_paths: usize,
    /// Also print the static per-block bound (stages and external events per call)
    #[arg(long)]
    bounds: bool,
    /// Print the report as one JSON document (the per-block bound included)
    #[arg(long)]
    json: bool,
    /// Where the compiled C runs: this machine (`host`, the system `cc`), or an emulated
    /// Cortex-M4/M7 (`arm-none-eabi-gcc` with the flags of a Paparazzi STM32 build, QEMU)
    #[arg(long, value_enum, default_value_t = TargetArg::Host)]
    target: TargetArg,
    /// Code-generation flags replacing the target's defaults (one string, split at blanks),
    /// e.g. --cflags '-mcpu=cortex-m4 -mthumb -O2 -fsingle-precision-constant'
    #[arg(long, value_name = "FLAGS", allow_hyphen_values = true)]
    cflags: Option<String>,
}

/// `--target` of `vouch fpl validate`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TargetArg {
    /// The system C compiler on this machine
    Host,
    /// Cortex-M4F (STM32F4 autopilots): arm-none-eabi-gcc, QEMU mps2-an386
    CortexM4,
    /// Cortex-M7 (STM32F7 autopilots): arm-none-eabi-gcc, QEMU mps2-an500
    CortexM7,
}

impl From<TargetArg> for validate::Target {
    fn from(t: TargetArg) -> Self {
        match t {
            TargetArg::Host => validate::Target::Host,
            TargetArg::CortexM4 => validate::Target::CortexM4,
            TargetArg::CortexM7 => validate::Target::CortexM7,
        }
    }
}

/// Arguments of `vouch fpl lint`.
#[derive(Args)]
pub struct LintArgs {
    #[command(flatten)]
    plan: PlanArgs,
    /// Print the warnings as one JSON document
    #[arg(long)]
    json: bool,
    /// Exit 3 when there is any warning (for CI)
    #[arg(long)]
    strict: bool,
}

/// Arguments of `vouch fpl check`.
#[derive(Args)]
pub struct CheckArgs {
    #[command(flatten)]
    plan: PlanArgs,
    /// A temporal property, e.g. 'always eventually block(Land)', 'never block(HOME)'
    /// (repeatable)
    #[arg(long = "property", value_name = "PROPERTY")]
    properties: Vec<String>,
    /// Every reachable state can reach one of these blocks (comma separated)
    #[arg(long, value_delimiter = ',', value_name = "BLOCKS")]
    safe_blocks: Vec<String>,
    /// No block change is ever refused by a forbidden deroute
    #[arg(long)]
    no_blocked: bool,
    /// No reachable state where every successor is forbidden
    #[arg(long)]
    deadlock_free: bool,
    /// State budget: beyond it the state space is cut and "holds" is not established
    #[arg(long, default_value_t = 1_000_000)]
    max_states: usize,
    /// Also model ground-station jumps to any block between calls
    #[arg(long)]
    operator: bool,
    /// Print the outcomes as one JSON document
    #[arg(long)]
    json: bool,
}

/// Arguments of `vouch fpl graph`.
#[derive(Args)]
pub struct GraphArgs {
    #[command(flatten)]
    plan: PlanArgs,
    /// Output SVG (default: standard output)
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

/// `vouch fpl validate`: the compiled C against the semantics.
pub fn validate(a: ValidateArgs, ctx: &mut Ctx) -> CmdResult {
    let plan = a.plan.load(ctx, true)?;
    lowered(&plan)?;
    let opts = validate::Options {
        depth: a.depth,
        operator_jumps: !a.no_operator_jumps,
        random_runs: a.random_runs,
        random_steps: a.random_steps,
        max_states: a.max_states,
        max_paths_per_call: a.max_paths,
        target: a.target.into(),
        cflags: a.cflags.as_deref().map(|f| f.split_whitespace().map(str::to_string).collect()),
        ..validate::Options::default()
    };
    let report = validate::validate(&plan, &opts).map_err(|e| {
        let interpreter = matches!(e, ValidateError::Interpreter(_));
        not_run(e, interpreter)
    })?;
    let mut text = report.render(&a.plan.name());
    if a.bounds {
        text.push_str(&report.bound.render());
    }
    print_report(ctx, a.json, &report, &text)?;
    // a walk cut by a budget has not established what was asked
    Ok(if report.passed() && !report.incomplete() { Exit::Ok } else { Exit::Findings })
}

/// `vouch fpl lint`: the warnings, then a count per code.
pub fn lint(a: LintArgs, ctx: &mut Ctx) -> CmdResult {
    let plan = a.plan.load(ctx, true)?;
    let warnings = vouch_fpl::lint::lint(&plan);
    // What `compile` warns about (upstream's notices, corrections) is reported too, on stderr
    // like compile does; a plan the generator rejects is still linted.
    let generator = match vouch_fpl::pipeline::generator_warnings(&plan, &EmitOptions::default()) {
        Ok(list) => list,
        Err(e) => {
            ctx.note(format_args!(
                "note: the generator rejects this plan ({}); `vouch fpl compile` locates it",
                e.items.first().map_or("", |d| d.message.as_str())
            ));
            Vec::new()
        }
    };
    for w in &generator {
        ctx.warn(w);
    }
    if a.json {
        ctx.out.json(&warnings)?;
    } else {
        ctx.out.text(&vouch_fpl::lint::render(&plan, &warnings))?;
        let mut counts: Vec<String> = vouch_fpl::lint::counts(&warnings)
            .into_iter()
            .filter(|c| c.1 > 0)
            .map(|(rule, n)| format!("{}: {n}", rule.code()))
            .collect();
        let mut codes: Vec<String> = generator.iter().map(|d| d.kind.code().to_string()).collect();
        codes.sort();
        for code in codes.iter().collect::<std::collections::BTreeSet<_>>() {
            let n = codes.iter().filter(|c| *c == code).count();
            counts.push(format!("{code}: {n} (generator)"));
        }
        let sep = if counts.is_empty() { "" } else { " — " };
        let total = warnings.len() + generator.len();
        writeln!(ctx.out, "{total} warning(s){sep}{}", counts.join(", "))?;
    }
    let any = !warnings.is_empty() || !generator.is_empty();
    Ok(if a.strict && any { Exit::Findings } else { Exit::Ok })
}

/// `vouch fpl check`: model checking of the plan's state space.
pub fn check(a: CheckArgs, ctx: &mut Ctx) -> CmdResult {
    let plan = a.plan.load(ctx, true)?;
    let fp = lowered(&plan)?;
    let spec = Spec {
        properties: a.properties,
        safe_blocks: a.safe_blocks,
        no_blocked: a.no_blocked,
        deadlock_free: a.deadlock_free,
        max_states: a.max_states,
        operator: a.operator,
    };
    // A property that does not parse, an unknown safe block, the interpreter's bound: the
    // checker's input is rejected (1), as the help page says.
    let report = model_check::run(&fp, &spec).map_err(Failure::rejected)?;
    print_report(ctx, a.json, &report, &report.render(&a.plan.name()))?;
    // a property that holds only on the part a budget left is not established
    Ok(if report.established() { Exit::Ok } else { Exit::Findings })
}

/// `vouch fpl graph`: the SVG block graph.
pub fn graph(a: GraphArgs, ctx: &mut Ctx) -> CmdResult {
    let plan = a.plan.load(ctx, true)?;
    let svg = vouch_fpl::graph::render_svg(&plan);
    match &a.output {
        Some(path) => write_file(path, svg.as_bytes())?,
        None => ctx.out.write_all(svg.as_bytes())?,
    }
    Ok(Exit::Ok)
}

/// Why an evidence run did not run: the interpreter's bound rejects the plan; anything else (no
/// C compiler, a property that does not parse) is a usage or I/O error.
fn not_run(e: impl miette::Diagnostic + Send + Sync + 'static, interpreter: bool) -> Failure {
    if interpreter { Failure::rejected(e) } else { Failure::Usage(miette::Report::new(e)) }
}

/// The report as one JSON document, or its text.
fn print_report(
    ctx: &mut Ctx,
    json: bool,
    report: &impl serde::Serialize,
    text: &str,
) -> Result<(), Failure> {
    if json { ctx.out.json(report) } else { ctx.out.text(text) }
}
