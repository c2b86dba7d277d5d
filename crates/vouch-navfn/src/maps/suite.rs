//! The paper's suite format: `test.txt` (line 1 `W H`, line 2 the map file name, line 3
//! ignored, then one case `x0 y0 x1 y1` per line; a line whose first number is `-1` is a
//! comment) and the map file (exactly W·H bytes, row-major). SEMANTICS.md §9.

use std::path::{Path, PathBuf};

use super::world::WorldParams;
use super::{MAX_CELLS, MapError};
use crate::diag::quote;

/// One case: a path *from* (x0, y0) *to* (x1, y1), numbers as read (doubles).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SuiteCase {
    /// Case number, from 0, comment lines skipped.
    pub number: usize,
    /// 1-based line in the test file.
    pub line: usize,
    /// `[x0, y0, x1, y1]`.
    pub coords: [f64; 4],
}

impl SuiteCase {
    /// The case as cells, truncating like the C++ harness; `None` when a number does not
    /// truncate into the map.
    pub fn cells(&self, width: usize, height: usize) -> Option<([usize; 2], [usize; 2])> {
        let cell = |x: f64, lim: usize| -> Option<usize> {
            let t = x.trunc();
            if t >= 0.0 && t < lim as f64 { Some(t as usize) } else { None }
        };
        let [x0, y0, x1, y1] = self.coords;
        Some(([cell(x0, width)?, cell(y0, height)?], [cell(x1, width)?, cell(y1, height)?]))
    }
}

/// A parsed `test.txt` with its map bytes.
#[derive(Clone, Debug)]
pub struct SuiteFile {
    pub test_path: PathBuf,
    pub map_path: PathBuf,
    pub width: usize,
    pub height: usize,
    /// W·H bytes, cell (x, y) at `y*W + x`.
    pub map: Vec<u8>,
    pub cases: Vec<SuiteCase>,
}

/// Read a test file and the map file it names.
pub fn read_suite_file(test_path: &Path) -> Result<SuiteFile, MapError> {
    let text = super::error::read_text(test_path)?;
    parse_suite_text(test_path, &text, |map_path| {
        std::fs::read(map_path).map_err(|e| MapError::io(map_path, e))
    })
}

/// Parse the text of a test file; `load_map` reads the named map (a seam for fuzzing).
pub fn parse_suite_text(
    test_path: &Path,
    text: &str,
    load_map: impl FnOnce(&Path) -> Result<Vec<u8>, MapError>,
) -> Result<SuiteFile, MapError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let (ln, header) = lines
        .next()
        .ok_or_else(|| MapError::file(test_path, "empty test file (expected `W H`)"))?;
    let dims: Vec<&str> = header.split_whitespace().collect();
    let parse_dim = |s: &str| -> Result<usize, MapError> {
        s.parse::<usize>().ok().filter(|&v| v > 0).ok_or_else(|| {
            MapError::syntax(
                test_path,
                text,
                ln,
                s,
                format!("map size `{}` is not a positive integer", quote(s)),
            )
        })
    };
    if dims.len() != 2 {
        return Err(MapError::syntax(
            test_path,
            text,
            ln,
            "",
            format!("expected `W H`, found `{}`", quote(header)),
        ));
    }
    let (width, height) = (parse_dim(dims[0])?, parse_dim(dims[1])?);
    let cells = width.checked_mul(height).filter(|&c| c <= super::MAX_CELLS);
    let cells = cells.ok_or_else(|| {
        MapError::syntax(
            test_path,
            text,
            ln,
            "",
            format!("map size {width}x{height} exceeds {MAX_CELLS} cells"),
        )
    })?;
    let (ln, name) = lines.next().ok_or_else(|| {
        MapError::syntax(test_path, text, ln, "", "missing line 2 (map file name)")
    })?;
    let name = name.trim();
    if name.is_empty() {
        return Err(MapError::syntax(test_path, text, ln, "", "line 2 must name the map file"));
    }
    let map_path = test_path.parent().unwrap_or(Path::new(".")).join(name);
    let _ignored_line_3 = lines.next();
    let mut cases = Vec::new();
    for (ln, line) in lines {
        if let Some(coords) = parse_case_line(test_path, text, ln, line)? {
            cases.push(SuiteCase { number: cases.len(), line: ln, coords });
        }
    }
    let map = load_map(&map_path)?;
    if map.len() != cells {
        return Err(MapError::file(
            &map_path,
            format!(
                "map has {} bytes, but {} declares {width}x{height} = {cells}",
                map.len(),
                test_path.display()
            ),
        ));
    }
    Ok(SuiteFile { test_path: test_path.to_path_buf(), map_path, width, height, map, cases })
}

/// One case line `x0 y0 x1 y1` (line `ln` of `text`): `None` for a blank or comment line.
fn parse_case_line(
    test_path: &Path,
    text: &str,
    ln: usize,
    line: &str,
) -> Result<Option<[f64; 4]>, MapError> {
    let mut tokens = line.split_whitespace();
    let mut fields = [""; 4];
    let mut n = 0;
    for (slot, tok) in fields.iter_mut().zip(&mut tokens) {
        *slot = tok;
        n += 1;
    }
    if n == 0 {
        return Ok(None);
    }
    // comment rule of the paper's harness: first number -1 (this also hides one genuine
    // case of suite_ros/map_circular/test_world.txt, see golden/README.md)
    if parse_number(fields[0]) == Some(-1.0) {
        return Ok(None);
    }
    if n < 4 {
        let msg = format!("expected `x0 y0 x1 y1`, found `{}`", quote(line));
        return Err(MapError::syntax(test_path, text, ln, "", msg));
    }
    let mut coords = [0.0f64; 4];
    for (c, f) in coords.iter_mut().zip(fields) {
        *c = parse_number(f).filter(|v| v.is_finite()).ok_or_else(|| {
            let msg = format!("`{}` is not a finite number", quote(f));
            MapError::syntax(test_path, text, ln, f, msg)
        })?;
    }
    Ok(Some(coords))
}

/// A number of a case line, as `f64::from_str` reads it; plain integers (nearly every field)
/// take a shorter path with the same result (exact below 2^53).
fn parse_number(tok: &str) -> Option<f64> {
    let (neg, digits) = match tok.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, tok),
    };
    if !digits.is_empty() && digits.len() <= 15 && digits.bytes().all(|b| b.is_ascii_digit()) {
        let v = digits.bytes().fold(0u64, |a, b| a * 10 + (b - b'0') as u64) as f64;
        return Some(if neg { -v } else { v });
    }
    tok.parse::<f64>().ok()
}

/// `path` itself if it is a file, else every file called `file_name` below it, depth-first
/// with directory entries sorted by name (a stable, platform-independent order).
pub fn find_test_files(path: &Path, file_name: &str) -> Result<Vec<PathBuf>, MapError> {
    let meta = std::fs::metadata(path).map_err(|e| MapError::io(path, e))?;
    if meta.is_file() {
        return Ok(vec![path.to_path_buf()]);
    }
    let mut out = Vec::new();
    walk(path, file_name, &mut out)?;
    Ok(out)
}

fn walk(dir: &Path, file_name: &str, out: &mut Vec<PathBuf>) -> Result<(), MapError> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| MapError::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            walk(&p, file_name, out)?;
        } else if p.file_name().is_some_and(|n| n == file_name) {
            out.push(p);
        }
    }
    Ok(())
}

/// `params.txt` of `suite_ros/<map>/`: `--origin=X,Y --res=R`.
pub fn read_world_params(path: &Path) -> Result<WorldParams, MapError> {
    let text = super::error::read_text(path)?;
    parse_world_params(path, &text)
}

/// Parse `--origin=X,Y --res=R` (both required, resolution > 0).
pub fn parse_world_params(path: &Path, text: &str) -> Result<WorldParams, MapError> {
    let mut origin = None;
    let mut res = None;
    let num = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    for (i, line) in text.lines().enumerate() {
        let bad = |tok: &str, msg: String| MapError::syntax(path, text, i + 1, tok, msg);
        for tok in line.split_whitespace() {
            if let Some(v) = tok.strip_prefix("--origin=") {
                let (x, y) = v.split_once(',').unwrap_or((v, ""));
                match (num(x), num(y)) {
                    (Some(x), Some(y)) => origin = Some([x, y]),
                    _ => return Err(bad(tok, format!("bad origin `{}` (expected X,Y)", quote(v)))),
                }
            } else if let Some(v) = tok.strip_prefix("--res=") {
                let r = num(v).filter(|r| *r > 0.0);
                res = Some(r.ok_or_else(|| {
                    bad(tok, format!("resolution `{}` must be a positive number", quote(v)))
                })?);
            } else {
                return Err(bad(tok, format!("unknown parameter `{}`", quote(tok))));
            }
        }
    }
    match (origin, res) {
        (Some(origin), Some(resolution)) => Ok(WorldParams { origin, resolution }),
        _ => Err(MapError::file(path, "expected `--origin=X,Y --res=R`")),
    }
}
