//! SRTM terrain heights, looked up the way upstream's generator does before it warns that a
//! plan flies below the ground (UPSTREAM_CHECKS.md H8, H12c, A2, A3).
//!
//! * Tile of a position: the 1°×1° square whose south-west corner is (floor lat, floor lon),
//!   named as upstream names it: `N43E001`, the latitude *not* zero-padded (`N5E001` at 5°N),
//!   the longitude padded to three digits, `S`/`W` for negative corners.
//! * Search: `NAME.SRTMGL1.hgt` (1", 3601×3601 samples) everywhere first, then `NAME.hgt`
//!   (3", 1201×1201), each in `$PAPARAZZI_HOME/data/srtm`, `.` and
//!   `$HOME/.local/share/pprzgcs/srtm` (upstream puts the home's directory in front each time
//!   it checks), each name as is or with `.gz`, `.Z`, `.bz2`, `.zip`, `.ZIP` appended, the first
//!   file that exists wins. The name alone sets the resolution.
//! * Decompression as upstream's pipes do: `gunzip -c` for `.gz`/`.Z`/`.zip`/`.ZIP` (the content
//!   decides: gzip members with `flate2`, the first member of a zip archive, `.Z`'s LZW is not
//!   supported), `bunzip2 -c` for `.bz2` (`bzip2`).
//! * Sample: column `round(frac_lon × n)`, row `n + 1 − round(frac_lat × n)` counted from the
//!   north edge (n = 1200 or 3600, rounding as `truncate(v + 0.5)`): one row south of the nearest
//!   sample, and past the end of the tile in its southernmost half row (upstream then fails with
//!   `index out of bounds`; here [`Sample::OffTile`]). Big-endian signed 16-bit metres; the void
//!   value -32768 is returned like any height (no plan flies below it).
//!
//! A tile is read whole, at most once per process and search path, and only when a position
//! falls in it.

use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

use super::geo::deg_of_rad;

/// Samples per degree of a 3" tile (`NAME.hgt`).
const COEF: f64 = 1200.0;
/// Compression suffixes upstream tries, in its order.
const SUFFIXES: [&str; 6] = ["", ".gz", ".Z", ".bz2", ".zip", ".ZIP"];

/// Why a tile that exists cannot be used (upstream: `End_of_file`, or a failing decompressor).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("SRTM tile {path}: {reason}")]
pub struct TileError {
    /// The file found.
    pub path: PathBuf,
    /// What is wrong with it.
    pub reason: String,
}

/// A loaded tile.
#[derive(Debug)]
pub struct Tile {
    /// The file it was read from.
    pub path: PathBuf,
    /// 1201 (3") or 3601 (1").
    side: usize,
    bytes: Vec<u8>,
}

/// The terrain height upstream reads at a position.
#[derive(Debug, Clone)]
pub enum Sample {
    /// Metres above the geoid, and the tile.
    Height(f64, Arc<Tile>),
    /// No tile for the position (upstream's `Tile_not_found`): the tile name.
    NoTile(String),
    /// The tile exists but upstream's sample index falls past its end.
    OffTile(Arc<Tile>),
    /// The tile exists and cannot be read.
    Unreadable(TileError),
}

/// Where tiles are searched.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct SearchPath(Vec<PathBuf>);

impl SearchPath {
    /// Upstream's directories for a Paparazzi home (none: `.` and the GCS cache only).
    pub fn of_home(home: Option<&Path>) -> SearchPath {
        let mut dirs: Vec<PathBuf> = home.map(|h| h.join("data/srtm")).into_iter().collect();
        dirs.push(PathBuf::from("."));
        if let Some(h) = std::env::var_os("HOME") {
            dirs.push(Path::new(&h).join(".local/share/pprzgcs/srtm"));
        }
        SearchPath(dirs)
    }

    /// The directories, in search order.
    pub fn searched(&self) -> &[PathBuf] {
        &self.0
    }

    /// Exactly these directories, in this order.
    pub fn dirs(dirs: Vec<PathBuf>) -> SearchPath {
        SearchPath(dirs)
    }

    /// The terrain sample upstream reads at a position in radians.
    pub fn sample(&self, lat_rad: f64, lon_rad: f64) -> Sample {
        let (lat, lon) = (deg_of_rad(lat_rad), deg_of_rad(lon_rad));
        if !lat.is_finite() || !lon.is_finite() {
            return Sample::NoTile(String::from("(no position)"));
        }
        let (bottom, left) = (lat.floor(), lon.floor());
        let tile = match self.tile(bottom, left) {
            Loaded::Missing(name) => return Sample::NoTile(name),
            Loaded::Broken(e) => return Sample::Unreadable(e),
            Loaded::Tile(t) => t,
        };
        match tile.height(lat - bottom, lon - left) {
            Some(h) => Sample::Height(h, tile),
            None => Sample::OffTile(tile),
        }
    }

    /// The tile with that south-west corner, read once per process.
    fn tile(&self, bottom: f64, left: f64) -> Loaded {
        type Cache = Mutex<HashMap<(SearchPath, i64, i64), Arc<OnceLock<Loaded>>>>;
        static CACHE: OnceLock<Cache> = OnceLock::new();
        let key = (self.clone(), bottom as i64, left as i64);
        let cell = match CACHE.get_or_init(Default::default).lock() {
            Ok(mut c) => c.entry(key).or_default().clone(),
            Err(_) => Arc::new(OnceLock::new()),
        };
        cell.get_or_init(|| self.load(bottom, left)).clone()
    }

    fn load(&self, bottom: f64, left: f64) -> Loaded {
        let name = tile_name(bottom, left);
        for (suffix, side) in [(".SRTMGL1.hgt", 3601), (".hgt", 1201)] {
            if let Some(path) = self.find(&format!("{name}{suffix}")) {
                return match read_tile(&path, side) {
                    Ok(bytes) => Loaded::Tile(Arc::new(Tile { path, side, bytes })),
                    Err(reason) => Loaded::Broken(TileError { path, reason }),
                };
            }
        }
        Loaded::Missing(name)
    }

    fn find(&self, file: &str) -> Option<PathBuf> {
        self.0.iter().find_map(|d| {
            SUFFIXES.iter().map(|s| d.join(format!("{file}{s}"))).find(|p| p.exists())
        })
    }
}

#[derive(Debug, Clone)]
enum Loaded {
    Tile(Arc<Tile>),
    Missing(String),
    Broken(TileError),
}

/// Upstream's tile name for a south-west corner.
pub fn tile_name(bottom: f64, left: f64) -> String {
    format!(
        "{}{:.0}{}{:03.0}",
        if bottom >= 0.0 { 'N' } else { 'S' },
        bottom.abs(),
        if left >= 0.0 { 'E' } else { 'W' },
        left.abs()
    )
}

impl Tile {
    /// A tile from its decompressed bytes (`side` 1201 or 3601); short data is an error.
    pub fn from_bytes(path: PathBuf, side: usize, bytes: Vec<u8>) -> Result<Tile, TileError> {
        let need = side * side * 2;
        if bytes.len() < need {
            let reason =
                format!("{} bytes, {need} expected for {side}×{side} samples", bytes.len());
            return Err(TileError { path, reason });
        }
        Ok(Tile { path, side, bytes })
    }

    /// Samples per side (1201 or 3601).
    pub fn side(&self) -> usize {
        self.side
    }

    /// The height upstream reads at a fraction of the tile (0 ≤ f < 1 from the south-west
    /// corner), or `None` where its index falls past the tile's end.
    pub fn height(&self, frac_lat: f64, frac_lon: f64) -> Option<f64> {
        let factor = if self.side == 3601 { 3.0 } else { 1.0 };
        let round = |f: f64| (f * factor * COEF + 0.5).trunc();
        let (x, y) = (round(frac_lon), round(frac_lat));
        if !(0.0..self.side as f64).contains(&x) || !(0.0..=self.side as f64).contains(&y) {
            return None;
        }
        let row = self.side - y as usize;
        let pos = 2 * (row * self.side + x as usize);
        let b = self.bytes.get(pos..pos + 2)?;
        Some(f64::from(i16::from_be_bytes([b[0], b[1]])))
    }
}

/// The first `side² × 2` bytes of a tile file, decompressed as upstream's pipe would.
fn read_tile(path: &Path, side: usize) -> Result<Vec<u8>, String> {
    let file = std::fs::File::open(path).map_err(|e| format!("cannot be read: {e}"))?;
    decode(&path.to_string_lossy(), file, side)
}

/// The first `side² × 2` bytes of the content of a tile file named `file_name` (its suffix
/// chooses the decompressor, as upstream's): short or undecodable content is an error.
pub fn decode(file_name: &str, data: impl Read + 'static, side: usize) -> Result<Vec<u8>, String> {
    let need = side * side * 2;
    let gunzip = [".gz", ".Z", ".zip", ".ZIP"].iter().any(|s| file_name.ends_with(s));
    let reader: Box<dyn Read> = if file_name.ends_with(".bz2") {
        Box::new(bzip2::read::MultiBzDecoder::new(data))
    } else if gunzip {
        gunzip_reader(std::io::BufReader::new(data))?
    } else {
        Box::new(data)
    };
    let mut bytes = Vec::with_capacity(need);
    match reader.take(need as u64).read_to_end(&mut bytes) {
        Ok(_) if bytes.len() == need => Ok(bytes),
        Ok(n) => Err(format!(
            "ends after {n} bytes, {need} expected for {side}×{side} samples (from its name)"
        )),
        Err(e) => Err(format!("cannot be read: {e}")),
    }
}

/// What `gunzip -c` makes of a file: gzip members, or a zip archive's first member; the
/// content decides, not the name.
fn gunzip_reader<R: Read + 'static>(mut r: std::io::BufReader<R>) -> Result<Box<dyn Read>, String> {
    use std::io::BufRead;
    let head = r.fill_buf().map_err(|e| e.to_string())?;
    match head {
        [0x1f, 0x8b, ..] => Ok(Box::new(flate2::bufread::MultiGzDecoder::new(r))),
        [0x1f, 0x9d, ..] => {
            Err("LZW-compressed (.Z) tiles are not supported: decompress it".into())
        }
        [b'P', b'K', 3, 4, ..] => zip_member(r),
        _ => Err("not in gzip or zip format".into()),
    }
}

/// The data of a zip archive's first member (stored or deflated), as gunzip reads it.
fn zip_member<R: Read + 'static>(mut r: std::io::BufReader<R>) -> Result<Box<dyn Read>, String> {
    let mut header = [0u8; 30];
    r.read_exact(&mut header).map_err(|_| "zip header cut short".to_string())?;
    let method = u16::from_le_bytes([header[8], header[9]]);
    let skip = u64::from(u16::from_le_bytes([header[26], header[27]]))
        + u64::from(u16::from_le_bytes([header[28], header[29]]));
    let copied = std::io::copy(&mut (&mut r).take(skip), &mut std::io::sink());
    if copied.map_err(|e| e.to_string())? != skip {
        return Err("zip header cut short".into());
    }
    match method {
        0 => Ok(Box::new(r)),
        8 => Ok(Box::new(flate2::bufread::DeflateDecoder::new(r))),
        m => {
            Err(format!("zip member compressed with method {m} (gunzip reads stored or deflated)"))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tile_names_follow_upstreams_format() {
        assert_eq!(tile_name(43.0, 1.0), "N43E001");
        assert_eq!(tile_name(5.0, 10.0), "N5E010");
        assert_eq!(tile_name(-1.0, -1.0), "S1W001");
        assert_eq!(tile_name(-34.0, -120.0), "S34W120");
        assert_eq!(tile_name(-0.0, 0.0), "N0E000");
    }

    fn tile(side: usize) -> Tile {
        // Each sample holds its row number (row 0 = north edge).
        let mut bytes = Vec::with_capacity(side * side * 2);
        for row in 0..side {
            for _ in 0..side {
                bytes.extend_from_slice(&(row as i16).to_be_bytes());
            }
        }
        Tile::from_bytes(PathBuf::from("t.hgt"), side, bytes).expect("complete")
    }

    #[test]
    fn the_row_read_is_one_south_of_the_nearest_and_the_south_edge_is_off_the_tile() {
        let t = tile(1201);
        // 0.5 of the tile: y = 600, row 1201 - 600 = 601 (the nearest would be 600).
        assert_eq!(t.height(0.5, 0.5), Some(601.0));
        // Just below the north edge: y = 1200, row 1.
        assert_eq!(t.height(0.9999, 0.0), Some(1.0));
        // Southernmost half row: y = 0, row 1201, past the end.
        assert_eq!(t.height(0.0001, 0.3), None);
        let gl1 = tile(3601);
        assert_eq!(gl1.height(0.5, 0.5), Some(1801.0));
    }

    #[test]
    fn heights_are_signed_big_endian() {
        let mut bytes = vec![0u8; 1201 * 1201 * 2];
        let pos = 2 * (601 * 1201 + 600);
        bytes[pos..pos + 2].copy_from_slice(&(-32768i16).to_be_bytes());
        let t = Tile::from_bytes(PathBuf::from("t.hgt"), 1201, bytes).expect("complete");
        assert_eq!(t.height(0.5, 0.5), Some(-32768.0));
        let short = Tile::from_bytes(PathBuf::from("t.hgt"), 1201, vec![0; 10]);
        assert!(short.is_err_and(|e| e.reason.contains("10 bytes")));
    }
}
