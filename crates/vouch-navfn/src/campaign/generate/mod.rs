//! `vouch navfn suite gen`: deterministic generators for the nine categories of the paper's suite.
//!
//! Determinism: every map gets its own SplitMix64 stream derived from (seed, category, index), so
//! the same seed always gives the same files, choosing a subset of categories does not change
//! the maps of the others, and a shard of the generation (`--shard I/N`) writes exactly the
//! files of the unsharded generation whose home shard it is.

mod cases;
mod categories;

pub use cases::sample_cases;
pub use categories::CATEGORIES;

use std::path::{Path, PathBuf};

use crate::campaign::error::{CampaignError, GenError};
use crate::campaign::grid::{Case, SuiteMap};
use crate::campaign::identity::{MANIFEST, SuiteManifest, costs_digest};
use crate::campaign::rng::SplitMix64;
use crate::campaign::ros_import::import_ros_map;
use crate::campaign::shard::Shard;
use crate::campaign::suite_io::{SuiteIoError, write_map};

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

/// The categories `opts` selects, in order.
fn selected(opts: &GenOptions) -> Result<Vec<&'static str>, GenError> {
    if opts.min_size < 5 || opts.min_size > opts.max_size || opts.max_size > 4096 {
        return Err(GenError::BadSize(opts.min_size, opts.max_size));
    }
    if opts.categories.is_empty() {
        return Ok(CATEGORIES.to_vec());
    }
    opts.categories
        .iter()
        .map(|c| {
            CATEGORIES.iter().copied().find(|k| *k == c.as_str()).ok_or_else(|| {
                GenError::UnknownCategory { name: c.clone(), expected: CATEGORIES.join(", ") }
            })
        })
        .collect()
}

/// Map `i` of category `cat`, without its cases (`digits` = width of the index in the name).
fn build_map(
    opts: &GenOptions,
    cat: &str,
    i: u32,
    digits: usize,
) -> Option<(SuiteMap, SplitMix64)> {
    let mut rng = SplitMix64::derive(opts.seed, cat, u64::from(i));
    let w = rng.range(opts.min_size, opts.max_size);
    let h = rng.range(opts.min_size, opts.max_size);
    let (mut m, suffix) = categories::build(cat, &mut rng, w, h)?;
    m.category = cat.to_string();
    m.name = format!("{i:0digits$}_{}x{}_{cat}{suffix}", m.width, m.height);
    Some((m, rng))
}

/// The cases of a built map: sampled, and for circus the paper's two lane cases first.
fn add_cases(m: &mut SuiteMap, rng: &mut SplitMix64, cases_per_map: usize) {
    m.cases = sample_cases(m, rng, cases_per_map);
    if m.category == "circus" && cases_per_map >= 2 {
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
}

/// Index width in map names: 3 digits, more when a category has more than 1,000 maps, so
/// that sorted names are in index order.
fn index_digits(maps: u32) -> usize {
    maps.saturating_sub(1).to_string().len().max(3)
}

/// Generate the maps of `shard` (those whose home shard it is, see [`crate::campaign::shard`])
/// one at a time into `emit`, and return the suite's manifest. Every map's stream depends only
/// on (seed, category, index), so the shards of a generation are, file for file, the unsharded
/// generation; every map is built (to learn its name) but only the shard's maps get cases.
pub fn generate_share(
    opts: &GenOptions,
    ros: &RosImport,
    shard: Shard,
    emit: &mut dyn FnMut(SuiteMap) -> Result<(), CampaignError>,
) -> Result<SuiteManifest, CampaignError> {
    let cats = selected(opts)?;
    let digits = index_digits(opts.maps_per_category);
    let mine = |m: &SuiteMap| {
        Shard::home(&format!("{}/{}", m.category, m.name), shard.count) == shard.index
    };
    let mut total = 0u64;
    for cat in &cats {
        for i in 0..opts.maps_per_category {
            let Some((mut m, mut rng)) = build_map(opts, cat, i, digits) else { continue };
            total += 1;
            if mine(&m) {
                add_cases(&mut m, &mut rng, opts.cases_per_map);
                emit(m)?;
            }
        }
    }
    let mut ros_maps = Vec::new();
    for (i, yaml) in ros.maps.iter().enumerate() {
        let name = yaml
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| format!("ros{i}"));
        let mut m = import_ros_map(yaml, &name, None)?;
        ros_maps.push((name, costs_digest(&m.costs)));
        total += 1;
        if mine(&m) {
            let mut rng = SplitMix64::derive(opts.seed, "ROS", i as u64);
            m.cases = sample_cases(&m, &mut rng, ros.cases);
            emit(m)?;
        }
    }
    Ok(SuiteManifest {
        format: 1,
        seed: opts.seed,
        categories: cats.iter().map(|c| c.to_string()).collect(),
        maps_per_category: opts.maps_per_category,
        size: [opts.min_size, opts.max_size],
        cases_per_map: opts.cases_per_map,
        ros_maps,
        ros_cases: ros.cases,
        maps: total,
    })
}

/// nav2 maps (map_server YAML + PGM) to import as category `ROS`, with `cases` sampled cases
/// each (deterministic for the seed).
#[derive(Clone, Debug, Default)]
pub struct RosImport {
    /// The YAML files.
    pub maps: Vec<PathBuf>,
    /// Cases per imported map.
    pub cases: usize,
}

/// Generate the whole suite in memory (maps in category order, then index order).
pub fn generate(opts: &GenOptions) -> Result<Vec<SuiteMap>, CampaignError> {
    generate_with_ros(opts, &RosImport::default())
}

/// [`generate`], then the imported nav2 maps.
pub fn generate_with_ros(
    opts: &GenOptions,
    ros: &RosImport,
) -> Result<Vec<SuiteMap>, CampaignError> {
    let mut maps = Vec::new();
    generate_share(opts, ros, Shard::ALL, &mut |m| {
        maps.push(m);
        Ok(())
    })?;
    Ok(maps)
}

/// What [`write_generated`] wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Written {
    /// Maps written (this shard's).
    pub maps: u64,
    /// Their cases.
    pub cases: u64,
    /// Maps of the whole suite.
    pub maps_total: u64,
}

/// Generate `shard`'s maps straight into the suite folder `dir` (one map in memory at a time)
/// and write the suite's manifest ([`MANIFEST`], the same bytes in every share).
pub fn write_generated(
    dir: &Path,
    opts: &GenOptions,
    ros: &RosImport,
    shard: Shard,
) -> Result<Written, CampaignError> {
    let (mut maps, mut cases) = (0u64, 0u64);
    let manifest = generate_share(opts, ros, shard, &mut |m| {
        write_map(dir, &m)?;
        maps += 1;
        cases += m.cases.len() as u64;
        Ok(())
    })?;
    std::fs::create_dir_all(dir)
        .map_err(|source| SuiteIoError::Io { path: dir.to_path_buf(), source })?;
    let path = dir.join(MANIFEST);
    std::fs::write(&path, manifest.to_text())
        .map_err(|source| SuiteIoError::Io { path, source })?;
    Ok(Written { maps, cases, maps_total: manifest.maps })
}
