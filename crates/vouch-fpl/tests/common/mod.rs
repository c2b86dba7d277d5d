//! What the compiler tests share: the upstream corpus (`../shared/fpl/corpus`, through
//! vouch-testkit: skipped when absent, a failure under `VOUCH_REQUIRE_SHARED=1`), the plans
//! upstream compiles, and the stub runtime.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// `../shared/fpl/corpus`, or `None` when the reference data is absent (see vouch-testkit).
pub fn corpus_dir() -> Option<PathBuf> {
    vouch_testkit::shared("fpl/corpus", "INDEX.tsv")
}

/// The 104 plans whose `upstream_generator_ok` column is `yes`.
pub fn corpus_plans(dir: &Path) -> Vec<PathBuf> {
    let index = std::fs::read_to_string(dir.join("INDEX.tsv")).expect("INDEX.tsv readable");
    index
        .lines()
        .skip(1)
        .filter_map(|l| {
            let cols: Vec<&str> = l.split('\t').collect();
            (cols.len() >= 7 && cols[1] == "flight_plan" && cols[6] == "yes")
                .then(|| dir.join(cols[0]))
        })
        .collect()
}

pub fn stub_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/stub")
}

/// The C compiler (`$CC` or `cc`), or `None` when none can be run (see vouch-testkit).
pub fn c_compiler() -> Option<String> {
    vouch_testkit::c_compiler()
}

/// Every corpus plan validated with `opts`, in parallel: (corpus-relative name, the report or
/// the error's text).
pub fn validate_corpus(
    opts: &vouch_fpl::evidence::validate::Options,
) -> Option<Vec<(String, Result<vouch_fpl::evidence::validate::Report, String>)>> {
    use rayon::prelude::*;
    let dir = corpus_dir()?;
    let plans = corpus_plans(&dir);
    assert_eq!(plans.len(), 104);
    let results = plans
        .par_iter()
        .map(|p| {
            let name = p.strip_prefix(&dir).unwrap_or(p).display().to_string();
            let r = vouch_fpl::front::parse_file(p).map_err(|d| d.listing()).and_then(|plan| {
                vouch_fpl::evidence::validate::validate(&plan, opts).map_err(|e| e.to_string())
            });
            (name, r)
        })
        .collect();
    Some(results)
}
