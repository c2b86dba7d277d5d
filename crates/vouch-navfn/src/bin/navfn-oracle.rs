//! `navfn-oracle`: vouch's NavFn speaking the oracle contract of `vouch navfn suite diff`
//! (docs/navfn-campaign.md), as a small stand-alone executable — the same code path as
//! `vouch navfn suite run --trace`. It doubles as the reference for anyone wrapping the C++
//! NavFn, and as the perturbed oracle of the differential harness's self test
//! (`--perturb-pri-inc`, test only).
//!
//! Usage: `navfn-oracle [--mode paper|navfn] [--algo dijkstra|astar] [--trace hash|cells] [--pot]
//! [--perturb-pri-inc X] TEST_TXT_OR_FOLDER`

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use vouch_navfn::campaign::CampaignError;
use vouch_navfn::campaign::oracle::{EmitOptions, emit_path};
use vouch_navfn::campaign::trace::TraceDetail;
use vouch_navfn::suite::RunMode;

/// Why the oracle stopped: bad input, or its own output went away.
enum Stop {
    Input(CampaignError),
    Output(std::io::Error),
}

impl From<CampaignError> for Stop {
    fn from(e: CampaignError) -> Self {
        Stop::Input(e)
    }
}

fn usage(msg: &str) -> ExitCode {
    eprintln!("navfn-oracle: {msg}");
    eprintln!(
        "usage: navfn-oracle [--mode paper|navfn] [--algo dijkstra|astar] [--trace hash|cells] [--pot] TEST_TXT"
    );
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let (mut mode, mut algo, mut trace, mut pot, mut perturb, mut path) =
        ("paper".to_string(), "dijkstra".to_string(), None, false, None, None::<PathBuf>);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--mode" => mode = args.next().unwrap_or_default(),
            "--algo" => algo = args.next().unwrap_or_default(),
            "--trace" => {
                trace = match args.next().as_deref() {
                    Some("hash") => Some(TraceDetail::Hash),
                    Some("cells") => Some(TraceDetail::Cells),
                    other => return usage(&format!("--trace takes hash or cells, not {other:?}")),
                }
            }
            "--pot" => pot = true,
            "--perturb-pri-inc" => match args.next().and_then(|v| v.parse::<f32>().ok()) {
                Some(v) => perturb = Some(v),
                None => return usage("--perturb-pri-inc takes a number"),
            },
            p if !p.starts_with("--") && path.is_none() => path = Some(PathBuf::from(p)),
            other => return usage(&format!("unexpected argument `{other}`")),
        }
    }
    let mode = match (mode.as_str(), algo.as_str()) {
        ("paper", _) => RunMode::Paper,
        ("navfn", "dijkstra") => RunMode::NavfnDijkstra,
        ("navfn", "astar") => RunMode::NavfnAstar,
        _ => return usage(&format!("unsupported --mode {mode} --algo {algo}")),
    };
    let Some(path) = path else { return usage("missing test file") };
    let opts = EmitOptions { mode, trace, pot, perturb_pri_inc: perturb };
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let written =
        emit_path(&path, &opts, |text| out.write_all(text.as_bytes()).map_err(Stop::Output));
    match written.and_then(|_| out.flush().map_err(Stop::Output)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Stop::Output(e)) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(Stop::Output(e)) => {
            eprintln!("navfn-oracle: standard output: {e}");
            ExitCode::from(2)
        }
        Err(Stop::Input(e)) => {
            eprintln!("navfn-oracle: {e}");
            ExitCode::from(if e.is_io() { 2 } else { 1 })
        }
    }
}
