//! `vouch fpl parse` and `vouch fpl compile`.

use std::path::{Component, Path, PathBuf};

use clap::Args;
use vouch_fpl::emit::{EmitOptions, Flavor};
use vouch_fpl::pipeline::Request;

use super::{PlanArgs, rejected, write_file};
use crate::contract::{CmdResult, Ctx, Exit, Failure, Verbosity};

/// Arguments of `vouch fpl parse`.
#[derive(Args)]
pub struct ParseArgs {
    #[command(flatten)]
    plan: PlanArgs,
    /// Print the resolved plan as one JSON document instead of an outline
    #[arg(long)]
    json: bool,
    /// Refuse the VFPG <forbidden_deroutes> extension, as upstream's DTD does
    #[arg(long)]
    no_extensions: bool,
}

/// Arguments of `vouch fpl compile`.
#[derive(Args)]
pub struct CompileArgs {
    /// The flight-plan XML file(s); several plans need --out-dir
    #[arg(required = true, value_name = "PLAN")]
    plans: Vec<PathBuf>,
    /// Where included procedures are searched after the plan's folder (repeatable)
    ///
    /// Default: the nearest ancestor directory holding flight_plan.dtd.
    #[arg(long = "include-dir", value_name = "DIR")]
    include_dirs: Vec<PathBuf>,
    /// Output header (default: stdout, unless the dump or the settings go there)
    #[arg(short, long, value_name = "FILE", conflicts_with = "out_dir")]
    output: Option<PathBuf>,
    /// Compile every plan into DIR, in parallel
    ///
    /// DIR/<plan path as given, .xml → .h>, or DIR/<file name>.h for absolute paths.
    #[arg(long, value_name = "DIR")]
    out_dir: Option<PathBuf>,
    /// Also write upstream's dump, Paparazzi's flight_plan.xml ("-": stdout)
    ///
    /// The expanded plan with numbered blocks and stages and the stage index of the ground
    /// station; "-" writes it to standard output instead of the header.
    #[arg(long, value_name = "FILE", conflicts_with = "out_dir")]
    dump: Option<PathBuf>,
    /// Also write the settings of the plan's variables, settings.xml ("-": stdout)
    ///
    /// Paparazzi's settings.xml made from the plan's variables; "-" writes it to standard output
    /// instead of the header.
    #[arg(long, value_name = "FILE", conflicts_with = "out_dir")]
    settings: Option<PathBuf>,
    /// Also write the C header of those settings (Paparazzi's settings.h)
    #[arg(long, value_name = "FILE", conflicts_with = "out_dir")]
    settings_header: Option<PathBuf>,
    /// Print exactly what upstream's generator prints, its known mistakes included
    ///
    /// EGM96 heights where the geoid is negative, WAYPOINTS_GLOBAL for "D M S" coordinates;
    /// included procedures searched in upstream's order (the plan's directory, then
    /// $PAPARAZZI_HOME/conf/flight_plans); upstream's own stderr line "No SRTM data found to
    /// check altitude." when no SRTM terrain tile covers the reference (-v says why).
    #[arg(long)]
    upstream_compat: bool,
    /// Paparazzi home for the geoid grid and conf/abi.xml (default: $PAPARAZZI_HOME)
    ///
    /// Its data/srtm/WW15MGH.DAC[.bz2] and conf/abi.xml are read; without a home the egm96
    /// crate stands in for the geoid grid.
    #[arg(long, value_name = "DIR")]
    paparazzi_home: Option<PathBuf>,
    /// Also show the mission-level warnings of `vouch fpl lint`
    #[arg(long)]
    lint: bool,
    /// Emit the instrumented flavour, for the stub runtime
    ///
    /// User C wrapped in FP_C/FP_X/FP_V/FP_I.
    #[arg(long)]
    instrumented: bool,
}

/// `vouch fpl parse`: the outline (or JSON) of the resolved plan.
pub fn parse(a: ParseArgs, ctx: &mut Ctx) -> CmdResult {
    let plan = a.plan.load(ctx, !a.no_extensions)?;
    if a.json {
        ctx.out.json(&ParseDocument { version: PARSE_JSON_VERSION, plan: &plan })?;
    } else {
        ctx.out.text(&vouch_fpl::ast::outline::outline(&plan))?;
    }
    Ok(Exit::Ok)
}

/// `vouch fpl compile`: the header (and the dump, the settings), or many headers with
/// --out-dir; upstream's notices and the corrections of upstream's output are warnings.
pub fn compile(a: CompileArgs, ctx: &mut Ctx) -> CmdResult {
    let req = request(&a);
    if ctx.verbosity == Verbosity::Verbose
        && let Ok(g) = req.emit.geoid()
    {
        ctx.note(format_args!("geoid heights: {}", g.describe()));
    }
    match &a.out_dir {
        Some(dir) => batch(&a, dir, &req, ctx),
        None if a.plans.len() > 1 => Err(Failure::usage("several plans need --out-dir DIR")),
        None => single(&a, &a.plans[0], &req, ctx),
    }
}

fn request(a: &CompileArgs) -> Request {
    let mut emit = EmitOptions {
        flavor: if a.instrumented { Flavor::Instrumented } else { Flavor::DropIn },
        upstream_compat: a.upstream_compat,
        ..EmitOptions::default()
    };
    if a.paparazzi_home.is_some() {
        emit.paparazzi_home.clone_from(&a.paparazzi_home);
    }
    Request {
        front: vouch_fpl::front::Options {
            search_dirs: a.include_dirs.clone(),
            upstream_includes: a.upstream_compat,
            upstream_flight_plans: vouch_fpl::front::upstream_flight_plans(
                emit.paparazzi_home.as_deref(),
            ),
            ..Default::default()
        },
        emit,
        dump: a.dump.is_some(),
        settings: a.settings.is_some() || a.settings_header.is_some(),
    }
}

/// Writes to a file, or to standard output for "-".
fn emit_to(path: &Path, bytes: &[u8], ctx: &mut Ctx) -> Result<(), Failure> {
    if path == Path::new("-") { ctx.out.write_all(bytes) } else { write_file(path, bytes) }
}

fn single(a: &CompileArgs, plan: &Path, req: &Request, ctx: &mut Ctx) -> CmdResult {
    if a.lint {
        let p = vouch_fpl::front::parse_file_with(plan, &req.front).map_err(rejected)?;
        for w in vouch_fpl::lint::lint(&p) {
            ctx.warn(&w);
        }
    }
    let built = vouch_fpl::pipeline::build(plan, req).map_err(rejected)?;
    super::report_built(ctx, &built, a.upstream_compat);
    let to_stdout = |p: &Option<PathBuf>| p.as_deref() == Some(Path::new("-"));
    match &a.output {
        Some(path) => write_file(path, built.header.as_bytes())?,
        None if to_stdout(&a.dump) || to_stdout(&a.settings) => {}
        None => ctx.out.write_all(built.header.as_bytes())?,
    }
    if let (Some(path), Some(dump)) = (&a.dump, &built.dump) {
        emit_to(path, dump.as_bytes(), ctx)?;
    }
    if let Some(s) = &built.settings {
        if let Some(path) = &a.settings {
            emit_to(path, s.xml.as_bytes(), ctx)?;
        }
        if let Some(path) = &a.settings_header {
            emit_to(path, s.header.as_bytes(), ctx)?;
        }
    }
    Ok(Exit::Ok)
}

/// Where a plan's header goes in --out-dir mode.
fn out_path(dir: &Path, plan: &Path) -> PathBuf {
    let relative =
        plan.is_relative() && !plan.components().any(|c| matches!(c, Component::ParentDir));
    let rel = if relative {
        plan.to_path_buf()
    } else {
        PathBuf::from(plan.file_name().unwrap_or_default())
    };
    dir.join(rel.with_extension("h"))
}

fn batch(a: &CompileArgs, dir: &Path, req: &Request, ctx: &mut Ctx) -> CmdResult {
    let outs: Vec<PathBuf> = a.plans.iter().map(|p| out_path(dir, p)).collect();
    let mut seen = std::collections::HashSet::new();
    if let Some(dup) = outs.iter().find(|o| !seen.insert(*o)) {
        return Err(Failure::usage(format_args!(
            "two plans would be written to {}",
            dup.display()
        )));
    }
    let results = vouch_fpl::pipeline::build_many(&a.plans, req);
    let mut rejected_plans = Vec::new();
    for (out, result) in outs.iter().zip(results) {
        match result {
            Ok(built) => {
                super::report_built(ctx, &built, a.upstream_compat);
                if let Some(parent) = out.parent() {
                    std::fs::create_dir_all(parent).map_err(|e| Failure::io(parent, &e))?;
                }
                write_file(out, built.header.as_bytes())?;
            }
            Err(d) => rejected_plans.push(d),
        }
    }
    let compiled = a.plans.len() - rejected_plans.len();
    ctx.note(format_args!("{compiled} of {} plans compiled into {}", a.plans.len(), dir.display()));
    match rejected_plans.pop() {
        None => Ok(Exit::Ok),
        Some(last) => {
            for d in &rejected_plans {
                crate::diagnostics::print(ctx.format, d, crate::contract::Severity::Error);
            }
            Err(rejected(last))
        }
    }
}

/// The version of `vouch fpl parse --json`; 2: enumerations (expressions, stages, waypoint
/// frames and origins, variables) in snake_case.
const PARSE_JSON_VERSION: u32 = 2;

/// `vouch fpl parse --json`: the resolved plan's fields beside the document's version.
#[derive(serde::Serialize)]
struct ParseDocument<'a> {
    version: u32,
    #[serde(flatten)]
    plan: &'a vouch_fpl::ast::FlightPlan,
}
