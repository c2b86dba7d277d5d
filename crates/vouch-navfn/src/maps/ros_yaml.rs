//! ROS map_server maps: the YAML metadata, the image (PGM, or 8-bit PNG), the map_server
//! pixel → occupancy conversion (`negate`, `occupied_thresh`, `free_thresh`, `mode`
//! trinary/scale/raw) and nav2's static layer occupancy → Costmap2D value.
//!
//! The YAML is the flat `key: value` file map_server writes; a dozen keys do not justify a
//! YAML dependency (serde_yaml is unmaintained), and a hand parser gives line-located errors.

use std::path::{Path, PathBuf};

use super::pgm::{parse_pgm, GreyImage};
use super::world::WorldParams;
use super::MapError;

/// map_server's interpretation mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum MapMode {
    Trinary,
    Scale,
    Raw,
}

/// The YAML metadata of a map.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RosMapMeta {
    pub image: PathBuf,
    pub resolution: f64,
    pub origin: [f64; 3],
    pub negate: bool,
    pub occupied_thresh: f64,
    pub free_thresh: f64,
    pub mode: MapMode,
}

impl Default for RosMapMeta {
    /// map_server defaults (and nav2_system_tests' planner tester frame: origin 0, 1 m cells).
    fn default() -> Self {
        RosMapMeta {
            image: PathBuf::new(),
            resolution: 1.0,
            origin: [0.0; 3],
            negate: false,
            occupied_thresh: 0.65,
            free_thresh: 0.196,
            mode: MapMode::Trinary,
        }
    }
}

/// A loaded map as a nav2 costmap (static layer, no inflation).
#[derive(Clone, Debug, PartialEq)]
pub struct RosMap {
    pub meta: RosMapMeta,
    pub width: usize,
    pub height: usize,
    /// Occupancy grid values (−1 unknown, 0..100), row 0 = bottom row of the image.
    pub occupancy: Vec<i8>,
    /// Costmap2D values (0 free, 254 lethal, 255 unknown; 1..253 only with scale mode when
    /// `trinary_costmap` is off), row 0 = bottom row of the image.
    pub costmap: Vec<u8>,
}

impl RosMap {
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
        let text = std::fs::read_to_string(path).map_err(|e| MapError::io(path, e))?;
        let mut meta = parse_map_yaml(path, &text)?;
        meta.image = path.parent().unwrap_or(Path::new(".")).join(&meta.image);
        meta
    } else {
        RosMapMeta { image: path.to_path_buf(), ..RosMapMeta::default() }
    };
    let data = std::fs::read(&meta.image).map_err(|e| MapError::io(&meta.image, e))?;
    let (img, alpha) = decode_image(&meta.image, &data)?;
    let occupancy = to_occupancy(&meta, &img, alpha.as_deref());
    let costmap = occupancy.iter().map(|&o| static_layer_value(o, trinary_costmap)).collect();
    Ok(RosMap { width: img.width, height: img.height, meta, occupancy, costmap })
}

/// Parse map_server YAML text (flat keys; `origin: [x, y, yaw]`).
pub fn parse_map_yaml(path: &Path, text: &str) -> Result<RosMapMeta, MapError> {
    let mut meta = RosMapMeta::default();
    let (mut seen_image, mut seen_res) = (false, false);
    for (i, raw) in text.lines().enumerate() {
        let ln = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let Some((key, value)) = line.split_once(':') else {
            let msg = format!("expected `key: value`, found `{line}`");
            return Err(MapError::syntax(path, text, ln, "", msg));
        };
        let value = value.trim().trim_matches(|c| c == '"' || c == '\'');
        let at = |msg: String| MapError::syntax(path, text, ln, value, msg);
        let key = key.trim();
        seen_image |= key == "image";
        seen_res |= key == "resolution";
        apply_key(&mut meta, key, value, at)?;
    }
    if !seen_image {
        return Err(MapError::file(path, "missing `image:`"));
    }
    if !seen_res {
        return Err(MapError::file(path, "missing `resolution:`"));
    }
    if meta.free_thresh > meta.occupied_thresh {
        return Err(MapError::file(
            path,
            format!(
                "free_thresh {} exceeds occupied_thresh {}",
                meta.free_thresh, meta.occupied_thresh
            ),
        ));
    }
    Ok(meta)
}

/// Sets one key of the metadata; `at` locates an error at the value.
fn apply_key(
    meta: &mut RosMapMeta,
    key: &str,
    value: &str,
    at: impl Fn(String) -> MapError,
) -> Result<(), MapError> {
    let num = |what: &str| -> Result<f64, MapError> {
        value
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| at(format!("{what} `{value}` is not a number")))
    };
    let threshold = |what: &str| -> Result<f64, MapError> {
        let v = num(what)?;
        if (0.0..=1.0).contains(&v) {
            Ok(v)
        } else {
            Err(at(format!("{what} {v} is outside [0, 1]")))
        }
    };
    match key {
        "image" if value.is_empty() => return Err(at("image must name a file".into())),
        "image" => meta.image = PathBuf::from(value),
        "resolution" => {
            meta.resolution = num("resolution")?;
            if meta.resolution <= 0.0 {
                return Err(at(format!("resolution {value} must be > 0")));
            }
        }
        "origin" => {
            let inner = value.trim_start_matches('[').trim_end_matches(']');
            let nums: Option<Vec<f64>> = inner
                .split(',')
                .map(|p| p.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect();
            match nums {
                Some(v) if v.len() == 3 => meta.origin = [v[0], v[1], v[2]],
                _ => return Err(at(format!("origin must be `[x, y, yaw]`, found `{value}`"))),
            }
        }
        "negate" => {
            meta.negate = match value {
                "0" | "false" | "False" => false,
                "1" | "true" | "True" => true,
                _ => return Err(at(format!("negate must be 0 or 1, found `{value}`"))),
            }
        }
        "occupied_thresh" => meta.occupied_thresh = threshold("occupied_thresh")?,
        "free_thresh" => meta.free_thresh = threshold("free_thresh")?,
        "mode" => {
            meta.mode = match value {
                "trinary" => MapMode::Trinary,
                "scale" => MapMode::Scale,
                "raw" => MapMode::Raw,
                _ => {
                    let msg = format!("mode must be trinary, scale or raw, found `{value}`");
                    return Err(at(msg));
                }
            }
        }
        _ => {} // map_type and other keys do not affect the grid
    }
    Ok(())
}

/// Decode PGM or PNG into grey samples (+ alpha for PNG with an alpha channel).
fn decode_image(path: &Path, data: &[u8]) -> Result<(GreyImage, Option<Vec<bool>>), MapError> {
    if data.starts_with(b"\x89PNG") {
        super::png_image::decode_png(path, data)
    } else {
        Ok((parse_pgm(path, data)?, None))
    }
}

/// map_server's `loadMapFromFile` conversion; the grid is flipped so row 0 is the bottom.
fn to_occupancy(meta: &RosMapMeta, img: &GreyImage, opaque: Option<&[bool]>) -> Vec<i8> {
    let (w, h) = (img.width, img.height);
    let mut grid = vec![-1i8; w * h];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let shade = img.pixels[i] as f64 / img.maxval as f64;
            let occ = if meta.negate { shade } else { 1.0 - shade };
            let v = match meta.mode {
                MapMode::Trinary => {
                    if meta.occupied_thresh < occ {
                        100
                    } else if occ < meta.free_thresh {
                        0
                    } else {
                        -1
                    }
                }
                MapMode::Scale => {
                    if opaque.is_some_and(|a| !a[i]) {
                        -1
                    } else if meta.occupied_thresh < occ {
                        100
                    } else if occ < meta.free_thresh {
                        0
                    } else {
                        ((occ - meta.free_thresh) / (meta.occupied_thresh - meta.free_thresh)
                            * 100.0)
                            .round_ties_even() as i8
                    }
                }
                MapMode::Raw => {
                    let pct = (shade * 255.0).round();
                    if (0.0..=100.0).contains(&pct) {
                        pct as i8
                    } else {
                        -1
                    }
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
