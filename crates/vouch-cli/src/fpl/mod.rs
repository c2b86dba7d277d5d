//! `vouch fpl …`: Paparazzi flight plans. Argument types and thin calls into `vouch_fpl`; one
//! file per group of subcommands (compile: `parse`/`compile`; evidence: `validate`/`lint`/
//! `check`/`graph`; sim; bench).

mod aircraft;
mod bench;
mod compile;
mod diff;
mod evidence;
mod sim;

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use vouch_fpl::ast::FlightPlan;
use vouch_fpl::diag::Diagnostics;
use vouch_fpl::passes::fp::Fp;

use crate::contract::{CmdResult, Ctx, Failure, Verbosity};

/// The `vouch fpl` subcommands.
#[derive(Subcommand)]
pub enum FplCmd {
    /// Parse a flight plan and print its outline, or its located errors
    ///
    /// Includes, paths and names are resolved; `--json` prints the resolved plan.
    #[command(after_help = after_help!(
        ["vouch fpl parse examples/fpl/demo.xml", "vouch fpl parse --json examples/fpl/demo.xml"],
        "0 parsed, 1 plan rejected, 2 usage or I/O error"
    ))]
    Parse(compile::ParseArgs),
    /// Compile flight plans to drop-in flight_plan.h files
    ///
    /// The header of Paparazzi's generator (2024-10), byte for byte with --upstream-compat, and on
    /// request upstream's dump and settings. Upstream's forms work too: `-dump`, `-settings` (to
    /// standard output).
    #[command(after_help = after_help!(
        [
            "vouch fpl compile examples/fpl/demo.xml -o flight_plan.h --dump flight_plan.xml",
            "vouch fpl compile plans/*.xml --out-dir generated/"
        ],
        "0 compiled, 1 plan rejected, 2 usage or I/O error"
    ))]
    Compile(compile::CompileArgs),
    /// Paparazzi's gen_aircraft, flight-plan part: writes an aircraft's generated files
    ///
    /// Reads conf/conf.xml, finds the aircraft's flight plan and writes flight_plan.h,
    /// flight_plan.xml (and with --settings the settings) under var/aircrafts/AC/, only when they
    /// change. Upstream's `-name AC` works.
    #[command(after_help = after_help!(
        ["PAPARAZZI_HOME=~/paparazzi vouch fpl aircraft --name Microjet --target sim"],
        "0 written or up to date, 1 plan or configuration rejected, 2 usage or I/O error"
    ))]
    Aircraft(aircraft::AircraftArgs),
    /// Run the reference interpreter and print the table of calls
    ///
    /// One row per `auto_nav()` call: block, stage, code run, conditions read. Conditions come
    /// from --conditions (whitespace-separated integers, odd = true), or a seeded random oracle
    /// (--seed), else are all false.
    #[command(after_help = after_help!(
        ["vouch fpl sim examples/fpl/demo.xml --steps 50 --seed 7"],
        "0 simulated, 1 plan rejected, 2 usage or I/O error"
    ))]
    Sim(sim::SimArgs),
    /// Check the compiled C against the reference semantics (translation validation)
    ///
    /// The compiled header, built with `cc` and the stub runtime, is run on every call path and
    /// operator jump from every reachable state (to the fixpoint; --depth N bounds it), plus
    /// seeded random runs.
    #[command(after_help = after_help!(
        ["vouch fpl validate examples/fpl/demo.xml --bounds"],
        "0 agree, 1 plan rejected, 2 usage, I/O or C compiler error, 3 disagreement"
    ))]
    Validate(evidence::ValidateArgs),
    /// Mission-level warnings (fpl::W001…) and compile's warnings, located in the XML
    ///
    /// The warnings `compile` gives (upstream's notices, fpl::W02x) are printed too, on stderr.
    #[command(after_help = after_help!(
        ["vouch fpl lint examples/fpl/demo.xml --strict"],
        "0 no warning (or warnings without --strict), 1 plan rejected, 2 usage or I/O error, \
         3 warnings with --strict"
    ))]
    Lint(evidence::LintArgs),
    /// Model-check properties on the plan's whole reachable state graph
    ///
    /// The validator's walk with free conditions. Without a property: --no-blocked
    /// --deadlock-free.
    #[command(after_help = after_help!(
        [
            "vouch fpl check examples/fpl/demo.xml --deadlock-free --no-blocked",
            "vouch fpl check examples/fpl/demo.xml --property 'never block(HOME)'"
        ],
        "0 every property holds, 1 plan or property rejected, 2 usage or I/O error, \
         3 a property fails or is not established (a budget cut the state space)"
    ))]
    Check(evidence::CheckArgs),
    /// Compare two versions of a plan by behaviour
    ///
    /// Equivalent, or the shortest run that tells them apart, side by side and located in both
    /// files; a structural summary first (blocks, stages, exceptions, waypoints).
    #[command(after_help = after_help!(
        [
            "vouch fpl diff old.xml new.xml",
            "vouch fpl diff --git HEAD~1 conf/flight_plans/mission.xml",
            "vouch fpl diff --git main --json"
        ],
        "0 equivalent, 1 a plan rejected, 2 usage or I/O error (git), 3 different or undecided"
    ))]
    Diff(diff::DiffArgs),
    /// Draw the block graph as SVG
    ///
    /// Edges: next, deroute, return, exception; forbidden deroutes marked.
    #[command(after_help = after_help!(
        ["vouch fpl graph examples/fpl/demo.xml -o demo.svg"],
        "0 drawn, 1 plan rejected, 2 usage or I/O error"
    ))]
    Graph(evidence::GraphArgs),
    /// Time the front end on a folder of plans
    ///
    /// Parses every .xml file under a directory, several passes, and prints the best and mean
    /// time of one pass (measured now, on this machine).
    #[command(after_help = after_help!(
        ["vouch fpl bench-parse examples/fpl --iterations 50"],
        "0 measured, 2 usage or I/O error"
    ))]
    BenchParse(bench::BenchParseArgs),
}

/// Runs one `vouch fpl` subcommand.
pub fn run(cmd: FplCmd, ctx: &mut Ctx) -> CmdResult {
    match cmd {
        FplCmd::Parse(a) => compile::parse(a, ctx),
        FplCmd::Compile(a) => compile::compile(a, ctx),
        FplCmd::Aircraft(a) => aircraft::aircraft(a, ctx),
        FplCmd::Sim(a) => sim::sim(a, ctx),
        FplCmd::Validate(a) => evidence::validate(a, ctx),
        FplCmd::Lint(a) => evidence::lint(a, ctx),
        FplCmd::Check(a) => evidence::check(a, ctx),
        FplCmd::Graph(a) => evidence::graph(a, ctx),
        FplCmd::Diff(a) => diff::diff(a, ctx),
        FplCmd::BenchParse(a) => bench::bench_parse(a, ctx),
    }
}

/// The plan file and where its included procedures are found (shared by every subcommand).
#[derive(Args)]
pub struct PlanArgs {
    /// The flight-plan XML file
    plan: PathBuf,
    /// Directory searched for included procedures after the plan's own directory (repeatable;
    /// default: the nearest ancestor directory holding flight_plan.dtd)
    #[arg(long = "include-dir", value_name = "DIR")]
    include_dirs: Vec<PathBuf>,
}

impl PlanArgs {
    /// Parses the plan; its warnings are shown, its errors become the failure.
    fn load(&self, ctx: &Ctx, allow_forbidden_deroutes: bool) -> Result<FlightPlan, Failure> {
        let opts = vouch_fpl::front::Options {
            search_dirs: self.include_dirs.clone(),
            allow_forbidden_deroutes,
            ..Default::default()
        };
        let plan = vouch_fpl::front::parse_file_with(&self.plan, &opts).map_err(rejected)?;
        for w in &plan.warnings {
            ctx.warn(w);
        }
        Ok(plan)
    }

    /// The plan's name as the user gave it.
    fn name(&self) -> String {
        self.plan.display().to_string()
    }
}

/// A parse or compile failure: an unreadable plan is an I/O error, anything else a rejection.
fn rejected(d: Diagnostics) -> Failure {
    if d.is_io() { Failure::Usage(miette::Report::new(d)) } else { Failure::rejected(d) }
}

/// The three passes (size checks included) and the FP the semantics runs on.
fn lowered(plan: &FlightPlan) -> Result<Fp, Failure> {
    let reject = |e: vouch_fpl::passes::CompileError| rejected(e.to_diagnostics(&plan.sources));
    vouch_fpl::passes::compile(plan).map_err(reject)?;
    vouch_fpl::passes::lower::lower(plan).map_err(reject)
}

/// A built plan's stderr: whether the terrain was checked, then its warnings. Without an SRTM
/// tile at the reference, `--upstream-compat` prints upstream's own line (as every upstream run
/// without tiles does); otherwise it is a note shown with `-v`.
fn report_built(ctx: &Ctx, built: &vouch_fpl::pipeline::Built, upstream_compat: bool) {
    use vouch_fpl::emit::terrain::Coverage;
    match &built.terrain {
        Coverage::NoTile { name, searched } if upstream_compat => {
            ctx.note("No SRTM data found to check altitude.");
            if ctx.verbosity == Verbosity::Verbose {
                let dirs: Vec<String> = searched.iter().map(|d| d.display().to_string()).collect();
                ctx.note(format_args!(
                    "note: the line above is upstream's generator's own stderr line, printed as \
                     upstream prints it under --upstream-compat: no SRTM tile {name} (searched \
                     {}), so the terrain is not checked",
                    dirs.join(", ")
                ));
            }
        }
        Coverage::NoTile { name, searched } if ctx.verbosity == Verbosity::Verbose => {
            let dirs: Vec<String> = searched.iter().map(|d| d.display().to_string()).collect();
            ctx.note(format_args!(
                "note: no SRTM tile {name} (searched {}): the terrain is not checked",
                dirs.join(", ")
            ));
        }
        Coverage::OffTile(path) if ctx.verbosity == Verbosity::Verbose => {
            ctx.note(format_args!(
                "note: the reference lies in the southernmost half row of {}, where upstream reads \
                 past the tile: the terrain is not checked there",
                path.display()
            ));
        }
        _ => {}
    }
    for w in &built.warnings {
        ctx.warn(w);
    }
}

/// Writes a result file.
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    std::fs::write(path, bytes).map_err(|e| Failure::io(path, &e))
}

/// Upstream's single-dash long options (`gen_flight_plan -dump`, `gen_aircraft -name AC`) as
/// clap's double-dash ones, for `vouch fpl compile` and `vouch fpl aircraft` only (called on the
/// whole command line before clap parses it). `-dump` and `-settings` on `compile` send that
/// output to standard output, as upstream's `-dump` did.
pub fn upstream_args(
    args: impl IntoIterator<Item = std::ffi::OsString>,
) -> Vec<std::ffi::OsString> {
    let mut args: Vec<std::ffi::OsString> = args.into_iter().collect();
    let words: Vec<Option<&str>> = args.iter().map(|a| a.to_str()).collect();
    let Some(sub) = words.iter().position(|w| *w == Some("fpl")).map(|i| i + 1) else {
        return args;
    };
    let map: &[(&str, &str)] = match words.get(sub).copied().flatten() {
        Some("compile") => &[("-dump", "--dump=-"), ("-settings", "--settings=-")],
        Some("aircraft") => &[
            ("-name", "--name"),
            ("-target", "--target"),
            ("-conf", "--conf"),
            ("-ac_dir", "--ac-dir"),
            ("-conf_dir", "--conf-dir"),
            ("-flight_plan", "--flight-plan"),
            ("-settings", "--settings"),
            ("-all", "--all"),
        ],
        _ => return args,
    };
    for a in args.iter_mut().skip(sub + 1) {
        if let Some((_, to)) = map.iter().find(|(from, _)| a.to_str() == Some(from)) {
            *a = std::ffi::OsString::from(to);
        }
    }
    args
}

#[cfg(test)]
mod tests {
    use super::upstream_args;

    fn run(line: &str) -> Vec<String> {
        let v = upstream_args(line.split(' ').map(std::ffi::OsString::from));
        v.into_iter().map(|s| s.to_string_lossy().into_owned()).collect()
    }

    #[test]
    fn upstream_forms_become_long_options() {
        assert_eq!(
            run("vouch fpl compile -dump p.xml"),
            ["vouch", "fpl", "compile", "--dump=-", "p.xml"]
        );
        assert_eq!(
            run("vouch fpl aircraft -name Microjet -target sim -all"),
            ["vouch", "fpl", "aircraft", "--name", "Microjet", "--target", "sim", "--all"]
        );
        // Other commands and families are left alone.
        assert_eq!(run("vouch fpl parse -dump"), ["vouch", "fpl", "parse", "-dump"]);
        assert_eq!(run("vouch navfn plan -name"), ["vouch", "navfn", "plan", "-name"]);
    }
}
