//! Reading and writing suites in the paper's format (SEMANTICS.md §9):
//! `<dir>/<category>/<map>/test.txt` + the map file it names (W·H bytes of NavFn costs).
//!
//! Reading goes through the core's reader (`maps::suite`); this module adds the category/map
//! labels the campaign reports by, and the writer used by `suite gen`.

use std::fs;
use std::path::{Path, PathBuf};

use crate::campaign::grid::{Case, SuiteMap};
use crate::campaign::identity::map_digest;
use crate::maps::{MapError, SuiteFile, parse_suite_text, read_suite_file};

/// A suite that cannot be read into the campaign IR or written.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum SuiteIoError {
    /// A file or folder that cannot be written.
    #[error("{}: {source}", path.display())]
    #[diagnostic(code(navfn::E060))]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A test or map file that cannot be read.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Map(#[from] MapError),
    /// A case point outside the map.
    #[error("{}:{line}: case {number}: a point lies outside the {width}x{height} map", path.display())]
    #[diagnostic(code(navfn::E061))]
    Outside {
        /// The test file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// Case number.
        number: usize,
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
    },
}

impl SuiteIoError {
    /// Whether a file could not be read or written.
    pub fn is_io(&self) -> bool {
        match self {
            SuiteIoError::Io { .. } => true,
            SuiteIoError::Map(m) => m.is_io(),
            SuiteIoError::Outside { .. } => false,
        }
    }
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> SuiteIoError + '_ {
    move |source| SuiteIoError::Io { path: path.to_path_buf(), source }
}

/// Convert the core reader's result into the campaign IR (cells truncated like the harness).
pub fn from_suite_file(
    f: &SuiteFile,
    category: &str,
    name: &str,
) -> Result<SuiteMap, SuiteIoError> {
    let mut cases = Vec::with_capacity(f.cases.len());
    for c in &f.cases {
        let ([x0, y0], [x1, y1]) =
            c.cells(f.width, f.height).ok_or_else(|| SuiteIoError::Outside {
                path: f.test_path.clone(),
                line: c.line,
                number: c.number,
                width: f.width,
                height: f.height,
            })?;
        cases.push(Case::new(x0 as u32, y0 as u32, x1 as u32, y1 as u32));
    }
    Ok(SuiteMap {
        category: category.to_string(),
        name: name.to_string(),
        width: f.width as u32,
        height: f.height as u32,
        costs: f.map.clone(),
        cases,
    })
}

/// Parse one `test.txt` (and load its map) with the core's reader (same comment rule, same
/// located errors). `category` and `name` label the result.
pub fn read_test_file(
    test_txt: &Path,
    category: &str,
    name: &str,
) -> Result<SuiteMap, SuiteIoError> {
    let f = read_suite_file(test_txt)?;
    from_suite_file(&f, category, name)
}

/// One map of a suite tree, not yet loaded.
#[derive(Clone, Debug)]
pub struct SuiteEntry {
    /// The map's folder relative to the suite root, `/`-separated (`walls/25x25_50walls`): the
    /// key reports, shards and merges identify the map by. When the suite is one file, the
    /// key is `category/name`.
    pub key: String,
    /// Category folder name.
    pub category: String,
    /// Map folder name.
    pub name: String,
    /// The test file.
    pub test_txt: PathBuf,
    /// Size of the test file in bytes (part of the suite's listing fingerprint).
    pub test_size: u64,
}

/// Every `test.txt` below a folder, depth-first with the entries of each folder sorted by name
/// (the order of [`crate::maps::find_test_files`]), one at a time: only the folders on the
/// current path are held in memory, never the whole tree (`walkdir`). The category is the
/// grand-parent folder name, the map name the parent folder name.
pub struct SuiteWalk {
    root: PathBuf,
    /// The suite argument is a single test file.
    single: bool,
    inner: walkdir::IntoIter,
}

/// Walk the suite at `path` (a folder, or one test file).
pub fn walk_suite(path: &Path) -> Result<SuiteWalk, SuiteIoError> {
    let meta = fs::metadata(path).map_err(|e| MapError::io(path, e))?;
    let inner = walkdir::WalkDir::new(path).follow_links(true).sort_by_file_name().into_iter();
    Ok(SuiteWalk { root: path.to_path_buf(), single: meta.is_file(), inner })
}

fn name_of(p: Option<&Path>) -> String {
    p.and_then(|p| p.file_name())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "-".into())
}

impl SuiteWalk {
    fn entry(&self, test_txt: PathBuf) -> Result<SuiteEntry, SuiteIoError> {
        let test_size = fs::metadata(&test_txt).map_err(|e| MapError::io(&test_txt, e))?.len();
        let map_dir = test_txt.parent();
        let (category, name) = (name_of(map_dir.and_then(Path::parent)), name_of(map_dir));
        let rel = map_dir.and_then(|d| d.strip_prefix(&self.root).ok()).filter(|_| !self.single);
        let key = match rel {
            Some(rel) if rel.as_os_str().is_empty() => ".".to_string(),
            Some(rel) => {
                let parts: Vec<String> =
                    rel.iter().map(|c| c.to_string_lossy().into_owned()).collect();
                parts.join("/")
            }
            None => format!("{category}/{name}"),
        };
        Ok(SuiteEntry { key, category, name, test_txt, test_size })
    }
}

impl Iterator for SuiteWalk {
    type Item = Result<SuiteEntry, SuiteIoError>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            match self.inner.next()? {
                Err(e) => {
                    let path = e.path().unwrap_or(&self.root).to_path_buf();
                    return Some(Err(MapError::io(&path, e.into()).into()));
                }
                Ok(ent)
                    if ent.file_type().is_file()
                        && (self.single || ent.file_name() == "test.txt") =>
                {
                    return Some(self.entry(ent.into_path()));
                }
                Ok(_) => {}
            }
        }
    }
}

/// Every `test.txt` under `dir` in walk order (deterministic), or an error when there is none.
pub fn list_suite(dir: &Path) -> Result<Vec<SuiteEntry>, SuiteIoError> {
    let entries = walk_suite(dir)?.collect::<Result<Vec<_>, _>>()?;
    if entries.is_empty() {
        return Err(no_test_files(dir));
    }
    Ok(entries)
}

/// The error of a folder without any `test.txt`.
pub fn no_test_files(dir: &Path) -> SuiteIoError {
    MapError::file(dir, "no test.txt found below this folder").into()
}

/// Read a whole suite tree.
pub fn read_suite(dir: &Path) -> Result<Vec<SuiteMap>, SuiteIoError> {
    list_suite(dir)?.iter().map(|e| read_test_file(&e.test_txt, &e.category, &e.name)).collect()
}

/// Read one map of a suite with the SHA-256 digest of its bytes (see
/// [`crate::campaign::identity::map_digest`]): the test file and the map file it names are
/// each read once.
pub fn read_entry_with_digest(e: &SuiteEntry) -> Result<(SuiteMap, String), SuiteIoError> {
    let path = &e.test_txt;
    let bytes = fs::read(path).map_err(|err| MapError::io(path, err))?;
    let text = std::str::from_utf8(&bytes).map_err(|err| MapError::not_text(path, &err))?;
    let mut digest = None;
    let f = parse_suite_text(path, text, |map_path| {
        let map = fs::read(map_path).map_err(|err| MapError::io(map_path, err))?;
        digest = Some(map_digest(&bytes, &map));
        Ok(map)
    })?;
    let m = from_suite_file(&f, &e.category, &e.name)?;
    Ok((m, digest.unwrap_or_default()))
}

/// The text of a `test.txt` for `m` (map file `map.bin`).
pub fn test_txt_text(m: &SuiteMap) -> String {
    let mut s = format!("{} {}\nmap.bin\n\n", m.width, m.height);
    for c in &m.cases {
        s.push_str(&format!("{} {} {} {}\n", c.x0, c.y0, c.x1, c.y1));
    }
    s
}

/// Write `m` as `<dir>/<category>/<name>/{test.txt,map.bin}`; returns the test file path.
pub fn write_map(dir: &Path, m: &SuiteMap) -> Result<PathBuf, SuiteIoError> {
    let d = dir.join(&m.category).join(&m.name);
    fs::create_dir_all(&d).map_err(io_err(&d))?;
    let bin = d.join("map.bin");
    fs::write(&bin, &m.costs).map_err(io_err(&bin))?;
    let t = d.join("test.txt");
    fs::write(&t, test_txt_text(m)).map_err(io_err(&t))?;
    Ok(t)
}

/// Write a whole suite.
pub fn write_suite(dir: &Path, maps: &[SuiteMap]) -> Result<(), SuiteIoError> {
    for m in maps {
        write_map(dir, m)?;
    }
    Ok(())
}
