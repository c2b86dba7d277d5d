//! `cargo bench -p vouch-navfn`: the same measurement as `vouch navfn bench` (paper suite
//! µs/path and the nav2 400×400 default pair ms/plan). Skips when `shared/` is absent.

fn main() {
    let data = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/navfn");
    if !data.join("suite").is_dir() {
        eprintln!("skipping: {} not found", data.display());
        return;
    }
    if let Err(e) = vouch_navfn::bench::run(&data, 5, 50, &mut std::io::stdout()) {
        eprintln!("bench failed: {e}");
        std::process::exit(2);
    }
}
