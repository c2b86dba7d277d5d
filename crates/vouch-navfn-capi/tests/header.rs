//! The committed header `include/vouch_navfn.h` is exactly what cbindgen generates from the
//! crate (regenerate with `VOUCH_BLESS_HEADER=1 cargo test -p vouch-navfn-capi --test header`).

use std::path::Path;

#[test]
fn the_committed_header_is_what_cbindgen_generates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_config(config)
        // The crate root only: cbindgen follows its `mod` declarations to ffi.rs,
        // ffi_costmap.rs and the rest (naming them too would declare every function twice).
        .with_src(dir.join("src/lib.rs"))
        .generate()
        .expect("cbindgen reads the crate")
        .write(&mut generated);
    let path = dir.join("include/vouch_navfn.h");
    if std::env::var("VOUCH_BLESS_HEADER").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &generated).expect("header written");
    }
    let committed = std::fs::read(&path).expect("include/vouch_navfn.h");
    assert!(
        committed == generated,
        "include/vouch_navfn.h is out of date: run VOUCH_BLESS_HEADER=1 cargo test -p vouch-navfn-capi --test header"
    );
}

/// The names of the `extern "C"` functions of every source file of the crate (`src/ffi.rs`,
/// `src/ffi_costmap.rs`), each with its body.
fn entry_points() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("src/")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .collect();
    files.sort();
    let mut out = Vec::new();
    for file in files {
        let src = std::fs::read_to_string(&file).expect("a source file");
        out.extend(entry_points_of(&src));
    }
    out
}

/// The names of the `extern "C"` functions of one file, each with its body.
fn entry_points_of(src: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for (at, _) in src.match_indices("extern \"C\" fn ") {
        let rest = &src[at + "extern \"C\" fn ".len()..];
        let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        // the body: from the first `{` after the signature to its matching `}`
        let open = rest.find('{').expect("a body");
        let mut depth = 0usize;
        let mut end = open;
        for (i, c) in rest[open..].char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + i;
                        break;
                    }
                }
                _ => {}
            }
        }
        out.push((name, rest[open..=end].to_string()));
    }
    out
}

/// Function names declared in the header: `name(` outside comments.
fn declared(header: &str) -> Vec<String> {
    let mut names = Vec::new();
    for line in header.lines().filter(|l| !l.trim_start().starts_with("//")) {
        for (at, _) in line.match_indices("vouch_navfn_") {
            let name: String =
                line[at..].chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            if line[at + name.len()..].starts_with('(') {
                names.push(name);
            }
        }
    }
    names
}

#[test]
fn every_function_is_declared_once_with_size_t_for_sizes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(dir.join("include/vouch_navfn.h")).expect("header");
    let mut names = declared(&header);
    let all = names.len();
    names.sort();
    names.dedup();
    assert_eq!(all, names.len(), "a function is declared more than once: {names:?}");
    let mut exported: Vec<String> = entry_points().into_iter().map(|(n, _)| n).collect();
    exported.sort();
    assert_eq!(names, exported, "the header declares exactly the exported functions");
    assert_eq!(exported.len(), 17);
    assert!(!header.contains("uintptr_t"), "sizes are size_t");
    assert!(header.contains("size_t width"), "{header}");
}

#[test]
fn every_entry_point_runs_under_catch_unwind() {
    let unguarded: Vec<String> = entry_points()
        .into_iter()
        .filter(|(_, body)| !body.contains("guarded(") && !body.contains("catch_unwind("))
        .map(|(n, _)| n)
        .collect();
    assert!(unguarded.is_empty(), "not under catch_unwind: {unguarded:?}");
}

/// The header as a C programmer's compiler sees it: strict C99, every warning an error,
/// redundant (duplicate) declarations included, and included twice (the guard).
#[test]
fn the_header_compiles_as_strict_c99_without_redundant_declarations() {
    let Some(cc) = vouch_testkit::c_compiler() else { return };
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().expect("temporary directory");
    let tu = tmp.path().join("use_header.c");
    std::fs::write(
        &tu,
        "#include \"vouch_navfn.h\"\n#include \"vouch_navfn.h\"\n\
         int main(void) {\n  VouchNavfnParams p = vouch_navfn_default_params();\n  \
         size_t w = 0, h = 0;\n  (void)p;\n  \
         return vouch_navfn_size(NULL, &w, &h) == VOUCH_NAVFN_STATUS_OK;\n}\n",
    )
    .expect("write");
    let o = std::process::Command::new(&cc)
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-Wredundant-decls"])
        .args(["-fsyntax-only", "-I"])
        .arg(dir.join("include"))
        .arg(&tu)
        .output()
        .expect("cc runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}
