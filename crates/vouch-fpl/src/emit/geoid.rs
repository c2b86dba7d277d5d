//! EGM96 geoid height, looked up the way upstream's generator does: latitude and longitude
//! truncated toward zero to whole degrees, no interpolation, the value of the 15-minute grid
//! `WW15MGH.DAC` at that node (signed 16-bit big-endian centimetres).
//!
//! Source of the grid values, in order:
//! 1. `$PAPARAZZI_HOME/data/srtm/WW15MGH.DAC` (uncompressed) when present — the exact file;
//! 2. otherwise the `egm96` crate's spherical-harmonic synthesis (the EGM96 coefficients from
//!    which the grid was computed) at the node, rounded to the centimetre like the grid.
//!    Agreement with the file is expected at nearly every node but is not verified bit for bit
//!    here (the file is not in `../shared`).

use std::collections::HashMap;
use std::path::Path;
use std::sync::{Mutex, OnceLock};

const COLS: usize = 1440;
const ROWS: usize = 721;

enum Source {
    Grid(Vec<i16>),
    Model,
}

fn source() -> &'static Source {
    static SRC: OnceLock<Source> = OnceLock::new();
    SRC.get_or_init(|| {
        if let Ok(home) = std::env::var("PAPARAZZI_HOME") {
            let p = Path::new(&home).join("data/srtm/WW15MGH.DAC");
            if let Ok(bytes) = std::fs::read(&p) {
                if bytes.len() == COLS * ROWS * 2 {
                    return Source::Grid(
                        bytes.chunks_exact(2).map(|c| i16::from_be_bytes([c[0], c[1]])).collect(),
                    );
                }
            }
        }
        Source::Model
    })
}

/// Node value in metres at whole degrees (`lat` in -90..=90, `lon` in -180..=180).
fn node(lat: i32, lon: i32) -> f64 {
    match source() {
        Source::Grid(g) => {
            let row = ((90 - lat) * 4) as usize;
            let col = (4 * if lon < 0 { lon + 360 } else { lon }) as usize;
            g.get(row * COLS + col.min(COLS - 1)).map(|v| f64::from(*v) / 100.0).unwrap_or(0.0)
        }
        Source::Model => {
            static CACHE: OnceLock<Mutex<HashMap<(i32, i32), f64>>> = OnceLock::new();
            let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
            if let Some(v) = cache.lock().ok().and_then(|c| c.get(&(lat, lon)).copied()) {
                return v;
            }
            let cm = (egm96::egm96_compute_altitude_offset(f64::from(lat), f64::from(lon)) * 100.0)
                .round();
            let v = cm / 100.0;
            if let Ok(mut c) = cache.lock() {
                c.insert((lat, lon), v);
            }
            v
        }
    }
}

/// Geoid height (metres above the WGS84 ellipsoid) at a position given in radians.
pub fn geoid_height(lat_rad: f64, lon_rad: f64) -> f64 {
    let lat = super::geo::deg_of_rad(lat_rad).trunc() as i32;
    let lon = super::geo::deg_of_rad(lon_rad).trunc() as i32;
    node(lat.clamp(-90, 90), lon.clamp(-180, 180))
}

/// Which grid source is in use (for `--verbose` output and docs).
pub fn source_name() -> &'static str {
    match source() {
        Source::Grid(_) => "WW15MGH.DAC from PAPARAZZI_HOME",
        Source::Model => "egm96 crate (spherical harmonics at the grid node, rounded to cm)",
    }
}
