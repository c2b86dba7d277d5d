//! Measurement helper behind `vouch fpl bench-parse` and the criterion bench: parse every
//! `.xml` file of a directory tree (procedure files are read too; they stop at the root check).

use std::path::{Path, PathBuf};
use std::time::Instant;

/// All `.xml` files under `dir`, sorted.
pub fn xml_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else { continue };
        for e in rd.flatten() {
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

#[derive(Debug, Clone)]
pub struct BenchResult {
    pub parsed: usize,
    pub rejected: usize,
    pub procedures: usize,
    pub bytes: u64,
    pub passes: u32,
    pub best_ms: f64,
    pub mean_ms: f64,
}

/// Parses every file `passes` times; reports the best and mean wall time of one pass.
pub fn parse_all(files: &[PathBuf], passes: u32) -> BenchResult {
    let bytes = files.iter().filter_map(|f| std::fs::metadata(f).ok()).map(|m| m.len()).sum();
    let (mut best, mut total) = (f64::INFINITY, 0.0);
    let (mut parsed, mut rejected, mut procedures) = (0, 0, 0);
    for _ in 0..passes {
        let t = Instant::now();
        let (mut p, mut r, mut pr) = (0, 0, 0);
        for f in files {
            match super::parse_file(f) {
                Ok(_) => p += 1,
                Err(d) if d.first().is_some_and(|e| e.kind == super::ErrorKind::WrongRoot) => {
                    pr += 1
                }
                Err(_) => r += 1,
            }
        }
        let ms = t.elapsed().as_secs_f64() * 1e3;
        best = f64::min(best, ms);
        total += ms;
        (parsed, rejected, procedures) = (p, r, pr);
    }
    BenchResult {
        parsed,
        rejected,
        procedures,
        bytes,
        passes,
        best_ms: best,
        mean_ms: total / passes as f64,
    }
}
