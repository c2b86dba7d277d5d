//! Criterion benchmark: parse all XML files of `../shared/fpl/corpus` (the flight plans with
//! their includes expanded and names resolved, and the procedure files, which stop at the root
//! check). Run: `cargo bench -p vouch-fpl --bench parse_corpus`. Skips when the corpus is absent.

use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, Criterion};

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

fn corpus_parse(c: &mut Criterion) {
    let Some(dir) = vouch_testkit::shared("fpl/corpus", "INDEX.tsv") else { return };
    let files = xml_files(&dir);
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
