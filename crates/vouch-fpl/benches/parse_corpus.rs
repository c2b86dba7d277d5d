//! Criterion benchmark: parse every file of `../shared/fpl/corpus/INDEX.tsv` (the flight plans
//! with their includes expanded and names resolved, and the procedure files, which stop at the
//! root check). Run: `cargo bench -p vouch-fpl --bench parse_corpus`. Skips when the corpus is absent.

use std::path::{Path, PathBuf};

use criterion::{Criterion, criterion_group, criterion_main};

/// Every file of the corpus index (flight plans and procedures).
fn corpus_files(dir: &Path) -> Vec<PathBuf> {
    let index = std::fs::read_to_string(dir.join("INDEX.tsv")).unwrap_or_default();
    index.lines().skip(1).filter_map(|l| l.split('\t').next()).map(|p| dir.join(p)).collect()
}

fn corpus_parse(c: &mut Criterion) {
    let Some(dir) = vouch_testkit::shared("fpl/corpus", "INDEX.tsv") else { return };
    let files = corpus_files(&dir);
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
