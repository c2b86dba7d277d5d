//! Source positions. Every node of the AST carries a [`Span`] into one of the files of the
//! plan's [`SourceMap`] (the main plan plus every included procedure file).

use serde::Serialize;

/// Index of a file in [`SourceMap::files`]; `FileId(0)` is always the main plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Default)]
pub struct FileId(pub u32);

/// A byte range in a source file, with the 1-based line and column of its start
/// (column counted in characters, as editors do).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Default)]
pub struct Span {
    pub file: FileId,
    pub start: u32,
    pub end: u32,
    pub line: u32,
    pub col: u32,
}

impl Span {
    pub fn range(&self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// One source file that contributed to the plan.
#[derive(Debug, Clone, Serialize)]
pub struct SourceFile {
    /// Path as given (main plan) or as found by the include search.
    pub path: String,
    /// Full original text (before the tolerant pre-pass), so spans index into it directly.
    #[serde(skip)]
    pub text: String,
}

/// All files read for one plan; spans refer to them by [`FileId`].
#[derive(Debug, Clone, Default, Serialize)]
pub struct SourceMap {
    pub files: Vec<SourceFile>,
}

impl SourceMap {
    pub fn add(&mut self, path: String, text: String) -> FileId {
        self.files.push(SourceFile { path, text });
        FileId((self.files.len() - 1) as u32)
    }
    pub fn get(&self, id: FileId) -> Option<&SourceFile> {
        self.files.get(id.0 as usize)
    }
    pub fn path(&self, id: FileId) -> &str {
        self.get(id).map(|f| f.path.as_str()).unwrap_or("<unknown>")
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
