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
    /// Directory searched for included procedures after the plan's own directory (repeatable;
    /// default: the nearest ancestor directory holding flight_plan.dtd)
    #[arg(long = "include-dir", value_name = "DIR")]
    include_dirs: Vec<PathBuf>,
    /// Output header (default: standard output, unless the dump or the settings go there)
    #[arg(short, long, value_name = "FILE", conflicts_with = "out_dir")]
    output: Option<PathBuf>,
    /// Compile every plan into DIR (in parallel): DIR/<plan path as given, .xml → .h>, or
    /// DIR/<file name>.h for absolute paths
    #[arg(long, value_name = "DIR")]
    out_dir: Option<PathBuf>,
    /// Also write upstream's dump (Paparazzi's flight_plan.xml): the expanded plan with
    /// numbered blocks and stages and the stage index of the ground station ("-": standard
    /// output, instead of the header)
    #[arg(long, value_name = "FILE", conflicts_with = "out_dir")]
    dump: Option<PathBuf>,
    /// Also write the settings made from the plan's variables (Paparazzi's settings.xml; "-":
    /// standard output, instead of the header)
    #[arg(long, value_name = "FILE", conflicts_with = "out_dir")]
    settings: Option<PathBuf>,
    /// Also write the C header of those settings (Paparazzi's settings.h)
    #[arg(long, value_name = "FILE", conflicts_with = "out_dir")]
    settings_header: Option<PathBuf>,
    /// Print exactly what upstream's generator prints, its known mistakes included (EGM96
    /// heights where the geoid is negative, WAYPOINTS_GLOBAL for "D M S" coordinates); search
    /// included procedures in upstream's order (the plan's directory, then
    /// $PAPARAZZI_HOME/conf/flight_plans); and print upstream's own stderr line "No SRTM data
    /// found to check altitude." when no SRTM terrain tile covers the reference (-v says why)
    #[arg(long)]
    upstream_compat: bool,
    /// Paparazzi home whose data/srtm/WW15MGH.DAC[.bz2] and conf/abi.xml are read (default:
    /// $PAPARAZZI_HOME; without one the egm96 crate stands in for the geoid grid)
    #[arg(long, value_name = "DIR")]
    paparazzi_home: Option<PathBuf>,
    /// Also show the mission-level warnings of `vouch fpl lint`
    #[arg(long)]
    lint: bool,
    /// Emit the instrumented flavour (user C wrapped in FP_C/FP_X/FP_V/FP_I for the stub runtime)
    #[arg(long)]
    instrumented: bool,
}

/// `vouch fpl parse`: the outline (or JSON) of the resolved plan.
pub fn parse(a: ParseArgs, ctx: &mut Ctx) -> CmdResult {
    let plan = a.plan.load(ctx, !a.no_extensions)?;
    if a.json {
        ctx.out.json(&plan)?;
    } else {
        ctx.out.write_all(vouch_fpl::ast::outline::outline(&plan).as_bytes())?;
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
