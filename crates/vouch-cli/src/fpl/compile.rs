//! `vouch fpl parse` and `vouch fpl compile`.

use std::path::PathBuf;

use clap::Args;
use vouch_fpl::emit::{EmitOptions, Flavor};

use super::{rejected, write_file, PlanArgs};
use crate::contract::{CmdResult, Ctx, Exit, Verbosity};

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
    #[command(flatten)]
    plan: PlanArgs,
    /// Output header (default: standard output)
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Also write upstream's dump (XML): the expanded plan with numbered blocks and stages, and
    /// the stage index used by the ground station
    #[arg(long, value_name = "FILE")]
    dump: Option<PathBuf>,
    /// Print exactly what upstream's generator prints, its known mistakes included (EGM96
    /// heights where the geoid is negative, WAYPOINTS_GLOBAL for "D M S" coordinates)
    #[arg(long)]
    upstream_compat: bool,
    /// Also show the mission-level warnings of `vouch fpl lint`
    #[arg(long)]
    lint: bool,
    /// Also write the settings made from the plan's variables (Paparazzi's settings.xml)
    #[arg(long, value_name = "FILE")]
    settings: Option<PathBuf>,
    /// Also write the C header of those settings (Paparazzi's settings.h)
    #[arg(long, value_name = "FILE")]
    settings_header: Option<PathBuf>,
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

/// `vouch fpl compile`: the header (and the dump); corrections of upstream's output are shown as
/// warnings.
pub fn compile(a: CompileArgs, ctx: &mut Ctx) -> CmdResult {
    let plan = a.plan.load(ctx, true)?;
    if a.lint {
        for w in vouch_fpl::lint::lint(&plan) {
            ctx.warn(&w);
        }
    }
    let opts = EmitOptions {
        source_path: a.plan.name(),
        flavor: if a.instrumented { Flavor::Instrumented } else { Flavor::DropIn },
        upstream_compat: a.upstream_compat,
        ..EmitOptions::default()
    };
    let emitted = vouch_fpl::emit::compile_plan_full(&plan, &opts)
        .map_err(|e| rejected(e.to_diagnostics(&plan.sources)))?;
    for c in emitted.notices.iter().chain(&emitted.corrections) {
        ctx.warn(c);
    }
    let header = emitted.header;
    if ctx.verbosity == Verbosity::Verbose {
        if let Ok(g) = opts.geoid() {
            ctx.note(format_args!("geoid heights: {}", g.describe()));
        }
    }
    match &a.output {
        Some(path) => write_file(path, header.as_bytes())?,
        None => ctx.out.write_all(header.as_bytes())?,
    }
    if let Some(path) = &a.dump {
        let text = vouch_fpl::emit::dump::dump(&plan)
            .map_err(|e| rejected(e.to_diagnostics(&plan.sources)))?;
        write_file(path, text.as_bytes())?;
    }
    if a.settings.is_some() || a.settings_header.is_some() {
        let s = vouch_fpl::emit::settings::settings(&plan, &opts.version)
            .map_err(|e| rejected(e.to_diagnostics(&plan.sources)))?;
        if let Some(path) = &a.settings {
            write_file(path, s.xml.as_bytes())?;
        }
        if let Some(path) = &a.settings_header {
            write_file(path, s.header.as_bytes())?;
        }
    }
    Ok(Exit::Ok)
}
