//! ROS map_server maps: the YAML metadata (`yaml_meta.rs`), the image (PGM, or PNG), nav2's
//! `loadMapFromFile` pixel → occupancy conversion and nav2's static layer occupancy → Costmap2D
//! value.
//!
//! The conversion follows map_server literally (navigation2 `a3a97043ee93`): the image becomes
//! 8-bit grey the way ImageMagick (Q16) exports it, `normalized = grey / 255.0f` in float, `1 −
//! normalized` unless `negate`, occupied when `≥ occupied_thresh`, free when `≤ free_thresh`
//! (free wins), scale mode rounds the values in between to 1..99, and in trinary and scale modes
//! a pixel whose alpha is below 255 is unknown. Thresholds are compared as floats, as Eigen does.

use std::path::Path;

use super::MapError;
use super::grey::{MapImage, grey8};
use super::pgm::parse_pgm;
use super::world::WorldParams;
pub use super::yaml_meta::{MapMode, RosMapMeta, parse_map_yaml};

/// A loaded map as a nav2 costmap (static layer, no inflation).
#[derive(Clone, Debug, PartialEq)]
pub struct RosMap {
    /// The metadata (the image path resolved against the YAML's folder).
    pub meta: RosMapMeta,
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Occupancy grid values (−1 unknown, 0..100), row 0 = bottom row of the image.
    pub occupancy: Vec<i8>,
    /// Costmap2D values (0 free, 254 lethal, 255 unknown; 1..253 only with scale mode when
    /// `trinary_costmap` is off), row 0 = bottom row of the image.
    pub costmap: Vec<u8>,
}

impl RosMap {
    /// The world frame of the map (origin x, y and resolution; nav2's costmap ignores the yaw).
    pub fn world(&self) -> WorldParams {
        WorldParams {
            origin: [self.meta.origin[0], self.meta.origin[1]],
            resolution: self.meta.resolution,
        }
    }
}

/// Load a map: a `.yaml` (map_server metadata naming the image) or an image directly
/// (`.pgm`/`.png`, with the defaults of [`RosMapMeta::default`]). `trinary_costmap` is the
/// static layer parameter (nav2 default true: every non-lethal known cell becomes free).
pub fn load_ros_map(path: &Path, trinary_costmap: bool) -> Result<RosMap, MapError> {
    let is_yaml = path.extension().is_some_and(|e| e == "yaml" || e == "yml");
    let meta = if is_yaml {
        let text = super::error::read_text(path)?;
        let mut meta = parse_map_yaml(path, &text)?;
        meta.image = path.parent().unwrap_or(Path::new(".")).join(&meta.image);
        meta
    } else {
        RosMapMeta { image: path.to_path_buf(), ..RosMapMeta::default() }
    };
    let data = std::fs::read(&meta.image).map_err(|e| MapError::io(&meta.image, e))?;
    let image = decode_image(&meta.image, &data)?;
    let occupancy = occupancy_grid(&meta, &image);
    let costmap = occupancy.iter().map(|&o| static_layer_value(o, trinary_costmap)).collect();
    Ok(RosMap { width: image.grey.width, height: image.grey.height, meta, occupancy, costmap })
}

/// Decode PGM or PNG (by content, not by name).
pub fn decode_image(path: &Path, data: &[u8]) -> Result<MapImage, MapError> {
    if data.starts_with(b"\x89PNG") {
        super::png_image::decode_png(path, data)
    } else {
        Ok(MapImage { grey: parse_pgm(path, data)?, alpha: None })
    }
}

/// map_server's occupancy grid of an image: values −1 (unknown) or 0..100, flipped so that row 0
/// is the bottom row of the image.
pub fn occupancy_grid(meta: &RosMapMeta, image: &MapImage) -> Vec<i8> {
    let img = &image.grey;
    let (w, h) = (img.width, img.height);
    let occupied_thresh = meta.occupied_thresh as f32;
    let free_thresh = meta.free_thresh as f32;
    let span = (meta.occupied_thresh - meta.free_thresh) as f32;
    let mut grid = vec![-1i8; w * h];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let grey = grey8(img.pixels[i], img.maxval);
            let v = if meta.mode == MapMode::Raw {
                if grey <= 100 { grey as i8 } else { -1 }
            } else if image.alpha.as_ref().is_some_and(|a| a[i] < 255) {
                -1
            } else {
                let mut n = grey as f32 / 255.0f32;
                if !meta.negate {
                    n = 1.0f32 - n;
                }
                if n <= free_thresh {
                    0
                } else if n >= occupied_thresh {
                    100
                } else if meta.mode == MapMode::Scale && n > free_thresh && n < occupied_thresh {
                    (((n - free_thresh) / span) * 100.0f32).round() as i8
                } else {
                    -1
                }
            };
            grid[w * (h - y - 1) + x] = v;
        }
    }
    grid
}

/// nav2 static layer `interpretValue` with its defaults (track_unknown_space true,
/// lethal_cost_threshold 100): unknown → 255, ≥ 100 → 254, else free (trinary) or scaled.
pub fn static_layer_value(occupancy: i8, trinary_costmap: bool) -> u8 {
    if occupancy == -1 {
        255
    } else if !(0..100).contains(&occupancy) {
        254
    } else if trinary_costmap {
        0
    } else {
        ((occupancy as f64 / 100.0) * 254.0) as u8
    }
}
