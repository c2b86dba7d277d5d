//! `vouch fpl …` subcommands (owned by the fpl family).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Subcommand;

#[derive(Subcommand)]
pub enum FplCmd {
    /// Print what this family can do so far
    Info,
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
    },
    /// Benchmark: parse every .xml file under DIR (default ../shared/fpl/corpus) N times
    BenchParse {
        dir: Option<PathBuf>,
        #[arg(long, default_value_t = 20)]
        iterations: u32,
    },
}

pub fn run(cmd: FplCmd) -> ExitCode {
    match cmd {
        FplCmd::Parse { plan, json, include_dirs } => parse_cmd(&plan, json, include_dirs),
        FplCmd::BenchParse { dir, iterations } => bench_parse_cmd(dir, iterations),
        FplCmd::Info => {
            println!("vouch fpl: not implemented yet");
            ExitCode::SUCCESS
        }
    }
}

fn parse_cmd(plan: &std::path::Path, json: bool, include_dirs: Vec<PathBuf>) -> ExitCode {
    use std::io::IsTerminal;
    let opts = vouch_fpl::front::Options { search_dirs: include_dirs, ..Default::default() };
    match vouch_fpl::front::parse_file_with(plan, &opts) {
        Ok(p) => {
            if json {
                match serde_json::to_string_pretty(&p) {
                    Ok(s) => println!("{s}"),
                    Err(e) => {
                        eprintln!("error: cannot serialise the plan: {e}");
                        return ExitCode::from(2);
                    }
                }
            } else {
                print!("{}", vouch_fpl::front::outline::outline(&p));
            }
            for w in &p.warnings {
                eprint!("{}", vouch_fpl::front::Diagnostics { items: vec![w.clone()], sources: p.sources.clone() }.render(false));
            }
            ExitCode::SUCCESS
        }
        Err(d) => {
            if json {
                println!("{}", serde_json::to_string_pretty(&d).unwrap_or_default());
            }
            eprint!("{}", d.render(std::io::stderr().is_terminal()));
            ExitCode::from(if d.is_io() { 2 } else { 1 })
        }
    }
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
