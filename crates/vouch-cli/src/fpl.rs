//! `vouch fpl …` subcommands (owned by the fpl family).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Subcommand;

#[derive(Subcommand)]
pub enum FplCmd {
    /// Parse a flight plan (includes, paths, names resolved) and print it, or its located errors.
    /// Exit 0 when it parses, 1 on a plan error, 2 when the file cannot be read.
    Parse {
        /// The flight-plan XML file
        plan: PathBuf,
        /// Print the resolved plan as JSON instead of an outline
        #[arg(long)]
        json: bool,
        /// Directory searched for included procedures (repeatable; default: the nearest
        /// ancestor directory holding flight_plan.dtd)
        #[arg(long = "include-dir")]
        include_dirs: Vec<PathBuf>,
        /// Refuse the VFPG <forbidden_deroutes> extension, as upstream's DTD does
        #[arg(long)]
        no_extensions: bool,
    },
    /// Compile a flight plan to a drop-in flight_plan.h (upstream Paparazzi generator, 2024-10).
    /// Exit 0 on success, 1 when the plan is rejected, 2 on a read/write error.
    Compile {
        /// The flight-plan XML file
        plan: PathBuf,
        /// Output header (default: standard output)
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Also write upstream's dump (XML): the expanded plan with numbered blocks and stages, and
        /// the stage index used by the ground station
        #[arg(long)]
        dump: Option<PathBuf>,
        /// Emit the instrumented flavour (user C wrapped in FP_C/FP_X/FP_V/FP_I for the stub runtime)
        #[arg(long)]
        instrumented: bool,
        /// Directory searched for included procedures (repeatable)
        #[arg(long = "include-dir")]
        include_dirs: Vec<PathBuf>,
    },
    /// Run the reference interpreter: the table of calls (block, stage, code, conditions).
    /// Conditions come from --conditions (whitespace-separated integers, odd = true), or a
    /// seeded random oracle (--seed), else are all false.
    Sim {
        /// The flight-plan XML file
        plan: PathBuf,
        /// Number of auto_nav calls
        #[arg(long, default_value_t = 20)]
        steps: usize,
        /// File of answers: integers, one consumed per condition (odd = true) or value (n/2)
        #[arg(long, conflicts_with = "seed")]
        conditions: Option<PathBuf>,
        /// Seed of the random oracle
        #[arg(long)]
        seed: Option<u64>,
        /// Percentage of true conditions for --seed
        #[arg(long, default_value_t = 30)]
        percent_true: u64,
        /// JSON output for tools
        #[arg(long)]
        json: bool,
        /// Print the trace format shared with the C stub driver
        #[arg(long, conflicts_with = "json")]
        trace: bool,
    },
    /// Translation validation: the compiled header (built with `cc` and the stub runtime) against
    /// the reference semantics, exhaustively over every condition outcome of the first --depth
    /// calls plus seeded random runs. Exit 0 agree, 1 plan rejected, 2 error, 3 mismatch.
    Validate {
        plan: PathBuf,
        /// Calls explored exhaustively
        #[arg(long, default_value_t = 8)]
        depth: usize,
        /// Seeded random runs compared after the exhaustive part
        #[arg(long, default_value_t = 3)]
        random_runs: usize,
        #[arg(long, default_value_t = 500)]
        random_steps: usize,
        /// Work budget: call paths compared before the exploration is cut
        #[arg(long, default_value_t = 500_000)]
        max_paths: usize,
        /// Print the static per-block bound (stages and external events per call)
        #[arg(long)]
        bounds: bool,
        #[arg(long)]
        json: bool,
        #[arg(long = "include-dir")]
        include_dirs: Vec<PathBuf>,
    },
    /// Mission-level warnings (codes FPL-W001...), located in the XML. Exit 0, or 3 with
    /// --strict when there are warnings.
    Lint {
        plan: PathBuf,
        #[arg(long)]
        json: bool,
        #[arg(long)]
        strict: bool,
        #[arg(long = "include-dir")]
        include_dirs: Vec<PathBuf>,
    },
    /// Model checking of the abstract state space (block, stage, last block, last stage; free
    /// conditions). Default: --no-blocked --deadlock-free. Exit 3 when a property fails.
    Check {
        plan: PathBuf,
        /// e.g. 'always eventually block(Land)', 'never block(HOME)' (repeatable)
        #[arg(long = "property")]
        properties: Vec<String>,
        /// Every reachable state can reach one of these blocks (comma separated)
        #[arg(long, value_delimiter = ',')]
        safe_blocks: Vec<String>,
        /// No block change is ever refused by a forbidden deroute
        #[arg(long)]
        no_blocked: bool,
        /// No reachable state where every successor is forbidden
        #[arg(long)]
        deadlock_free: bool,
        #[arg(long, default_value_t = 200_000)]
        max_states: usize,
        /// Also model ground-station jumps to any block at any call
        #[arg(long)]
        operator: bool,
        #[arg(long)]
        json: bool,
        #[arg(long = "include-dir")]
        include_dirs: Vec<PathBuf>,
    },
    /// SVG picture of the block graph (next, deroute, return, exception edges; forbidden marked)
    Graph {
        plan: PathBuf,
        /// Output SVG (default: standard output)
        #[arg(short, long)]
        output: Option<PathBuf>,
        #[arg(long = "include-dir")]
        include_dirs: Vec<PathBuf>,
    },
    /// Benchmark: parse every .xml file under DIR (default ../shared/fpl/corpus) N times
    BenchParse {
        dir: Option<PathBuf>,
        #[arg(long, default_value_t = 20)]
        iterations: u32,
    },
}

pub fn run(cmd: FplCmd, _ctx: &mut crate::contract::Ctx) -> crate::contract::CmdResult {
    crate::legacy(run_legacy(cmd))
}

fn run_legacy(cmd: FplCmd) -> ExitCode {
    match cmd {
        FplCmd::Parse { plan, json, include_dirs, no_extensions } => {
            parse_cmd(&plan, json, include_dirs, no_extensions)
        }
        FplCmd::BenchParse { dir, iterations } => bench_parse_cmd(dir, iterations),
        FplCmd::Compile { plan, output, dump, instrumented, include_dirs } => {
            compile_cmd(&plan, output, dump, instrumented, include_dirs)
        }
        FplCmd::Sim { plan, steps, conditions, seed, percent_true, json, trace } => {
            sim_cmd(&plan, steps, conditions, seed, percent_true, json, trace)
        }
        FplCmd::Validate {
            plan,
            depth,
            random_runs,
            random_steps,
            max_paths,
            bounds,
            json,
            include_dirs,
        } => {
            let opts = vouch_fpl::evidence::validate::Options {
                depth,
                random_runs,
                random_steps,
                max_paths,
                ..Default::default()
            };
            ExitCode::from(vouch_fpl::evidence::commands::validate_cmd(
                &plan,
                include_dirs,
                &opts,
                json,
                bounds,
            ))
        }
        FplCmd::Lint { plan, json, strict, include_dirs } => ExitCode::from(
            vouch_fpl::evidence::commands::lint_cmd(&plan, include_dirs, json, strict),
        ),
        FplCmd::Check {
            plan,
            properties,
            safe_blocks,
            no_blocked,
            deadlock_free,
            max_states,
            operator,
            json,
            include_dirs,
        } => {
            let a = vouch_fpl::evidence::commands::CheckArgs {
                properties,
                safe_blocks,
                no_blocked,
                deadlock_free,
                max_states,
                operator,
                json,
            };
            ExitCode::from(vouch_fpl::evidence::commands::check_cmd(&plan, include_dirs, &a))
        }
        FplCmd::Graph { plan, output, include_dirs } => ExitCode::from(
            vouch_fpl::evidence::commands::graph_cmd(&plan, include_dirs, output.as_deref()),
        ),
    }
}

fn parse_cmd(
    plan: &std::path::Path,
    json: bool,
    include_dirs: Vec<PathBuf>,
    no_extensions: bool,
) -> ExitCode {
    use std::io::IsTerminal;
    let opts = vouch_fpl::front::Options {
        search_dirs: include_dirs,
        allow_forbidden_deroutes: !no_extensions,
    };
    match vouch_fpl::front::parse_file_with(plan, &opts) {
        Ok(p) => {
            if json {
                match serde_json::to_string_pretty(&p) {
                    Ok(s) => out(&format!("{s}\n")),
                    Err(e) => {
                        eprintln!("error: cannot serialise the plan: {e}");
                        return ExitCode::from(2);
                    }
                }
            } else {
                out(&vouch_fpl::front::outline::outline(&p));
            }
            print_warnings(&p);
            ExitCode::SUCCESS
        }
        Err(d) => {
            if json {
                out(&format!("{}\n", serde_json::to_string_pretty(&d).unwrap_or_default()));
            }
            eprint!("{}", d.render(std::io::stderr().is_terminal()));
            ExitCode::from(if d.is_io() { 2 } else { 1 })
        }
    }
}

/// The plan's warnings on stderr, one rendered diagnostic each.
fn print_warnings(plan: &vouch_fpl::ast::FlightPlan) {
    for w in &plan.warnings {
        eprint!(
            "{}",
            vouch_fpl::front::Diagnostics { items: vec![w.clone()], sources: plan.sources.clone() }
                .render(false)
        );
    }
}

/// Writes a result file; a failure is reported and becomes exit code 2.
fn write_file(path: &std::path::Path, text: &str) -> Result<(), ExitCode> {
    std::fs::write(path, text).map_err(|e| {
        eprintln!("error: cannot write {}: {e}", path.display());
        ExitCode::from(2)
    })
}

/// Writes to stdout, ignoring a closed pipe (`vouch fpl parse plan.xml | head`).
fn out(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

fn bench_parse_cmd(dir: Option<PathBuf>, iterations: u32) -> ExitCode {
    let dir = dir.unwrap_or_else(|| PathBuf::from("../shared/fpl/corpus"));
    let files = vouch_fpl::front::bench::xml_files(&dir);
    if files.is_empty() {
        eprintln!("error: no .xml file under {}", dir.display());
        return ExitCode::from(2);
    }
    let r = vouch_fpl::front::bench::parse_all(&files, iterations.max(1));
    println!(
        "{} files ({} flight plans parsed, {} rejected, {} procedures), {} bytes: best {:.2} ms, mean {:.2} ms per pass over all files ({} passes)",
        files.len(), r.parsed, r.rejected, r.procedures, r.bytes, r.best_ms, r.mean_ms, r.passes
    );
    ExitCode::SUCCESS
}

/// Parses a plan for the back-end commands, printing located errors (exit 1, or 2 for I/O).
fn parse_for_backend(
    plan: &std::path::Path,
    include_dirs: Vec<PathBuf>,
) -> Result<vouch_fpl::ast::FlightPlan, ExitCode> {
    use std::io::IsTerminal;
    let opts = vouch_fpl::front::Options { search_dirs: include_dirs, ..Default::default() };
    vouch_fpl::front::parse_file_with(plan, &opts).map_err(|d| {
        eprint!("{}", d.render(std::io::stderr().is_terminal()));
        ExitCode::from(if d.is_io() { 2 } else { 1 })
    })
}

fn compile_cmd(
    plan_path: &std::path::Path,
    output: Option<PathBuf>,
    dump: Option<PathBuf>,
    instrumented: bool,
    include_dirs: Vec<PathBuf>,
) -> ExitCode {
    use std::io::IsTerminal;
    use vouch_fpl::emit::{EmitOptions, Flavor};
    let plan = match parse_for_backend(plan_path, include_dirs) {
        Ok(p) => p,
        Err(code) => return code,
    };
    // Lint findings (issue 4) are shown on stderr; they never change the exit code.
    eprint!("{}", vouch_fpl::lint::render(&plan, &vouch_fpl::lint::lint(&plan)));
    let opts = EmitOptions {
        source_path: plan_path.display().to_string(),
        flavor: if instrumented { Flavor::Instrumented } else { Flavor::DropIn },
        ..EmitOptions::default()
    };
    let header = match vouch_fpl::emit::compile_plan(&plan, &opts) {
        Ok(h) => h,
        Err(e) => {
            eprint!("{}", e.to_diagnostics(&plan).render(std::io::stderr().is_terminal()));
            return ExitCode::from(1);
        }
    };
    match &output {
        Some(path) => {
            if let Err(code) = write_file(path, &header) {
                return code;
            }
        }
        None => out(&header),
    }
    if let Some(path) = dump {
        if let Err(code) = write_file(&path, &vouch_fpl::emit::dump::dump(&plan)) {
            return code;
        }
    }
    print_warnings(&plan);
    ExitCode::SUCCESS
}

fn sim_cmd(
    plan_path: &std::path::Path,
    steps: usize,
    conditions: Option<PathBuf>,
    seed: Option<u64>,
    percent_true: u64,
    json: bool,
    trace: bool,
) -> ExitCode {
    use vouch_fpl::semantics::oracle::{Oracle, Scripted, Seeded};
    let plan = match parse_for_backend(plan_path, Vec::new()) {
        Ok(p) => p,
        Err(code) => return code,
    };
    let fp = match vouch_fpl::passes::lower::lower(&plan) {
        Ok(fp) => fp,
        Err(e) => {
            eprint!("{}", e.to_diagnostics(&plan).render(false));
            return ExitCode::from(1);
        }
    };
    let mut oracle: Box<dyn Oracle> = match (conditions, seed) {
        (Some(path), _) => match std::fs::read_to_string(&path)
            .map_err(|e| e.to_string())
            .and_then(|t| Scripted::parse(&t))
        {
            Ok(s) => Box::new(s),
            Err(e) => {
                eprintln!("error: {}: {e}", path.display());
                return ExitCode::from(2);
            }
        },
        (None, Some(s)) => Box::new(Seeded::new(s, percent_true.min(100))),
        (None, None) => Box::new(Scripted::default()),
    };
    let run = match vouch_fpl::sim::simulate(&fp, oracle.as_mut(), steps) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: the interpreter exceeded its per-call bound: {e:?}");
            return ExitCode::from(3);
        }
    };
    if json {
        out(&format!("{}\n", vouch_fpl::sim::json(&fp, &run)));
    } else if trace {
        out(&run.to_text());
    } else {
        out(&vouch_fpl::sim::table(&fp, &run));
    }
    ExitCode::SUCCESS
}
