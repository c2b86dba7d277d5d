//! ns per message for decode + monitor on a recording: `cargo bench -p vouch-mav --bench
//! decode_monitor [-- FILE.tlog] [--baseline DIR]` (default: the largest recording of
//! `../shared/mavlink/tlogs`). `--baseline DIR` also times the protocol files of DIR (e.g. an
//! earlier version of the standard library, `git show REV:crates/vouch-mav/protocols/…`) in the
//! same run, interleaved with the standard library, so that both see the same machine load.
//!
//! A plain timing loop (harness = false) instead of criterion: the figure wanted is one mean over
//! ~97k real messages, repeated a few times; criterion would add a large dependency build to a
//! 2-core CI for no extra information. Prints min and median of the repetitions, wall time and
//! time on a CPU (see `support`).

mod support;

use std::path::PathBuf;
use std::sync::Arc;

use support::{Figures, timed};
use vouch_mav::codec::{MessageView, TlogReader};
use vouch_mav::dialect::Dialect;
use vouch_mav::monitor::{Monitor, Verdict};
use vouch_mav::protocol::load_protocols;

/// The `.vproto` files of `dir`, in name order, as `(name, text)`.
fn protocol_files(dir: &std::path::Path) -> Vec<(String, String)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "vproto"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let text =
                std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            (p.display().to_string(), text)
        })
        .collect()
}

/// Decode + monitor over the whole recording; the number of violations.
fn run_monitor(m: &mut Monitor, data: &[u8], dialect: &Dialect) -> u64 {
    let mut violations = 0;
    for rec in TlogReader::new(data, dialect) {
        if let Some(v) = MessageView::of_frame(&rec.frame, dialect)
            && let Verdict::Violation(_) =
                m.observe(&v, rec.frame.sysid, rec.frame.compid, None, rec.time_us)
        {
            violations += 1;
        }
    }
    violations
}

fn main() {
    // The recording given on the command line, else the largest one of the reference data.
    let file = match std::env::args().skip(1).find(|a| a.ends_with(".tlog")) {
        Some(f) => PathBuf::from(f),
        None => {
            let Some(dir) = vouch_testkit::shared("mavlink/tlogs", "uavlogviewer_flight_logs.tlog")
            else {
                return;
            };
            dir.join("uavlogviewer_flight_logs.tlog")
        }
    };
    let data = std::fs::read(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let dialect = Arc::new(Dialect::default_dialect().expect("default dialect"));
    let args: Vec<String> = std::env::args().collect();
    let baseline = args
        .iter()
        .position(|a| a == "--baseline")
        .and_then(|i| args.get(i + 1))
        .map(|d| protocol_files(std::path::Path::new(d)));
    let reps = 7;
    let (mut decode_only, mut full) = (Figures::default(), Figures::default());
    let mut base = Figures::default();
    let mut base_violations = 0;
    let mut frames = 0u64;
    for _ in 0..reps {
        // Decode only: tlog record → frame (CRC) → view → read one field.
        let mut n = 0u64;
        let mut acc = 0.0;
        let t = timed(|| {
            for rec in TlogReader::new(&data, &dialect) {
                if let Some(v) = MessageView::of_frame(&rec.frame, &dialect) {
                    acc += v.payload.first().copied().unwrap_or(0) as f64;
                }
                n += 1;
            }
        });
        decode_only.add(t, n);
        std::hint::black_box(acc);
        // Decode + monitor with the standard library.
        let mut m = Monitor::with_stdlib(dialect.clone(), &[]).expect("stdlib");
        let mut violations = 0;
        let t = timed(|| violations = run_monitor(&mut m, &data, &dialect));
        full.add(t, n);
        assert_eq!(violations, 0);
        if let Some(sources) = &baseline {
            let set = load_protocols(&dialect, sources, &[]).expect("baseline protocols");
            let mut m = Monitor::new(dialect.clone(), set);
            let t = timed(|| violations = run_monitor(&mut m, &data, &dialect));
            base.add(t, n);
            base_violations = violations;
        }
        frames = n;
    }
    println!("{}: {frames} messages, {reps} repetitions", file.display());
    println!("decode only (tlog + CRC + view): {}", decode_only.line());
    println!("decode + monitor (stdlib):       {}", full.line());
    if baseline.is_some() {
        println!("decode + monitor (baseline):     {} ({base_violations} violations)", base.line());
    }
}
