//! EGM96 geoid height, looked up the way upstream's generator does: latitude and longitude
//! normalised, converted to degrees and truncated toward zero, no interpolation, the value of
//! the 15-minute grid `WW15MGH.DAC` at that node (16-bit big-endian centimetres).
//!
//! The grid is read from `$PAPARAZZI_HOME/data/srtm/`, as upstream reads it: `WW15MGH.DAC`,
//! else `WW15MGH.DAC.bz2` (the file Paparazzi ships, decompressed with the `bzip2` crate), else
//! `WW15MGH.DAC.gz` (`flate2`). Without a Paparazzi home the `egm96` crate's spherical-harmonic
//! synthesis at the node, rounded to the centimetre, stands in (it differs from the grid by a
//! centimetre at a few nodes; the CLI says so).
//!
//! Every node is known both as the grid says (signed) and as upstream prints it on 64-bit
//! OCaml, where the sign extension of the 16-bit value is a no-op and negative heights come out
//! 655.36 m too high ([`Node::upstream`]).

use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

use super::geo::deg_of_rad;

const COLS: usize = 1440;
const ROWS: usize = 721;
/// Size of the uncompressed grid.
pub const GRID_BYTES: usize = COLS * ROWS * 2;

/// The grid's file names, in upstream's search order (supported compressions only).
const NAMES: [&str; 3] = ["WW15MGH.DAC", "WW15MGH.DAC.bz2", "WW15MGH.DAC.gz"];

/// Why the geoid grid of a Paparazzi home cannot be used (upstream: `Not_found`,
/// `End_of_file`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GeoidError {
    /// No `WW15MGH.DAC` (plain, `.bz2` or `.gz`) in the directory.
    #[error("no EGM96 geoid grid WW15MGH.DAC (or .bz2, .gz) in {0}")]
    Missing(PathBuf),
    /// The file is shorter than the grid, or does not decompress.
    #[error("{0}: not a complete EGM96 grid ({1})")]
    Broken(PathBuf, String),
}

/// Where geoid heights come from.
pub enum Geoid {
    /// The official grid (raw big-endian bytes), decompressed progressively: only as far as the
    /// southernmost node asked for so far (rows run from 90°N to 90°S).
    Grid { path: PathBuf, grid: Mutex<Progressive> },
    /// The `egm96` crate's synthesis (no Paparazzi home given).
    Model,
}

impl std::fmt::Debug for Geoid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.describe())
    }
}

/// The grid bytes read so far and the stream they come from.
pub struct Progressive {
    bytes: Vec<u8>,
    rest: Option<Box<dyn Read + Send>>,
}

impl Progressive {
    /// Makes sure the first `n` bytes are there (false when the stream ends or fails first).
    fn fill(&mut self, n: usize) -> bool {
        while self.bytes.len() < n {
            let Some(r) = self.rest.as_mut() else { return false };
            let at = self.bytes.len();
            let want = (n - at).max(64 * 1024).min(GRID_BYTES - at);
            self.bytes.resize(at + want, 0);
            match r.read(&mut self.bytes[at..]) {
                Ok(0) | Err(_) => {
                    self.bytes.truncate(at);
                    self.rest = None;
                    return false;
                }
                Ok(k) => self.bytes.truncate(at + k),
            }
        }
        true
    }
}

/// The geoid height at one grid node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    /// The raw 16-bit value (centimetres).
    pub raw: u16,
}

impl Node {
    /// The true height in metres (the 16-bit value read as signed).
    pub fn metres(self) -> f64 {
        f64::from(self.raw as i16) / 100.0
    }
    /// What upstream prints on 64-bit OCaml: the value read as unsigned.
    pub fn upstream(self) -> f64 {
        f64::from(self.raw) / 100.0
    }
    /// True when upstream prints a wrong value for this node.
    pub fn upstream_is_wrong(self) -> bool {
        (self.raw as i16) < 0
    }
}

impl Geoid {
    /// Opens the grid in `dir` (a Paparazzi home's `data/srtm`). The first and the last node
    /// are read at once, so a short or broken file is an error here.
    pub fn from_dir(dir: &Path) -> Result<Geoid, GeoidError> {
        let path = NAMES
            .iter()
            .map(|n| dir.join(n))
            .find(|p| p.is_file())
            .ok_or_else(|| GeoidError::Missing(dir.to_path_buf()))?;
        let broken = |e: String| GeoidError::Broken(path.clone(), e);
        let file = std::fs::File::open(&path).map_err(|e| broken(e.to_string()))?;
        let name = path.to_string_lossy();
        let (len, rest): (u64, Box<dyn Read + Send>) = if name.ends_with(".bz2") {
            (u64::MAX, Box::new(bzip2::read::BzDecoder::new(file)))
        } else if name.ends_with(".gz") {
            (u64::MAX, Box::new(flate2::read::GzDecoder::new(file)))
        } else {
            let len = file.metadata().map(|m| m.len()).map_err(|e| broken(e.to_string()))?;
            (len, Box::new(std::io::BufReader::new(file)))
        };
        if len < GRID_BYTES as u64 {
            return Err(broken(format!("{len} bytes, {GRID_BYTES} expected")));
        }
        let mut grid = Progressive { bytes: Vec::with_capacity(GRID_BYTES), rest: Some(rest) };
        if !grid.fill(2) {
            return Err(broken("cannot be read or decompressed".into()));
        }
        Ok(Geoid::Grid { path, grid: Mutex::new(grid) })
    }

    /// Decompresses ahead in steps, releasing the grid between steps, until the whole grid is
    /// there or `stop` is set (for a thread running beside the parsing of many plans).
    pub fn prefetch(&self, stop: &std::sync::atomic::AtomicBool) {
        let Geoid::Grid { grid, .. } = self else { return };
        while !stop.load(std::sync::atomic::Ordering::Relaxed) {
            let Ok(mut g) = grid.lock() else { return };
            let next = (g.bytes.len() + 128 * 1024).min(GRID_BYTES);
            if g.bytes.len() >= GRID_BYTES || !g.fill(next) {
                return;
            }
        }
    }

    /// Reads the whole grid now (a compressed grid that ends early is an error).
    pub fn check_complete(&self) -> Result<(), GeoidError> {
        if let Geoid::Grid { path, grid } = self {
            let complete = grid.lock().map(|mut g| g.fill(GRID_BYTES)).unwrap_or(false);
            if !complete {
                return Err(GeoidError::Broken(
                    path.clone(),
                    format!("fewer than {GRID_BYTES} bytes"),
                ));
            }
        }
        Ok(())
    }

    /// The grid of a Paparazzi home (`HOME/data/srtm`), loaded once per process and shared.
    pub fn of_home(home: &Path) -> Result<Arc<Geoid>, GeoidError> {
        static CACHE: OnceLock<Mutex<HashMap<PathBuf, Arc<Geoid>>>> = OnceLock::new();
        let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
        let key = home.to_path_buf();
        if let Some(g) = cache.lock().ok().and_then(|c| c.get(&key).cloned()) {
            return Ok(g);
        }
        let g = Arc::new(Geoid::from_dir(&home.join("data/srtm"))?);
        if let Ok(mut c) = cache.lock() {
            c.insert(key, g.clone());
        }
        Ok(g)
    }

    /// The synthesis stand-in, shared.
    pub fn model() -> Arc<Geoid> {
        static MODEL: OnceLock<Arc<Geoid>> = OnceLock::new();
        MODEL.get_or_init(|| Arc::new(Geoid::Model)).clone()
    }

    /// Where the values come from (for `--verbose` output).
    pub fn describe(&self) -> String {
        match self {
            Geoid::Grid { path, .. } => path.display().to_string(),
            Geoid::Model => {
                "egm96 crate (spherical harmonics at the grid node, rounded to cm)".into()
            }
        }
    }

    /// The node upstream reads for a position in radians (an error when a compressed grid ends
    /// before it).
    pub fn node(&self, lat_rad: f64, lon_rad: f64) -> Result<Node, GeoidError> {
        let lat = deg_of_rad(norm_angle(lat_rad)).trunc() as i32;
        let lon = deg_of_rad(norm_angle(lon_rad)).trunc() as i32;
        let lat = lat.clamp(-90, 90);
        let lon = lon.clamp(-180, 179);
        match self {
            Geoid::Grid { path, grid } => {
                let row = ((90 - lat) * 4) as usize;
                let col = (4 * if lon < 0 { lon + 360 } else { lon }) as usize;
                let i = 2 * (row * COLS + col);
                let broken =
                    || GeoidError::Broken(path.clone(), format!("ends before byte {}", i + 2));
                let mut g = grid.lock().map_err(|_| broken())?;
                if !g.fill(i + 2) {
                    return Err(broken());
                }
                Ok(Node { raw: u16::from_be_bytes([g.bytes[i], g.bytes[i + 1]]) })
            }
            Geoid::Model => Ok(Node { raw: model_node(lat, lon) as u16 }),
        }
    }
}

/// Upstream's `norm_angle`, applied to both coordinates before the lookup.
fn norm_angle(l: f64) -> f64 {
    use std::f64::consts::PI;
    if l >= PI {
        l - 2.0 * PI
    } else if l < -PI {
        l + 2.0 * PI
    } else {
        l
    }
}

fn model_node(lat: i32, lon: i32) -> i16 {
    static CACHE: OnceLock<Mutex<HashMap<(i32, i32), i16>>> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    if let Some(v) = cache.lock().ok().and_then(|c| c.get(&(lat, lon)).copied()) {
        return v;
    }
    let cm = (egm96::egm96_compute_altitude_offset(f64::from(lat), f64::from(lon)) * 100.0).round();
    let v = cm.clamp(f64::from(i16::MIN), f64::from(i16::MAX)) as i16;
    if let Ok(mut c) = cache.lock() {
        c.insert((lat, lon), v);
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn upstream_reading_of_a_negative_node_is_655_36_m_too_high() {
        // 64139 is the cell at 41N/111W (UPSTREAM_CHECKS.md): -13.97 m.
        let n = Node { raw: 64139 };
        assert_eq!(n.metres(), -13.97);
        assert_eq!(n.upstream(), 641.39);
        assert!(n.upstream_is_wrong());
        let p = Node { raw: 5185 };
        assert_eq!(p.metres(), p.upstream());
        assert!(!p.upstream_is_wrong());
    }

    #[test]
    fn a_missing_or_short_grid_is_an_error() {
        let tmp = tempfile::tempdir().expect("tmp dir");
        let dir = tmp.path();
        assert!(matches!(Geoid::from_dir(dir), Err(GeoidError::Missing(_))));
        std::fs::write(dir.join("WW15MGH.DAC"), [0u8; 1000]).expect("write");
        assert!(matches!(Geoid::from_dir(dir), Err(GeoidError::Broken(..))));
    }
}
