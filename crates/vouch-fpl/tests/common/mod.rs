//! Shared helpers of the compiler tests: locating `../shared/fpl/corpus` (skipping cleanly
//! when absent) and listing the plans upstream compiles.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// `../shared/fpl/corpus`, or `None` (with a message) when the reference data is absent.
pub fn corpus_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/fpl/corpus");
    if dir.join("INDEX.tsv").is_file() {
        Some(dir)
    } else {
        eprintln!("skipping: {} not found", dir.display());
        None
    }
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

/// The C compiler (`$CC` or `cc`), or `None` with a message when none can be run.
pub fn c_compiler() -> Option<String> {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_string());
    match std::process::Command::new(&cc).arg("--version").output() {
        Ok(o) if o.status.success() => Some(cc),
        _ => {
            eprintln!("skipping: no C compiler ({cc}) can be run");
            None
        }
    }
}
