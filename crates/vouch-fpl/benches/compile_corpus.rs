//! Benchmark: compile the whole corpus (parse + three passes + header emission).
//! Run: `cargo bench -p vouch-fpl --bench compile_corpus`.

use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};

fn corpus_plans() -> Vec<PathBuf> {
    let Some(dir) = vouch_testkit::shared("fpl/corpus", "INDEX.tsv") else { return Vec::new() };
    let Ok(index) = std::fs::read_to_string(dir.join("INDEX.tsv")) else { return Vec::new() };
    index
        .lines()
        .skip(1)
        .filter_map(|l| {
            let cols: Vec<&str> = l.split('\t').collect();
            (cols.len() >= 7 && cols[6] == "yes").then(|| dir.join(cols[0]))
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let plans = corpus_plans();
    if plans.is_empty() {
        return;
    }
    c.bench_function("compile_corpus_104_plans", |b| {
        b.iter(|| {
            let mut bytes = 0usize;
            for p in &plans {
                if let Ok(h) =
                    vouch_fpl::pipeline::compile_file(p, &vouch_fpl::emit::EmitOptions::default())
                {
                    bytes += h.len();
                }
            }
            bytes
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
