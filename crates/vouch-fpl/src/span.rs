//! Source positions. Every node of the plan carries a [`Span`] into one of the files of the
//! plan's [`SourceMap`] (the main plan plus every included procedure file).

use std::sync::Arc;

use serde::{Serialize, Serializer};

/// Index of a file in [`SourceMap::files`]; `FileId(0)` is always the main plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Default)]
pub struct FileId(pub u32);

/// A byte range in a source file, with the 1-based line and column of its start
/// (column counted in characters, as editors do).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Default)]
pub struct Span {
    /// The file the range is in.
    pub file: FileId,
    /// First byte.
    pub start: u32,
    /// One past the last byte.
    pub end: u32,
    /// 1-based line of `start`.
    pub line: u32,
    /// 1-based column of `start`, in characters.
    pub col: u32,
}

impl Span {
    /// The byte range, for slicing the file's text.
    pub fn range(&self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// One source file that contributed to the plan.
#[derive(Debug, Clone, Serialize)]
pub struct SourceFile {
    /// Path as given (main plan) or as found by the include search.
    pub path: String,
    /// Full original text (before any rewriting), so spans index into it directly.
    #[serde(skip)]
    pub text: String,
}

/// All files read for one plan; spans refer to them by [`FileId`]. Files are shared, so cloning
/// the map (into a diagnostic, a later pass) does not copy their text.
#[derive(Debug, Clone, Default, Serialize)]
pub struct SourceMap {
    /// The files, main plan first.
    #[serde(serialize_with = "serialize_files")]
    pub files: Vec<Arc<SourceFile>>,
}

fn serialize_files<S: Serializer>(files: &[Arc<SourceFile>], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(files.iter().map(|f| f.as_ref()))
}

impl SourceMap {
    /// Adds a file and returns its id.
    pub fn add(&mut self, path: String, text: String) -> FileId {
        self.files.push(Arc::new(SourceFile { path, text }));
        FileId((self.files.len() - 1) as u32)
    }
    /// The file with that id, if any.
    pub fn get(&self, id: FileId) -> Option<&Arc<SourceFile>> {
        self.files.get(id.0 as usize)
    }
    /// The path of a file (`<unknown>` for an id of another map).
    pub fn path(&self, id: FileId) -> &str {
        self.get(id).map(|f| f.path.as_str()).unwrap_or("<unknown>")
    }
    /// The text of a file (empty for an id of another map).
    pub fn text(&self, id: FileId) -> &str {
        self.get(id).map(|f| f.text.as_str()).unwrap_or("")
    }
    /// The source text covered by `span` (empty when out of range).
    pub fn snippet(&self, span: Span) -> &str {
        self.get(span.file).and_then(|f| f.text.get(span.range())).unwrap_or("")
    }
}

/// Computes (line, column), both 1-based, of byte offset `pos` in `text`.
pub fn line_col(text: &str, pos: usize) -> (u32, u32) {
    let pos = pos.min(text.len());
    let before = &text.as_bytes()[..pos];
    let line = before.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
    let line_start = before.iter().rposition(|&b| b == b'\n').map(|p| p + 1).unwrap_or(0);
    let col =
        text.get(line_start..pos).map(|s| s.chars().count()).unwrap_or(pos - line_start) as u32 + 1;
    (line, col)
}
