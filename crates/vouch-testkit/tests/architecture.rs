//! What ARCHITECTURE.md and the engineering standards say about the code, checked where a test
//! can check it: the fuzz targets each family's section names are the ones that exist, and no
//! function of the crates' sources (tests aside) is longer than 100 lines.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use syn::spanned::Spanned;
use syn::visit::Visit;

/// Longest function allowed, in lines from `fn` to the closing brace.
const MAX_FN_LINES: usize = 100;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The `cargo-fuzz` targets of a family: the files of `crates/<crate>/fuzz/fuzz_targets`.
fn fuzz_targets(krate: &str) -> BTreeSet<String> {
    let dir = root().join("crates").join(krate).join("fuzz/fuzz_targets");
    let mut files = vec![];
    rust_files(&dir, &mut files);
    files.iter().filter_map(|f| f.file_stem()).map(|s| s.to_string_lossy().into_owned()).collect()
}

/// The names in backticks after "fuzz targets" on the one line of a family's section of
/// ARCHITECTURE.md that lists them (up to the end of its table cell).
fn documented_targets(architecture: &str, section: &str) -> BTreeSet<String> {
    let start = architecture.find(section).unwrap_or_else(|| panic!("no section `{section}`"));
    let body = &architecture[start + section.len()..];
    let body = &body[..body.find("\n## ").unwrap_or(body.len())];
    let lines: Vec<&str> = body.lines().filter(|l| l.contains("fuzz targets")).collect();
    assert_eq!(lines.len(), 1, "`{section}`: one line lists the fuzz targets: {lines:#?}");
    let list = lines[0].split("fuzz targets").nth(1).unwrap_or("");
    let list = list.split('|').next().unwrap_or("");
    list.split('`').skip(1).step_by(2).map(str::to_string).collect()
}

#[test]
fn architecture_names_every_fuzz_target_and_no_other() {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let families =
        [("## fpl — ", "vouch-fpl"), ("## mav — ", "vouch-mav"), ("## navfn — ", "vouch-navfn")];
    for (section, krate) in families {
        let on_disk = fuzz_targets(krate);
        assert!(!on_disk.is_empty(), "{krate} has fuzz targets");
        assert_eq!(documented_targets(&text, section), on_disk, "{krate}: ARCHITECTURE.md");
        let manifest =
            std::fs::read_to_string(root().join("crates").join(krate).join("fuzz/Cargo.toml"))
                .expect("the fuzz crate's manifest");
        for t in &on_disk {
            assert!(manifest.contains(&format!("name = \"{t}\"")), "{krate}: [[bin]] {t}");
        }
    }
}

fn is_cfg_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && a.meta.require_list().is_ok_and(|l| l.tokens.to_string().starts_with("test"))
    })
}

/// Functions longer than the limit in one file: (name, lines, first line).
#[derive(Default)]
struct LongFns {
    found: Vec<(String, usize, usize)>,
}

impl LongFns {
    fn measure(&mut self, name: String, span: proc_macro2::Span) {
        let (from, to) = (span.start().line, span.end().line);
        let lines = to + 1 - from;
        if lines > MAX_FN_LINES {
            self.found.push((name, lines, from));
        }
    }
}

impl<'ast> Visit<'ast> for LongFns {
    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        if !is_cfg_test(&m.attrs) {
            syn::visit::visit_item_mod(self, m);
        }
    }
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        if !is_cfg_test(&f.attrs) {
            let span = f.sig.fn_token.span().join(f.block.span()).unwrap_or(f.block.span());
            self.measure(f.sig.ident.to_string(), span);
            syn::visit::visit_item_fn(self, f);
        }
    }
    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        let span = f.sig.fn_token.span().join(f.block.span()).unwrap_or(f.block.span());
        self.measure(f.sig.ident.to_string(), span);
        syn::visit::visit_impl_item_fn(self, f);
    }
    fn visit_trait_item_fn(&mut self, f: &'ast syn::TraitItemFn) {
        if let Some(block) = &f.default {
            let span = f.sig.fn_token.span().join(block.span()).unwrap_or(block.span());
            self.measure(f.sig.ident.to_string(), span);
        }
        syn::visit::visit_trait_item_fn(self, f);
    }
}

/// Files of unit tests (`#[cfg(test)] mod tests;` declared elsewhere) are not library code.
fn is_test_file(file: &Path) -> bool {
    file.file_name().is_some_and(|n| n == "tests.rs")
        || file.components().any(|c| c.as_os_str() == "tests")
}

#[test]
fn no_function_is_longer_than_100_lines() {
    let mut files = vec![];
    for krate in std::fs::read_dir(root().join("crates")).expect("crates/").flatten() {
        rust_files(&krate.path().join("src"), &mut files);
    }
    files.sort();
    let mut long = vec![];
    for file in files.iter().filter(|f| !is_test_file(f.strip_prefix(root()).unwrap_or(f))) {
        let text = std::fs::read_to_string(file).expect("source readable");
        let ast = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let mut v = LongFns::default();
        v.visit_file(&ast);
        let rel = file.strip_prefix(root()).unwrap_or(file).display().to_string();
        long.extend(v.found.into_iter().map(|(name, lines, at)| (rel.clone(), name, lines, at)));
    }
    let report: Vec<String> =
        long.iter().map(|(f, n, lines, at)| format!("{f}:{at}: fn {n}: {lines} lines")).collect();
    assert!(report.is_empty(), "functions over {MAX_FN_LINES} lines:\n{}", report.join("\n"));
}
