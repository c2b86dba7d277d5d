//! `vouch navfn suite gen`: deterministic generators for the nine categories of the paper's suite.
//!
//! Determinism: every map gets its own SplitMix64 stream derived from (seed, category, index), so
//! the same seed always gives the same files, and choosing a subset of categories does not change
//! the maps of the others.

mod cases;
mod categories;

pub use cases::sample_cases;
pub use categories::CATEGORIES;

use std::path::PathBuf;

use crate::campaign::error::{CampaignError, GenError};
use crate::campaign::grid::{Case, SuiteMap};
use crate::campaign::rng::SplitMix64;
use crate::campaign::ros_import::import_ros_map;

/// What to generate.
#[derive(Clone, Debug)]
pub struct GenOptions {
    /// The seed: the same seed always gives the same suite.
    pub seed: u64,
    /// Subset of [`CATEGORIES`]; empty = all nine.
    pub categories: Vec<String>,
    pub maps_per_category: u32,
    /// Smallest map width/height, border included (≥ 5).
    pub min_size: u32,
    /// Largest map width/height (inclusive).
    pub max_size: u32,
    /// Cases per map (all ordered pairs when the map has fewer).
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
                None => {
                    return Err(GenError::UnknownCategory {
                        name: c.clone(),
                        expected: CATEGORIES.join(", "),
                    })
                }
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

/// [`generate`], then import nav2 maps (map_server YAML + PGM) as category `ROS` with
/// `ros_cases` sampled cases each (deterministic for the seed).
pub fn generate_with_ros(
    opts: &GenOptions,
    ros_maps: &[PathBuf],
    ros_cases: usize,
) -> Result<Vec<SuiteMap>, CampaignError> {
    let mut maps = generate(opts)?;
    for (i, yaml) in ros_maps.iter().enumerate() {
        let name = yaml
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| format!("ros{i}"));
        let mut m = import_ros_map(yaml, &name, None)?;
        let mut rng = SplitMix64::derive(opts.seed, "ROS", i as u64);
        m.cases = sample_cases(&m, &mut rng, ros_cases);
        maps.push(m);
    }
    Ok(maps)
}
