//! `vouch fpl bench-parse`: the front end's timing harness (kept out of the library). Parses
//! every `.xml` file of a directory tree several times and reports the best and mean wall time
//! of one pass, measured by this run. Procedure files are read too; they stop at the root check.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use vouch_fpl::diag::ErrorKind;

use crate::contract::{CmdResult, Ctx, Exit, Failure};

/// Arguments of `vouch fpl bench-parse`.
#[derive(Args)]
pub struct BenchParseArgs {
    /// Directory searched (recursively) for .xml files, e.g. a Paparazzi conf/flight_plans
    dir: PathBuf,
    /// Passes over all files (the best and the mean pass are reported)
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..))]
    iterations: u32,
}

/// All `.xml` files under `dir`, sorted.
fn xml_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "xml") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// Outcome counts of one pass.
#[derive(Default, Clone, Copy)]
struct Counts {
    parsed: usize,
    rejected: usize,
    procedures: usize,
}

fn one_pass(files: &[PathBuf]) -> Counts {
    let mut c = Counts::default();
    for f in files {
        match vouch_fpl::front::parse_file(f) {
            Ok(_) => c.parsed += 1,
            Err(d) if d.first().is_some_and(|e| e.kind == ErrorKind::WrongRoot) => {
                c.procedures += 1
            }
            Err(_) => c.rejected += 1,
        }
    }
    c
}

/// `vouch fpl bench-parse`: one summary line on standard output.
pub fn bench_parse(a: BenchParseArgs, ctx: &mut Ctx) -> CmdResult {
    if !a.dir.is_dir() {
        return Err(Failure::usage(format_args!("{}: not a directory", a.dir.display())));
    }
    let files = xml_files(&a.dir);
    if files.is_empty() {
        return Err(Failure::usage(format_args!("no .xml file under {}", a.dir.display())));
    }
    let bytes: u64 = files.iter().filter_map(|f| std::fs::metadata(f).ok()).map(|m| m.len()).sum();
    let (mut best, mut total, mut counts) = (f64::INFINITY, 0.0, Counts::default());
    for _ in 0..a.iterations {
        let t = Instant::now();
        counts = one_pass(&files);
        let ms = t.elapsed().as_secs_f64() * 1e3;
        best = best.min(ms);
        total += ms;
    }
    let mean = total / f64::from(a.iterations);
    writeln!(
        ctx.out,
        "{} files ({} flight plans parsed, {} rejected, {} procedures), {bytes} bytes: best {best:.2} ms, mean {mean:.2} ms per pass over all files ({} passes)",
        files.len(),
        counts.parsed,
        counts.rejected,
        counts.procedures,
        a.iterations
    )?;
    Ok(Exit::Ok)
}
