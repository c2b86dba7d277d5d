//! `vouch navfn suite gen`: deterministic generators for the nine categories of the paper's suite.
//!
//! Determinism: every map gets its own SplitMix64 stream derived from (seed, category, index), so
//! the same seed always gives the same files, and choosing a subset of categories does not change
//! the maps of the others.

mod cases;
mod categories;

pub use cases::sample_cases;
pub use categories::CATEGORIES;

use crate::campaign::grid::{Case, SuiteMap};
use crate::campaign::rng::SplitMix64;

/// What to generate.
#[derive(Clone, Debug)]
pub struct GenOptions {
    pub seed: u64,
    /// Subset of [`CATEGORIES`]; empty = all nine.
    pub categories: Vec<String>,
    pub maps_per_category: u32,
    /// Inclusive range of map widths/heights, border included (≥ 5).
    pub min_size: u32,
    pub max_size: u32,
    pub cases_per_map: usize,
}

impl Default for GenOptions {
    fn default() -> Self {
        GenOptions {
            seed: 1,
            categories: Vec::new(),
            maps_per_category: 10,
            min_size: 5,
            max_size: 30,
            cases_per_map: 500,
        }
    }
}

/// Errors in generator options (the CLI maps them to exit code 2).
#[derive(Debug, thiserror::Error)]
pub enum GenError {
    #[error("unknown category `{0}` (expected one of: {list})", list = CATEGORIES.join(", "))]
    UnknownCategory(String),
    #[error("bad size range {0}..{1}: sizes must satisfy 5 <= min <= max <= 4096")]
    BadSize(u32, u32),
}

/// Generate the suite in memory (maps in category order, then index order).
pub fn generate(opts: &GenOptions) -> Result<Vec<SuiteMap>, GenError> {
    if opts.min_size < 5 || opts.min_size > opts.max_size || opts.max_size > 4096 {
        return Err(GenError::BadSize(opts.min_size, opts.max_size));
    }
    let cats: Vec<&str> = if opts.categories.is_empty() {
        CATEGORIES.to_vec()
    } else {
        let mut v = Vec::new();
        for c in &opts.categories {
            match CATEGORIES.iter().find(|k| **k == c.as_str()) {
                Some(k) => v.push(*k),
                None => return Err(GenError::UnknownCategory(c.clone())),
            }
        }
        v
    };
    let mut maps = Vec::new();
    for cat in cats {
        for i in 0..opts.maps_per_category {
            let mut rng = SplitMix64::derive(opts.seed, cat, u64::from(i));
            let w = rng.range(opts.min_size, opts.max_size);
            let h = rng.range(opts.min_size, opts.max_size);
            let Some((mut m, suffix)) = categories::build(cat, &mut rng, w, h) else { continue };
            m.category = cat.to_string();
            m.name = format!("{:03}_{}x{}_{}{}", i, m.width, m.height, cat, suffix);
            m.cases = sample_cases(&m, &mut rng, opts.cases_per_map);
            if cat == "circus" && opts.cases_per_map >= 2 {
                // The paper's circus cases: from the bottom of each lane to the top middle cell.
                let h = m.height;
                for c in [Case::new(1, h - 2, 2, 1), Case::new(3, h - 2, 2, 1)].into_iter().rev() {
                    if let Some(i) = m.cases.iter().position(|x| *x == c) {
                        m.cases.remove(i);
                    } else {
                        m.cases.pop();
                    }
                    m.cases.insert(0, c);
                }
            }
            maps.push(m);
        }
    }
    Ok(maps)
}
