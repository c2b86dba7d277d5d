//! Import a nav2 map (map_server YAML + PGM) as a suite map in NavFn costs, the way the paper's
//! suite made its `ROS` category (SEMANTICS.md §9): `value = 255 − pixel` (or `pixel` when
//! `negate`), `value < free_thresh·255` → 50, `value ≥ occupied_thresh·255` → 254, otherwise
//! `round(min(50 + 0.8·value, 253))`; then the 254 border. Rows stay in image order (no flip).
//! The YAML and PGM readers are the core's (`maps`).

use std::path::Path;

use crate::campaign::grid::{FREE, MAX_TRAVERSABLE, OBSTACLE, SuiteMap};
use crate::maps::MapError;
use crate::maps::pgm::parse_pgm;
use crate::maps::ros_yaml::parse_map_yaml;

/// Convert one grey sample (0..=maxval) with the yaml thresholds.
pub fn pixel_to_navfn(
    pixel: u16,
    maxval: u16,
    negate: bool,
    free_thresh: f64,
    occupied_thresh: f64,
) -> u8 {
    let p = f64::from(pixel) * 255.0 / f64::from(maxval.max(1));
    let value = if negate { p } else { 255.0 - p };
    if value < free_thresh * 255.0 {
        FREE
    } else if value >= occupied_thresh * 255.0 {
        OBSTACLE
    } else {
        (f64::from(FREE) + 0.8 * value).min(f64::from(MAX_TRAVERSABLE)).round() as u8
    }
}

/// Read `yaml` (and the image it names, relative to it) into a suite map of category `ROS`.
/// `image_override` replaces the yaml's image name (nav2's `empty_room.yaml` names a missing file).
pub fn import_ros_map(
    yaml: &Path,
    name: &str,
    image_override: Option<&Path>,
) -> Result<SuiteMap, MapError> {
    let text = crate::maps::read_text(yaml)?;
    let meta = parse_map_yaml(yaml, &text)?;
    let dir = yaml.parent().unwrap_or(Path::new("."));
    let image = match image_override {
        Some(p) => p.to_path_buf(),
        None => dir.join(&meta.image),
    };
    let data = std::fs::read(&image).map_err(|e| MapError::io(&image, e))?;
    let img = parse_pgm(&image, &data)?;
    if img.width < 3 || img.height < 3 {
        return Err(MapError::file(
            &image,
            format!("a {}x{} map is too small for NavFn (needs 3x3)", img.width, img.height),
        ));
    }
    let costs = img
        .pixels
        .iter()
        .map(|&p| {
            pixel_to_navfn(p, img.maxval, meta.negate, meta.free_thresh, meta.occupied_thresh)
        })
        .collect();
    let mut m = SuiteMap {
        category: "ROS".into(),
        name: name.into(),
        width: img.width as u32,
        height: img.height as u32,
        costs,
        cases: Vec::new(),
    };
    m.stamp_border();
    Ok(m)
}
