//! Criterion benchmark: parse all 116 XML files of `shared/fpl/corpus` (106 flight plans with
//! their includes expanded and names resolved, 10 procedure files that stop at the root check).
//! Run: `cargo bench -p vouch-fpl --bench parse_corpus`. Skips when the corpus is absent.

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};

fn corpus_parse(c: &mut Criterion) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/fpl/corpus");
    let files = vouch_fpl::front::bench::xml_files(&dir);
    if files.is_empty() {
        eprintln!("skipping: no corpus at {}", dir.display());
        return;
    }
    c.bench_function(&format!("parse all {} corpus files", files.len()), |b| {
        b.iter(|| {
            let mut ok = 0usize;
            for f in &files {
                if vouch_fpl::front::parse_file(f).is_ok() {
                    ok += 1;
                }
            }
            std::hint::black_box(ok)
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = corpus_parse
}
criterion_main!(benches);
