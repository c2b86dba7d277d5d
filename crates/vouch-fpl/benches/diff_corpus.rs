//! `vouch fpl diff` of every corpus plan against its reformatted copy (equivalent: the walk goes
//! to the fixpoint of the product, ground-station jumps included). Prints, for the 104 plans,
//! the median and the worst of the per-plan times (each the median of `RUNS` runs), and the
//! plan that is the worst. Needs `../shared` (skips with a message without it).
//!
//! `cargo bench -p vouch-fpl --bench diff_corpus`

#[path = "../tests/support/reformat.rs"]
mod reformat;

use std::path::Path;
use std::time::{Duration, Instant};

use vouch_fpl::diff::{DiffOptions, Verdict, Version, diff};
use vouch_fpl::front::{Options, parse_file_with};

const RUNS: usize = 5;

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("mkdir");
    for e in std::fs::read_dir(from).expect("read_dir") {
        let e = e.expect("entry");
        let target = to.join(e.file_name());
        if e.file_type().expect("type").is_dir() {
            copy_tree(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), &target).expect("copy");
        }
    }
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort_unstable();
    v[v.len() / 2]
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/fpl/corpus");
    let Ok(index) = std::fs::read_to_string(root.join("INDEX.tsv")) else {
        println!("diff_corpus: ../shared/fpl/corpus is absent, nothing measured");
        return;
    };
    let dir = tempfile::tempdir().expect("tempdir");
    copy_tree(&root, dir.path());
    let mut times: Vec<(Duration, String, usize)> = Vec::new();
    for line in index.lines().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        if f.get(1) != Some(&"flight_plan") || f.get(6) != Some(&"yes") {
            continue;
        }
        let path = dir.path().join(f[0]);
        let copy = path.with_extension("reformatted.xml");
        let text = std::fs::read_to_string(&path).expect("read");
        std::fs::write(&copy, reformat::reformat(&text)).expect("write");
        let mut runs = Vec::with_capacity(RUNS);
        let mut pairs = 0;
        for _ in 0..RUNS {
            // Timed: what `vouch fpl diff OLD NEW` does after reading the files.
            let start = Instant::now();
            let a = parse_file_with(&path, &Options::default()).expect("parses");
            let b = parse_file_with(&copy, &Options::default()).expect("parses");
            let fa = vouch_fpl::passes::lower::lower(&a).expect("lowers");
            let fb = vouch_fpl::passes::lower::lower(&b).expect("lowers");
            let r = diff(
                Version { plan: &a, fp: &fa },
                Version { plan: &b, fp: &fb },
                &DiffOptions::default(),
            )
            .expect("runs");
            runs.push(start.elapsed());
            assert_eq!(r.verdict, Verdict::Equivalent, "{}", f[0]);
            pairs = r.state_pairs;
        }
        times.push((median(runs), f[0].to_string(), pairs));
    }
    times.sort();
    let n = times.len();
    let total: Duration = times.iter().map(|t| t.0).sum();
    let (worst, worst_plan, worst_pairs) = &times[n - 1];
    println!(
        "fpl diff, each corpus plan against its reformatted copy ({n} plans, median of {RUNS} runs each):"
    );
    println!(
        "  median {:.2} ms, worst {:.1} ms ({worst_plan}, {worst_pairs} state pairs), all plans {:.2} s",
        times[n / 2].0.as_secs_f64() * 1e3,
        worst.as_secs_f64() * 1e3,
        total.as_secs_f64()
    );
}
