//! Shared helpers of the integration tests: locating `../shared` and comparing golden text.
#![allow(dead_code)]

use std::path::PathBuf;

/// `../shared/navfn`: `None` with a skip message when absent, a failure when
/// `VOUCH_REQUIRE_SHARED=1`.
pub fn shared_navfn() -> Option<PathBuf> {
    vouch_testkit::shared("navfn", "SEMANTICS.md")
}

/// Lines of a golden file that our runner must reproduce (CASE, PATH, WORLD).
pub fn golden_lines(text: &str) -> Vec<&str> {
    text.lines()
        .filter(|l| l.starts_with("CASE ") || l.starts_with("PATH") || l.starts_with("WORLD"))
        .collect()
}

/// Compare produced and golden text case by case; returns (cases, equal cases, first diff).
pub fn compare(produced: &str, golden: &str) -> (usize, usize, Option<String>) {
    let p = golden_lines(produced);
    let g = golden_lines(golden);
    let split = |lines: &[&str]| -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for l in lines {
            if l.starts_with("CASE ") {
                out.push(String::new());
            }
            if let Some(last) = out.last_mut() {
                last.push_str(l);
                last.push('\n');
            }
        }
        out
    };
    let (pc, gc) = (split(&p), split(&g));
    let mut equal = 0;
    let mut first = None;
    for (i, gcase) in gc.iter().enumerate() {
        match pc.get(i) {
            Some(pcase) if pcase == gcase => equal += 1,
            other => {
                if first.is_none() {
                    first = Some(format!(
                        "case {i}:\n  golden:   {}\n  produced: {}",
                        gcase.chars().take(600).collect::<String>(),
                        other.map(|s| s.chars().take(600).collect::<String>()).unwrap_or_default()
                    ));
                }
            }
        }
    }
    if pc.len() != gc.len() && first.is_none() {
        first = Some(format!("produced {} cases, golden {}", pc.len(), gc.len()));
    }
    (gc.len(), equal, first)
}
