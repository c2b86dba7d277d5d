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
        .with_src(dir.join("src/lib.rs"))
        .with_src(dir.join("src/ffi.rs"))
        .with_src(dir.join("src/planner.rs"))
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
