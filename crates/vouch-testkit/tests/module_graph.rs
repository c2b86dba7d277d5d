//! Module graphs without loops or upward imports, for every library crate of the workspace.
//!
//! Each source file is a node; an edge A → B means that A names an item of module B (a `use` or
//! any path through `crate::`, `super::`, `self::` or a child module), except when B is inside A
//! (a module re-exporting or using its own children). Edges out of the crate root
//! (`lib.rs`, a façade of `pub mod`/`pub use`) are not counted, and `crate::X` that the root
//! re-exports is resolved to the module that defines `X`. `#[cfg(test)]` items are ignored.
//!
//! Two rules are checked: the graph has no cycle, and a top-level module only imports from its
//! own layer or a lower one, in the layer order declared in [`LAYERS`].

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use syn::visit::Visit;

/// Per crate, its top-level modules from the lowest layer to the highest. Modules in one inner
/// list are in the same layer (they may import each other as long as no cycle appears).
const LAYERS: &[(&str, &[&[&str]])] = &[
    (
        "vouch-fpl",
        &[
            &["span", "ids"],
            &["diag"],
            &["expr"],
            &["ast"],
            &["front"],
            &["passes"],
            &["semantics", "lint"],
            &["emit", "graph"],
            &["evidence", "model_check", "diff"],
            &["pipeline"],
            &["aircraft"],
        ],
    ),
    (
        "vouch-mav",
        &[
            &["crc", "side", "text"],
            &["dialect"],
            &["codec"],
            &["signing"],
            &["vehicle_state"],
            &["protocol"],
            &["monitor"],
            &["guard"],
            &["bench"],
        ],
    ),
    (
        "vouch-navfn",
        &[
            &["diag"],
            &["core"],
            &["checks"],
            &["maps", "rosbag"],
            &["costmap"],
            &["planner"],
            &["suite"],
            &["picture"],
            &["campaign", "bagcheck"],
            &["guarantee"],
            &["bench"],
        ],
    ),
];

type Module = Vec<String>;

struct Crate {
    /// module path → file
    files: BTreeMap<Module, PathBuf>,
    /// name re-exported at the crate root → module that defines it
    root_exports: BTreeMap<String, Module>,
}

fn module_of(src: &Path, file: &Path) -> Module {
    let rel = file.strip_prefix(src).expect("file under src");
    let mut parts: Vec<String> =
        rel.iter().map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string()).collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib" | "main")) {
        parts.pop();
    }
    parts
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n != "bin") {
                rust_files(&p, out);
            }
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

fn is_cfg_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && a.meta.require_list().is_ok_and(|l| {
                let t = l.tokens.to_string();
                t == "test" || t.starts_with("all(test") || t.starts_with("any(test")
            })
    })
}

/// Every path a file names (use trees expanded), as segment lists.
#[derive(Default)]
struct PathCollector {
    paths: Vec<Vec<String>>,
}

fn flatten_use(prefix: &[String], tree: &syn::UseTree, out: &mut Vec<Vec<String>>) {
    match tree {
        syn::UseTree::Path(p) => {
            let mut next = prefix.to_vec();
            next.push(p.ident.to_string());
            flatten_use(&next, &p.tree, out);
        }
        syn::UseTree::Name(n) => {
            let mut next = prefix.to_vec();
            if n.ident != "self" {
                next.push(n.ident.to_string());
            }
            out.push(next);
        }
        syn::UseTree::Rename(r) => {
            let mut next = prefix.to_vec();
            next.push(r.ident.to_string());
            out.push(next);
        }
        syn::UseTree::Glob(_) => out.push(prefix.to_vec()),
        syn::UseTree::Group(g) => g.items.iter().for_each(|t| flatten_use(prefix, t, out)),
    }
}

impl<'ast> Visit<'ast> for PathCollector {
    fn visit_item(&mut self, item: &'ast syn::Item) {
        let attrs: &[syn::Attribute] = match item {
            syn::Item::Mod(m) => &m.attrs,
            syn::Item::Fn(f) => &f.attrs,
            syn::Item::Use(u) => &u.attrs,
            syn::Item::Impl(i) => &i.attrs,
            _ => &[],
        };
        if !is_cfg_test(attrs) {
            syn::visit::visit_item(self, item);
        }
    }
    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        flatten_use(&[], &u.tree, &mut self.paths);
    }
    fn visit_path(&mut self, p: &'ast syn::Path) {
        self.paths.push(p.segments.iter().map(|s| s.ident.to_string()).collect());
        syn::visit::visit_path(self, p);
    }
}

fn parse(file: &Path) -> syn::File {
    let text = std::fs::read_to_string(file).expect("source readable");
    syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

fn load_crate(src: &Path) -> Crate {
    let mut list = Vec::new();
    rust_files(src, &mut list);
    let files: BTreeMap<Module, PathBuf> =
        list.into_iter().map(|f| (module_of(src, &f), f)).collect();
    let mut root_exports = BTreeMap::new();
    if let Some(root) = files.get(&Vec::new()) {
        for item in parse(root).items {
            if let syn::Item::Use(u) = item {
                let mut paths = Vec::new();
                flatten_use(&[], &u.tree, &mut paths);
                for p in paths {
                    let p: Vec<String> = p.into_iter().skip_while(|s| s == "crate").collect();
                    if let Some((name, module)) = p.split_last() {
                        root_exports.insert(name.clone(), module.to_vec());
                    }
                }
            }
        }
    }
    Crate { files, root_exports }
}

/// The module (node) that an absolute path inside the crate points into.
fn target(krate: &Crate, abs: &[String]) -> Option<Module> {
    let mut abs = abs.to_vec();
    if let Some(first) = abs.first()
        && let Some(module) = krate.root_exports.get(first)
        && !krate.files.contains_key(&vec![first.clone()])
    {
        let mut v = module.clone();
        v.extend(abs.drain(1..));
        abs = v;
    }
    (1..=abs.len()).rev().map(|n| abs[..n].to_vec()).find(|m| krate.files.contains_key(m))
}

fn resolve(krate: &Crate, from: &Module, path: &[String]) -> Option<Vec<String>> {
    let (head, rest) = path.split_first()?;
    match head.as_str() {
        "crate" => Some(rest.to_vec()),
        "self" => Some(from.iter().chain(rest).cloned().collect()),
        "super" => {
            let mut base = from.clone();
            let mut rest = rest;
            base.pop()?;
            while rest.first().is_some_and(|s| s == "super") {
                base.pop()?;
                rest = &rest[1..];
            }
            Some(base.into_iter().chain(rest.iter().cloned()).collect())
        }
        _ => {
            let child: Module = from.iter().chain(std::iter::once(head)).cloned().collect();
            krate.files.contains_key(&child).then(|| from.iter().chain(path).cloned().collect())
        }
    }
}

fn edges(krate: &Crate) -> BTreeMap<Module, BTreeSet<Module>> {
    let mut g: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (module, file) in &krate.files {
        if module.is_empty() {
            continue;
        }
        let mut c = PathCollector::default();
        c.visit_file(&parse(file));
        let out = g.entry(module.clone()).or_default();
        for p in &c.paths {
            if let Some(t) = resolve(krate, module, p).and_then(|abs| target(krate, &abs)) {
                // A module naming its own descendants (re-exports, its children's items) is the
                // natural downward direction and not counted.
                if &t != module && !t.is_empty() && !t.starts_with(module) {
                    out.insert(t);
                }
            }
        }
    }
    g
}

/// Strongly connected components with more than one node (Tarjan).
fn cycles(g: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<Module>> {
    struct T<'a> {
        g: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'a Module, usize>,
        low: BTreeMap<&'a Module, usize>,
        stack: Vec<&'a Module>,
        on: BTreeSet<&'a Module>,
        out: Vec<Vec<Module>>,
    }
    fn strong<'a>(t: &mut T<'a>, v: &'a Module) {
        let i = t.index.len();
        t.index.insert(v, i);
        t.low.insert(v, i);
        t.stack.push(v);
        t.on.insert(v);
        for w in t.g.get(v).into_iter().flatten() {
            if !t.index.contains_key(w) {
                strong(t, w);
                let lw = t.low[w];
                let lv = t.low.get_mut(v).expect("visited");
                *lv = (*lv).min(lw);
            } else if t.on.contains(w) {
                let iw = t.index[w];
                let lv = t.low.get_mut(v).expect("visited");
                *lv = (*lv).min(iw);
            }
        }
        if t.low[v] == t.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = t.stack.pop() {
                t.on.remove(w);
                comp.push(w.clone());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                t.out.push(comp);
            }
        }
    }
    let mut t = T {
        g,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: vec![],
        on: BTreeSet::new(),
        out: vec![],
    };
    for v in g.keys() {
        if !t.index.contains_key(v) {
            strong(&mut t, v);
        }
    }
    t.out
}

fn name(m: &Module) -> String {
    m.join("::")
}

fn check_crate(krate_name: &str) -> Vec<String> {
    let src = vouch_testkit::repo_root().join("crates").join(krate_name).join("src");
    let krate = load_crate(&src);
    let g = edges(&krate);
    let mut problems = Vec::new();
    for comp in cycles(&g) {
        let names: Vec<String> = comp.iter().map(name).collect();
        problems.push(format!("{krate_name}: import loop among {}", names.join(", ")));
    }
    if let Some((_, layers)) = LAYERS.iter().find(|(c, _)| *c == krate_name) {
        let layer_of = |m: &Module| {
            m.first().and_then(|top| layers.iter().position(|l| l.contains(&top.as_str())))
        };
        for (from, tos) in &g {
            let Some(lf) = layer_of(from) else {
                problems.push(format!("{krate_name}: module {} has no layer", name(from)));
                continue;
            };
            for to in tos {
                if layer_of(to).is_some_and(|lt| lt > lf) {
                    problems.push(format!(
                        "{krate_name}: upward import {} → {}",
                        name(from),
                        name(to)
                    ));
                }
            }
        }
    }
    problems
}

#[test]
fn library_module_graphs_have_no_loops_and_no_upward_imports() {
    let mut problems = Vec::new();
    for krate in ["vouch-fpl", "vouch-mav", "vouch-navfn", "vouch-cli"] {
        problems.extend(check_crate(krate));
    }
    assert!(problems.is_empty(), "module graph problems:\n{}", problems.join("\n"));
}

#[test]
fn the_checker_sees_a_planted_loop() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let dir = tmp.path();
    let src = dir.join("src");
    std::fs::create_dir_all(src.join("a")).expect("temp dir");
    std::fs::write(src.join("lib.rs"), "pub mod a;\npub mod b;\npub use a::Thing;\n")
        .expect("write");
    std::fs::write(src.join("a/mod.rs"), "pub mod inner;\npub struct Thing;\n").expect("write");
    std::fs::write(src.join("a/inner.rs"), "use crate::b::Other;\n").expect("write");
    std::fs::write(src.join("b.rs"), "pub struct Other;\nfn f(_: crate::Thing) {}\n")
        .expect("write");
    let krate = load_crate(&src);
    let found = cycles(&edges(&krate));
    // a::inner → b → a (through the root re-export); a → a::inner is not counted: no loop.
    assert!(found.is_empty(), "{found:?}");
    std::fs::write(src.join("a/mod.rs"), "pub mod inner;\npub struct Thing;\nuse crate::b::*;\n")
        .expect("write");
    std::fs::write(src.join("b.rs"), "pub struct Other;\nfn f(_: crate::a::inner::X) {}\n")
        .expect("write");
    std::fs::write(src.join("a/inner.rs"), "pub struct X;\nuse super::Thing;\n").expect("write");
    let found = cycles(&edges(&load_crate(&src)));
    assert_eq!(found.len(), 1, "a → b → a::inner → a is one loop: {found:?}");
}
