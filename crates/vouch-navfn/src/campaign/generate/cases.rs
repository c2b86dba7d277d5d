//! Case sampling: ordered pairs of traversable cells, like the paper's suite — a random sample of
//! all pairs that always contains start = goal cases and, when the map has several 4-connected
//! regions, unreachable pairs.

use std::collections::HashSet;

use crate::campaign::grid::{Case, SuiteMap};
use crate::campaign::rng::SplitMix64;

/// Sample up to `want` distinct cases on `m`. Guarantees (when the map has a traversable cell):
/// at least one `start == goal` case, and at least one pair in different components when the
/// map has more than one. The result is sorted in the order it was drawn (deterministic).
pub fn sample_cases(m: &SuiteMap, rng: &mut SplitMix64, want: usize) -> Vec<Case> {
    let cells = m.traversable_cells();
    if cells.is_empty() || want == 0 {
        return Vec::new();
    }
    let total_pairs = cells.len() * cells.len();
    let want = want.min(total_pairs);
    let mut seen: HashSet<Case> = HashSet::new();
    let mut out = Vec::with_capacity(want);
    let mut push = |c: Case, out: &mut Vec<Case>| {
        if out.len() < want && seen.insert(c) {
            out.push(c);
        }
    };

    // 1. One start == goal case.
    let (x, y) = cells[rng.index(cells.len())];
    push(Case::new(x, y, x, y), &mut out);

    // 2. One pair across components, if there are several.
    let (label, count) = m.components();
    if count > 1 {
        let a = cells[rng.index(cells.len())];
        let la = label[m.idx(a.0, a.1)];
        let others: Vec<_> =
            cells.iter().copied().filter(|&(x, y)| label[m.idx(x, y)] != la).collect();
        if !others.is_empty() {
            let b = others[rng.index(others.len())];
            push(Case::new(a.0, a.1, b.0, b.1), &mut out);
        }
    }

    // 3. The rest: all pairs when the sample would cover most of them, else random draws.
    if want * 2 >= total_pairs {
        let mut all: Vec<Case> = Vec::with_capacity(total_pairs);
        for &(x0, y0) in &cells {
            for &(x1, y1) in &cells {
                all.push(Case::new(x0, y0, x1, y1));
            }
        }
        // Fisher–Yates with our generator, then take what is needed.
        for i in (1..all.len()).rev() {
            let j = rng.index(i + 1);
            all.swap(i, j);
        }
        for c in all {
            push(c, &mut out);
        }
    } else {
        let mut attempts = 0usize;
        while out.len() < want && attempts < want * 20 {
            attempts += 1;
            let a = cells[rng.index(cells.len())];
            let b = cells[rng.index(cells.len())];
            push(Case::new(a.0, a.1, b.0, b.1), &mut out);
        }
    }
    out
}
