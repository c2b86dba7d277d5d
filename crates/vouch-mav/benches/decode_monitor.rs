//! ns per message for decode + monitor on a recording: `cargo bench -p vouch-mav --bench
//! decode_monitor [-- FILE.tlog]` (default: the largest recording of `../shared/mavlink/tlogs`).
//!
//! A plain timing loop (harness = false) instead of criterion: the figure wanted is one mean over
//! ~97k real messages, repeated a few times; criterion would add a large dependency build to a
//! 2-core CI for no extra information. Prints min and median of the repetitions.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use vouch_mav::codec::{MessageView, TlogReader};
use vouch_mav::dialect::Dialect;
use vouch_mav::monitor::{Monitor, Verdict};

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
    let reps = 7;
    let mut decode_only = Vec::new();
    let mut full = Vec::new();
    let mut frames = 0u64;
    for _ in 0..reps {
        // Decode only: tlog record → frame (CRC) → view → read one field.
        let t = Instant::now();
        let mut n = 0u64;
        let mut acc = 0.0;
        for rec in TlogReader::new(&data, &dialect) {
            if let Some(v) = MessageView::of_frame(&rec.frame, &dialect) {
                acc += v.payload.first().copied().unwrap_or(0) as f64;
            }
            n += 1;
        }
        decode_only.push(t.elapsed().as_nanos() as f64 / n as f64);
        std::hint::black_box(acc);
        // Decode + monitor with the standard library.
        let mut m = Monitor::with_stdlib(dialect.clone(), &[]).expect("stdlib");
        let t = Instant::now();
        let mut violations = 0;
        for rec in TlogReader::new(&data, &dialect) {
            if let Some(v) = MessageView::of_frame(&rec.frame, &dialect) {
                if let Verdict::Violation(_) =
                    m.observe(&v, rec.frame.sysid, rec.frame.compid, None, rec.time_us)
                {
                    violations += 1;
                }
            }
        }
        full.push(t.elapsed().as_nanos() as f64 / n as f64);
        frames = n;
        assert_eq!(violations, 0);
    }
    let stats = |v: &mut Vec<f64>| {
        v.sort_by(|a, b| a.total_cmp(b));
        (v[0], v[v.len() / 2])
    };
    let (dmin, dmed) = stats(&mut decode_only);
    let (fmin, fmed) = stats(&mut full);
    println!("{}: {frames} messages, {reps} repetitions", file.display());
    println!("decode only (tlog + CRC + view): min {dmin:.0} ns/msg, median {dmed:.0} ns/msg");
    println!("decode + monitor (stdlib):       min {fmin:.0} ns/msg, median {fmed:.0} ns/msg");
}
